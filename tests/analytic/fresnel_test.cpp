// The references' Fresnel forms (analytic/fresnel.h: Walter 2007 eq. 22 for
// the dielectric, the real-arithmetic form for the conductor) against the
// 50-digit textbook values of tests/fresnel_50.h, on the grids of
// tests/core/fresnel_test.cpp: the worst relative error per class printed
// and held to kPrecisionTarget (the bar), the neighbourhood of the
// critical angle from inside (within 1e-10 rad) apart with its condition
// number, total internal reflection exactly 1, and the degenerate
// conductors (0, 1) (F ≡ 1) and (1, 0) (F ≡ 0, absolute error).
// Negative control: the reference evaluated at the other side's index
// (η ↔ 1/η, the classic inside/outside slip) misses the 50-digit values by
// far, and the comparison says so.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

#include "analytic/fresnel.h"
#include "tests/fresnel_checks.h"

namespace furnace::analytic {
namespace {

using testing_support::Real50;
using testing_support::fresnel_dielectric_50;
using testing_support::relative_error;

// The requirement: 1e-13 relative (~450 ε).
constexpr double kPrecisionTarget = 1e-13;


TEST(FresnelReference, DielectricAgreesWithFiftyDigits) {
  testing_support::check_dielectric_grid("reference dielectric", fresnel_dielectric_reference, kPrecisionTarget);
  for (double c : testing_support::fresnel_cosines()) EXPECT_EQ(fresnel_dielectric_reference(c, 1.0), 0.0) << c;
}

// Within 1e-10 … 1e-4 rad of the critical angle from inside
// (tests/fresnel_checks.h): g² = η² − 1 + c² formed without rounding its parts.
TEST(FresnelReference, DielectricNearCriticalAngleFromInside) {
  testing_support::check_near_critical_angle("reference dielectric", fresnel_dielectric_reference,
                                             kPrecisionTarget);
}

TEST(FresnelReference, DielectricTotalInternalReflectionIsExactlyOne) {
  const long points = testing_support::for_each_total_internal_reflection([](double c, double eta) {
    EXPECT_EQ(fresnel_dielectric_reference(c, eta), 1.0) << "c " << c << " eta " << eta;
  });
  EXPECT_GT(points, 100);
}

// (1, 0) gave NaN at c = 0 and 0.0387 at c = 1e-8 until t = n² − k² − s²
// was formed as (n − 1)(n + 1) − k² + c².
TEST(FresnelReference, ConductorAgreesWithFiftyDigits) {
  testing_support::check_conductor_grid("reference conductor", fresnel_conductor_reference, kPrecisionTarget);
}

// Negative control: η and 1/η swapped (the inside/outside slip) is caught.
TEST(FresnelReference, SwappedIndexIsRejected) {
  double worst = 0;
  for (double c : testing_support::fresnel_cosines()) {
    const Real50 ref = fresnel_dielectric_50(c, 1.5);
    worst = std::fmax(worst, relative_error(fresnel_dielectric_reference(c, 1 / 1.5), ref));
  }
  std::cout << "  reference dielectric at 1/eta instead of eta (control): worst rel err " << worst << "\n";
  EXPECT_GT(worst, kPrecisionTarget);
  EXPECT_GT(worst, 1.0);
}

}  // namespace
}  // namespace furnace::analytic
