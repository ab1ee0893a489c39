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
#include "tests/fresnel_50.h"

namespace furnace::analytic {
namespace {

using testing_support::ComplexIndex;
using testing_support::Real50;
using testing_support::WorstError;
using testing_support::fresnel_conductor_50;
using testing_support::fresnel_dielectric_50;
using testing_support::relative_error;

constexpr double kEps = std::numeric_limits<double>::epsilon();
// The requirement: 1e-13 relative (~450 ε).
constexpr double kPrecisionTarget = 1e-13;

void print_worst(const std::string& what, const WorstError& w, const char* a_name, const char* b_name) {
  std::cout << "  " << what << " worst rel err " << w.error << " at c = " << w.cos_i << ", " << a_name << " = " << w.a;
  if (b_name != nullptr) std::cout << ", " << b_name << " = " << w.b;
  std::cout << " (F = " << w.value << ", 50-digit " << w.reference << "; " << w.points << " points)\n";
}

TEST(FresnelReference, DielectricAgreesWithFiftyDigits) {
  WorstError outside, inside, near_one, grazing;
  for (double eta : testing_support::kFresnelEtas)
    for (double c : testing_support::fresnel_cosines()) {
      const double f = fresnel_dielectric_reference(c, eta);
      const Real50 ref = fresnel_dielectric_50(c, eta);
      const double e = relative_error(f, ref);
      if (std::fabs(eta - 1) <= 1e-3) near_one.add(e, c, eta, 0, f, ref);
      else if (eta > 1) outside.add(e, c, eta, 0, f, ref);
      else inside.add(e, c, eta, 0, f, ref);
      if (c <= 1e-4) grazing.add(e, c, eta, 0, f, ref);
      EXPECT_LE(e, kPrecisionTarget) << "c " << c << " eta " << eta << " F " << f;
    }
  print_worst("reference dielectric eta > 1", outside, "eta", nullptr);
  print_worst("reference dielectric eta < 1", inside, "eta", nullptr);
  print_worst("reference dielectric |eta - 1| <= 1e-3", near_one, "eta", nullptr);
  print_worst("reference dielectric grazing c <= 1e-4", grazing, "eta", nullptr);
  for (double c : testing_support::fresnel_cosines()) EXPECT_EQ(fresnel_dielectric_reference(c, 1.0), 0.0) << c;
}

// θ = θc − dtheta from inside: ill-conditioned (see tests/core/fresnel_test.cpp;
// measured when written: 5.9e-11 at 1e-10 rad, as core/fresnel.h: g² = η² − 1 + c²
// is formed from rounded c² and η² − 1).
TEST(FresnelReference, DielectricNearCriticalAngleFromInside) {
  const std::vector<double> etas{0.25, 0.5, 1 / 1.5, 1 / 1.05, 0.999, 1 - 1e-6};
  for (double dtheta : {1e-10, 1e-8, 1e-6, 1e-4}) {
    WorstError w;
    double kappa_at_worst = 0;
    for (double eta : etas) {
      const double c = testing_support::cos_near_critical(eta, -dtheta);
      const Real50 ref = fresnel_dielectric_50(c, eta);
      ASSERT_LT(ref, 1) << "not on the transmitting side: eta " << eta << " dtheta " << dtheta;
      const double f = fresnel_dielectric_reference(c, eta);
      const double e = relative_error(f, ref);
      if (e >= w.error) kappa_at_worst = testing_support::fresnel_dielectric_condition(c, eta);
      w.add(e, c, eta, dtheta, f, ref);
      EXPECT_LE(e, kPrecisionTarget) << "theta_c - " << dtheta << " rad, eta " << eta << ", c " << c << ": F " << f
                                     << " vs 50-digit " << static_cast<double>(ref);
    }
    std::cout << "  reference dielectric theta_c - " << dtheta << " rad: worst rel err " << w.error << " at eta = "
              << w.a << ", c = " << w.cos_i << " (condition number " << kappa_at_worst << ", kappa*eps/2 = "
              << kappa_at_worst * kEps / 2 << ")\n";
  }
}

TEST(FresnelReference, DielectricTotalInternalReflectionIsExactlyOne) {
  long points = 0;
  for (double eta : testing_support::kFresnelEtas) {
    if (!(eta < 1)) continue;
    std::vector<double> cosines{0.0};
    for (double dtheta : {1e-10, 1e-8, 1e-6, 1e-3, 0.1}) {
      const double c = testing_support::cos_near_critical(eta, dtheta);
      if (c >= 0) cosines.push_back(c);
    }
    for (double c : testing_support::fresnel_cosines())
      if (fresnel_dielectric_50(c, eta) == 1) cosines.push_back(c);
    for (double c : cosines) {
      ASSERT_EQ(fresnel_dielectric_50(c, eta), 1) << "not TIR: c " << c << " eta " << eta;
      ++points;
      EXPECT_EQ(fresnel_dielectric_reference(c, eta), 1.0) << "c " << c << " eta " << eta;
    }
  }
  std::cout << "  " << points << " points past the critical angle\n";
  EXPECT_GT(points, 100);
}

// Measured when written: ≤ 3.0e-15 for the four metals, 1e-50 for (0, 1);
// (1, 0) fails: NaN at c = 0, 0.0387 at c = 1e-8 (t = n² − k² − s² cancels).
TEST(FresnelReference, ConductorAgreesWithFiftyDigits) {
  for (const ComplexIndex& x : testing_support::kConductors) {
    WorstError w;
    for (double c : testing_support::fresnel_cosines()) {
      const double f = fresnel_conductor_reference(c, x.n, x.k);
      const Real50 ref = fresnel_conductor_50(c, x.n, x.k);
      const double e = relative_error(f, ref);  // absolute for (1, 0), where F ≡ 0
      w.add(e, c, x.n, x.k, f, ref);
      EXPECT_LE(e, kPrecisionTarget) << "conductor (" << x.n << ", " << x.k << ") c " << c << ": F " << f
                                     << " vs 50-digit " << static_cast<double>(ref);
    }
    const std::string name = "reference conductor (" + std::to_string(x.n).substr(0, 4) + ", " +
                             std::to_string(x.k).substr(0, 4) + ")" +
                             (x.n == 1 && x.k == 0 ? " (absolute: F = 0)" : "");
    print_worst(name, w, "n", "k");
  }
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
