// Zero variance wherever the sampling is exact,
// end to end through render() and through the light strategy:
//  1. a Lambertian floor (ρ) under an unblocked constant sky (L): cosine
//     sampling gives Y = (ρ/π)·π·L = ρ·L in every sample; so do bsdf
//     (Lambertian = cosine), light_area and light_solid_angle (the sky is the
//     only light and is sampled cosine-weighted) and both MIS heuristics (one
//     light: p_light = p_bsdf, weights ½ + ½). Control: uniform_hemisphere on
//     the same scene has Y = 2ρL·cos θ, never zero-variance.
//  2. solid-angle sampling of an unoccluded sphere, triangle or rectangle
//     light (one light, pmf 1) for the solid-angle integral ∫L dω: every
//     sample's L/p equals L·Ω exactly. (Not for the irradiance E: its
//     estimate L·cos θ·Ω carries cos θ, which varies over the cone, so cone
//     sampling is not exact for E; the test shows that variance is > 0.)
//     Control: area sampling of the same light, whose L/p = L·A·cos θ'/r²
//     varies.
// "Exactly" means to round-off: every sample within kRoundOffRel of the
// exact value (a few ulps per arithmetic step of the estimator).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <ostream>
#include <string>

#include "renderer/direct_strategies.h"
#include "renderer/embree_scene.h"
#include "renderer/light_strategy.h"
#include "renderer/lights.h"
#include "renderer/render.h"
#include "tests/renderer/strategy_names.h"

namespace furnace {
namespace {

constexpr uint64_t kSeed = 0x2e70;
constexpr int kSpp = 256;
// Each estimate is a product/quotient of ~10 rounded doubles (warp, frame
// change, pdf, weight, MIS weights): ≤ 64 ulps relative.
constexpr double kRoundOffRel = 64 * std::numeric_limits<double>::epsilon();

constexpr double kAlbedo = 0.6, kSky = 1.5;

// A floor under an open sky, written by the test; the camera sees only the floor.
Scene sky_floor_scene() {
  const std::string json = R"({
    "name": "sky_floor",
    "camera": {"type": "orthographic", "center": [0, 0, 1], "forward": [0, 0, -1], "up": [0, 1, 0],
               "size": [2, 2], "resolution": [16, 16]},
    "environment": {"radiance": 1.5},
    "objects": [
      {"name": "floor", "shape": {"type": "rectangle", "corner": [-2, -2, 0], "edge_u": [4, 0, 0], "edge_v": [0, 4, 0]},
       "material": {"type": "lambertian", "albedo": 0.6}}
    ]
  })";
  return parse_scene(json, "zero_variance_test sky_floor");
}

// Largest |y − exact|/exact over all samples, from the pixel's moments:
// max over pixels of (|mean − exact| + √(m2/n)·√n) bounds it (a single
// sample deviating by δ makes m2 ≥ δ²·(n−1)/n).
double worst_relative_spread(const Image& image, double exact) {
  double worst = 0;
  for (const PixelMoments& m : image.pixels) {
    const double spread = std::fabs(m.mean - exact) + std::sqrt(m.m2);
    worst = std::fmax(worst, spread / exact);
  }
  return worst;
}

class SkyFloorZeroVariance : public testing::TestWithParam<Strategy> {};

TEST_P(SkyFloorZeroVariance, EverySampleIsAlbedoTimesSky) {
  const Scene scene = sky_floor_scene();
  RenderOptions options;
  options.strategy = GetParam();
  options.spp = kSpp;
  options.seed = kSeed;
  options.threads = 1;
  const Image image = render(scene, options);
  const double exact = kAlbedo * kSky;
  const double spread = worst_relative_spread(image, exact);
  std::printf("  %s: %d pixels x %d spp, worst relative spread %.3g (bound %.3g)\n", strategy_name(GetParam()).c_str(),
              image.width * image.height, kSpp, spread, kRoundOffRel);
  EXPECT_LE(spread, kRoundOffRel);
  EXPECT_EQ(image.nonfinite_samples, 0u);
}

INSTANTIATE_TEST_SUITE_P(ExactStrategies, SkyFloorZeroVariance,
                         testing::Values(Strategy::kCosineHemisphere, Strategy::kBsdf, Strategy::kLightArea,
                                         Strategy::kLightSolidAngle, Strategy::kMisBalance, Strategy::kMisPower),
                         testing_support::strategy_param_name);

// Control: uniform hemisphere sampling is not exact; every pixel varies by
// far more than round-off (Var Y/E² = 1/3 for the sky).
TEST(SkyFloorZeroVarianceControl, UniformHemisphereVaries) {
  const Scene scene = sky_floor_scene();
  RenderOptions options;
  options.strategy = Strategy::kUniformHemisphere;
  options.spp = kSpp;
  options.seed = kSeed;
  options.threads = 1;
  const Image image = render(scene, options);
  const double exact = kAlbedo * kSky;
  double smallest_relative_sd = HUGE_VAL;
  for (const PixelMoments& m : image.pixels)
    smallest_relative_sd = std::fmin(smallest_relative_sd, std::sqrt(m.sample_variance()) / exact);
  std::printf("  uniform_hemisphere control: smallest per-pixel relative sd %.3g (expected about 1/sqrt(3) = 0.577)\n",
              smallest_relative_sd);
  EXPECT_GT(smallest_relative_sd, 1e6 * kRoundOffRel);
  EXPECT_GT(worst_relative_spread(image, exact), kRoundOffRel);
}

// ---------------------------------------------------------------------------
// Light samples of one unoccluded emitter seen from the floor point (0, 0, 0).

