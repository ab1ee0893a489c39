// Point lights in LightStrategy: a delta sample in position (direction to the
// light, Li = I/r², pdf 0, weight f·cos θ/pmf, its light's pmf attached),
// which pdf() never gives a density, and which MIS weighs by 1.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>

#include "renderer/direct_strategies.h"
#include "floor_fixture.h"
#include "test_support.h"
#include "tests/renderer/strategy_names.h"

namespace furnace {
namespace {

using testing_support::make_floor;
using testing_support::make_object;

constexpr double kRelTol = 8 * std::numeric_limits<double>::epsilon();
constexpr int kDraws = 4096;
constexpr uint64_t kSeed = 0x9017;

struct Fixture : testing_support::FloorFixture {

  explicit Fixture(LightSelection selection) {
    scene.name = "point_light_sampling";
    scene.objects.push_back(make_floor(0.5));
    scene.objects.push_back(make_object("ball", Sphere{{-1, 0.5, 1.2}, 0.3}, 0, 2.0));
    scene.point_lights.push_back({"bulb", {0.3, -0.2, 1.5}, 2.0});
    build(selection);
  }
};

class PointLightSampling : public testing::TestWithParam<LightSelection> {};

TEST_P(PointLightSampling, DeltaSampleCarriesInverseSquareRadianceAndPmf) {
  const Fixture f(GetParam());
  ASSERT_EQ(f.lights->count(), 2u);
  ASSERT_TRUE(f.lights->is_point_light(1));
  const double pmf = f.lights->pmf(1);
  const LightStrategy strategy{f.rtc.get(), f.lights.get(), EmitterSampling::kSolidAngle, Defect::kNone};
  const ShadingContext ctx = f.context();
  const Vec3 to_light = f.scene.point_lights[0].position - ctx.point;
  const double r2 = length_squared(to_light);
  const Vec3 wi = to_light / std::sqrt(r2);
  int deltas = 0;
  Rng rng(kSeed, 0, 0);
  for (int i = 0; i < kDraws; ++i) {
    const auto s = strategy.sample(ctx, next_uniform3(rng));
    ASSERT_TRUE(s);
    if (!s->delta) continue;
    ++deltas;
    EXPECT_EQ(s->pdf_solid_angle, 0.0);
    EXPECT_EQ(s->selection_pmf, pmf);
    EXPECT_NEAR(length(s->wi_world - wi), 0.0, kRelTol);
    EXPECT_NEAR(s->radiance, 2.0 / r2, kRelTol * 2.0 / r2);
    const double expected_weight = 0.5 * kInvPi * wi.z / pmf;  // (ρ/π)·cos θ/pmf
    EXPECT_NEAR(s->weight, expected_weight, kRelTol * expected_weight);
    // The shadow ray ends at the light.
    EXPECT_NEAR(length(s->shadow_origin + s->shadow_direction * s->shadow_t_max - f.scene.point_lights[0].position),
                0.0, 1e-12);
    // No ray finds a point light: the direction to it has no light density (it escapes).
    EXPECT_EQ(strategy.pdf(ctx, s->wi_world, std::nullopt), 0.0);
    // MIS: weight 1 against any BSDF density; the defect weighs it below 1.
    EXPECT_EQ(delta_light_mis_weight(*s, 0.3, Defect::kNone), 1.0);
    EXPECT_LT(delta_light_mis_weight(*s, 0.3, Defect::kPointLightMisWeighted), 1.0);
  }
  EXPECT_GT(deltas, 0);
}

INSTANTIATE_TEST_SUITE_P(Selections, PointLightSampling,
                         testing::Values(LightSelection::kUniform, LightSelection::kPower),
                         [](const testing::TestParamInfo<LightSelection>& info) {
                           return info.param == LightSelection::kPower ? std::string("Power") : std::string("Uniform");
                         });

// The emitter's density in pdf() uses its own pmf under power selection.
TEST(PointLightSampling, EmitterPdfUsesItsPowerPmf) {
  const Fixture uniform(LightSelection::kUniform), power(LightSelection::kPower);
  const LightStrategy su{uniform.rtc.get(), uniform.lights.get(), EmitterSampling::kSolidAngle, Defect::kNone};
  const LightStrategy sp{power.rtc.get(), power.lights.get(), EmitterSampling::kSolidAngle, Defect::kNone};
  const ShadingContext ctx = uniform.context();
  const Vec3 wi = normalize(Vec3{-1, 0.5, 1.2});
  TraceCounters counters;
  const auto hit = trace_from(*uniform.rtc, ctx, wi, counters);
  ASSERT_TRUE(hit);
  ASSERT_EQ(hit->object, 1u);
  const double ratio = sp.pdf(ctx, wi, hit) / su.pdf(ctx, wi, hit);
  const double expected = power.lights->pmf(0) / uniform.lights->pmf(0);
  EXPECT_NEAR(ratio, expected, 1e-12 * expected);
}

}  // namespace
}  // namespace furnace
