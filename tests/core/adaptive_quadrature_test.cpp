// The adaptive Gauss–Kronrod of core/adaptive_quadrature.h: exact on
// polynomials its rule integrates exactly, within tolerance on smooth and
// discontinuous integrands, terminating on tiny intervals, and the relative
// form with one initial piece equal to the absolute form at its tolerance.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <utility>

#include <boost/math/constants/constants.hpp>

#include "core/adaptive_quadrature.h"

namespace furnace {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr int kDepth = 40;  // the deepest callers go (analytic/, stats/chi2.h)

TEST(AdaptiveGaussKronrod, ExactOnPolynomialsUpToTheRuleDegree) {
  // 31-point Kronrod: degree 3·15 + 1 = 46; ∫_0^1 x^k = 1/(k + 1).
  for (int k : {0, 1, 7, 30, 46}) {
    const double value = adaptive_gauss_kronrod([&](double x) { return std::pow(x, k); }, 0.0, 1.0, 0.0, 0);
    EXPECT_NEAR(value, 1.0 / (k + 1), 16 * kEps) << "x^" << k;
  }
}

TEST(AdaptiveGaussKronrod, SmoothIntegrandMeetsTolerance) {
  const double exact = std::expm1(3.0);
  // Down to ~250 ε·|∫f|: the header's floor for a reachable tolerance.
  for (double tolerance : {1e-6, 1e-10, 1e-12}) {
    const double value = adaptive_gauss_kronrod([](double x) { return std::exp(x); }, 0.0, 3.0, tolerance, kDepth);
    EXPECT_NEAR(value, exact, tolerance + 4 * kEps * exact) << tolerance;
  }
}

// A jump at an irrational point is never on a node or a bisection point:
// each level halves the error of the piece holding it.
TEST(AdaptiveGaussKronrod, JumpIsResolvedByBisection) {
  const double jump = 1 / std::sqrt(2.0);
  const auto step = [&](double x) { return x < jump ? 1.0 : 0.0; };
  const double one_rule = adaptive_gauss_kronrod(step, 0.0, 1.0, 0.0, 0);
  const double bisected = adaptive_gauss_kronrod(step, 0.0, 1.0, 1e-12, kDepth);
  EXPECT_GT(std::fabs(one_rule - jump), 1e-4);  // negative control: one rule cannot resolve it
  EXPECT_NEAR(bisected, jump, 1e-11);
}

TEST(AdaptiveGaussKronrod, TerminatesOnATinyInterval) {
  // The t-range of a cone of half-angle 1e-6 (t = 1 − cos θ ≈ θ²/2).
  const double t_max = 5e-13;
  const double value =
      adaptive_gauss_kronrod_relative([](double t) { return 1 - t; }, 0.0, t_max, 1e-12, kDepth);
  EXPECT_NEAR(value, t_max - t_max * t_max / 2, 4 * kEps * t_max);
}

TEST(AdaptiveGaussKronrodRelative, OnePieceEqualsAbsoluteFormAtItsTolerance) {
  const auto f = [](double x) { return std::sqrt(x) * std::cos(5 * x); };
  const double rel = 1e-10;
  double error = 0;
  const double first = boost::math::quadrature::gauss_kronrod<double, 31>::integrate(f, 0.0, 2.0, 0, 0.0, &error);
  EXPECT_EQ(adaptive_gauss_kronrod_relative(f, 0.0, 2.0, rel, kDepth),
            adaptive_gauss_kronrod(f, 0.0, 2.0, rel * std::fabs(first), kDepth));
}

TEST(AdaptiveGaussKronrodRelative, InitialPiecesFindANarrowPeak) {
  // A peak of width 1e-3 at 0.8: 7 widths from the nearest node of one
  // 15-point rule on [0, 1], under 2 widths from a node of the rules on four
  // quarters.
  const double centre = 0.8, width = 1e-3;
  const auto peak = [&](double x) { return std::exp(-0.5 * std::pow((x - centre) / width, 2)); };
  const double exact = width * boost::math::constants::root_two_pi<double>();
  // Negative control: what the first estimate of one piece sees (no bisection).
  EXPECT_LT(adaptive_gauss_kronrod_relative<15>(peak, 0.0, 1.0, 1e-10, 0, 1), 1e-6 * exact);
  EXPECT_NEAR(adaptive_gauss_kronrod_relative<15>(peak, 0.0, 1.0, 1e-10, kDepth, 4), exact, 1e-10 * exact);
}

// Pseudo-random 0/1 noise: every piece's error estimate fails at every
// level, so only the bisection cap ends the recursion.
TEST(AdaptiveGaussKronrodRelative, BisectionCapBoundsTheCostOfNoise) {
  size_t evaluations = 0;
  const auto noise = [&](double x) {
    ++evaluations;
    return std::fmod(std::fabs(std::sin(1e6 * x)) * 1e4, 1.0) < 0.5 ? 1.0 : 0.0;
  };
  constexpr size_t kCap = 200;
  const double value = adaptive_gauss_kronrod_relative<15>(noise, 0.0, 1.0, 1e-11, kDepth, 4, kCap);
  // 4 first estimates, 4 pieces before bisecting, 2 rules per bisection.
  EXPECT_LE(evaluations, 15 * (4 + 4 + 2 * kCap));
  EXPECT_GT(value, 0.0);
  EXPECT_LT(value, 1.0);
}

// On a short interval away from 0, tanh_sinh_integral keeps full precision
// and states an error in the integral's units that covers the actual error.
// Negative controls: Boost's integrate on the same interval drops the end
// slivers (a relative error ~ ulp(a)/width) and states an error that is not
// in the integral's units.
TEST(TanhSinhIntegral, ShortIntervalsKeepPrecisionAndAnHonestError) {
  boost::math::quadrature::tanh_sinh<double> integrator;
  auto f = [](double x) { return std::sin(x); };
  for (const double width : {1e-12, 1e-9, 1e-6, 1e-3}) {
    const double a = 0.38, b = a + width;
    // cos a − cos b without cancellation.
    const double exact = 2 * std::sin((a + b) / 2) * std::sin((b - a) / 2);
    double error = 0, boost_error = 0;
    const double value = tanh_sinh_integral(integrator, f, a, b, 1e-13, &error);
    const double boost_value = integrator.integrate(f, a, b, 1e-13, &boost_error);
    std::printf("width %g: relative error %.2g, stated %.2g; Boost's own: relative error %.2g, stated %.2g\n", width,
                std::fabs(value - exact) / exact, error / exact, std::fabs(boost_value - exact) / exact,
                boost_error / exact);
    EXPECT_LE(std::fabs(value - exact), 8 * std::numeric_limits<double>::epsilon() * exact);
    EXPECT_LE(error, 1e-12 * exact);
    if (width <= 1e-6) {
      EXPECT_GT(std::fabs(boost_value - exact), 1e-12 * exact);  // the dropped end slivers
      EXPECT_GT(boost_error, 1e-9 * exact);                       // not in the integral's units
    }
  }
}

// The N-component form: with one component it is the scalar form to the
// bit (its rule is Boost's, value and error estimate alike, and the same
// pieces are bisected), and with several each component is at least as
// accurate as alone, on integrands that need different pieces.
TEST(AdaptiveGaussKronrodComponents, OneComponentIsTheScalarFormToTheBit) {
  const auto smooth = [](double x) { return std::exp(-3 * x) * std::cos(7 * x); };
  const auto kink = [](double x) { return std::fabs(x - 0.3137); };
  const auto jump = [](double x) { return x < 0.61 ? 1.0 : 2.5; };
  for (int which = 0; which < 3; ++which) {
    const auto f = [&](double x) { return which == 0 ? smooth(x) : which == 1 ? kink(x) : jump(x); };
    for (const auto& [a, b] : {std::pair{0.0, 1.0}, std::pair{-2.0, 3.5}, std::pair{0.2, 0.2 + 1e-9}}) {
      for (size_t cap : {kUnlimitedBisections, size_t(3)}) {
        for (int pieces : {1, 3}) {
          double error = 0;
          const double scalar = adaptive_gauss_kronrod_relative(f, a, b, 1e-11, 30, pieces, cap, &error);
          std::array<double, 1> error1{};
          const std::array<double, 1> vector = adaptive_gauss_kronrod_relative_components(
              [&](double x) { return std::array<double, 1>{f(x)}; }, a, b, 1e-11, 30, pieces, cap, &error1);
          EXPECT_EQ(scalar, vector[0]) << which << " [" << a << ", " << b << "] cap " << cap << " pieces " << pieces;
          EXPECT_EQ(error, error1[0]) << which << " [" << a << ", " << b << "] cap " << cap << " pieces " << pieces;
        }
      }
    }
  }
  // Degenerate and reversed intervals, as Boost's rule.
  std::array<double, 1> error{};
  EXPECT_EQ((gauss_kronrod_rule<31>([](double) { return std::array<double, 1>{1.0}; }, 2.0, 2.0, &error)[0]), 0.0);
  EXPECT_EQ(error[0], 0.0);
  double boost_error = 0;
  const double reversed = boost::math::quadrature::gauss_kronrod<double, 31>::integrate(
      [](double x) { return std::exp(x); }, 1.0, 0.0, 0, 0.0, &boost_error);
  EXPECT_EQ((gauss_kronrod_rule<31>([](double x) { return std::array<double, 1>{std::exp(x)}; }, 1.0, 0.0, &error)[0]),
            reversed);
  EXPECT_EQ(error[0], boost_error);
}

TEST(AdaptiveGaussKronrodComponents, EveryComponentMeetsItsOwnTolerance) {
  // A kink at 0.3137 in one component, a jump at 0.61 in the other, a smooth
  // third: each needs pieces of its own; together, each is within its
  // tolerance and no worse than alone.
  const auto f = [](double x) {
    return std::array<double, 3>{std::fabs(x - 0.3137), x < 0.61 ? 1.0 : 2.5, std::exp(x)};
  };
  const std::array<double, 3> exact{(0.3137 * 0.3137 + 0.6863 * 0.6863) / 2, 0.61 + 2.5 * 0.39, std::expm1(1.0)};
  const double tolerance = 1e-10;
  std::array<double, 3> error{};
  const std::array<double, 3> together =
      adaptive_gauss_kronrod_relative_components(f, 0.0, 1.0, tolerance, kDepth, 1, kUnlimitedBisections, &error);
  for (size_t c = 0; c < 3; ++c) {
    const double alone = adaptive_gauss_kronrod_relative([&](double x) { return f(x)[c]; }, 0.0, 1.0, tolerance, kDepth);
    EXPECT_LE(std::fabs(together[c] - exact[c]), tolerance * exact[c]) << c;
    EXPECT_LE(std::fabs(together[c] - exact[c]), std::fabs(alone - exact[c]) + 4 * kEps * exact[c]) << c;
    EXPECT_GE(error[c], 0.0) << c;
  }
}

// One ulp (a cut and an end point differing by rounding): a value of the
// right size and an error far below it.
TEST(TanhSinhIntegral, IntervalOfOneUlp) {
  boost::math::quadrature::tanh_sinh<double> integrator;
  const double a = 0.38, b = std::nextafter(a, 1.0);
  double error = -1;
  const double value = tanh_sinh_integral(integrator, [](double x) { return std::sin(x); }, a, b, 1e-13, &error);
  EXPECT_NEAR(value, std::sin(a) * (b - a), 1e-6 * std::sin(a) * (b - a));
  EXPECT_GE(error, 0.0);
  EXPECT_LE(error, 1e-6 * value);
}

}  // namespace
}  // namespace furnace

