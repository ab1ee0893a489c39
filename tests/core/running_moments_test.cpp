// RunningMoments: the one-pass central moments agree with two-pass sums, the
// derived variance and standard error follow their definitions, and the
// update is exact where exact arithmetic allows (constant streams).
#include <gtest/gtest.h>

#include <cmath>
#include <iterator>
#include <limits>

#include "core/running_moments.h"

namespace furnace {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

// Mixed signs and magnitudes, so that every central moment is nonzero.
constexpr double kValues[] = {0.3, 1.7, -2.2, 0.0, 5.5, 1.25, 3.0, -0.75, 2.0, 0.1};

TEST(RunningMoments, MatchTwoPassMoments) {
  RunningMoments m;
  double sum = 0;
  for (double y : kValues) {
    m.add(y);
    sum += y;
  }
  const double n = double(std::size(kValues)), mean = sum / n;
  double m2 = 0, m3 = 0, m4 = 0;
  for (double y : kValues) {
    const double d = y - mean;
    m2 += d * d;
    m3 += d * d * d;
    m4 += d * d * d * d;
  }
  // Ten updates, each a few roundings on O(1) terms: 64 ε bounds the drift.
  const double tolerance = 64 * kEps;
  EXPECT_EQ(m.count, std::size(kValues));
  EXPECT_NEAR(m.mean, mean, tolerance * std::fabs(mean));
  EXPECT_NEAR(m.m2 / m2, 1.0, tolerance);
  EXPECT_NEAR(m.m3 / m3, 1.0, 16 * tolerance);  // m3 sums terms of both signs: some cancellation
  EXPECT_NEAR(m.m4 / m4, 1.0, tolerance);
  EXPECT_NEAR(m.sample_variance(), m2 / (n - 1), tolerance * m2 / (n - 1));
  EXPECT_NEAR(m.mean_standard_error(), std::sqrt(m2 / (n - 1) / n), tolerance * std::sqrt(m2 / (n - 1) / n));
}

TEST(RunningMoments, ConstantStreamHasExactlyZeroSpread) {
  RunningMoments m;
  for (int i = 0; i < 1000; ++i) m.add(0.7);
  EXPECT_EQ(m.mean, 0.7);
  EXPECT_EQ(m.m2, 0.0);
  EXPECT_EQ(m.m3, 0.0);
  EXPECT_EQ(m.m4, 0.0);
  EXPECT_EQ(m.sample_variance(), 0.0);
}

TEST(RunningMoments, FewerThanTwoValuesHaveNoVariance) {
  RunningMoments m;
  EXPECT_EQ(m.sample_variance(), 0.0);
  EXPECT_EQ(m.mean_standard_error(), 0.0);
  m.add(3.0);
  EXPECT_EQ(m.count, 1u);
  EXPECT_EQ(m.mean, 3.0);
  EXPECT_EQ(m.sample_variance(), 0.0);
  EXPECT_EQ(m.mean_standard_error(), 0.0);
}

// Negative control: the odd moment changes sign with the data, the even ones do not.
TEST(RunningMoments, MirroredDataFlipsOnlyTheThirdMoment) {
  RunningMoments a, b;
  for (double y : kValues) {
    a.add(y);
    b.add(-y);
  }
  EXPECT_EQ(a.mean, -b.mean);
  EXPECT_EQ(a.m2, b.m2);
  EXPECT_EQ(a.m3, -b.m3);
  EXPECT_EQ(a.m4, b.m4);
  EXPECT_NE(a.m3, 0.0);
}

}  // namespace
}  // namespace furnace
