// sin_cos_of_atan2 (analytic/sin_cos.h) against cpp_bin_float_50, in
// relative error, with its negative control: the plain quotient; and
// HalfAngleArc(s), the half-angle variable of the MIS and Phong quadratures:
// cos φ, sin φ against cpp_bin_float_50, integrals over arcs of every width
// up to 2π against their closed forms, with the negative control of a
// quadrature that forgets dφ/dτ.
#include "analytic/sin_cos.h"

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include <boost/multiprecision/cpp_bin_float.hpp>
#include <gtest/gtest.h>

#include "core/adaptive_quadrature.h"
#include "core/vec3.h"

namespace furnace::analytic {
namespace {

using Big = boost::multiprecision::cpp_bin_float_50;

constexpr double kEps = std::numeric_limits<double>::epsilon();

// sin_cos_of_atan2 to about half an ulp (correct rounding is 0.5 ε
// relative at worst; 0.55 allows the residual's own last rounding) over
// y/x from 1e-12 to 1e12 with x from 1e-6 to 1e6; its negative control, the
// plain y/sqrt(x*x + y*y), is off by up to 1.25 ε and must fail.
constexpr double kAtan2Ulps = 0.55;

double worst_sin_cos_error(SinCos (*f)(double, double)) {
  std::mt19937_64 rng(20261125);  // a fixed seed: the same grid every run
  std::uniform_real_distribution<double> u(0, 1);
  double worst = 0;
  for (int i = 0; i < 20000; ++i) {
    const double x = std::pow(10.0, -6 + 12 * u(rng)), y = x * std::pow(10.0, -12 + 24 * u(rng));
    const Big r = sqrt(Big(x) * x + Big(y) * y);
    const SinCos v = f(y, x);
    worst = std::fmax(worst, static_cast<double>(abs(Big(v.S) / (Big(y) / r) - 1)));
    worst = std::fmax(worst, static_cast<double>(abs(Big(v.C) / (Big(x) / r) - 1)));
  }
  return worst;
}

TEST(SinCosOfAtan2, WithinHalfAnUlp) {
  const double e = worst_sin_cos_error(sin_cos_of_atan2);
  std::printf("[ sin cos ] sin_cos_of_atan2: worst relative error %.3g (%.2f eps)\n", e, e / kEps);
  EXPECT_LE(e, kAtan2Ulps * kEps);
  const SinCos axis = sin_cos_of_atan2(0.0, 2.0), up = sin_cos_of_atan2(3.0, 0.0);
  EXPECT_EQ(axis.S, 0.0);
  EXPECT_EQ(axis.C, 1.0);
  EXPECT_EQ(up.S, 1.0);
  EXPECT_EQ(up.C, 0.0);
}

TEST(SinCosOfAtan2, RejectsThePlainQuotient) {
  const double e = worst_sin_cos_error([](double y, double x) {
    const double r = std::sqrt(x * x + y * y);
    return SinCos{y / r, x / r};
  });
  EXPECT_GT(e, kAtan2Ulps * kEps);
}

// cos φ and sin φ of HalfAngleArc::at within 4 ε of those of c + 2·atan τ,
// c the arc's midpoint as rounded (absolute: both are bounded by 1 and cross
// 0), at 20 000 points of random arcs of width up to
// π anywhere in [−2π, 4π], and dφ/dτ = 2/(1 + τ²) to 2 ε relative.
TEST(HalfAngleArc, CosSinAndJacobianMatchTheAngle) {
  std::mt19937_64 rng(20261203);
  std::uniform_real_distribution<double> u(0, 1);
  double worst = 0, worst_jacobian = 0, widest_tau = 0;
  for (int i = 0; i < 20000; ++i) {
    const double lo = -2 * kPi + 6 * kPi * u(rng), width = kPi * u(rng);
    const HalfAngleArc arc = HalfAngleArc::of(lo, lo + width);
    widest_tau = std::fmax(widest_tau, arc.tau_max);
    const double tau = arc.tau_max * (2 * u(rng) - 1);
    double c, s, jacobian;
    arc.at(tau, &c, &s, &jacobian);
    // About the midpoint as the arc rounds it (a quadrature node φ = c + h·x in
    // double precision rounds the same way).
    const Big phi = Big(0.5 * (lo + (lo + width))) + 2 * atan(Big(tau));
    worst = std::fmax(worst, static_cast<double>(abs(Big(c) - cos(phi))));
    worst = std::fmax(worst, static_cast<double>(abs(Big(s) - sin(phi))));
    worst_jacobian = std::fmax(worst_jacobian, static_cast<double>(abs(Big(jacobian) / (2 / (1 + Big(tau) * tau)) - 1)));
  }
  std::printf("HalfAngleArc: worst |cos, sin error| %.3g (%.2f eps), dphi/dtau %.3g relative, tau_max <= %.17g\n",
              worst, worst / kEps, worst_jacobian, widest_tau);
  EXPECT_LE(worst, 4 * kEps);
  EXPECT_LE(worst_jacobian, 2 * kEps);
  EXPECT_LE(widest_tau, 1.0 + kEps);
}

// ∫ over [lo, hi] of cos φ and of e^{sin φ} cos φ (closed forms sin hi − sin lo
// and e^{sin hi} − e^{sin lo}), and the arc length, by adaptive Gauss–Kronrod
// in τ over HalfAngleArcs pieces, for 2 000 arcs of width 1e-6 … 2π: within
// 1e-13 absolute. The negative control integrates without dφ/dτ and must miss
// the arc length by more than 1 % on arcs wider than 1.
double arc_integral(double lo, double hi, int which, bool with_jacobian) {
  const HalfAngleArcs arcs = HalfAngleArcs::of(lo, hi);
  double total = 0;
  for (int k = 0; k < arcs.count; ++k) {
    const HalfAngleArc& arc = arcs.piece[k];
    auto f = [&](double tau) {
      double c, s, jacobian;
      arc.at(tau, &c, &s, &jacobian);
      const double value = which == 0 ? c : which == 1 ? std::exp(s) * c : 1.0;
      return with_jacobian ? value * jacobian : value;
    };
    total += adaptive_gauss_kronrod(f, -arc.tau_max, arc.tau_max, 1e-15, 12);
  }
  return total;
}

TEST(HalfAngleArcs, IntegralsOverArcsOfEveryWidthMatchTheirClosedForms) {
  std::mt19937_64 rng(20261204);
  std::uniform_real_distribution<double> u(0, 1);
  double worst = 0;
  int two_pieces = 0;
  for (int i = 0; i < 2000; ++i) {
    const double lo = -kPi + 2 * kPi * u(rng), width = 2 * kPi * std::pow(10.0, -6.8 * u(rng));
    const double hi = lo + width;
    two_pieces += HalfAngleArcs::of(lo, hi).count == 2;
    worst = std::fmax(worst, std::fabs(arc_integral(lo, hi, 0, true) - (std::sin(hi) - std::sin(lo))));
    worst = std::fmax(worst, std::fabs(arc_integral(lo, hi, 1, true) - (std::exp(std::sin(hi)) - std::exp(std::sin(lo)))));
    worst = std::fmax(worst, std::fabs(arc_integral(lo, hi, 2, true) - width));
  }
  std::printf("HalfAngleArcs: 2000 arcs (%d in two pieces), worst absolute error %.3g\n", two_pieces, worst);
  EXPECT_LE(worst, 1e-13);
  EXPECT_GT(two_pieces, 50);
  EXPECT_EQ(HalfAngleArcs::of(1.0, 1.0).count, 0);
  EXPECT_EQ(HalfAngleArcs::of(0.0, 2 * kPi).count, 2);
}

TEST(HalfAngleArcs, NegativeControlWithoutTheJacobianMissesTheArcLength) {
  for (double width : {1.0, 2.0, kPi, 2 * kPi}) {
    const double missed = std::fabs(arc_integral(0.3, 0.3 + width, 2, false) / width - 1);
    std::printf("without dphi/dtau, width %.4g: arc length off by %.3g relative\n", width, missed);
    EXPECT_GT(missed, 0.01) << width;
  }
}

}  // namespace
}  // namespace furnace::analytic
