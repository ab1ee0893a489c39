// The Fresnel reflectances of core/fresnel.h against 50-digit values
// computed from the textbook definitions (tests/fresnel_50.h: Snell's law
// and the two amplitudes for the dielectric; the normal wave-vector
// component q = √(η̃² − sin²θi) for the conductor, in cpp_complex_50):
//  - the dielectric over c ∈ [0, 1] (exact 0 and 1, grazing to 1e-8,
//    1 − 1e-8) × η ∈ [0.25, 4] (1 ± 1e-6, 0.999, 1.001 included), the worst
//    relative error per class printed and held to kPrecisionTarget (the
//    issue's bar); the neighbourhood of the critical angle from inside (the
//    angle within 1e-10 rad of it) is its own test, with the condition
//    number printed beside the error;
//  - total internal reflection returns exactly 1 (and refracted_cos exactly 0);
//  - Fresnel symmetry F(θi; η) = F(θt; 1/η) for Snell pairs;
//  - spot values from outside the project (Mitsuba 3's test_fresnel.py:
//    F(1; 1.5) = 0.04, F(cos 80°; 1.5) = 0.387704 to 6 digits);
//  - the conductor at (n, k) ∈ {(0.2, 3.4), (1.5, 0.1), (2, 4), (0.05, 2),
//    (1, 0), (0, 1)}, worst relative error per (n, k) printed; (0, 1) is
//    F ≡ 1 and (1, 0) F ≡ 0 (absolute error: no relative error exists);
//  - the two 50-digit references agree with each other for k = 0 (two
//    independent forms of the same physics).
// Negative control: fresnel_conductor_approximate (Cycles < 5.0) misses the
// 50-digit value at (1.5, 0.1) by more than 1e-2, and the comparison says so.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

#include "core/fresnel.h"
#include "core/vec3.h"
#include "tests/fresnel_checks.h"

