// The glass and conductor-Fresnel defects end to end: each of the seven
// (core/strategy.h) fails the harness's tests on a scene of the built-in
// suite that can see it, and leaves a Lambertian and a GGX scene without
// Fresnel bit for bit unchanged (the old suite cannot see them). The correct
// glass cases are in the default suite (strategy_verification_test.cpp).
//
// Which scene sees which defect (docs/statistics.md has every case's z):
//  - transmission f and pdf both without η² (pbrt-v4 before dfa11074): the
//    weight f·cos/pdf is unchanged, so BSDF sampling passes it (asserted
//    below, as the issue predicts) and only light sampling or MIS, which
//    evaluate f at a direction the BSDF did not draw, see it;
//  - the reflection Jacobian for refraction: the same cases;
//  - the radiance convention's 1/η′² dropped: an open interface that
//    transmits (a closed sphere cancels it);
//  - Fresnel at the macro normal: a rough interface;
//  - TIR absorbed: the view from inside past the critical angle;
//  - η not inverted from inside: any view from inside, the sphere's paths;
//  - the approximate conductor Fresnel: the conductor strips.
//
// Budget and levels (builtin_case.h): kSpp samples per pixel, seed kSeed,
// each case's tests sharing kCaseAlpha by the Šidák correction.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "analytic/glass.h"
#include "core/environment_map.h"
#include "core/fresnel.h"
#include "renderer/render.h"
#include "tests/integration/builtin_case.h"
#include "verify/harness.h"

