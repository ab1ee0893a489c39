// sin_cos_power_integral (analytic/sin_cos_power_integral.h) against a
// 50-digit reference: 30-point Gauss–Legendre in cpp_bin_float_50 of the
// positive integrand over [0, T] (a trigonometric polynomial of degree ≤ 6
// on at most [0, π/2]: the rule's error is ~(6·π/4)^60/60! ≈ 1e-41 relative,
// and nothing cancels for small T, where the closed forms lose T⁻² of their
// digits). The reference itself is checked against the closed forms
//   J_{2,4}(T) = T/16 − sin 4T/64 + sin³2T/48,  J_{4,2}(T) = T/16 − sin 4T/64 − sin³2T/48
// (sin²t cos²t = sin²2t/4, and cos²t, sin²t = (1 ± cos 2t)/2) where those
// keep 40 digits. Other branches of the series: (0, 0) (ν = −1/2, the
// slowest series), (2, 0), (1, 1) (a polynomial). Over T ∈ (0, π/2]: a uniform grid,
// tiny T (10^-k), T next to π/4 (where the series hands over to its
// complement) and next to π/2. Inputs S, C are sin T and cos T rounded to
// double; the reference is taken at the T those inputs determine (asin S for
// S ≤ C, acos C beyond: the function's contract). Negative controls: the
// series without its complement, and the closed form in double.
#include "analytic/sin_cos_power_integral.h"

#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <vector>

#include <boost/math/constants/constants.hpp>
#include <boost/math/quadrature/gauss.hpp>
#include <boost/multiprecision/cpp_bin_float.hpp>
#include <gtest/gtest.h>

