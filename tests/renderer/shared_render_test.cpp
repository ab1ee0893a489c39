// render_sharing_samples(): strategies that draw the same samples and trace
// the same rays (mis_balance and mis_power, which differ only in the MIS
// heuristic) rendered together, once. Each image must be the one render()
// gives its strategy alone, to the bit (moments, ray count, non-finite
// count), on every built-in scene that MIS can render, in either order, and
// under the defects that touch the MIS weights or the render loop. `furnace
// verify` relies on it (run_cases renders such cases together). Negative
// control: the comparison tells the two strategies' images apart. Lists that
// do not share their samples are refused.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "core/error.h"
#include "renderer/lights.h"
#include "renderer/render.h"
#include "test_support.h"

namespace furnace {
namespace {

constexpr uint64_t kSeed = 0x5ba4ed;
constexpr int kSpp = 24;  // three packets of eight: full batches through the shared MIS estimator

using testing_support::bitwise_equal;

// The built-in scenes MIS can render (a light to sample).
std::vector<Scene> mis_scenes() {
  std::vector<Scene> scenes;
  for (const auto& entry : std::filesystem::directory_iterator(FURNACE_SCENE_DIR))
    if (entry.path().extension() == ".json") {
      Scene scene = load_scene(entry.path().string());
      if (LightSet(scene).count() > 0) scenes.push_back(std::move(scene));
    }
  return scenes;
}

RenderOptions options(Defect defect, LightSelection selection) {
  RenderOptions o;
  o.spp = kSpp;
  o.seed = kSeed;
  o.defect = defect;
  o.light_selection = selection;
  return o;
}

Image alone(const Scene& scene, RenderOptions o, Strategy s) {
  o.strategy = s;
  return render(scene, o);
}

TEST(RenderSharingSamples, EachImageIsItsStrategyRenderedAloneToTheBit) {
  const std::vector<Scene> scenes = mis_scenes();
  ASSERT_GE(scenes.size(), 15u);
  const Defect defects[] = {Defect::kNone, Defect::kMisUnnormalisedWeight, Defect::kMisPowerExponent3,
                            Defect::kPointLightMisWeighted, Defect::kNanSample, Defect::kBackFaceEmits};
  int compared = 0, differ = 0;
  for (const Scene& scene : scenes)
    for (Defect defect : defects)
      for (LightSelection selection : {LightSelection::kUniform, LightSelection::kPower}) {
        // The default defect on every scene under both selections; the others under the uniform one.
        if (defect != Defect::kNone && selection == LightSelection::kPower) continue;
        const RenderOptions o = options(defect, selection);
        const Image balance = alone(scene, o, Strategy::kMisBalance);
        const Image power = alone(scene, o, Strategy::kMisPower);
        const std::vector<Image> together =
            render_sharing_samples(scene, o, {Strategy::kMisBalance, Strategy::kMisPower});
        const std::vector<Image> reversed =
            render_sharing_samples(scene, o, {Strategy::kMisPower, Strategy::kMisBalance});
        ASSERT_EQ(together.size(), 2u);
        ASSERT_EQ(reversed.size(), 2u);
        const bool equal[] = {bitwise_equal(together[0], balance), bitwise_equal(together[1], power),
                              bitwise_equal(reversed[0], power), bitwise_equal(reversed[1], balance)};
        for (bool e : equal) {
          ++compared;
          differ += !e;
          EXPECT_TRUE(e) << scene.name << " under " << defect_name(defect);
        }
      }
  std::printf("%d shared-render images compared with their strategy's own render: %d differ\n", compared, differ);
}

TEST(RenderSharingSamples, OneStrategyIsRender) {
  const Scene scene = load_scene(std::string(FURNACE_SCENE_DIR) + "/three_lights.json");
  for (Strategy s : {Strategy::kLightArea, Strategy::kBsdf, Strategy::kMisOneSample, Strategy::kPathMis}) {
    const RenderOptions o = options(Defect::kNone, LightSelection::kUniform);
    const std::vector<Image> one = render_sharing_samples(scene, o, {s});
    ASSERT_EQ(one.size(), 1u);
    EXPECT_TRUE(bitwise_equal(one[0], alone(scene, o, s))) << strategy_name(s);
  }
}

// Negative control: the comparison sees the heuristic (the two images differ
// wherever both strategies find a light with positive density).
TEST(RenderSharingSamples, NegativeControlTheTwoHeuristicsImagesDiffer) {
  const Scene scene = load_scene(std::string(FURNACE_SCENE_DIR) + "/disk_occluder.json");
  const std::vector<Image> images = render_sharing_samples(scene, options(Defect::kNone, LightSelection::kUniform),
                                                           {Strategy::kMisBalance, Strategy::kMisPower});
  EXPECT_FALSE(bitwise_equal(images[0], images[1]));
}

TEST(RenderSharingSamples, RefusesListsThatDoNotShareTheirSamples) {
  const Scene scene = load_scene(std::string(FURNACE_SCENE_DIR) + "/disk_occluder.json");
  const RenderOptions o = options(Defect::kNone, LightSelection::kUniform);
  EXPECT_THROW(render_sharing_samples(scene, o, {}), Error);
  EXPECT_THROW(render_sharing_samples(scene, o, {Strategy::kMisPower, Strategy::kLightSolidAngle}), Error);
  EXPECT_THROW(render_sharing_samples(scene, o, {Strategy::kMisBalance, Strategy::kMisOneSample}), Error);
  EXPECT_THROW(render_sharing_samples(scene, o, {Strategy::kPathMis, Strategy::kPathMis}), Error);
  EXPECT_THROW(
      render_sharing_samples(scene, o, {Strategy::kMisBalance, Strategy::kMisPower, Strategy::kMisBalance}), Error);
}

TEST(SharesSamples, OnlyTheMultiSampleMisPairAndEachStrategyWithItself) {
  // Every strategy of the table (a new one is covered without an edit here);
  // the expected pair is named by hand, independently of the table's mis_beta.
  int pairs = 0;
  for (const StrategyInfo& row_a : kStrategyTable)
    for (const StrategyInfo& row_b : kStrategyTable) {
      const Strategy a = row_a.strategy, b = row_b.strategy;
      const bool mis_pair = (a == Strategy::kMisBalance && b == Strategy::kMisPower) ||
                            (a == Strategy::kMisPower && b == Strategy::kMisBalance);
      EXPECT_EQ(shares_samples(a, b), a == b || mis_pair) << strategy_name(a) << " " << strategy_name(b);
      pairs += shares_samples(a, b) && a != b;
    }
  EXPECT_EQ(pairs, 2);
}

}  // namespace
}  // namespace furnace
