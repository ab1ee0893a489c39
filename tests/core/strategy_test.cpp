// The shared vocabulary: the strategy and defect tables are complete and
// consistent, names round-trip, and bad names are rejected with the list of
// accepted ones.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "core/error.h"
#include "core/strategy.h"

namespace furnace {
namespace {

TEST(StrategyTable, NamesAreUniqueAndRoundTrip) {
  std::set<std::string> names;
  for (const StrategyInfo& info : kStrategyTable) {
    EXPECT_TRUE(names.insert(info.name).second) << info.name;
    EXPECT_EQ(parse_strategy(info.name), info.strategy);
    EXPECT_EQ(strategy_name(info.strategy), info.name);
  }
  EXPECT_EQ(strategy_names().size(), kStrategyTable.size());
}

TEST(StrategyTable, DirectAndPathStrategiesPartitionTheTable) {
  EXPECT_EQ(direct_strategies().size() + path_tracing_strategies().size(), kStrategyTable.size());
  for (Strategy s : direct_strategies()) EXPECT_FALSE(is_path_tracer(s)) << strategy_name(s);
  for (Strategy s : path_tracing_strategies()) EXPECT_TRUE(is_path_tracer(s)) << strategy_name(s);
}

TEST(StrategyTable, VarianceModelsAreDirectStrategiesThatModelThemselves) {
  for (const StrategyInfo& info : kStrategyTable) {
    if (!info.variance_model) continue;
    EXPECT_EQ(info.kind, StrategyKind::kDirect) << info.name;
    const StrategyInfo& model = strategy_info(*info.variance_model);
    EXPECT_EQ(model.variance_model, model.strategy) << info.name << " is modelled by " << model.name;
    // A model must sample lights exactly when the strategy does.
    EXPECT_EQ(model.samples_lights, info.samples_lights) << info.name;
  }
  for (Strategy s : path_tracing_strategies()) EXPECT_FALSE(has_variance_model(s)) << strategy_name(s);
}

TEST(StrategyTable, OnlyLightSamplersSeeDeltaLights) {
  for (const StrategyInfo& info : kStrategyTable)
    EXPECT_EQ(strategy_sees_delta_lights(info.strategy), info.samples_lights) << info.name;
  EXPECT_TRUE(samples_lights(Strategy::kLightArea));
  EXPECT_FALSE(samples_lights(Strategy::kBsdf));
  EXPECT_FALSE(samples_lights(Strategy::kPathNaive));
  EXPECT_TRUE(samples_lights(Strategy::kPathMis));
}

TEST(StrategyTable, MisExponents) {
  EXPECT_EQ(strategy_info(Strategy::kMisBalance).mis_beta, 1);
  EXPECT_EQ(strategy_info(Strategy::kMisPower).mis_beta, 2);
  EXPECT_EQ(strategy_info(Strategy::kLightArea).mis_beta, 0);
}

// The table's multi-sample MIS (one render and one quadrature serve them all)
// is exactly the balance and power heuristics; path_mis weighs with β = 2
// too but is a path tracer, and mis_one_sample is one-sample MIS.
TEST(StrategyTable, MultiSampleMisIsTheBalanceAndPowerPair) {
  EXPECT_EQ(multi_sample_mis_strategies(), (std::vector<Strategy>{Strategy::kMisBalance, Strategy::kMisPower}));
  EXPECT_EQ(multi_sample_mis_count(), 2u);
  EXPECT_FALSE(is_multi_sample_mis(Strategy::kPathMis));
  EXPECT_FALSE(is_multi_sample_mis(Strategy::kMisOneSample));
}

TEST(StrategyTable, UnknownNamesListTheAcceptedOnes) {
  try {
    parse_strategy("light_areaa");
    FAIL() << "no error";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("'light_areaa'"), std::string::npos) << message;
    for (const StrategyInfo& info : kStrategyTable) EXPECT_NE(message.find(info.name), std::string::npos) << message;
  }
  EXPECT_THROW(parse_defect("nonee"), Error);
  EXPECT_THROW(parse_light_selection("Power"), Error);
}

TEST(DefectTable, NamesAreUniqueAndRoundTrip) {
  std::set<std::string> names;
  for (const DefectInfo& info : kDefectTable) {
    EXPECT_TRUE(names.insert(info.name).second) << info.name;
    EXPECT_EQ(parse_defect(info.name), info.defect);
    EXPECT_EQ(defect_name(info.defect), info.name);
  }
  EXPECT_EQ(defect_names().size(), kDefectTable.size());
  EXPECT_EQ(parse_defect("none"), Defect::kNone);
}

TEST(LightSelectionNames, RoundTrip) {
  for (const auto& [name, selection] : light_selection_names()) {
    EXPECT_EQ(parse_light_selection(name), selection);
    EXPECT_EQ(light_selection_name(selection), name);
  }
  EXPECT_EQ(light_selection_names().size(), 2u);
}

TEST(Depth, UnlimitedHasOneSpelling) {
  EXPECT_EQ(depth_name(kUnlimitedDepth), "unlimited");
  EXPECT_EQ(depth_name(4), "4");
}

}  // namespace
}  // namespace furnace