namespace furnace {
namespace {

using testing_support::ComplexIndex;
using testing_support::Real50;
using testing_support::fresnel_conductor_50;
using testing_support::fresnel_dielectric_50;
using testing_support::relative_error;

constexpr double kEps = std::numeric_limits<double>::epsilon();
// The requirement on every Fresnel value: 1e-13 relative (~450 ε).
constexpr double kPrecisionTarget = 1e-13;
// Fresnel symmetry: the issue asks 1e-14 (~45 ε), beyond the exact effect
// of the rounded inputs, for pairs away from the critical angle (see the test).
constexpr double kSymmetryTarget = 1e-14;
// Mitsuba's spot values carry 6 significant digits: half a unit of the 6th.
constexpr double kSixDigits = 5e-7;


// ---------------------------------------------------------------------------
// Dielectric.

TEST(FresnelDielectric, AgreesWithFiftyDigitsOverGrid) {
  testing_support::check_dielectric_grid("dielectric", fresnel_dielectric, kPrecisionTarget);
}

// Index-matched: no interface, F = 0 exactly at every angle (grazing
// included, where every η ≠ 1 gives F → 1).
TEST(FresnelDielectric, IndexMatchedIsExactlyZero) {
  for (double c : testing_support::fresnel_cosines()) EXPECT_EQ(fresnel_dielectric(c, 1.0), 0.0) << c;
}

// Within 1e-10 … 1e-4 rad of the critical angle from inside, where F is
// ill-conditioned (tests/fresnel_checks.h). Rounding c² and η² − 1 before
// adding them cost 5.9e-11 at 1e-10 rad (η = 0.25, κ = 4.7e6) until
// core/fresnel.h formed η² − 1 + c² without rounding its parts.
TEST(FresnelDielectric, NearCriticalAngleFromInside) {
  testing_support::check_near_critical_angle("dielectric", fresnel_dielectric, kPrecisionTarget);
}

// Past the critical angle from inside, and at grazing incidence from inside,
// F is exactly 1, refracted_cos exactly 0 and total_internal_reflection true.
TEST(FresnelDielectric, TotalInternalReflectionIsExactlyOne) {
  const long points = testing_support::for_each_total_internal_reflection([](double c, double eta) {
    EXPECT_EQ(fresnel_dielectric(c, eta), 1.0) << "c " << c << " eta " << eta;
    EXPECT_EQ(refracted_cos(c, eta), 0.0) << "c " << c << " eta " << eta;
    EXPECT_TRUE(total_internal_reflection(c, eta)) << "c " << c << " eta " << eta;
  });
  EXPECT_GT(points, 100);
}

// total_internal_reflection and refracted_cos on the transmitting side: no
// TIR, and cos θt to a few ε times its condition number. cos²θt =
// (η² − 1 + c²)/η² is formed from c² and η² − 1, each with a relative
// rounding ε/2, so its relative error is about ε(c² + |η² − 1|)/(η²cos²θt),
// large near the critical angle where the sum cancels; cos θt has half of it.
TEST(FresnelDielectric, RefractedCosineFollowsSnell) {
  double worst = 0, worst_ratio = 0;
  for (double eta : testing_support::kFresnelEtas)
    for (double c : testing_support::fresnel_cosines()) {
      const Real50 ref = testing_support::refracted_cos_50(c, eta);
      if (ref == 0) continue;
      EXPECT_FALSE(total_internal_reflection(c, eta)) << "c " << c << " eta " << eta;
      const double ct = refracted_cos(c, eta);
      const double e = relative_error(ct, ref);
      const double ct_ref = static_cast<double>(ref);
      const double kappa = (c * c + std::fabs((eta - 1) * (eta + 1))) / (2 * eta * eta * ct_ref * ct_ref);
      const double tol = 4 * kEps * (1 + kappa);
      worst = std::fmax(worst, e);
      worst_ratio = std::fmax(worst_ratio, e / tol);
      EXPECT_LE(e, tol) << "c " << c << " eta " << eta;
    }
  std::cout << "  refracted_cos worst rel err " << worst << ", worst error / (4 eps (1 + kappa)) " << worst_ratio
            << "\n";
}

// F(θi; η) = F(θt; 1/η) for a Snell pair. The second evaluation's inputs
// are rounded: cos θt (the 50-digit Snell value) and 1/η. Near η = 1 the
// rounding of 1/η alone moves F ∝ (η − 1)² by ~2ε/|η − 1| relative, so each
// pair is allowed kSymmetryTarget plus the exact effect of its rounded
// inputs, |F50(cos θi; η) − F50(fl(cos θt); fl(1/η))|/F (printed).
// The pair is well conditioned only away from the critical angle of the
// dense side: θi ≤ 80° from outside (θt at least 0.8° short of θc at
// η = 1.001, the worst of the grid), and from inside θi at least 1° short
// of θc; closer, the code's own rounding is amplified by the condition
// number (NearCriticalAngleFromInside).
TEST(FresnelDielectric, SymmetricUnderSnellPairs) {
  double worst = 0, worst_c = 0, worst_eta = 0, worst_input = 0;
  long pairs = 0;
  const double c_min_outside = std::cos(80 * kPi / 180);
  for (double eta : testing_support::kFresnelEtas)
    for (int k = 0; k <= 400; ++k) {
      const double c = k / 400.0;
      if (eta > 1 && c < c_min_outside) continue;
      if (eta < 1) {
        const double theta_c = std::asin(eta), theta = std::acos(c);
        if (theta > theta_c - kPi / 180) continue;
      }
      const double ct = static_cast<double>(testing_support::refracted_cos_50(c, eta)), inv = 1 / eta;
      const Real50 exact = fresnel_dielectric_50(c, eta);
      const double input_gap = static_cast<double>(abs(exact - fresnel_dielectric_50(ct, inv)) / exact);
      const double forward = fresnel_dielectric(c, eta), backward = fresnel_dielectric(ct, inv);
      const double e = std::fabs(forward - backward) / forward;
      ++pairs;
      worst_input = std::fmax(worst_input, input_gap);
      if (e > worst) worst = e, worst_c = c, worst_eta = eta;
      EXPECT_LE(e, kSymmetryTarget + input_gap) << "c " << c << " eta " << eta << " ct " << ct;
    }
  std::cout << "  symmetry F(ti; eta) = F(tt; 1/eta): worst rel diff " << worst << " at c = " << worst_c
            << ", eta = " << worst_eta << " (" << pairs << " pairs); worst effect of the rounded inputs "
            << worst_input << "\n";
}

TEST(FresnelDielectric, SpotValuesFromMitsuba) {
  // Normal incidence: ((η − 1)/(η + 1))² = 0.04 at η = 1.5 (exact in decimal).
  EXPECT_NEAR(fresnel_dielectric(1.0, 1.5), 0.04, 4 * kEps * 0.04);
  const double c80 = std::cos(80 * kPi / 180);
  EXPECT_NEAR(fresnel_dielectric(c80, 1.5), 0.387704, kSixDigits);
  std::cout << "  F(1; 1.5) = " << fresnel_dielectric(1.0, 1.5) << ", F(cos 80 deg; 1.5) = "
            << fresnel_dielectric(c80, 1.5) << "\n";
}

// ---------------------------------------------------------------------------
// Conductor.


// The index-matched (1, 0) gave NaN at c = 0 and 0.0387 at c = 1e-8 until
// core/fresnel.h formed cos²θt as (η̃² − 1 + c²)/η̃² (1 − s²/η̃² with s²
// rounded cancels to nothing when η̃² = 1).
TEST(FresnelConductor, AgreesWithFiftyDigitsOverGrid) {
  testing_support::check_conductor_grid("conductor", fresnel_conductor, kPrecisionTarget);
}

// The degenerate indices, in the references themselves: the ideal conductor
// reflects everything, an index-matched "conductor" nothing.
TEST(FresnelConductor, FiftyDigitReferenceLimits) {
  for (double c : testing_support::fresnel_cosines()) {
    EXPECT_LT(abs(fresnel_conductor_50(c, 0, 1) - 1), Real50(1e-45)) << c;
    EXPECT_LT(abs(fresnel_conductor_50(c, 1, 0)), Real50(1e-45)) << c;
  }
}

// For k = 0 the two 50-digit forms (Snell with cos θt; the wave vector with
// q) must agree to their own precision: a slip in either shows here.
TEST(FresnelConductor, FiftyDigitFormsAgreeForRealIndex) {
  double worst = 0;
  for (double eta : testing_support::kFresnelEtas)
    for (double c : testing_support::fresnel_cosines()) {
      const Real50 a = fresnel_dielectric_50(c, eta), b = fresnel_conductor_50(c, eta, 0);
      worst = std::fmax(worst, static_cast<double>(abs(a - b) / a));
    }
  std::cout << "  50-digit dielectric vs conductor(k = 0): worst rel diff " << worst << "\n";
  EXPECT_LT(worst, 1e-40);
}

// Negative control: the approximation Cycles used before 5.0 (R∥, R⊥ from
// n² + k² without the complex root) is off by up to ~0.1 at (1.5, 0.1), and
// the comparison above detects it.
TEST(FresnelConductor, ApproximationIsRejected) {
  const ComplexIndex x{1.5, 0.1};
  double worst_abs = 0, worst_rel = 0, at = 0;
  for (double c : testing_support::fresnel_cosines()) {
    const Real50 ref = fresnel_conductor_50(c, x.n, x.k);
    const double f = fresnel_conductor_approximate(c, x.n, x.k);
    const double a = static_cast<double>(abs(Real50(f) - ref));
    if (a > worst_abs) worst_abs = a, at = c;
    worst_rel = std::fmax(worst_rel, relative_error(f, ref));
  }
  std::cout << "  approximate conductor (1.5, 0.1): worst abs err " << worst_abs << " at c = " << at
            << ", worst rel err " << worst_rel << " (control)\n";
  EXPECT_GT(worst_abs, 1e-2);
  EXPECT_GT(worst_rel, kPrecisionTarget);
}

}  // namespace
}  // namespace furnace
