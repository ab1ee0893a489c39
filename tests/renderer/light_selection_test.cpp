// Light selection (renderer/lights.h): the pmf, uniform or proportional to
// emitted power, and its sampling by CDF inversion.
//  1. the power pmf is Φ_l/ΣΦ with the powers lights.h states, recomputed
//     here from the scene fields; every light of positive power has pmf > 0
//     and is selected;
//  2. chi-square goodness of fit of select(u)'s frequencies against pmf(),
//     N = 400 000 draws per test, family-wise α = 0.01, Šidák over the tests;
//  3. negative control: the power selection's counts tested against the
//     uniform pmf must be rejected.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <ostream>
#include <string>
#include <vector>

#include "core/scene.h"
#include "renderer/lights.h"
#include "renderer/rng.h"
#include "stats/chi2.h"
#include "stats/statistics.h"

namespace furnace {
namespace {

constexpr uint64_t kSeed = 0x5e1ec7;  // fixed: deterministic
constexpr size_t kDraws = 400000;
constexpr double kFamilyAlpha = 0.01;
constexpr size_t kChi2Tests = 4;  // uniform and power on kScene, power on kSkyScene, the negative control

// All four kinds of light: a one-sided disk, a two-sided rectangle, a sphere,
// a point light; powers spread over ~20×.
const char* kScene = R"({
  "camera": {"type": "orthographic", "center": [0, 0, 1], "forward": [0, 0, -1], "up": [0, 1, 0],
             "size": [4, 4], "resolution": [4, 4]},
  "point_lights": [{"name": "bulb", "position": [0.5, -0.5, 1.0], "intensity": 4.0}],
  "objects": [
    {"name": "floor", "shape": {"type": "rectangle", "corner": [-2, -2, 0], "edge_u": [4, 0, 0], "edge_v": [0, 4, 0]},
     "material": {"type": "lambertian", "albedo": 0.5}},
    {"name": "disk", "shape": {"type": "disk", "center": [0, 1, 1.5], "normal": [0, 0, -1], "radius": 0.5}, "emission": 10},
    {"name": "panel", "shape": {"type": "rectangle", "corner": [1, 1, 0.5], "edge_u": [0.3, 0, 0], "edge_v": [0, 0.2, 0]},
     "emission": 3, "two_sided": true},
    {"name": "ball", "shape": {"type": "sphere", "center": [-1, -1, 0.6], "radius": 0.25}, "emission": 2}
  ]
})";
// A sphere light, a point light and the environment (its power uses the
// bounding radius of the scene).
const char* kSkyScene = R"({
  "camera": {"type": "orthographic", "center": [0, 0, 1], "forward": [0, 0, -1], "up": [0, 1, 0],
             "size": [4, 4], "resolution": [4, 4]},
  "environment": {"radiance": 0.25},
  "point_lights": [{"position": [0, 0, 2], "intensity": 1.5}],
  "objects": [
    {"name": "floor", "shape": {"type": "rectangle", "corner": [-2, -2, 0], "edge_u": [4, 0, 0], "edge_v": [0, 4, 0]},
     "material": {"type": "lambertian", "albedo": 0.5}},
    {"name": "ball", "shape": {"type": "sphere", "center": [1, 1, 1], "radius": 0.3}, "emission": 5}
  ]
})";

std::vector<double> selection_counts(const LightSet& lights) {
  std::vector<double> counts(lights.count(), 0.0);
  for (size_t i = 0; i < kDraws; ++i) {
    Rng rng(kSeed, 0, i);
    counts[lights.select(rng.next_double())] += 1;
  }
  return counts;
}

std::vector<double> expected_counts(const LightSet& lights) {
  std::vector<double> expected;
  for (size_t l = 0; l < lights.count(); ++l) expected.push_back(lights.pmf(l) * double(kDraws));
  return expected;
}

double alpha_each() { return stats::sidak_alpha(kFamilyAlpha, kChi2Tests); }

