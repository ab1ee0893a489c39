// render(): bit-identical images across thread counts and runs, distinct
// images for distinct seeds, exact furnace scenes (zero variance where the
// sampling is exact), Russian roulette's 1/p reweighting, names and errors
// (the moment accumulator itself is tested in tests/core).
#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <vector>

#include "core/error.h"
#include "renderer/embree_scene.h"
#include "renderer/render.h"
#include "test_support.h"
#include "tests/renderer/strategy_names.h"

namespace furnace {
namespace {

using testing_support::make_camera;
using testing_support::make_floor;
using testing_support::make_object;
using testing_support::strategy_param_name;

constexpr uint64_t kSeed = 0x0e2d;

std::vector<Strategy> every_strategy() {
  std::vector<Strategy> s = direct_strategies();
  for (Strategy p : path_tracing_strategies()) s.push_back(p);
  return s;
}

Scene default_scene() { return load_scene(std::string(FURNACE_SCENE_DIR) + "/disk_occluder.json"); }

using testing_support::bitwise_equal;

class EveryStrategy : public testing::TestWithParam<Strategy> {};

TEST_P(EveryStrategy, ImageIsIdenticalForOneAndTwoThreadsAndAcrossRuns) {
  const Scene scene = default_scene();
  RenderOptions o;
  o.strategy = GetParam();
  o.spp = 8;
  o.seed = kSeed;
  o.threads = 1;
  const Image one = render(scene, o);
  o.threads = 2;
  const Image two = render(scene, o);
  const Image again = render(scene, o);
  EXPECT_TRUE(bitwise_equal(one, two));
  EXPECT_TRUE(bitwise_equal(two, again));
  EXPECT_EQ(one.nonfinite_samples, 0u);
  EXPECT_GT(one.rays, uint64_t(one.width) * one.height);
}

TEST_P(EveryStrategy, DifferentSeedsGiveDifferentImages) {
  const Scene scene = default_scene();
  RenderOptions o;
  o.strategy = GetParam();
  o.spp = 4;
  o.seed = kSeed;
  const Image a = render(scene, o);
  o.seed = kSeed + 1;
  const Image b = render(scene, o);
  EXPECT_FALSE(bitwise_equal(a, b));
}

// White furnace: a Lambertian floor under a constant environment L (nothing
// else). Every camera ray sees ρ·L exactly; a strategy that samples the cosine
// (or the environment by its cosine density, or MIS of two such) returns ρ·L
// in every sample, so the per-pixel variance is zero up to round-off.
TEST_P(EveryStrategy, FurnaceFloorGivesRhoTimesEnvironment) {
  constexpr double kRho = 0.6, kEnvironment = 2.5;
  Scene scene;
  scene.name = "furnace_floor";
  scene.camera = make_camera(4);
  scene.objects.push_back(make_floor(kRho));
  scene.environment.radiance = kEnvironment;
  RenderOptions o;
  o.strategy = GetParam();
  o.spp = 256;
  o.seed = kSeed;
  const Image image = render(scene, o);
  const double expected = kRho * kEnvironment;
  const bool exact = GetParam() != Strategy::kUniformHemisphere;
  for (const PixelMoments& p : image.pixels) {
    if (exact) {
      EXPECT_NEAR(p.mean / expected, 1.0, 1e-14);
      EXPECT_LE(p.sample_variance(), 1e-28);
    } else {
      // The pixel's own mean and variance as a z-test.
      EXPECT_TRUE(testing_support::mean_consistent(p, expected)) << p.mean;
      EXPECT_GT(p.sample_variance(), 0.0);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Strategies, EveryStrategy, testing::ValuesIn(every_strategy()), strategy_param_name);

// A convex Lambertian sphere in a constant environment: no interreflection,
// so every path tracer pixel on it is ρ·L, exactly for each sample without
// Russian roulette.
Scene furnace_sphere(double rho, double environment) {
  Scene scene;
  scene.name = "furnace_sphere";
  scene.camera = make_camera(6);
  scene.camera.center = {0, 0, 3};
  scene.objects.push_back(make_object("ball", Sphere{{0, 0, 0}, 0.9}, rho));
  scene.environment.radiance = environment;
  return scene;
}

class PathTracerTest : public testing::TestWithParam<Strategy> {};

TEST_P(PathTracerTest, ConvexFurnaceSphereIsExact) {
  const Scene scene = furnace_sphere(0.7, 1.5);
  RenderOptions o;
  o.strategy = GetParam();
  o.spp = 64;
  o.roulette_depth = 1000;  // roulette off: the estimator is exact per sample
  const Image image = render(scene, o);
  for (const PixelMoments& p : image.pixels) {
    const bool sees_ball = std::fabs(p.mean - 1.5) > 1e-9;  // background pixels see L itself
    if (sees_ball) {
      EXPECT_NEAR(p.mean / (0.7 * 1.5), 1.0, 1e-13);
    }
    EXPECT_LE(p.sample_variance(), 1e-26);
  }
}

TEST_P(PathTracerTest, RussianRouletteIsUnbiased) {
  // Roulette from the first bounce: survivors carry throughput 1 (ρ/ρ), so each
  // sample is L or 0 and only the mean stays ρ·L. The image-wide z-test uses
  // the pixels' own variances.
  constexpr double kRho = 0.7, kEnvironment = 1.5;
  const Scene scene = furnace_sphere(kRho, kEnvironment);
  RenderOptions o;
  o.strategy = GetParam();
  o.spp = 512;
  o.seed = kSeed;
  o.roulette_depth = 1;
  const Image image = render(scene, o);
  double sum = 0, variance_of_sum = 0;
  int n = 0;
  for (const PixelMoments& p : image.pixels) {
    if (p.sample_variance() == 0) continue;  // background
    sum += p.mean;
    variance_of_sum += p.sample_variance() / double(p.count);
    ++n;
  }
  ASSERT_GT(n, 10);
  const double mean = sum / n, se = std::sqrt(variance_of_sum) / n;
  EXPECT_LE(std::fabs(mean - kRho * kEnvironment), testing_support::z_critical(testing_support::kAlpha) * se)
      << mean << " ± " << se;
}

TEST_P(PathTracerTest, MaxDepthOneSeesOnlyEmission) {
  const Scene scene = furnace_sphere(0.7, 1.5);
  RenderOptions o;
  o.strategy = GetParam();
  o.spp = 4;
  o.max_depth = 1;
  const Image image = render(scene, o);
  for (const PixelMoments& p : image.pixels) EXPECT_TRUE(p.mean == 0.0 || p.mean == 1.5) << p.mean;
}

INSTANTIATE_TEST_SUITE_P(PathTracers, PathTracerTest, testing::ValuesIn(path_tracing_strategies()),
                         strategy_param_name);

// Every direct strategy estimates the same quantity: on a scene with a
// rectangle, triangle and sphere light, a blocker and an environment, their
// image means agree with light_area's (two-sample z-tests with data-derived
// variances, each at level kAlpha).
TEST(DirectStrategies, AgreeOnAMixedLightScene) {
  Scene scene;
  scene.name = "mixed_lights";
  scene.camera = make_camera(8);
  scene.objects.push_back(make_floor(0.8));
  scene.objects.push_back(make_object("rect_light", Rectangle{{-1.2, -0.6, 1.5}, {0, 0.5, 0}, {0.6, 0, 0}}, 0, 4.0));
  scene.objects.push_back(make_object("tri_light", Triangle{{0.4, 0.3, 1.0}, {0.9, 0.3, 1.1}, {0.6, 0.8, 1.0}}, 0, 6.0));
  scene.objects.push_back(make_object("ball_light", Sphere{{0.5, -0.7, 1.3}, 0.25}, 0, 3.0));
  scene.objects.push_back(make_object("blocker", Disk{{0, 0, 0.8}, {0, 0, 1}, 0.3}, 0.5));
  scene.environment.radiance = 0.2;
  const auto image_mean = [&](Strategy s) {
    RenderOptions o;
    o.strategy = s;
    o.spp = 1024;
    o.seed = kSeed;
    const Image image = render(scene, o);
    // The mean of the pixel means; pixels are independent, so its variance is Σ s²/N over P².
    double sum = 0, variance_of_sum = 0;
    for (const PixelMoments& p : image.pixels) {
      sum += p.mean;
      variance_of_sum += p.sample_variance() / double(p.count);
    }
    const double n = double(image.pixels.size());
    return testing_support::Estimate{sum / n, std::sqrt(variance_of_sum) / n};
  };
  const testing_support::Estimate reference = image_mean(Strategy::kLightArea);
  const std::vector<Strategy> others = {Strategy::kUniformHemisphere, Strategy::kCosineHemisphere,
                                        Strategy::kLightSolidAngle,   Strategy::kBsdf,
                                        Strategy::kMisBalance,        Strategy::kMisPower};
  for (Strategy s : others) {
    const testing_support::Estimate m = image_mean(s);
    EXPECT_TRUE(testing_support::means_consistent(reference, m))
        << strategy_name(s) << ": " << m.mean << " ± " << m.standard_error << " vs light_area " << reference.mean
        << " ± " << reference.standard_error;
  }
}

// A glossy scene: Phong floor, Lambertian ball, rectangle and sphere lights,
// an environment. BSDF sampling, light sampling and their MIS must agree for
// non-Lambertian BSDFs too (direct strategies), and the naive and NEE+MIS
// path tracers must agree with each other (two-sample z-tests on image means).
Scene glossy_scene() {
  Scene scene;
  scene.name = "glossy";
  scene.camera = make_camera(8);
  scene.camera.center = {0, 0, 3};
  scene.objects.push_back(make_object("floor", Rectangle{{-4, -4, 0}, {8, 0, 0}, {0, 8, 0}}, 0.8, 0, Phong{20}));
  scene.objects.push_back(make_object("ball", Sphere{{0.4, 0.3, 0.5}, 0.5}, 0.6));
  scene.objects.push_back(make_object("panel", Rectangle{{-1.5, -0.5, 1.2}, {0, 1.0, 0}, {0.6, 0, 0}}, 0, 5.0));
  scene.objects.push_back(make_object("bulb", Sphere{{-0.6, 1.0, 1.0}, 0.2}, 0, 8.0));
  scene.environment.radiance = 0.3;
  return scene;
}

testing_support::Estimate image_mean_estimate(const Scene& scene, Strategy s, int spp) {
  RenderOptions o;
  o.strategy = s;
  o.spp = spp;
  o.seed = kSeed;
  const Image image = render(scene, o);
  double sum = 0, variance_of_sum = 0;
  for (const PixelMoments& p : image.pixels) {
    sum += p.mean;
    variance_of_sum += p.sample_variance() / double(p.count);
  }
  const double n = double(image.pixels.size());
  return {sum / n, std::sqrt(variance_of_sum) / n};
}

TEST(DirectStrategies, AgreeOnAGlossyScene) {
  const Scene scene = glossy_scene();
  const auto reference = image_mean_estimate(scene, Strategy::kMisPower, 4096);
  for (Strategy s : {Strategy::kBsdf, Strategy::kLightArea, Strategy::kLightSolidAngle, Strategy::kMisBalance}) {
    const auto m = image_mean_estimate(scene, s, 4096);
    std::printf("%s: %.6f ± %.6f (mis_power %.6f ± %.6f)\n", strategy_name(s).c_str(), m.mean, m.standard_error,
                reference.mean, reference.standard_error);
    EXPECT_TRUE(testing_support::means_consistent(reference, m))
        << strategy_name(s) << ": " << m.mean << " ± " << m.standard_error << " vs mis_power " << reference.mean
        << " ± " << reference.standard_error;
  }
}

TEST(PathTracer, NaiveAndMisAgreeOnAGlossyScene) {
  const Scene scene = glossy_scene();
  const auto naive = image_mean_estimate(scene, Strategy::kPathNaive, 8192);
  const auto mis = image_mean_estimate(scene, Strategy::kPathMis, 4096);
  std::printf("path_naive %.6f ± %.6f, path_mis %.6f ± %.6f\n", naive.mean, naive.standard_error, mis.mean,
              mis.standard_error);
  EXPECT_TRUE(testing_support::means_consistent(naive, mis))
      << "naive " << naive.mean << " ± " << naive.standard_error << " vs mis " << mis.mean << " ± "
      << mis.standard_error;
}

TEST(PathTracer, MirrorReflectsTheLight) {
  // A mirror floor under an emitting disk facing down: the camera looking down
  // at the mirror sees, reflected, the disk's emission Le·R where the mirror
  // image of the disk covers the pixel, 0 elsewhere; exact per sample.
  Scene scene;
  scene.camera = make_camera(8);
  scene.objects.push_back(make_object("mirror", Rectangle{{-4, -4, 0}, {8, 0, 0}, {0, 8, 0}}, 0.8, 0,
                                      Mirror{}));
  scene.objects.push_back(make_object("light", Disk{{0, 0, 2}, {0, 0, -1}, 0.5}, 0, 5.0));
  for (Strategy s : path_tracing_strategies()) {
    RenderOptions o;
    o.strategy = s;
    o.spp = 16;
    const Image image = render(scene, o);
    // The camera plane (z = 0.5) lies below the light: the centre pixels see
    // the disk's mirror image, the corner pixels (|x| = 0.875) do not.
    EXPECT_NEAR(image.at(3, 3).mean, 0.8 * 5.0, 1e-12) << strategy_name(s);
    EXPECT_EQ(image.at(0, 0).mean, 0.0) << strategy_name(s);
  }
}

TEST(Render, NonFiniteSamplesAreDroppedAndCounted) {
  // Emission near the largest double: weight·Le overflows to +inf wherever the
  // light-sampling weight exceeds ~1.2 (light points close above), and only there.
  // The light (z = 0.7) is above the camera plane (z = 0.5): camera rays see the floor.
  Scene scene;
  scene.name = "overflow";
  scene.camera = make_camera(4);
  scene.objects.push_back(make_floor(1.0));
  scene.objects.push_back(make_object("light", Disk{{0, 0, 0.7}, {0, 0, -1}, 2.0}, 0, 1.5e308));
  RenderOptions o;
  o.strategy = Strategy::kLightArea;
  o.spp = 64;
  const Image image = render(scene, o);
  EXPECT_GT(image.nonfinite_samples, 0u);
  uint64_t kept = 0;
  for (const PixelMoments& p : image.pixels) {
    EXPECT_TRUE(std::isfinite(p.mean));
    kept += p.count;
  }
  EXPECT_EQ(kept + image.nonfinite_samples, uint64_t(o.spp) * image.pixels.size());
}

TEST(Names, RoundTripAndErrorsNameTheValue) {
  for (Strategy s : every_strategy()) EXPECT_EQ(parse_strategy(strategy_name(s)), s);
  for (Defect d : {Defect::kNone, Defect::kDropLightCosine, Defect::kPdfOffByConstant, Defect::kSkipShadowRay})
    EXPECT_EQ(parse_defect(defect_name(d)), d);
  try {
    parse_strategy("uniform_hemisphre");
    FAIL() << "no exception";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("'uniform_hemisphre'"), std::string::npos) << what;
    EXPECT_NE(what.find("uniform_hemisphere, cosine_hemisphere, light_area"), std::string::npos) << what;
  }
  EXPECT_THROW(parse_defect("skip_shadow"), Error);
}

TEST(Render, RayLogHoldsEveryTracedRay) {
  const Scene scene = default_scene();
  for (Strategy strategy : {Strategy::kLightArea, Strategy::kMisPower, Strategy::kPathMis}) {
    std::vector<TracedRay> log;
    RenderOptions o;
    o.strategy = strategy;
    o.spp = 4;
    o.threads = 1;
    o.ray_log = &log;
    const Image logged = render(scene, o);
    EXPECT_EQ(log.size(), logged.rays) << strategy_name(strategy);
    o.ray_log = nullptr;
    o.threads = 2;
    const Image plain = render(scene, o);  // logging changes nothing in the image
    ASSERT_EQ(plain.pixels.size(), logged.pixels.size());
    for (size_t i = 0; i < plain.pixels.size(); ++i) ASSERT_EQ(plain.pixels[i].mean, logged.pixels[i].mean) << i;
  }
  std::vector<TracedRay> log;
  RenderOptions o;
  o.ray_log = &log;
  o.threads = 2;
  EXPECT_THROW(render(scene, o), Error);
}

TEST(Render, RejectsBadOptionsAndLightlessScenes) {
  const Scene scene = default_scene();
  RenderOptions o;
  o.spp = 0;
  try {
    render(scene, o);
    FAIL() << "no exception";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("spp"), std::string::npos);
  }
  Scene dark;
  dark.name = "dark";
  dark.camera = make_camera(2);
  dark.objects.push_back(make_floor(0.5));
  RenderOptions light;
  light.strategy = Strategy::kLightArea;
  EXPECT_THROW(render(dark, light), Error);
  light.strategy = Strategy::kCosineHemisphere;  // nothing to sample, nothing wrong: a black image
  const Image black = render(dark, light);
  for (const PixelMoments& p : black.pixels) EXPECT_EQ(p.mean, 0.0);
}

}  // namespace
}  // namespace furnace
