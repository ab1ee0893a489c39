// sin_cos_of_atan2 (analytic/sin_cos.h) against cpp_bin_float_50, in
// relative error, with its negative control: the plain quotient.
#include "analytic/sin_cos.h"

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include <boost/multiprecision/cpp_bin_float.hpp>
#include <gtest/gtest.h>

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

}  // namespace
}  // namespace furnace::analytic