struct OneLight {
  Scene scene;
  std::unique_ptr<EmbreeDevice> device;
  std::unique_ptr<EmbreeScene> rtc;
  std::unique_ptr<LightSet> lights;
  explicit OneLight(const Shape& shape, double le) {
    scene.name = "one_light";
    scene.source = "zero_variance_test";
    scene.objects.push_back({"floor", Rectangle{{-3, -3, 0}, {6, 0, 0}, {0, 6, 0}}, {0.5, Lambertian{}}, 0});
    scene.objects.push_back({"light", shape, {}, le});
    device = std::make_unique<EmbreeDevice>();
    rtc = std::make_unique<EmbreeScene>(*device, scene);
    lights = std::make_unique<LightSet>(scene);
  }
  ShadingContext context() const {
    SurfaceHit hit;
    hit.object = 0;
    hit.point = {0, 0, 0};
    hit.normal = {0, 0, 1};
    hit.front_facing = true;
    return ShadingContext::at(hit, normalize(Vec3{0.1, 0.2, 1}), scene.objects[0].material);
  }
};

// Ω of the light from the origin, written here: the sphere's cap
// 2π(1 − cos α) = 2π sin²α/(1 + cos α); polygons as a fan of Van Oosterom–
// Strackee triangles.
double solid_angle_from_origin(const Shape& shape) {
  if (const auto* s = std::get_if<Sphere>(&shape)) {
    const double sin2 = s->radius * s->radius / length_squared(s->center);
    return 2 * kPi * sin2 / (1 + std::sqrt(1 - sin2));
  }
  std::vector<Vec3> v;
  if (const auto* r = std::get_if<Rectangle>(&shape))
    v = {r->corner, r->corner + r->edge_u, r->corner + r->edge_u + r->edge_v, r->corner + r->edge_v};
  else {
    const auto& t = std::get<Triangle>(shape);
    v = {t.p0, t.p1, t.p2};
  }
  double omega = 0;
  const Vec3 a = normalize(v[0]);
  for (size_t k = 1; k + 1 < v.size(); ++k) {
    const Vec3 b = normalize(v[k]), c = normalize(v[k + 1]);
    omega += 2 * std::atan2(dot(a, cross(b, c)), 1 + dot(a, b) + dot(b, c) + dot(c, a));
  }
  return std::fabs(omega);
}

struct Spread {
  double worst_relative = 0;  // max |L/p − L·Ω| / (L·Ω)
  double irradiance_relative_sd = 0;  // sd of the E estimate weight·L over its mean
  int samples = 0;
};

Spread light_spread(const OneLight& world, EmitterSampling mode, double exact) {
  const LightStrategy strategy{world.rtc.get(), world.lights.get(), mode, Defect::kNone};
  const ShadingContext ctx = world.context();
  Spread s;
  double sum = 0, sum2 = 0;
  for (int i = 0; i < 4096; ++i) {
    Rng rng(kSeed, 1, uint64_t(i));
    const auto sample = strategy.sample(ctx, next_uniform3(rng));
    if (!sample) continue;
    ++s.samples;
    s.worst_relative = std::fmax(s.worst_relative, std::fabs(sample->radiance / sample->pdf_solid_angle - exact) / exact);
    const double y = sample->weight * sample->radiance;
    sum += y, sum2 += y * y;
  }
  const double mean = sum / s.samples;
  s.irradiance_relative_sd = std::sqrt(std::fmax(sum2 / s.samples - mean * mean, 0.0)) / mean;
  return s;
}

struct LightCase {
  std::string name;
  Shape shape;
};

void PrintTo(const LightCase& c, std::ostream* os) { *os << c.name; }

class SolidAngleZeroVariance : public testing::TestWithParam<LightCase> {};

TEST_P(SolidAngleZeroVariance, RadianceOverPdfIsRadianceTimesSolidAngle) {
  const double le = 2.5;
  const OneLight world(GetParam().shape, le);
  const double exact = le * solid_angle_from_origin(GetParam().shape);
  const Spread exact_sampling = light_spread(world, EmitterSampling::kSolidAngle, exact);
  const Spread control = light_spread(world, EmitterSampling::kArea, exact);
  std::printf("  %s: solid angle: %d samples, worst |L/p - L*Omega|/(L*Omega) %.3g; E-estimate relative sd %.3g "
              "(cos theta varies: not exact for E); area control: worst %.3g\n",
              GetParam().name.c_str(), exact_sampling.samples, exact_sampling.worst_relative,
              exact_sampling.irradiance_relative_sd, control.worst_relative);
  EXPECT_GT(exact_sampling.samples, 4000);
  EXPECT_LE(exact_sampling.worst_relative, kRoundOffRel);
  EXPECT_GT(exact_sampling.irradiance_relative_sd, 1e6 * kRoundOffRel);
  EXPECT_GT(control.worst_relative, 1e6 * kRoundOffRel);
}

INSTANTIATE_TEST_SUITE_P(
    Lights, SolidAngleZeroVariance,
    testing::Values(LightCase{"Sphere", Sphere{{0.4, -0.2, 0.9}, 0.5}},
                    LightCase{"Triangle", Triangle{{0.9, 0.8, 1.2}, {1.3, 1.5, 1.2}, {1.7, 0.7, 1.2}}},
                    LightCase{"Rectangle", Rectangle{{-0.6, -0.4, 1.5}, {0, 0.8, 0.3}, {1.2, 0, 0}}}),
    [](const auto& info) { return info.param.name; });

}  // namespace
}  // namespace furnace