namespace furnace::analytic {
namespace {

using Big = boost::multiprecision::cpp_bin_float_50;

constexpr double kEps = std::numeric_limits<double>::epsilon();

// The accuracy the header promises for (2, 4) and (4, 2): a few ulps. The
// worst measured is about 3 ε, at the hand-over T ≈ π/4 where (4, 2)'s
// complement takes 2.5 times the result from π/32 (see the header).
constexpr double kToleranceUlps = 8;

// The grid's T values: uniform, tiny, next to π/4 and next to π/2. The tiny
// ones stop at 1e-60: below, S^5 of J_{4,2} leaves the normal range.
std::vector<double> t_grid() {
  const double pi = boost::math::constants::pi<double>();
  std::vector<double> t;
  for (int i = 1; i <= 2000; ++i) t.push_back(pi / 2 * i / 2000);
  for (int k = 1; k <= 60; ++k) t.push_back(std::pow(10.0, -k));
  for (int k = 1; k <= 16; ++k) {
    t.push_back(pi / 4 - std::pow(10.0, -k)), t.push_back(pi / 4 + std::pow(10.0, -k));
    t.push_back(pi / 2 - std::pow(10.0, -k));
  }
  t.push_back(pi / 4), t.push_back(pi / 2);
  return t;
}

struct Inputs {
  double S, C;
  Big T;  // the T the rounded inputs determine
};

Inputs inputs_at(double t) {
  const Big T = Big(t);
  Inputs in;
  in.S = static_cast<double>(sin(T)), in.C = static_cast<double>(cos(T));
  in.T = in.S <= in.C ? asin(Big(in.S)) : acos(Big(in.C));
  return in;
}

// ∫_0^T sin^m t cos^n t dt by 30-point Gauss–Legendre in 50 digits.
template <int M, int N>
Big reference(const Big& T) {
  return boost::math::quadrature::gauss<Big, 30>::integrate(
      [](const Big& t) { return pow(sin(t), M) * pow(cos(t), N); }, Big(0), T);
}
Big j24_closed(const Big& T) { return T / 16 - sin(4 * T) / 64 + pow(sin(2 * T), 3) / 48; }
Big j42_closed(const Big& T) { return T / 16 - sin(4 * T) / 64 - pow(sin(2 * T), 3) / 48; }

// Worst relative error of `value(S, C)` against `exact(T)` over the grid.
double worst_error(const std::function<double(double, double)>& value, const std::function<Big(const Big&)>& exact,
                   double* worst_t = nullptr) {
  double worst = 0;
  for (double t : t_grid()) {
    const Inputs in = inputs_at(t);
    const double expected = static_cast<double>(exact(in.T));
    const double error = std::fabs(value(in.S, in.C) - expected) / expected;
    if (!(error <= worst)) {
      worst = error;
      if (worst_t) *worst_t = t;
    }
  }
  return worst;
}

TEST(SinCosPowerIntegral, ReferenceMatchesTheClosedForms) {
  for (double t : {1e-3, 0.1, 0.7, 0.8, 1.2, 1.5707}) {
    const Big T(t);
    EXPECT_LT(abs(reference<2, 4>(T) / j24_closed(T) - 1), Big(1e-35)) << t;
    EXPECT_LT(abs(reference<4, 2>(T) / j42_closed(T) - 1), Big(1e-35)) << t;
  }
}

TEST(SinCosPowerIntegral, MatchesFiftyDigitReferenceOverTheQuarterTurn) {
  double t24 = 0, t42 = 0;
  const double e24 =
      worst_error([](double S, double C) { return sin_cos_power_integral<2, 4>(S, C); }, reference<2, 4>, &t24);
  const double e42 =
      worst_error([](double S, double C) { return sin_cos_power_integral<4, 2>(S, C); }, reference<4, 2>, &t42);
  std::printf("[ sin cos ] J_{2,4}: worst relative error %.3g (%.1f eps) at T %.17g\n", e24, e24 / kEps, t24);
  std::printf("[ sin cos ] J_{4,2}: worst relative error %.3g (%.1f eps) at T %.17g\n", e42, e42 / kEps, t42);
  EXPECT_LE(e24, kToleranceUlps * kEps);
  EXPECT_LE(e42, kToleranceUlps * kEps);
}

TEST(SinCosPowerIntegral, OtherPowersMatchTheirClosedForms) {
  // ν = −1/2 (n = 0, the slowest series) and a polynomial (n odd).
  EXPECT_LE(worst_error([](double S, double C) { return sin_cos_power_integral<0, 0>(S, C); },
                        [](const Big& T) { return T; }),
            kToleranceUlps * kEps);
  EXPECT_LE(worst_error([](double S, double C) { return sin_cos_power_integral<2, 0>(S, C); }, reference<2, 0>),
            kToleranceUlps * kEps);
  EXPECT_LE(worst_error([](double S, double C) { return sin_cos_power_integral<1, 1>(S, C); },
                        [](const Big& T) { return pow(sin(T), 2) / 2; }),
            kToleranceUlps * kEps);
}

TEST(SinCosPowerIntegral, ExactAtTheEnds) {
  EXPECT_EQ((sin_cos_power_integral<2, 4>(0.0, 1.0)), 0.0);
  EXPECT_EQ((sin_cos_power_integral<4, 2>(0.0, 1.0)), 0.0);
  // T = π/2: the complement's series vanishes, leaving the full integral π/32.
  const double pi_over_32 = static_cast<double>(boost::math::constants::pi<Big>() / 32);
  EXPECT_EQ((sin_cos_power_integral<2, 4>(1.0, 0.0)), pi_over_32);
  EXPECT_EQ((sin_cos_power_integral<4, 2>(1.0, 0.0)), pi_over_32);
}

// Negative controls: what the test must reject.
TEST(SinCosPowerIntegral, RejectsTheSeriesWithoutItsComplement) {
  // Past π/4 the series in S converges too slowly for its truncation (near
  // π/2 its terms fall as S^(2k) with S → 1).
  const double e = worst_error([](double S, double) { return sin_cos_power_detail::series<2, 4>(S); }, reference<2, 4>);
  EXPECT_GT(e, kToleranceUlps * kEps);
}

TEST(SinCosPowerIntegral, RejectsTheClosedFormInDouble) {
  // T/16 − sin 4T/64 + sin³2T/48 cancels to ~T³/3 from terms ~T/16.
  const double e = worst_error(
      [](double S, double C) {
        const double T = std::atan2(S, C);
        return T / 16 - std::sin(4 * T) / 64 + std::pow(std::sin(2 * T), 3) / 48;
      },
      reference<2, 4>);
  EXPECT_GT(e, kToleranceUlps * kEps);
}

}  // namespace
}  // namespace furnace::analytic
