// EmitterSetups (renderer/light_strategy.h): the light strategy's per-emitter
// set-up (cone, spherical triangle or rectangle map) kept between the samples
// of one shading point. It must never change a result: every field of every
// light sample and every density equal to the bit with and without it, from
// the point it is bound to and from any other point (which must compute its
// own set-up, not read the bound point's).
#include <gtest/gtest.h>

#include <optional>

#include "renderer/light_strategy.h"
#include "floor_fixture.h"
#include "test_support.h"

namespace furnace {
namespace {

using testing_support::make_floor;
using testing_support::make_object;

constexpr int kDraws = 2000;
constexpr uint64_t kSeed = 0x5e7;

// A floor under one light of every shape with a solid-angle method (sphere:
// cone; triangle; rectangle) and a disk (area sampling in both modes).
struct Fixture : testing_support::FloorFixture {
  Fixture() {
    scene.name = "emitter_setups";
    scene.objects.push_back(make_floor(0.5));
    scene.objects.push_back(make_object("ball", Sphere{{-1, 0.5, 1.2}, 0.3}, 0, 2.0));
    scene.objects.push_back(make_object("tri", Triangle{{0.5, 0.5, 1.5}, {0.5, 1.5, 1.5}, {1.5, 0.5, 1.5}}, 0, 3.0));
    scene.objects.push_back(make_object("rect", Rectangle{{-1, -1.5, 1.0}, {0, 1, 0}, {1, 0, 0}}, 0, 1.5));
    scene.objects.push_back(make_object("disk", Disk{{1, -1, 2}, {0, 0, -1}, 0.4}, 0, 4.0));
    build(LightSelection::kPower);
  }
};

void expect_same(const std::optional<LightSample>& a, const std::optional<LightSample>& b) {
  ASSERT_EQ(a.has_value(), b.has_value());
  if (!a) return;
  EXPECT_EQ(a->wi_world, b->wi_world);
  EXPECT_EQ(a->pdf_solid_angle, b->pdf_solid_angle);
  EXPECT_EQ(a->weight, b->weight);
  EXPECT_EQ(a->radiance, b->radiance);
  EXPECT_EQ(a->delta, b->delta);
  EXPECT_EQ(a->selection_pmf, b->selection_pmf);
  EXPECT_EQ(a->shadow_origin, b->shadow_origin);
  EXPECT_EQ(a->shadow_direction, b->shadow_direction);
  EXPECT_EQ(a->shadow_t_max, b->shadow_t_max);
  EXPECT_EQ(a->shadow_ends.origin_object, b->shadow_ends.origin_object);
  EXPECT_EQ(a->shadow_ends.end_object, b->shadow_ends.end_object);
  EXPECT_EQ(a->assume_visible, b->assume_visible);
}

class EmitterSetupsTest : public testing::TestWithParam<EmitterSampling> {};

// Samples and densities from the bound point (the set-ups computed on first
// use, then reused) and from a second point queried through the same store
// (computed aside), interleaved, against a strategy with no store at all.
TEST_P(EmitterSetupsTest, NeverChangesASampleOrADensity) {
  const Fixture f;
  const LightStrategy strategy{f.rtc.get(), f.lights.get(), GetParam(), Defect::kNone};
  const ShadingContext bound = f.context_at({0, 0, 0});
  const ShadingContext other = f.context_at({0.7, -0.4, 0});
  EmitterSetups setups;
  setups.bind(bound, f.scene.objects.size());
  ASSERT_TRUE(setups.holds(bound));
  ASSERT_FALSE(setups.holds(other));
  Rng rng(kSeed, 0, 0);
  TraceCounters counters;
  int sampled = 0;
  for (int i = 0; i < kDraws; ++i) {
    const ShadingContext& ctx = i % 3 == 2 ? other : bound;
    const Uniform3 u = next_uniform3(rng);
    const std::optional<LightSample> with = strategy.sample(ctx, u, &setups);
    const std::optional<LightSample> without = strategy.sample(ctx, u);
    expect_same(with, without);
    if (!without) continue;
    ++sampled;
    // The density of the same direction, as MIS asks for it, and of a
    // direction a light sample from the other point took.
    const std::optional<SurfaceHit> hit = trace_from(*f.rtc, ctx, without->wi_world, counters);
    EXPECT_EQ(strategy.pdf(ctx, without->wi_world, hit, &setups), strategy.pdf(ctx, without->wi_world, hit));
    const ShadingContext& swapped = &ctx == &bound ? other : bound;
    const std::optional<SurfaceHit> swapped_hit = trace_from(*f.rtc, swapped, without->wi_world, counters);
    EXPECT_EQ(strategy.pdf(swapped, without->wi_world, swapped_hit, &setups),
              strategy.pdf(swapped, without->wi_world, swapped_hit));
    if (HasFailure()) FAIL() << "draw " << i;
  }
  EXPECT_GT(sampled, kDraws / 2);
}

// The store is keyed by the point: the same direction has another density
// from the other point, so a store that answered for any point would fail
// the test above (its negative control, checked here on the data it uses).
TEST(EmitterSetups, TheTwoPointsDensitiesDiffer) {
  const Fixture f;
  const LightStrategy strategy{f.rtc.get(), f.lights.get(), EmitterSampling::kSolidAngle, Defect::kNone};
  const ShadingContext a = f.context_at({0, 0, 0});
  const ShadingContext b = f.context_at({0.7, -0.4, 0});
  TraceCounters counters;
  int differ = 0, both = 0;
  Rng rng(kSeed, 1, 0);
  for (int i = 0; i < kDraws; ++i) {
    const auto s = strategy.sample(a, next_uniform3(rng));
    if (!s) continue;
    const auto hit_a = trace_from(*f.rtc, a, s->wi_world, counters);
    const auto hit_b = trace_from(*f.rtc, b, s->wi_world, counters);
    if (!hit_a || !hit_b || hit_a->object != hit_b->object || hit_a->object == 4) continue;  // disk: area, same map
    ++both;
    if (strategy.pdf(a, s->wi_world, hit_a) != strategy.pdf(b, s->wi_world, hit_b)) ++differ;
  }
  EXPECT_GT(both, 20);
  EXPECT_EQ(differ, both);
}

INSTANTIATE_TEST_SUITE_P(Modes, EmitterSetupsTest,
                         testing::Values(EmitterSampling::kArea, EmitterSampling::kSolidAngle),
                         [](const testing::TestParamInfo<EmitterSampling>& info) {
                           return std::string(info.param == EmitterSampling::kArea ? "Area" : "SolidAngle");
                         });

}  // namespace
}  // namespace furnace