TEST(LightSelection, PowerPmfIsProportionalToTheStatedPowers) {
  const Scene scene = parse_scene(kScene, "light_selection_scene");
  const LightSet lights(scene, LightSelection::kPower);
  ASSERT_EQ(lights.count(), 4u);
  // Φ from the scene fields: π·Le·A one-sided, 2π·Le·A two-sided, 4π·I.
  std::vector<double> power;
  for (const Object& o : scene.objects)
    if (o.is_emitter()) power.push_back((o.two_sided ? 2 : 1) * kPi * o.emitted_radiance * shape_area(o.shape));
  power.push_back(4 * kPi * scene.point_lights[0].intensity);
  double total = 0;
  for (double p : power) total += p;
  double sum = 0;
  for (size_t l = 0; l < lights.count(); ++l) {
    EXPECT_NEAR(lights.pmf(l), power[l] / total, 4 * std::numeric_limits<double>::epsilon()) << "light " << l;
    EXPECT_GT(lights.pmf(l), 0.0) << "light " << l << " unreachable";
    sum += lights.pmf(l);
  }
  EXPECT_NEAR(sum, 1.0, 8 * std::numeric_limits<double>::epsilon());
  EXPECT_TRUE(lights.is_point_light(3));
}

TEST(LightSelection, UniformPmfIsOneOverK) {
  const Scene scene = parse_scene(kScene, "light_selection_scene");
  const LightSet lights(scene, LightSelection::kUniform);
  for (size_t l = 0; l < lights.count(); ++l) EXPECT_DOUBLE_EQ(lights.pmf(l), 1.0 / double(lights.count()));
}

TEST(LightSelection, EnvironmentPowerUsesTheBoundingRadius) {
  const Scene scene = parse_scene(kSkyScene, "sky_scene");
  const LightSet lights(scene, LightSelection::kPower);
  ASSERT_EQ(lights.count(), 3u);
  ASSERT_TRUE(lights.is_environment(2));
  // Box [-2, 2]×[-2, 2]×[0, 2] (floor, sphere top at 1.3, point light at z = 2): R = ½·√(16 + 16 + 4).
  const double r = 0.5 * std::sqrt(36.0);
  EXPECT_NEAR(lights.powers()[2], kPi * 0.25 * kPi * r * r, 1e-12 * lights.powers()[2]);
  for (size_t l = 0; l < lights.count(); ++l) EXPECT_GT(lights.pmf(l), 0.0);
}

struct SelectionCase {
  const char* name;
  const char* scene;
  LightSelection selection;
};

void PrintTo(const SelectionCase& c, std::ostream* os) { *os << c.name; }

class LightSelectionChi2 : public testing::TestWithParam<SelectionCase> {};

TEST_P(LightSelectionChi2, FrequenciesMatchThePmf) {
  const Scene scene = parse_scene(GetParam().scene, "chi2_scene");
  const LightSet lights(scene, GetParam().selection);
  const std::vector<double> counts = selection_counts(lights);
  for (size_t l = 0; l < lights.count(); ++l) EXPECT_GT(counts[l], 0.0) << "light " << l << " never selected";
  const stats::Chi2Result r = stats::chi2_from_counts(counts, expected_counts(lights), alpha_each());
  std::printf("chi2 %s: statistic %.3f, dof %d, p %.4f (alpha %.3g), detectable w %.3g\n", GetParam().name,
              r.statistic, r.dof, r.p_value, r.alpha, r.detectable_effect);
  EXPECT_TRUE(r.pass) << r.message;
}

INSTANTIATE_TEST_SUITE_P(LightSelection, LightSelectionChi2,
                         testing::Values(SelectionCase{"UniformFourLights", kScene, LightSelection::kUniform},
                                         SelectionCase{"PowerFourLights", kScene, LightSelection::kPower},
                                         SelectionCase{"PowerWithEnvironment", kSkyScene, LightSelection::kPower}),
                         [](const testing::TestParamInfo<SelectionCase>& info) { return std::string(info.param.name); });

// Negative control: power-selected frequencies are not uniform, and the same
// test must say so.
TEST(LightSelection, Chi2RejectsPowerFrequenciesAgainstTheUniformPmf) {
  const Scene scene = parse_scene(kScene, "light_selection_scene");
  const LightSet power(scene, LightSelection::kPower);
  const LightSet uniform(scene, LightSelection::kUniform);
  const stats::Chi2Result r = stats::chi2_from_counts(selection_counts(power), expected_counts(uniform), alpha_each());
  std::printf("chi2 negative control: statistic %.3f, dof %d, p %.3g\n", r.statistic, r.dof, r.p_value);
  EXPECT_FALSE(r.pass);
}

}  // namespace
}  // namespace furnace
