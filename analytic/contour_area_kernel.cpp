#include "analytic/contour_area_kernel.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <boost/math/quadrature/gauss_kronrod.hpp>

#include "analytic/error_ledger.h"
#include "analytic/polygon_patch.h"
#include "analytic/sin_cos.h"
#include "analytic/sin_cos_power_integral.h"
#include "core/adaptive_quadrature.h"
#include "core/vec3.h"

namespace furnace::analytic {

namespace {

// Caps of each piece's adaptive quadrature (contour_area_kernel's contract):
// 40 levels resolve a feature 1e-12 of the piece wide (F within 1e-12·r of
// an arc); 2000 bisections bound the cost where round-off noise keeps every
// piece failing. What is not reached goes to the ledger.
constexpr double kContourAreaTolerance = 1e-14;
constexpr int kContourAreaDepth = 40;
constexpr size_t kContourAreaBisections = 2000;


// Distance from the origin F to a boundary piece.
double distance_to_piece(const Curve2& c) {
  if (!c.is_arc) {
    const double ex = c.end.x - c.start.x, ey = c.end.y - c.start.y, len2 = ex * ex + ey * ey;
    const double t = len2 > 0 ? std::clamp(-(c.start.x * ex + c.start.y * ey) / len2, 0.0, 1.0) : 0.0;
    return std::hypot(c.start.x + t * ex, c.start.y + t * ey);
  }
  const Circle2& k = c.circle;
  const double lo = std::fmin(c.t0, c.t0 + c.sweep), hi = std::fmax(c.t0, c.t0 + c.sweep);
  const double t_near = std::atan2(-k.cy, -k.cx);
  for (int j = -2; j <= 2; ++j) {
    const double t = t_near + 2 * j * kPi;
    if (t >= lo && t <= hi) return std::fabs(std::hypot(k.cx, k.cy) - k.radius);
  }
  return std::fmin(std::hypot(c.start.x, c.start.y), std::hypot(c.end.x, c.end.y));
}

double distance_to_boundary(const std::vector<Curve2>& boundary) {
  double d = INFINITY;
  for (const Curve2& c : boundary) d = std::fmin(d, distance_to_piece(c));
  return d;
}

}  // namespace

double contour_area_kernel(const std::vector<Curve2>& boundary, double h, double a, double n1, double n2,
                           bool foot_inside, double coordinate_scale) {
  const double h2 = h * h, h3 = h2 * h;
  // The direct form unless F is outside by more than h (see the header).
  const bool direct = foot_inside || !(distance_to_boundary(boundary) > h);
  // G/ρ² (F inside) or −(G∞ − G)/ρ² (F outside) at q ≠ 0, with
  // cq = n1·qx + n2·qy = c·ρ; divided by ρ² so that s²dφ = q × dq is the measure.
  auto radial_over_rho2 = [&](double qx, double qy) {
    const double rho2 = qx * qx + qy * qy, rho = std::sqrt(rho2);
    const double W = h2 + rho2, W3 = W * W * W;
    const double cq = n1 * qx + n2 * qy;
    if (direct) {
      const double i1 = (W * W + W * h2 + h2 * h2) / (6 * h2 * h2 * W3);  // I1/ρ²
      const double i3 = (rho2 + 3 * h2) / (12 * h2 * W3);                 // I3/ρ⁴
      // I2/ρ³ = J2(T)/(h³ρ³) → 1/(3h⁶) as ρ → 0 (J2 ~ T³/3).
      double i2 = 1 / (3 * h3 * h3);
      if (rho > 0) {
        const SinCos t = sin_cos_of_atan2(rho, h);  // of T = atan2(ρ, h)
        i2 = sin_cos_power_integral<2, 4>(t.S, t.C) / (h3 * rho2 * rho);
      }
      return a * a * i1 + 2 * a * cq * i2 + cq * cq * i3;
    }
    const double t1 = h2 / (6 * W3);
    const SinCos t = sin_cos_of_atan2(h, rho);  // of π/2 − T = atan2(h, ρ)
    const double t2 = sin_cos_power_integral<4, 2>(t.S, t.C) / h3;
    const double t3 = h2 * (h2 + 3 * rho2) / (12 * W3);
    return -(a * a * t1 + 2 * a * (cq / rho) * t2 + (cq / rho) * (cq / rho) * t3) / rho2;
  };
  double sum = 0, magnitude = 0, error = 0;
  auto integrate = [&](const auto& f, double lo, double hi) {
    if (!(hi > lo)) return 0.0;
    double piece_error = 0;
    const double value = adaptive_gauss_kronrod_relative<31>(f, lo, hi, kContourAreaTolerance, kContourAreaDepth, 1,
                                                             kContourAreaBisections, &piece_error);
    error += piece_error;
    magnitude += std::fabs(value);
    return value;
  };
  // ∫ over [cuts[0], cuts[1]] split at the other cuts strictly inside it.
  // The kernel on the boundary, f = (n·x)²h²/W⁴, for the sensitivity ∮ f ds.
  auto kernel_at = [&](double qx, double qy) {
    const double W = h2 + qx * qx + qy * qy, nx = a + n1 * qx + n2 * qy;
    return nx * nx * h2 / (W * W * W * W);
  };
  double sensitivity = 0;  // ≈ ∮ f ds: K's change per unit normal displacement of the boundary
  // ∫ over [cuts[0], cuts[1]] split at the other cuts strictly inside it;
  // `f_ds` (the kernel times ds/dparameter) adds one Gauss–Kronrod estimate
  // per piece to the sensitivity.
  auto integrate_pieces = [&](const auto& f, std::vector<double> cuts, const auto& f_ds) {
    const double lo = cuts[0], hi = cuts[1];
    std::vector<double> points = {lo, hi};
    for (size_t i = 2; i < cuts.size(); ++i)
      if (cuts[i] > lo && cuts[i] < hi) points.push_back(cuts[i]);
    std::sort(points.begin(), points.end());
    double total = 0;
    for (size_t i = 0; i + 1 < points.size(); ++i) {
      total += integrate(f, points[i], points[i + 1]);
      sensitivity += std::fabs(boost::math::quadrature::gauss_kronrod<double, 31>::integrate(f_ds, points[i], points[i + 1], 0, 0.0));
    }
    return total;
  };
  for (const Curve2& c : boundary) {
    if (!c.is_arc) {
      const std::optional<EdgeAboutFoot> e = edge_about_foot(c.start.x, c.start.y, c.end.x, c.end.y);
      if (!e) continue;  // no length, or on a line through F: dφ = 0
      const double dist = e->dist;
      // dφ = ±dψ along the segment: the integrand is the radial term itself.
      auto g = [&](double psi) {
        const double qx = e->x(psi), qy = e->y(psi);
        return radial_over_rho2(qx, qy) * (qx * qx + qy * qy);
      };
      // Cuts at the perpendicular's foot (ψ = 0) and, for a line closer to F
      // than h, where the ray reaches ρ = h (cos ψ = dist/h): the radial term
      // rises over a ψ-range of width ~ dist/h next to each of those.
      std::vector<double> cuts = {std::fmin(e->psi_a, e->psi_b), std::fmax(e->psi_a, e->psi_b), 0.0};
      if (dist < h) {
        const double psi_h = std::acos(dist / h);
        cuts.push_back(psi_h);
        cuts.push_back(-psi_h);
      }
      auto f_ds = [&](double psi) {
        const double cp = std::cos(psi);
        return kernel_at(e->x(psi), e->y(psi)) * dist / (cp * cp);
      };
      sum += e->oriented(integrate_pieces(g, cuts, f_ds));
      continue;
    }
    const Circle2& k = c.circle;
    const double r = k.radius;
    // In Δ = t − t_near, t_near the parameter of the arc's point nearest F,
    // with û = (cx, cy)/|c| and û⊥ = û turned by +90°:
    //   q = û·((|c| − r) + 2r sin²(Δ/2)) − û⊥·r sin Δ,
    //   q × dq/dΔ = r·((r − |c|) + 2|c| sin²(Δ/2)),
    // so that neither q nor the measure cancels when F is close to the circle.
    const double dc = std::hypot(k.cx, k.cy), gap = dc - r;
    const double ux = dc > 0 ? k.cx / dc : 1.0, uy = dc > 0 ? k.cy / dc : 0.0;
    const double t_near = std::atan2(-uy, -ux);
    auto g = [&](double delta) {
      const double half = std::sin(0.5 * delta), s2 = half * half, sd = std::sin(delta);
      const double along = gap + 2 * r * s2, across = -r * sd;
      const double qx = ux * along - uy * across, qy = uy * along + ux * across;
      return radial_over_rho2(qx, qy) * r * (-gap + 2 * dc * s2);
    };
    const double lo = std::fmin(c.t0, c.t0 + c.sweep) - t_near, hi = std::fmax(c.t0, c.t0 + c.sweep) - t_near;
    // Cuts at the arc's points nearest to (Δ = 0 mod 2π) and farthest from
    // F, and where the arc is max(F's distance from the circle, h) from the
    // nearest point (the width of the kernel's peak when F is close to it),
    // then at 4, 16, 64 … times that width up to 0.5: the radial term
    // approaches its limit over many widths (a deficit ~ (width/Δ)² that
    // integrates to a term ~ 1/h of K), and on one piece [width, π] the
    // Gauss–Kronrod nodes nearest its end lie ~1e-3·π in, beyond that
    // deficit once width < ~1e-4: its error estimate would see a constant
    // and accept a value missing part of it (1.4e-7 of K at h = 1e-5).
    std::vector<double> cuts = {lo, hi};
    const double width = std::fmax(std::fabs(gap), h) / r;
    for (int j = -4; j <= 4; ++j) {
      cuts.push_back(j * kPi);
      for (double w = width; w < 0.5; w *= 4) cuts.push_back(2 * j * kPi - w), cuts.push_back(2 * j * kPi + w);
    }
    auto f_ds = [&](double delta) {
      const double half = std::sin(0.5 * delta), along = gap + 2 * r * half * half, across = -r * std::sin(delta);
      return kernel_at(ux * along - uy * across, uy * along + ux * across) * r;
    };
    const double value = integrate_pieces(g, cuts, f_ds);
    sum += c.sweep >= 0 ? value : -value;
  }
  const double result = std::fmax(sum, 0.0);
  const double cancelled = std::fmax(magnitude - std::fabs(sum), 0.0);
  // Round-off: what cancels between pieces, and the boundary's own position,
  // rounded at ε·coordinate_scale (K moves by ∮ f·δ ds for a displacement δ).
  const double eps = std::numeric_limits<double>::epsilon();
  if (result > 0)
    ErrorLedger::report(error + kRoundoffUlps * eps * (cancelled + coordinate_scale * sensitivity), result);
  return result;
}

}  // namespace furnace::analytic
