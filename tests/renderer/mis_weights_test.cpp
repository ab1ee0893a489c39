// mis_weights(): the weights of the BSDF and the light sample of one
// direction sum to 1 under both heuristics wherever either density is
// positive, reduce to the single strategy where the other density is 0, and
// DEFECT(mis_unnormalised_weight) breaks the sum. Deterministic identities:
// tolerances in ulps, no sampling.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "renderer/direct_strategies.h"

namespace furnace {
namespace {

// Two divisions and a sum of two ratios: a few rounding steps.
constexpr double kSumTolerance = 4 * std::numeric_limits<double>::epsilon();

// Densities over 24 decades, as MIS meets them (a tiny light seen from far
// away against a cosine lobe, or a near-delta lobe against a huge light).
std::vector<double> densities() {
  std::vector<double> out = {0.0};
  for (int e = -12; e <= 12; ++e) out.push_back(0.7 * std::pow(10.0, e));
  return out;
}

class MisWeightsSum : public testing::TestWithParam<int> {};

TEST_P(MisWeightsSum, SumToOneWhereEitherDensityIsPositive) {
  const int beta = GetParam();
  for (double p_bsdf : densities())
    for (double p_light : densities()) {
      const MisWeights w = mis_weights({p_bsdf, p_light}, beta, Defect::kNone);
      EXPECT_GE(w.w_bsdf, 0);
      EXPECT_GE(w.w_light, 0);
      if (p_bsdf == 0 && p_light == 0) {
        EXPECT_EQ(w.w_bsdf + w.w_light, 0.0);
        continue;
      }
      EXPECT_NEAR(w.w_bsdf + w.w_light, 1.0, kSumTolerance) << "p_bsdf " << p_bsdf << " p_light " << p_light;
      if (p_light == 0) {
        EXPECT_EQ(w.w_bsdf, 1.0);
      }
      if (p_bsdf == 0) {
        EXPECT_EQ(w.w_light, 1.0);
      }
    }
}

TEST_P(MisWeightsSum, UnnormalisedDefectExceedsOneWhereBothArePositive) {
  const int beta = GetParam();
  const MisWeights w = mis_weights({0.5, 0.25}, beta, Defect::kMisUnnormalisedWeight);
  EXPECT_DOUBLE_EQ(w.w_bsdf + w.w_light, 1.0 + std::pow(0.5, beta));
}

INSTANTIATE_TEST_SUITE_P(Heuristics, MisWeightsSum, testing::Values(1, 2),
                         [](const testing::TestParamInfo<int>& info) {
                           return info.param == 1 ? std::string("Balance") : std::string("Power");
                         });

}  // namespace
}  // namespace furnace
