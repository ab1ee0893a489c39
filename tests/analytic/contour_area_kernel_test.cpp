// contour_area_kernel (analytic/contour_area_kernel.h) where its Green's-
// theorem form is hardest: the foot point F on the rim of a disk at height h
// above it, h from 1e-2 down to 1e-8 of the radius, receiver parallel to the
// disk. There K has a closed form (polar coordinates about F, the rim
// ρ = 2R·cos φ; t = tan φ turns the rest into three standard integrals):
//   K = ∫ h⁴/(h² + ρ²)⁴ dA = π/(6h²) − (π/(6h))·(B^-½ − 4B^-3/2 + 6B^-5/2),
//   B = 4R² + h² (R = 1; for other R scale h).
// Evaluated in 50 digits. The second term, ~π/(32h), is the slow approach of
// the radial integral to its limit along the rim next to F: a quadrature that
// does not resolve it is off by ~h relative (1.4e-7 of K at h = 1e-5 before
// the arcs were cut at widths graded from h up).
#include "analytic/contour_area_kernel.h"

#include <cmath>
#include <cstdio>
#include <limits>

#include <boost/multiprecision/cpp_bin_float.hpp>
#include <gtest/gtest.h>

#include "analytic/error_ledger.h"
#include "core/vec3.h"

namespace furnace::analytic {
namespace {

using Big = boost::multiprecision::cpp_bin_float_50;

// The accuracy target for every printed value.
constexpr double kTarget = 1e-13;

double closed_form_rim(double h, double R) {
  // K(h, R) = K(h/R, 1)/R² (K has units m⁻²).
  const Big H = Big(h) / Big(R), B = 4 + H * H, pi = boost::math::constants::pi<Big>();
  const Big k = pi / (6 * H * H) - pi / (6 * H) * (1 / sqrt(B) - 4 / (B * sqrt(B)) + 6 / (B * B * sqrt(B)));
  return static_cast<double>(k / (Big(R) * Big(R)));
}

// The circle of radius R through F, centre R·(cos α, sin α), as CGAL hands it
// over: two x-monotone half-circle arcs.
std::vector<Curve2> circle_through_foot(double R, double cx, double cy) {
  Curve2 a;
  a.is_arc = true;
  a.circle.cx = cx;
  a.circle.cy = cy;
  a.circle.radius = R;
  a.t0 = 0;
  a.sweep = kPi;
  a.start = {cx + R, cy};
  a.end = {cx - R, cy};
  Curve2 b = a;
  b.t0 = kPi;
  b.start = a.end;
  b.end = a.start;
  return {a, b};
}

TEST(ContourAreaKernel, FootOnTheRimMatchesTheClosedFormDownToHeight1e8) {
  double worst = 0;
  for (double R : {1.0, 3.0})
    for (double h : {1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8})
      for (const auto& [cx, cy] : {std::pair<double, double>{R, 0}, {0, R}, {-R, 0}, {0, -R}}) {
        ErrorLedger ledger;
        const double value = contour_area_kernel(circle_through_foot(R, cx, cy), h, h, 0, 0, true, R);
        const double expected = closed_form_rim(h, R);
        const double err = std::fabs(value - expected) / expected;
        worst = std::fmax(worst, err);
        EXPECT_LE(err, kTarget) << "R " << R << ", h " << h << ", centre (" << cx << ", " << cy << "): " << value
                                << " vs " << expected;
        EXPECT_LE(err, ledger.bound(value) / value) << "R " << R << ", h " << h;
      }
  std::printf("[ contour ] foot point on the rim, h/R 1e-2 … 3e-9: worst relative error %.3g\n", worst);
}

}  // namespace
}  // namespace furnace::analytic
