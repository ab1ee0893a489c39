// Direct-lighting strategies at a shading point of a small scene built in
// code: sample() agrees with pdf() (for light strategies: with the density of
// the traced hit, as MIS queries it), solid-angle sampling has the exact
// constant density 1/Ω, area sampling's mean 1/pdf is that same Ω, and the MIS
// weights of two strategies sum to one.
#include <gtest/gtest.h>

#include <optional>
#include <ostream>
#include <string>
#include <tuple>

#include "renderer/direct_strategies.h"
#include "renderer/sampling.h"
#include "renderer/spherical_sampling.h"
#include "floor_fixture.h"
#include "test_support.h"

namespace furnace {

// GoogleTest prints an EmitterSampling parameter through this (found by
// argument-dependent lookup, so in the enum's namespace).
void PrintTo(EmitterSampling m, std::ostream* os) { *os << (m == EmitterSampling::kArea ? "area" : "solid_angle"); }

namespace {

using testing_support::make_floor;
using testing_support::make_object;

constexpr uint64_t kSeed = 0x57a7;
constexpr int kSamples = 1 << 14;
// The light pdf of a traced hit uses Embree's single-precision hit refined in
// double: planes exactly, spheres by a radial projection of the float hit,
// whose tangential error (~1e-7 relative) moves r² and cos θ' by ~1e-7.
constexpr double kTracedPdfRelTol = 1e-5;
constexpr double kExactRelTol = 1e-10;

struct LightCase {
  std::string name;
  Shape shape;
  double solid_angle_from_origin;  // Ω seen from the shading point (0,0,0), computed independently
};

double triangle_omega(const Triangle& t) {
  return spherical_triangle_solid_angle(normalize(t.p0), normalize(t.p1), normalize(t.p2));
}
double rectangle_omega(const Rectangle& r) {
  const Vec3 a = normalize(r.corner), b = normalize(r.corner + r.edge_u), c = normalize(r.corner + r.edge_u + r.edge_v),
             d = normalize(r.corner + r.edge_v);
  return spherical_triangle_solid_angle(a, b, c) + spherical_triangle_solid_angle(a, c, d);
}

std::vector<LightCase> light_cases() {
  const Rectangle rect{{-0.5, -0.3, 1.5}, {0, 0.8, 0}, {1.0, 0, 0}};
  const Rectangle sheared{{-0.5, -0.3, 1.5}, {0, 0.8, 0}, {1.0, 0.3, 0}};
  const Triangle tri{{-0.4, -0.2, 1.2}, {0.1, 0.6, 1.4}, {0.5, -0.3, 1.1}};
  const Sphere sphere{{0.3, -0.2, 2.0}, 0.5};
  const double d = length(sphere.center);
  const double sin2 = sphere.radius * sphere.radius / (d * d);
  const double sphere_omega = kTwoPi * sin2 / (1 + std::sqrt(1 - sin2));  // 2π(1 − cos θmax)
  // A disk facing the shading point on its axis: Ω = 2π(1 − d/√(d²+R²)),
  // written as 2πR²/(√(d²+R²)(√(d²+R²)+d)) to avoid the cancellation.
  const Disk disk{{0, 0, 1.0}, {0, 0, -1}, 0.4};
  const double hyp = std::hypot(1.0, disk.radius);
  const double disk_omega = kTwoPi * disk.radius * disk.radius / (hyp * (hyp + 1.0));
  return {{"Rectangle", rect, rectangle_omega(rect)},
          {"Parallelogram", sheared, rectangle_omega(sheared)},
          {"Triangle", tri, triangle_omega(tri)},
          {"Sphere", sphere, sphere_omega},
          {"Disk", disk, disk_omega}};
}

void PrintTo(const LightCase& c, std::ostream* os) { *os << c.name; }

// Floor at z = 0 plus one emitter; the shading point is the origin, viewed from above.
struct Fixture : testing_support::FloorFixture {
  Material floor_material;

