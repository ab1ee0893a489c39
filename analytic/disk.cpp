#include "analytic/disk.h"

#include <cmath>
#include <string>

#include "core/error.h"
#include "core/vec3.h"

namespace furnace::analytic {

namespace {

// 1 − a/S for S = αβ > 0 and S² − a² = 4r²h² (the identity holds for both the
// unoccluded disk and an arc's circle). For a ≥ 0 the subtraction cancels, so
// use the difference of squares over the sum; for a < 0 the terms add.
double one_minus_a_over_s(double a, double S, double r, double h) {
  if (a < 0) return 1.0 - a / S;
  const double two_rh = 2.0 * r * h;
  return (two_rh / S) * (two_rh / (S + a));  // split so that (2rh)² cannot overflow
}

}  // namespace

double disk_irradiance_parallel(double R, double h, double d) {
  if (!(h > 0) || !(R >= 0) || !(d >= 0) || !std::isfinite(h) || !std::isfinite(R) || !std::isfinite(d))
    throw Error("disk_irradiance_parallel: needs finite h > 0, R >= 0, d >= 0; got h = " + std::to_string(h) +
                ", R = " + std::to_string(R) + ", d = " + std::to_string(d) + ".");
  // S² = (h²+d²+R²)² − 4R²d² = (h²+(d−R)²)(h²+(d+R)²): a product of two hypots.
  const double S = std::hypot(h, d - R) * std::hypot(h, d + R);
  // a = h² + d² − R² with d² − R² as (d−R)(d+R): exact when d ≈ R.
  const double a = h * h + (d - R) * (d + R);
  return 0.5 * kPi * one_minus_a_over_s(a, S, R, h);
}

double disk_irradiance_parallel_complement(double R, double h, double d) {
  (void)disk_irradiance_parallel(R, h, d);  // the same domain check
  const double S = std::hypot(h, d - R) * std::hypot(h, d + R);
  const double a = h * h + (d - R) * (d + R);
  if (a >= 0) return 0.5 * kPi * (1.0 + a / S);
  const double two_rh = 2.0 * R * h;
  return 0.5 * kPi * (two_rh / S) * (two_rh / (S - a));  // split so that (2Rh)² cannot overflow
}

double arc_contour(double h, const Circle2& circle, double t0, double sweep) {
  FURNACE_CHECK(h > 0 && circle.radius >= 0);
  const double r = circle.radius;
  const double D = std::hypot(circle.cx, circle.cy);
  const double alpha = std::hypot(h, D - r);
  const double beta = std::hypot(h, D + r);
  const double S = alpha * beta;
  const double a = h * h + (D - r) * (D + r);
  // β − α = (β² − α²)/(β + α) = 4rD/(β + α): no cancellation for small r or D.
  const double beta_minus_alpha = 4.0 * r * D / (beta + alpha);
  const double beta_plus_alpha = beta + alpha;
  const double centre_angle = std::atan2(circle.cy, circle.cx);
  auto delta = [&](double t) {
    const double u = t - centre_angle;
    return std::atan2(beta_minus_alpha * std::sin(u), beta_plus_alpha + beta_minus_alpha * std::cos(u));
  };
  const double smooth = one_minus_a_over_s(a, S, r, h) * (0.5 * sweep);
  // A whole turn brings δ back to its start; skip it so that a full circle
  // equals disk_irradiance_parallel to the last bit.
  const bool full_turn = std::fabs(sweep) == 2.0 * kPi;
  const double periodic = full_turn ? 0.0 : (a / S) * (delta(t0 + sweep) - delta(t0));
  return 0.5 * (smooth + periodic);
}

}  // namespace furnace::analytic