namespace furnace::verify {
namespace {

using test::kSeed;
using test::run_builtin_case;

struct GlassControl {
  std::string name;
  std::string scene;
  Strategy strategy;
  Defect defect;
};
void PrintTo(const GlassControl& c, std::ostream* os) { *os << c.name; }

class GlassDefect : public testing::TestWithParam<GlassControl> {};

TEST_P(GlassDefect, FailsTheCaseThatCanSeeIt) {
  const GlassControl& c = GetParam();
  const Verdict v = run_builtin_case(c.scene, c.strategy, c.defect);
  EXPECT_FALSE(v.pass) << defect_name(c.defect) << " passed " << c.scene << " " << strategy_name(c.strategy);
}

INSTANTIATE_TEST_SUITE_P(
    GlassControls, GlassDefect,
    testing::Values(
        GlassControl{"TransmissionWithoutEta2", "glass_rough_outside_60.json", Strategy::kMisBalance,
                     Defect::kDielectricTransmissionWithoutEta2},
        GlassControl{"TransmissionWithoutEta2LightSampling", "glass_rough_inside_45.json", Strategy::kLightSolidAngle,
                     Defect::kDielectricTransmissionWithoutEta2},
        GlassControl{"ReflectionJacobian", "glass_rough_outside_60.json", Strategy::kLightSolidAngle,
                     Defect::kDielectricReflectionJacobian},
        GlassControl{"NoRadianceScaling", "glass_smooth_outside_60.json", Strategy::kBsdf,
                     Defect::kDielectricNoRadianceScaling},
        GlassControl{"MacroFresnel", "glass_rough_outside_60.json", Strategy::kBsdf, Defect::kDielectricMacroFresnel},
        GlassControl{"TirAbsorbs", "glass_smooth_inside_60.json", Strategy::kPathMis, Defect::kDielectricTirAbsorbs},
        GlassControl{"EtaNotInverted", "glass_sphere.json", Strategy::kPathNaive, Defect::kDielectricEtaNotInverted},
        GlassControl{"ConductorFresnelApproximate", "conductor_fresnel_sphere_60.json", Strategy::kMisPower,
                     Defect::kConductorFresnelApproximate}),
    [](const testing::TestParamInfo<GlassControl>& info) { return info.param.name; });

// The 2021 class hides from BSDF sampling: with f and pdf both off by the
// same factor the sampled weight is right, so a BSDF-sampling-only furnace
// test passes it. Asserted, so that the suite's claim (light sampling and
// MIS are what catch it) stays true.
TEST(GlassDefect, TransmissionWithoutEta2HidesFromBsdfSampling) {
  const Verdict v = run_builtin_case("glass_rough_outside_60.json", Strategy::kBsdf,
                                     Defect::kDielectricTransmissionWithoutEta2);
  EXPECT_TRUE(v.pass);
}

// Light sampling alone at rough glass (cosine-weighted environment
// directions on both sides) is out of the default suite: a narrow lobe makes
// most pixels too skewed for the pixel t-test at 4096 spp (Cochran's rule).
// Its image-mean test, which covers every pixel, must pass, with no pixel
// failure, and it prints how many pixels went untested.
TEST(GlassRough, LightSamplingPassesItsImageMeanTest) {
  for (const char* scene : {"glass_rough_outside_60.json", "glass_rough_inside_45.json"}) {
    const Verdict v = run_builtin_case(scene, Strategy::kLightSolidAngle, Defect::kNone);
    std::printf("[ glass ] %s, light_solid_angle: %d of %d pixels untested by the pixel t-test\n", scene,
                v.pixels_untested, v.pixels);
    EXPECT_EQ(v.nonfinite_samples, 0u);
    EXPECT_EQ(v.pixel_failures, 0);
    EXPECT_TRUE(v.pass) << scene;
  }
}

// The smooth glass sphere at unlimited depth: every path returns L_env·1 or
// is never cut, so the image is L_env exactly with zero variance (to
// round-off: the 1/η² and η² of the radiance convention cancel in floating
// point only to an ulp).
TEST(GlassSphere, UnlimitedDepthIsTheEnvironmentExactly) {
  const Scene scene = load_scene(std::string(FURNACE_SCENE_DIR) + "/glass_sphere.json");
  RenderOptions options;
  options.strategy = Strategy::kPathNaive;
  options.spp = 64;
  options.seed = kSeed;
  const Image image = render(scene, options);
  double worst = 0;
  for (const auto& p : image.pixels) worst = std::fmax(worst, std::fabs(p.mean - scene.environment.radiance));
  std::printf("[ glass ] sphere at unlimited depth: worst |pixel − L_env| = %.3g\n", worst);
  EXPECT_LE(worst, 1e-14);
  // Negative control: with η not inverted inside, paths leave with the wrong weight.
  options.defect = Defect::kDielectricEtaNotInverted;
  const Image wrong = render(scene, options);
  double worst_wrong = 0;
  for (const auto& p : wrong.pixels) worst_wrong = std::fmax(worst_wrong, std::fabs(p.mean - scene.environment.radiance));
  EXPECT_GT(worst_wrong, 1e-3);
}

// A disk light inside the glass seen from outside through rough strips
// (glass_rough_disk_inside.json, analytic/glass_light.h): the case where the
// 2021 class shows under light sampling alone. Each case: kSpp samples per
// pixel, seed kSeed, its pixel, image-mean and variance tests sharing
// kCaseAlpha by the Šidák correction (builtin_case.h); the z of each row is
// printed by run_builtin_case.
constexpr const char* kDiskInside = "glass_rough_disk_inside.json";

// Light sampling alone, which the suite leaves out of this scene (42 of 256
// pixels too skewed for the pixel t-test at 4096 spp; the other strategies
// are suite cases, strategy_verification_test.cpp), passes with no NaN sample
// and no pixel failure. On a disk light_solid_angle samples by area, so one
// of the two suffices.
TEST(GlassDiskInside, LightSamplingPasses) {
  for (Strategy s : {Strategy::kLightArea}) {
    const Verdict v = run_builtin_case(kDiskInside, s, Defect::kNone);
    std::printf("[ glass ] %s, %s: z %.3g, detectable bias %.3g, %d of %d pixels untested\n", kDiskInside,
                strategy_name(s).c_str(), v.z, v.detectable_rel_bias, v.pixels_untested, v.pixels);
    EXPECT_EQ(v.nonfinite_samples, 0u) << strategy_name(s);
    EXPECT_EQ(v.pixel_failures, 0) << strategy_name(s);
    EXPECT_TRUE(v.pass) << strategy_name(s);
  }
}

// f and pdf of the transmission both without η²: every strategy that
// evaluates f at a direction the BSDF did not draw fails; BSDF sampling,
// whose weight f·cos/pdf is unchanged, passes (the prediction).
TEST(GlassDiskInside, TransmissionWithoutEta2FailsLightSamplingAndMisNotBsdf) {
  for (Strategy s : {Strategy::kLightArea, Strategy::kMisBalance, Strategy::kMisOneSample, Strategy::kPathMis}) {
    const Verdict v = run_builtin_case(kDiskInside, s, Defect::kDielectricTransmissionWithoutEta2);
    std::printf("[ glass ] %s, %s, dielectric_transmission_without_eta2: z %.3g\n", kDiskInside,
                strategy_name(s).c_str(), v.z);
    EXPECT_FALSE(v.pass) << strategy_name(s);
  }
  for (Strategy s : {Strategy::kBsdf, Strategy::kPathNaive}) {
    const Verdict v = run_builtin_case(kDiskInside, s, Defect::kDielectricTransmissionWithoutEta2);
    std::printf("[ glass ] %s, %s, dielectric_transmission_without_eta2: z %.3g\n", kDiskInside,
                strategy_name(s).c_str(), v.z);
    EXPECT_TRUE(v.pass) << strategy_name(s);
  }
}

// The radiance convention's 1/η′² dropped: all the light here crosses the
// interface once, so every strategy sees the image 2.25 times too bright.
TEST(GlassDiskInside, NoRadianceScalingFails) {
  for (Strategy s : {Strategy::kBsdf, Strategy::kLightArea}) {
    const Verdict v = run_builtin_case(kDiskInside, s, Defect::kDielectricNoRadianceScaling);
    std::printf("[ glass ] %s, %s, dielectric_no_radiance_scaling: z %.3g\n", kDiskInside, strategy_name(s).c_str(),
                v.z);
    EXPECT_FALSE(v.pass) << strategy_name(s);
  }
}

// A sky on one side (scenes/sky_above.exr: 1 above the horizon, 0 below;
// analytic/glass.h): from above at 60° the glass shows the sky by reflection
// alone, from below at 30° by transmission alone. The smooth strip (pixel
// columns 0–3 from above; 12–15 from below, whose camera's right is −x) by hand: R at cos θ 0.5 and η 1.5 from above; s·(1 − R) at
// cos θ √3/2 and η 1/1.5 from below, s = 2.25 in the radiance convention and
// 1 in none. Negative controls: maps that are not constant on each
// hemisphere, a glass plane that is not z = const and the sphere under a map
// are refused with their reason.
TEST(GlassSky, EachLobeSeesItsOwnSide) {
  const Scene above = load_scene(std::string(FURNACE_SCENE_DIR) + "/glass_sky_outside_60.json");
  const Scene below = load_scene(std::string(FURNACE_SCENE_DIR) + "/glass_sky_inside_30.json");
  const int width = above.camera.width_px;
  for (TransportConvention convention : {TransportConvention::kRadiance, TransportConvention::kNone}) {
    const std::vector<double> from_above =
        analytic::glass_reference_image(above, kUnlimitedDepth, convention, /*direct_only=*/false);
    const std::vector<double> from_below =
        analytic::glass_reference_image(below, kUnlimitedDepth, convention, /*direct_only=*/false);
    const double r_above = fresnel_dielectric(0.5, 1.5);
    const double s = convention == TransportConvention::kRadiance ? 1.5 * 1.5 : 1.0;
    const double t_below = s * (1 - fresnel_dielectric(std::sqrt(3.0) / 2, 1 / 1.5));
    for (int y = 0; y < above.camera.height_px; ++y)
      for (int x = 0; x < 4; ++x) {
        EXPECT_NEAR(from_above[size_t(y * width + x)], r_above, 1e-15) << x << ", " << y;
        EXPECT_NEAR(from_below[size_t(y * width + 15 - x)], t_below, 4e-15) << x << ", " << y;
      }
    // The α = 1 strip (columns 12–15 from above, 0–3 from below): each lobe's
    // directional albedo alone.
    const Dielectric& rough = *above.objects[3].material.as<Dielectric>();
    const double e_r = analytic::dielectric_interface_albedo(rough, 1.5, 0.5, convention).reflection;
    EXPECT_NEAR(from_above[size_t(14)], e_r, 1e-15);
    const double e_t =
        analytic::dielectric_interface_albedo(rough, 1 / 1.5, std::sqrt(3.0) / 2, convention).transmission;
    EXPECT_NEAR(from_below[size_t(1)], s * e_t, 1e-14);
  }
  const auto refusal = [](Scene scene, const char* map_file) {
    scene.environment.map = std::make_shared<LatLongMap>(load_latlong_exr(std::string(FURNACE_SCENE_DIR) + "/" +
                                                                          map_file));
    scene.environment.map_file = map_file;
    return analytic::glass_scene_refusal(scene).value_or("");
  };
  EXPECT_EQ(refusal(above, "sky_above.exr"), "");
  EXPECT_NE(refusal(above, "environment_map.exr").find("not constant on each hemisphere"), std::string::npos);
  Scene tilted = above;
  for (Object& o : tilted.objects) std::get<Rectangle>(o.shape).edge_v = {0, 8, 0.1};
  EXPECT_NE(refusal(tilted, "sky_above.exr").find("not z = const"), std::string::npos);
  const Scene sphere = load_scene(std::string(FURNACE_SCENE_DIR) + "/glass_sphere.json");
  EXPECT_NE(refusal(sphere, "sky_above.exr").find("is a map"), std::string::npos);
}

TEST(GlassDefect, NoneChangesALambertianOrFresnelFreeGgxScene) {
  for (const char* file : {"three_lights.json", "ggx_oblique_sphere_60.json"}) {
    const Scene scene = load_scene(std::string(FURNACE_SCENE_DIR) + "/" + file);
    RenderOptions options;
    options.strategy = Strategy::kMisPower;
    options.spp = 16;
    options.seed = kSeed;
    const Image right = render(scene, options);
    for (Defect d : {Defect::kDielectricTransmissionWithoutEta2, Defect::kDielectricReflectionJacobian,
                     Defect::kDielectricNoRadianceScaling, Defect::kDielectricMacroFresnel,
                     Defect::kDielectricTirAbsorbs, Defect::kDielectricEtaNotInverted,
                     Defect::kConductorFresnelApproximate}) {
      options.defect = d;
      const Image wrong = render(scene, options);
      EXPECT_EQ(test::differing_pixels(right, wrong), 0u) << file << " " << defect_name(d);
    }
  }
}

}  // namespace
}  // namespace furnace::verify