  explicit Fixture(const Shape& light, double environment = 0, bool two_sided = false) {
    scene.name = "strategy_test";
    scene.objects.push_back(make_floor(0.5));
    scene.objects.push_back(make_object("light", light, 0, 3.0));
    scene.objects.back().two_sided = two_sided;
    scene.environment.radiance = environment;
    build();
  }
};

using LightParam = std::tuple<LightCase, EmitterSampling>;
class LightStrategyTest : public testing::TestWithParam<LightParam> {
 protected:
  const LightCase& light() const { return std::get<0>(GetParam()); }
  EmitterSampling mode() const { return std::get<1>(GetParam()); }
};

TEST_P(LightStrategyTest, SamplePdfMatchesPdfOfTracedHit) {
  Fixture f(light().shape);
  const LightStrategy strategy{f.rtc.get(), f.lights.get(), mode(), Defect::kNone};
  const ShadingContext ctx = f.context();
  TraceCounters counters;
  int checked = 0;
  for (int i = 0; i < 2000; ++i) {
    Rng rng(kSeed, 0, uint64_t(i));
    const auto s = strategy.sample(ctx, next_uniform3(rng));
    if (!s) continue;
    const auto hit = trace_from(*f.rtc, ctx, s->wi_world, counters);
    ASSERT_TRUE(hit.has_value());
    EXPECT_EQ(hit->object, 1u);
    EXPECT_TRUE(hit->front_facing);
    // The traced ray starts at the shading point itself: the hit it finds is
    // the sampled point up to Embree's refined round-off.
    EXPECT_NEAR(strategy.pdf(ctx, s->wi_world, hit) / s->pdf_solid_angle, 1.0, kTracedPdfRelTol);
    EXPECT_TRUE(light_visible(*f.rtc, *s, counters));
    ++checked;
  }
  EXPECT_GT(checked, 500);
}

TEST_P(LightStrategyTest, MeanInversePdfIsSolidAngle) {
  // E[1/p] = ∫ p·(1/p) dω = Ω over the directions the strategy reaches.
  Fixture f(light().shape);
  const LightStrategy strategy{f.rtc.get(), f.lights.get(), mode(), Defect::kNone};
  const ShadingContext ctx = f.context();
  RunningMoments inverse_pdf;
  for (int i = 0; i < kSamples; ++i) {
    Rng rng(kSeed, 1, uint64_t(i));
    const auto s = strategy.sample(ctx, next_uniform3(rng));
    inverse_pdf.add(s ? 1.0 / s->pdf_solid_angle : 0.0);
  }
  EXPECT_TRUE(testing_support::mean_consistent(inverse_pdf, light().solid_angle_from_origin))
      << inverse_pdf.mean << " ± " << inverse_pdf.mean_standard_error() << " vs " << light().solid_angle_from_origin;
}

INSTANTIATE_TEST_SUITE_P(
    Lights, LightStrategyTest,
    testing::Combine(testing::ValuesIn(light_cases()), testing::Values(EmitterSampling::kArea, EmitterSampling::kSolidAngle)),
    [](const testing::TestParamInfo<LightParam>& info) {
      return std::get<0>(info.param).name + (std::get<1>(info.param) == EmitterSampling::kArea ? "Area" : "SolidAngle");
    });

// Zero variance where the sampling is exact: 1/p = Ω for every sample (the
// shapes with an exact solid-angle map: rectangle, triangle, sphere).
class ExactSolidAngleTest : public testing::TestWithParam<LightCase> {};

TEST_P(ExactSolidAngleTest, DensityIsConstantInverseSolidAngle) {
  Fixture f(GetParam().shape);
  const LightStrategy strategy{f.rtc.get(), f.lights.get(), EmitterSampling::kSolidAngle, Defect::kNone};
  for (int i = 0; i < 256; ++i) {
    Rng rng(kSeed, 2, uint64_t(i));
    const auto s = strategy.sample(f.context(), next_uniform3(rng));
    ASSERT_TRUE(s.has_value());
    EXPECT_NEAR(s->pdf_solid_angle * GetParam().solid_angle_from_origin, 1.0, kExactRelTol);
  }
}

std::vector<LightCase> exact_solid_angle_cases() {
  std::vector<LightCase> out;
  for (const LightCase& c : light_cases())
    if (c.name == "Rectangle" || c.name == "Triangle" || c.name == "Sphere") out.push_back(c);
  return out;
}

INSTANTIATE_TEST_SUITE_P(Lights, ExactSolidAngleTest, testing::ValuesIn(exact_solid_angle_cases()),
                         [](const testing::TestParamInfo<LightCase>& info) { return info.param.name; });

TEST(LightStrategy, TinySphereLightKeepsEveryConeSample) {
  // θmax ≈ 5e-6: every cone sample, rim included, must hit the sphere and keep
  // its density 1/Ω (no sample lost to round-off at the cone's edge).
  const Sphere tiny{{0.1, 0.2, 2.0}, 1e-5};
  const double d = length(tiny.center);
  const double sin2 = tiny.radius * tiny.radius / (d * d);
  const double omega = kTwoPi * sin2 / (1 + std::sqrt(1 - sin2));
  Fixture f(tiny);
  const LightStrategy strategy{f.rtc.get(), f.lights.get(), EmitterSampling::kSolidAngle, Defect::kNone};
  const double rim = std::nextafter(1.0, 0.0);
  for (int i = 0; i < 1024; ++i) {
    Rng rng(kSeed, 7, uint64_t(i));
    Uniform3 u = next_uniform3(rng);
    if (i % 2 == 0) u[1] = rim;
    const auto s = strategy.sample(f.context(), u);
    ASSERT_TRUE(s.has_value()) << i;
    EXPECT_NEAR(s->pdf_solid_angle * omega, 1.0, kExactRelTol);
  }
}

TEST(LightStrategy, TwoSidedLightIsSampledFromBehindAndOneSidedIsNot) {
  // A rectangle whose front faces away (+z) from the shading point below it.
  const Rectangle away{{-0.5, -0.3, 1.5}, {1.0, 0, 0}, {0, 0.8, 0}};
  ASSERT_GT(away.normal().z, 0);
  const double omega = rectangle_omega(away);
  for (EmitterSampling mode : {EmitterSampling::kArea, EmitterSampling::kSolidAngle}) {
    Fixture two(away, 0, true), one(away, 0, false);
    const LightStrategy two_sided{two.rtc.get(), two.lights.get(), mode, Defect::kNone};
    const LightStrategy one_sided{one.rtc.get(), one.lights.get(), mode, Defect::kNone};
    RunningMoments inverse_pdf;
    TraceCounters counters;
    for (int i = 0; i < kSamples; ++i) {
      Rng rng(kSeed, 5, uint64_t(i));
      const Uniform3 u = next_uniform3(rng);
      EXPECT_FALSE(one_sided.sample(one.context(), u).has_value());
      const auto s = two_sided.sample(two.context(), u);
      ASSERT_TRUE(s.has_value());
      inverse_pdf.add(1.0 / s->pdf_solid_angle);
      if (i < 200) {
        const auto hit = trace_from(*two.rtc, two.context(), s->wi_world, counters);
        ASSERT_TRUE(hit.has_value());
        EXPECT_FALSE(hit->front_facing);
        EXPECT_EQ(emitted_radiance_towards(two.scene, hit, s->wi_world), 3.0);
        EXPECT_EQ(emitted_radiance_towards(one.scene, hit, s->wi_world), 0.0);
        EXPECT_NEAR(two_sided.pdf(two.context(), s->wi_world, hit) / s->pdf_solid_angle, 1.0, kTracedPdfRelTol);
      }
    }
    EXPECT_TRUE(testing_support::mean_consistent(inverse_pdf, omega)) << inverse_pdf.mean << " vs " << omega;
  }
}

TEST(LightStrategy, FlatLightDoesNotSampleItsOwnPoints) {
  // The floor itself emits: from a point on it, the floor is seen edge-on.
  Fixture f(Disk{{0, 0, 1}, {0, 0, -1}, 0.3});
  f.scene.objects[0].emitted_radiance = 1.0;
  const LightSet lights(f.scene);
  ASSERT_EQ(lights.count(), 2u);
  const LightStrategy strategy{f.rtc.get(), &lights, EmitterSampling::kSolidAngle, Defect::kNone};
  int floor_picks = 0;
  for (int i = 0; i < 200; ++i) {
    Rng rng(kSeed, 6, uint64_t(i));
    const Uniform3 u = next_uniform3(rng);
    if (lights.select(u[0]) != 0) continue;
    ++floor_picks;
    EXPECT_FALSE(strategy.sample(f.context(), u).has_value());
  }
  EXPECT_GT(floor_picks, 50);
}

TEST(LightStrategy, EnvironmentIsSampledAsALight) {
  Fixture f(Disk{{0, 0, 1}, {0, 0, -1}, 0.3}, 2.0);
  ASSERT_EQ(f.lights->count(), 2u);
  const LightStrategy strategy{f.rtc.get(), f.lights.get(), EmitterSampling::kArea, Defect::kNone};
  const ShadingContext ctx = f.context();
  TraceCounters counters;
  int environment_samples = 0;
  for (int i = 0; i < 1000; ++i) {
    Rng rng(kSeed, 3, uint64_t(i));
    const auto s = strategy.sample(ctx, next_uniform3(rng));
    if (!s || s->radiance != 2.0) continue;
    ++environment_samples;
    const auto hit = trace_from(*f.rtc, ctx, s->wi_world, counters);
    if (hit) continue;  // blocked by the disk: pdf of that hit is the disk's
    EXPECT_NEAR(strategy.pdf(ctx, s->wi_world, hit) / s->pdf_solid_angle, 1.0, kExactRelTol);
  }
  EXPECT_GT(environment_samples, 400);
}

TEST(DirectionStrategies, SamplePdfMatchesPdf) {
  Fixture f(Disk{{0, 0, 1}, {0, 0, -1}, 0.3});
  const ShadingContext ctx = f.context();
  for (int i = 0; i < 1000; ++i) {
    Rng rng(kSeed, 4, uint64_t(i));
    const Uniform3 u = next_uniform3(rng);
    const auto a = UniformHemisphereStrategy{}.sample(ctx, u);
    const auto b = CosineHemisphereStrategy{}.sample(ctx, u);
    const auto c = BsdfStrategy{}.sample(ctx, u);
    ASSERT_TRUE(a && b && c);
    EXPECT_NEAR(UniformHemisphereStrategy{}.pdf(ctx, a->wi_world) / a->pdf_solid_angle, 1.0, kExactRelTol);
    EXPECT_NEAR(CosineHemisphereStrategy{}.pdf(ctx, b->wi_world) / b->pdf_solid_angle, 1.0, kExactRelTol);
    EXPECT_NEAR(BsdfStrategy{}.pdf(ctx, c->wi_world) / c->pdf_solid_angle, 1.0, kExactRelTol);
    // Return convention: weight = f·cos/pdf, f = ρ/π for the floor.
    const double cos_theta = dot(a->wi_world, Vec3{0, 0, 1});
    EXPECT_NEAR(a->weight, 0.5 / kPi * cos_theta / a->pdf_solid_angle, 1e-14);
  }
}

TEST(DirectionStrategies, DefectScalesTheWeightOnly) {
  Fixture f(Disk{{0, 0, 1}, {0, 0, -1}, 0.3});
  const ShadingContext ctx = f.context();
  const Uniform3 u{0.3, 0.4, 0.5};
  const auto good = CosineHemisphereStrategy{Defect::kNone}.sample(ctx, u);
  const auto bad = CosineHemisphereStrategy{Defect::kPdfOffByConstant}.sample(ctx, u);
  ASSERT_TRUE(good && bad);
  EXPECT_EQ(good->pdf_solid_angle, bad->pdf_solid_angle);
  EXPECT_NEAR(good->weight / bad->weight, 1.1, 1e-14);
}

TEST(MisWeight, WeightsOfTwoStrategiesSumToOne) {
  for (int beta : {1, 2})
    for (double a : {0.0, 1e-3, 0.5, 2.0, 1e4})
      for (double b : {1e-3, 0.5, 2.0, 1e4}) {
        EXPECT_NEAR(mis_weight(a, b, beta) + mis_weight(b, a, beta), 1.0, 1e-15) << a << " " << b;
      }
  EXPECT_EQ(mis_weight(0.0, 0.0, 2), 0.0);
  EXPECT_EQ(mis_weight(1.0, 0.0, 2), 1.0);
}

}  // namespace
}  // namespace furnace
