// Light sampling of an image-based environment through LightStrategy: the
// sample's density is the one LightStrategy::pdf gives an escaped ray of the
// same direction (what MIS queries), including the light-selection pmf;
// directions below the receiver's horizon are drawn but carry weight 0; the
// radiance is the map's along the direction; the weight follows the return
// convention f·cos θ/pdf. A constant environment keeps cosine sampling.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include "renderer/direct_strategies.h"
#include "renderer/sampling.h"
#include "floor_fixture.h"
#include "test_support.h"

namespace furnace {
namespace {

using testing_support::make_floor;
using testing_support::make_object;

constexpr uint64_t kSeed = 0xe5a9;
constexpr int kSamples = 20000;

struct MapFixture : testing_support::FloorFixture {

  // A floor (shading point at the origin, normal +z), optionally a rectangle
  // light, under the committed map scaled by 2.
  explicit MapFixture(bool with_emitter) {
    scene.name = "environment_light_test";
    scene.objects.push_back(make_floor(0.5));
    if (with_emitter) scene.objects.push_back(make_object("light", Rectangle{{3, 3, 2}, {0.5, 0, 0}, {0, -0.5, 0}}, 0, 4.0));
    scene.environment = load_scene(std::string(FURNACE_SCENE_DIR) + "/environment_map.json").environment;
    scene.environment.radiance = 2.0;
    build();
  }
};

class EnvironmentLight : public testing::TestWithParam<bool> {};

TEST_P(EnvironmentLight, SampleAgreesWithPdfOfEscapedRay) {
  const MapFixture f(GetParam());
  ASSERT_TRUE(f.lights->environment_sampler);
  const LightStrategy strategy{f.rtc.get(), f.lights.get(), EmitterSampling::kSolidAngle, Defect::kNone};
  const ShadingContext ctx = f.context();
  const double pmf = f.lights->pmf(f.lights->count() - 1);  // the environment is the last light
  TraceCounters counters;
  int environment_samples = 0, below_horizon = 0;
  for (int i = 0; i < kSamples; ++i) {
    Rng rng(kSeed, 0, uint64_t(i));
    const auto s = strategy.sample(ctx, next_uniform3(rng));
    if (!s || !std::isinf(s->shadow_t_max)) continue;  // emitter samples are strategy_test's
    ++environment_samples;
    EXPECT_EQ(s->pdf_solid_angle, pmf * f.lights->environment_sampler->pdf_solid_angle(s->wi_world));
    EXPECT_EQ(s->pdf_solid_angle, strategy.pdf(ctx, s->wi_world, std::nullopt));
    EXPECT_EQ(s->radiance, environment_radiance(f.scene.environment, s->wi_world));
    const double cos_theta = dot(s->wi_world, ctx.normal);
    if (cos_theta <= 0) {
      ++below_horizon;
      EXPECT_EQ(s->weight, 0.0);
    } else {
      EXPECT_NEAR(s->weight, (0.5 / kPi) * cos_theta / s->pdf_solid_angle, 1e-12 * s->weight);
      // An escaped upward ray (no other object above the floor here but the light).
      const auto hit = trace_from(*f.rtc, ctx, s->wi_world, counters);
      if (!hit) {
        EXPECT_EQ(strategy.pdf(ctx, s->wi_world, hit), s->pdf_solid_angle);
      }
    }
  }
  EXPECT_GT(environment_samples, kSamples / 3);
  EXPECT_GT(below_horizon, 0) << "the map's lower hemisphere (ground 0.1) is sampled too";
}

INSTANTIATE_TEST_SUITE_P(WithAndWithoutEmitter, EnvironmentLight, testing::Bool(),
                         [](const testing::TestParamInfo<bool>& info) {
                           return std::string(info.param ? "WithEmitter" : "MapOnly");
                         });

// A constant environment is still sampled cosine-weighted.
TEST(EnvironmentLightConstant, KeepsCosineSampling) {
  MapFixture f(false);
  f.scene.environment.map.reset();
  const LightSet lights(f.scene);
  EXPECT_FALSE(lights.environment_sampler);
  const LightStrategy strategy{f.rtc.get(), &lights, EmitterSampling::kSolidAngle, Defect::kNone};
  const ShadingContext ctx = f.context();
  for (int i = 0; i < 1000; ++i) {
    Rng rng(kSeed, 1, uint64_t(i));
    const auto s = strategy.sample(ctx, next_uniform3(rng));
    ASSERT_TRUE(s.has_value());
    EXPECT_NEAR(s->pdf_solid_angle, cosine_hemisphere_pdf(ctx.frame.local_from_world(s->wi_world)),
                1e-12 * s->pdf_solid_angle);
    EXPECT_EQ(s->radiance, 2.0);
  }
}

}  // namespace
}  // namespace furnace
