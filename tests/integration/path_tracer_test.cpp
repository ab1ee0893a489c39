// The path tracers against the closed-form global-illumination answers
// (analytic/global.h): negative controls that must fail, Russian roulette on
// against off, enclosure variants (sphere shell, box with emitting interior
// blockers, several albedos ρ), and a NaN/Inf census over every scene.
//
// Levels: each run_case() call spends kCaseAlpha (Šidák within the case over
// its pixel tests and its image-mean test, verify/harness.cpp); each Welch
// comparison spends kComparisonAlpha. Fixed named seed: deterministic.
// Every test prints its verdict rows (format_table): z, the critical value
// and `detect`, the smallest relative bias of the image mean it finds with
// power kReportedPower.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <ostream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "analytic/global.h"
#include "renderer/render.h"
#include "tests/test_names.h"
#include "verify/harness.h"
#include "verify/verdict_table.h"
#include "stats/statistics.h"

namespace furnace::verify {
namespace {

using testing_support::camel_case;

constexpr uint64_t kSeed = 0x9a7e2026;  // fixed: a pass today fails only when the code changes
constexpr double kCaseAlpha = 1e-3;
constexpr double kComparisonAlpha = 1e-3;
constexpr int kUnlimited = kUnlimitedDepth;
// Scenes are 16×16 = 256 pixels; 256 spp gives 65,536 paths per image, so the
// image-mean test resolves relative biases of about 1–2 % (printed per case).
constexpr int kSpp = 256;
// The image-mean test of every correct case must resolve at least this
// relative bias, or its pass proves little. The weakest control below
// (double counting on the box) moves the mean by far more than this.
constexpr double kRequiredDetectableBias = 0.05;
// Never roulette: roulette starts at this depth, beyond every max_depth used with it.
constexpr int kNoRoulette = std::numeric_limits<int>::max();

std::string scene(const std::string& name) { return std::string(FURNACE_SCENE_DIR) + "/" + name + ".json"; }

Case make_case(const std::string& name, Strategy s, int max_depth, int roulette_depth, Defect d = Defect::kNone,
               int spp = kSpp) {
  Case c;
  c.scene_path = scene(name);
  c.options.strategy = s;
  c.options.defect = d;
  c.options.spp = spp;
  c.options.seed = kSeed;
  c.options.max_depth = max_depth;
  c.options.roulette_depth = roulette_depth;
  return c;
}

Verdict run_and_print(const Case& c) {
  const Verdict v = run_case(c, kCaseAlpha);
  std::printf("roulette_depth %s\n%s",
              c.options.roulette_depth == kNoRoulette ? "off" : std::to_string(c.options.roulette_depth).c_str(),
              format_table({v}, kCaseAlpha).c_str());
  testing::Test::RecordProperty("z", std::to_string(v.z));
  testing::Test::RecordProperty("detectable_relative_bias", std::to_string(v.detectable_rel_bias));
  return v;
}

// A zero-variance case: path_naive without roulette in a uniform enclosure
// (every bounce multiplies the throughput by exactly ρ and every vertex sees
// Le, so every path returns Le·Σ_{j<d} ρ^j). Its image-mean "standard error"
// is float round-off (~1e-17), and verify::run_case's image-mean z-test then
// fails on the last-bit difference between the renderer's running sum and
// the closed form's expm1 (z ≈ −1106 for a difference of 1e-16 relative).
// Here such a case must instead match exactly within
// stats::kZeroVarianceRelTolerance, as the harness requires of its
// zero-variance pixels.
bool zero_variance(const Verdict& v) { return v.detectable_rel_bias < stats::kZeroVarianceRelTolerance; }

void expect_pass(const Verdict& v) {
  EXPECT_EQ(v.nonfinite_samples, 0u);
  EXPECT_EQ(v.pixel_failures, 0) << "worst |t| " << v.worst_pixel_t << " at (" << v.worst_px << ", " << v.worst_py
                                 << ")";
  if (zero_variance(v)) {
    EXPECT_LE(std::fabs(v.image_mean - v.reference_mean), stats::kZeroVarianceRelTolerance * v.reference_mean);
    return;
  }
  EXPECT_LT(std::fabs(v.z), v.threshold);
  EXPECT_TRUE(v.pass);
  EXPECT_LT(v.detectable_rel_bias, kRequiredDetectableBias) << "the test has too little power to mean anything";
}

// ---------------------------------------------------------------------------
// Negative controls. Expected effects (Le = 1, ρ = 0.9, unlimited depth, so
// the truth is Le/(1−ρ) = 10):
//  - roulette_no_reweight with roulette from depth 1: survival min(1, ρ^j)
//    after j bounces is never undone, so vertex j contributes
//    Le·ρ^j·Π_{i≤j} ρ^i = Le·ρ^(j + j(j+1)/2); the series sums to ≈ 3.2, a
//    relative bias of ≈ −68 %;
//  - double_count_emission on path_mis: every emission found by the BSDF
//    continuation gets weight 1 although the light sample already counts its
//    share, so the mean exceeds the truth by the light strategy's MIS share
//    (measured at kSpp: +30 % on the box, z ≈ 63; +99 % on disk_occluder,
//    whose reference is direct light only, z ≈ 117).
// Measured for roulette_no_reweight: 3.24 (path_naive) and 3.46 (path_mis)
// against 10, z ≈ −1285 and −1233. The clean twins' image-mean tests detect
// ≈ 2.1 % (box) and 0.7 % (disk_occluder) with power 0.9.
// The clean twins of the same cases must pass with detectable bias
// < kRequiredDetectableBias, far below those effects.

struct ControlCase {
  const char* name;
  const char* scene;
  Strategy strategy;
  Defect defect;
  int roulette_depth;
};

void PrintTo(const ControlCase& c, std::ostream* os) { *os << c.name; }

class PathControl : public testing::TestWithParam<ControlCase> {};

TEST_P(PathControl, DefectFailsAndCleanTwinPasses) {
  const ControlCase& p = GetParam();
  const Verdict clean = run_and_print(make_case(p.scene, p.strategy, kUnlimited, p.roulette_depth));
  expect_pass(clean);
  const Verdict wrong = run_and_print(make_case(p.scene, p.strategy, kUnlimited, p.roulette_depth, p.defect));
  EXPECT_FALSE(wrong.pass) << "a deliberately wrong path tracer passed: the test has no power against it";
  EXPECT_GT(std::fabs(wrong.z), wrong.threshold);
}

INSTANTIATE_TEST_SUITE_P(
    Path, PathControl,
    testing::Values(
        ControlCase{"RouletteNoReweightNaiveBox", "enclosure_box", Strategy::kPathNaive, Defect::kRouletteNoReweight, 1},
        ControlCase{"RouletteNoReweightMisBox", "enclosure_box", Strategy::kPathMis, Defect::kRouletteNoReweight, 1},
        ControlCase{"DoubleCountEmissionBox", "enclosure_box", Strategy::kPathMis, Defect::kDoubleCountEmission, 3},
        ControlCase{"DoubleCountEmissionDiskOccluder", "disk_occluder", Strategy::kPathMis,
                    Defect::kDoubleCountEmission, 3}),
    [](const testing::TestParamInfo<ControlCase>& info) { return std::string(info.param.name); });

// ---------------------------------------------------------------------------
// Russian roulette on (from depth 1) against off, at max_depth d: the two
// estimators have the same mean Le(1−ρ^d)/(1−ρ). Welch's t on the image
// means (pixels × spp samples of a uniform-radiance image, whose pixels share
// one distribution, so the image mean's variance is the mean pixel s² over
// P·N), and each against the closed form by run_case.

stats::SampleSummary image_summary(const Image& image) {
  double sum_mean = 0, sum_s2 = 0;
  uint64_t count = 0;
  for (const PixelMoments& m : image.pixels) {
    sum_mean += m.mean;
    sum_s2 += m.sample_variance();
    count += m.count;
  }
  const double p = double(image.pixels.size());
  return {count, sum_mean / p, sum_s2 / p};
}

struct RouletteCase {
  const char* scene;
  int max_depth;
};

void PrintTo(const RouletteCase& c, std::ostream* os) { *os << c.scene << " depth " << c.max_depth; }

class RouletteAgreement : public testing::TestWithParam<RouletteCase> {};

TEST_P(RouletteAgreement, OnAndOffAgreeWithEachOtherAndTheClosedForm) {
  const RouletteCase& p = GetParam();
  const Case on = make_case(p.scene, Strategy::kPathNaive, p.max_depth, 1);
  const Case off = make_case(p.scene, Strategy::kPathNaive, p.max_depth, kNoRoulette);
  const Scene s = load_scene(on.scene_path);
  const stats::SampleSummary a = image_summary(render(s, on.options));
  const stats::SampleSummary b = image_summary(render(s, off.options));
  const stats::ComparisonTestResult w = stats::comparison_test(a, b, kComparisonAlpha);
  std::printf("%s depth %d: roulette on %.6g (s² %.4g), off %.6g (s² %.4g); Welch t %.3f, crit %.2f, "
              "detectable relative difference %.3g%% at power %.2f\n",
              p.scene, p.max_depth, a.mean, a.sample_variance, b.mean, b.sample_variance, w.statistic, w.threshold,
              100 * w.detectable_relative_difference, stats::kDefaultPower);
  RecordProperty("welch_t", std::to_string(w.statistic));
  EXPECT_TRUE(w.pass) << w.message;
  // Depth 1 is emission only: both are exactly Le, nothing to resolve.
  if (p.max_depth > 1) {
    EXPECT_LT(w.detectable_relative_difference, kRequiredDetectableBias);
  }
  expect_pass(run_and_print(on));
  expect_pass(run_and_print(off));
}

INSTANTIATE_TEST_SUITE_P(
    EnclosureBox, RouletteAgreement,
    testing::Values(RouletteCase{"enclosure_box", 1}, RouletteCase{"enclosure_box", 2},
                    RouletteCase{"enclosure_box", 4}, RouletteCase{"enclosure_box", 8},
                    RouletteCase{"enclosure_box_rho5", 1}, RouletteCase{"enclosure_box_rho5", 2},
                    RouletteCase{"enclosure_box_rho5", 4}, RouletteCase{"enclosure_box_rho5", 8},
                    RouletteCase{"enclosure_box_rho99", 1}, RouletteCase{"enclosure_box_rho99", 2},
                    RouletteCase{"enclosure_box_rho99", 4}, RouletteCase{"enclosure_box_rho99", 8}),
    [](const testing::TestParamInfo<RouletteCase>& info) {
      return camel_case(info.param.scene) + "Depth" + std::to_string(info.param.max_depth);
    });

// ---------------------------------------------------------------------------
// Enclosure variants at unlimited depth and at a short depth, both path
// tracers: sphere shell (camera inside, two-sided emitter), box with
// two-sided emitting interior blockers, and the box at ρ = 0.5 and 0.99.
// ρ = 0.99 at unlimited depth: mean 100·Le and paths of ~100 segments; the
// estimate per path is ~Le·(number of vertices), relative spread ~1, so
// kSpp still resolves a few percent (printed).

struct EnclosureCase {
  const char* scene;
  Strategy strategy;
  int max_depth;
  int spp = kSpp;
};
// ρ = 0.99 at unlimited depth with path_mis: ~100 vertices, each with a
// light sample and an MIS density query over 6 walls, per path; 96 spp keeps
// the case near 3 s on two loaded cores and still resolves ≈ 4 % (printed;
// 2.3 % at 256 spp).
constexpr int kRho99MisSpp = 96;

void PrintTo(const EnclosureCase& c, std::ostream* os) {
  *os << c.scene << " " << strategy_name(c.strategy) << " depth " << c.max_depth << " spp " << c.spp;
}

class Enclosure : public testing::TestWithParam<EnclosureCase> {};

TEST_P(Enclosure, MatchesUniformClosedForm) {
  const EnclosureCase& p = GetParam();
  const Scene s = load_scene(scene(p.scene));
  // The reference must be the uniform enclosure's Le(1−ρ^d)/(1−ρ) everywhere.
  const std::vector<double> reference = analytic::global_reference_image(s, p.max_depth);
  const double expected =
      analytic::uniform_enclosure_radiance(s.objects[0].emitted_radiance, s.objects[0].material.albedo, p.max_depth);
  for (double r : reference) ASSERT_EQ(r, expected);
  expect_pass(run_and_print(make_case(p.scene, p.strategy, p.max_depth, 3, Defect::kNone, p.spp)));
}

INSTANTIATE_TEST_SUITE_P(
    Variants, Enclosure,
    testing::Values(EnclosureCase{"enclosure_sphere", Strategy::kPathNaive, kUnlimited},
                    EnclosureCase{"enclosure_sphere", Strategy::kPathMis, kUnlimited},
                    EnclosureCase{"enclosure_sphere", Strategy::kPathMis, 3},
                    EnclosureCase{"enclosure_blockers", Strategy::kPathNaive, kUnlimited},
                    EnclosureCase{"enclosure_blockers", Strategy::kPathMis, kUnlimited},
                    EnclosureCase{"enclosure_blockers", Strategy::kPathNaive, 3},
                    EnclosureCase{"enclosure_box_rho5", Strategy::kPathMis, kUnlimited},
                    EnclosureCase{"enclosure_box_rho99", Strategy::kPathNaive, kUnlimited},
                    EnclosureCase{"enclosure_box_rho99", Strategy::kPathMis, kUnlimited, kRho99MisSpp}),
    [](const testing::TestParamInfo<EnclosureCase>& info) {
      const EnclosureCase& c = info.param;
      return camel_case(c.scene) + camel_case(strategy_name(c.strategy)) +
             (c.max_depth == kUnlimited ? std::string("Unlimited") : "Depth" + std::to_string(c.max_depth));
    });

// ---------------------------------------------------------------------------
// Error tier 3: no path of either tracer yields NaN or Inf on any scene of
// scenes/ (built-in and variants), at a modest budget with the default
// depth and roulette options.
constexpr int kCensusSpp = 16;

TEST(PathTracerNonfinite, NoNonfiniteSamplesOnAnyScene) {
  int scenes = 0;
  for (const auto& entry : std::filesystem::directory_iterator(FURNACE_SCENE_DIR)) {
    if (entry.path().extension() != ".json") continue;
    const Scene s = load_scene(entry.path());
    ++scenes;
    for (Strategy strategy : path_tracing_strategies()) {
      // render() refuses a strategy blind to the scene's point lights (tested in point_light_test.cpp).
      if (!s.point_lights.empty() && !strategy_sees_delta_lights(strategy)) continue;
      RenderOptions o;
      o.strategy = strategy;
      o.spp = kCensusSpp;
      o.seed = kSeed;
      const Image image = render(s, o);
      std::printf("%-22s %-10s %8.3f s  nonfinite %llu\n", s.name.c_str(), strategy_name(strategy).c_str(),
                  image.seconds, static_cast<unsigned long long>(image.nonfinite_samples));
      EXPECT_EQ(image.nonfinite_samples, 0u) << entry.path() << " " << strategy_name(strategy);
    }
  }
  EXPECT_GE(scenes, 9);
}

}  // namespace
}  // namespace furnace::verify
