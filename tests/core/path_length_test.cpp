// core/path_length.h: the infinite-answer rule, the bound on a path tracer's
// expected segments, the refusals and the statement.
#include "core/path_length.h"

#include <cmath>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "core/error.h"
#include "core/scene.h"
#include "core/strategy.h"

namespace furnace {
namespace {

constexpr int kRoulette = 3;  // RenderOptions' default roulette depth
constexpr double kInf = std::numeric_limits<double>::infinity();

// enclosure_sphere's shell: a closed, two-sided, emitting Lambertian sphere.
Scene enclosure(double albedo, bool closed = true, BsdfType type = BsdfType::kLambertian) {
  Scene s;
  s.name = "shell_scene";
  s.source = "scenes/shell.json";
  s.closed = closed;
  Object o;
  o.name = "shell";
  o.shape = Sphere{{0, 0, 0}, 1.0};
  o.material = Material{albedo, default_parameters(type)};
  if (type == BsdfType::kGgx) o.material.bsdf = Ggx{0.5, MicrofacetShadowing::kHeightCorrelated, std::nullopt};
  if (type == BsdfType::kPhong) o.material.bsdf = Phong{10};
  o.emitted_radiance = 1.5;
  o.two_sided = true;
  s.objects.push_back(o);
  return s;
}

std::string refusal(const Scene& s, int max_segments, int roulette) {
  try {
    require_bounded_paths(s, max_segments, roulette);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(InfiniteAnswer, ClosedAlbedoOneEnclosureAtUnlimitedDepth) {
  EXPECT_TRUE(infinite_answer_reason(enclosure(1), kUnlimitedDepth));
  // A mirror keeps all the light too.
  Scene mirrored = enclosure(1);
  Object m = mirrored.objects[0];
  m.name = "mirror";
  m.material.bsdf = Mirror{};
  m.emitted_radiance = 0;
  mirrored.objects.push_back(m);
  EXPECT_TRUE(infinite_answer_reason(mirrored, kUnlimitedDepth));
}

TEST(InfiniteAnswer, FiniteCasesAreNotRefusedAsInfinite) {
  EXPECT_FALSE(infinite_answer_reason(enclosure(1), 1000));                 // finite depth
  EXPECT_FALSE(infinite_answer_reason(enclosure(1 - 1e-9), kUnlimitedDepth));  // Le/(1−ρ), finite
  EXPECT_FALSE(infinite_answer_reason(enclosure(1, false), kUnlimitedDepth));  // open: light escapes
  // Phong and single-scattering GGX lose energy at every bounce: finite.
  EXPECT_FALSE(infinite_answer_reason(enclosure(1, true, BsdfType::kPhong), kUnlimitedDepth));
  EXPECT_FALSE(infinite_answer_reason(enclosure(1, true, BsdfType::kGgx), kUnlimitedDepth));
  // Nothing emits: the answer is 0.
  Scene dark = enclosure(1);
  dark.objects[0].emitted_radiance = 0;
  EXPECT_FALSE(infinite_answer_reason(dark, kUnlimitedDepth));
  // One absorbing object is enough.
  Scene absorbing = enclosure(1);
  Object blocker = absorbing.objects[0];
  blocker.name = "blocker";
  blocker.shape = Sphere{{0, 0, 0}, 0.1};
  blocker.material.albedo = 0.5;
  absorbing.objects.push_back(blocker);
  EXPECT_FALSE(infinite_answer_reason(absorbing, kUnlimitedDepth));
}

TEST(PathLengthBound, IsRouletteDepthPlusRhoOverOneMinusRho) {
  EXPECT_DOUBLE_EQ(expected_path_segments_bound(enclosure(0.8), kUnlimitedDepth, kRoulette), 3 + 0.8 / 0.2);
  EXPECT_DOUBLE_EQ(expected_path_segments_bound(enclosure(0.99), kUnlimitedDepth, 5), 5 + 0.99 / (1 - 0.99));
  EXPECT_DOUBLE_EQ(expected_path_segments_bound(enclosure(0), kUnlimitedDepth, kRoulette), 3);
  // The depth limit caps it.
  EXPECT_DOUBLE_EQ(expected_path_segments_bound(enclosure(0.99), 10, kRoulette), 10);
  EXPECT_DOUBLE_EQ(expected_path_segments_bound(enclosure(1), 10, kRoulette), 10);
  // Albedo 1, or a roulette that never starts, at unlimited depth: no bound.
  EXPECT_EQ(expected_path_segments_bound(enclosure(1), kUnlimitedDepth, kRoulette), kInf);
  EXPECT_EQ(expected_path_segments_bound(enclosure(0.5), kUnlimitedDepth, kUnlimitedDepth), kInf);
  EXPECT_DOUBLE_EQ(expected_path_segments_bound(enclosure(0.5), 7, 7), 7);
}

TEST(RequireBoundedPaths, RefusesInfiniteAnswersNamingTheFile) {
  const std::string e = refusal(enclosure(1), kUnlimitedDepth, kRoulette);
  EXPECT_NE(e.find("scenes/shell.json"), std::string::npos) << e;
  EXPECT_NE(e.find("infinite radiance"), std::string::npos) << e;
  EXPECT_NE(e.find("--max-depth"), std::string::npos) << e;
  EXPECT_EQ(refusal(enclosure(1), 100, kRoulette), "");
}

TEST(RequireBoundedPaths, RefusesClosedScenesPastTheBoundNamingTheObject) {
  // The bound at ρ: 3 + ρ/(1−ρ); kMaxExpectedPathSegments = 1e5 falls
  // between 1 − 1e-4 (1.0e4) and 1 − 1e-5 (1.0e5 + 2).
  for (const double rho : {1 - 1e-5, 1 - 1e-6, 1 - 1e-9}) {
    const std::string e = refusal(enclosure(rho), kUnlimitedDepth, kRoulette);
    EXPECT_NE(e.find("'shell'"), std::string::npos) << rho << ": " << e;
    EXPECT_NE(e.find("scenes/shell.json"), std::string::npos) << rho << ": " << e;
  }
  for (const double rho : {0.0, 0.5, 0.99, 1 - 1e-4}) EXPECT_EQ(refusal(enclosure(rho), kUnlimitedDepth, kRoulette), "");
  // Glossy albedo 1 in a closed scene: finite answer, but no bound.
  EXPECT_NE(refusal(enclosure(1, true, BsdfType::kGgx), kUnlimitedDepth, kRoulette), "");
  // No roulette at unlimited depth: no closed-scene path ever ends.
  const std::string e = refusal(enclosure(0.5), kUnlimitedDepth, kUnlimitedDepth);
  EXPECT_NE(e.find("roulette"), std::string::npos) << e;
  // Open scenes are rendered (paths escape), with a cap on each path.
  EXPECT_EQ(refusal(enclosure(1, false), kUnlimitedDepth, kRoulette), "");
  EXPECT_TRUE(needs_path_segment_cap(enclosure(1, false), kUnlimitedDepth, kRoulette));
  EXPECT_FALSE(needs_path_segment_cap(enclosure(0.99, false), kUnlimitedDepth, kRoulette));
  EXPECT_FALSE(needs_path_segment_cap(enclosure(1, false), 1000, kRoulette));
}

TEST(PathLengthStatement, StatedPastAThousandSegments) {
  EXPECT_FALSE(path_length_statement(enclosure(0.99), kUnlimitedDepth, kRoulette));  // 102
  const auto long_paths = path_length_statement(enclosure(0.9999), kUnlimitedDepth, kRoulette);
  ASSERT_TRUE(long_paths);
  EXPECT_NE(long_paths->find("1e+04"), std::string::npos) << *long_paths;
  const auto unbounded = path_length_statement(enclosure(1, false), kUnlimitedDepth, kRoulette);
  ASSERT_TRUE(unbounded);
  EXPECT_NE(unbounded->find(std::to_string(kOpenScenePathSegmentCap)), std::string::npos) << *unbounded;
}

}  // namespace
}  // namespace furnace
