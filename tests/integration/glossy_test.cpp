// The glossy receiver's negative control end to end: DEFECT(phong_wrong_normalisation)
// (Phong eval normalised by (n+1)/(2π) instead of (n+2)/(2π), a bias of
// −1/(n+2): −8.3 % at n = 10, −0.98 % at n = 100) fails the harness's tests on
// the glossy scenes, and leaves every Lambertian scene bit for bit unchanged
// (no old scene has a Phong surface, so the old suite cannot see it).
// The correct glossy cases are in the default suite (strategy_verification_test.cpp).
//
// Budget and levels (tests/integration/builtin_case.h): each case renders
// 16×16 pixels at kSpp samples per pixel with the fixed seed kSeed; its 256
// pixel tests, image-mean test and variance test share kCaseAlpha by the
// Šidák correction (verify/harness.cpp). The controls' verdicts print their z and detectable bias.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "renderer/render.h"
#include "tests/integration/builtin_case.h"
#include "verify/harness.h"

namespace furnace::verify {
namespace {

using test::kCaseAlpha;
using test::kSeed;
using test::kSpp;
using test::run_builtin_case;

TEST(GlossyControl, WrongNormalisationFailsUnderTheSky) {
  const Verdict v = run_builtin_case("glossy_environment.json", Strategy::kBsdf, Defect::kPhongWrongNormalisation);
  EXPECT_FALSE(v.pass) << "a Phong lobe normalised by (n+1)/(2π) passed: no power against it";
  EXPECT_GT(std::fabs(v.z), v.threshold);
}

TEST(GlossyControl, WrongNormalisationFailsUnderTheSphereLight) {
  const Verdict v = run_builtin_case("glossy_sphere_light.json", Strategy::kMisPower, Defect::kPhongWrongNormalisation);
  EXPECT_FALSE(v.pass) << "a Phong lobe normalised by (n+1)/(2π) passed: no power against it";
  EXPECT_GT(std::fabs(v.z), v.threshold);
}

TEST(GlossyControl, WrongNormalisationLeavesLambertianScenesUnchanged) {
  // Why the old suite passes under this defect: its images are bit-identical.
  const Scene scene = load_scene(std::string(FURNACE_SCENE_DIR) + "/sphere_light.json");
  RenderOptions options;
  options.strategy = Strategy::kMisPower;
  options.spp = 64;
  options.seed = kSeed;
  const Image right = render(scene, options);
  options.defect = Defect::kPhongWrongNormalisation;
  const Image wrong = render(scene, options);
  ASSERT_EQ(right.pixels.size(), wrong.pixels.size());
  for (size_t i = 0; i < right.pixels.size(); ++i) {
    EXPECT_EQ(right.pixels[i].mean, wrong.pixels[i].mean) << "pixel " << i;
    EXPECT_EQ(right.pixels[i].sample_variance(), wrong.pixels[i].sample_variance()) << "pixel " << i;
  }
}

}  // namespace
}  // namespace furnace::verify
