// The Blender Cycles peer test: Cycles renders every built-in scene the
// exporter can express, K times with distinct seeds (one Blender process per
// scene), and `furnace check` must pass each (exit 0); what furnace found in
// Cycles is kept as expected failures that must keep failing (a Blender that
// fixes them shows up as an unexpected pass); deliberately wrong exports
// rendered the same way must fail (exit 1), proving the check can tell. The
// scenes too costly for the peer label's budget are tested by a second build
// of this file (label slow). Finds Blender as blender_binary() says; without
// one every test reports "skipped: no Blender (set FURNACE_BLENDER; tried …)"
// and none fails.
//
// Each test prints one line: scene, K, spp, check's exit code, the worst
// per-pixel |t| and the image-mean t, the image-mean bias the check detects
// (from its output), and the test's wall time.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "analytic/global.h"
#include "core/exr.h"
#include "core/scene.h"
#include "tests/command.h"
#include "tests/export/peer_support.h"
#include "export/cycles.h"
#include "export/pbrt_v4.h"

namespace furnace::exporter {
namespace {

namespace fs = std::filesystem;

// Renders per scene and samples per pixel: with them the image-mean bias the
// check detects stays below 0.7 % on every exportable built-in scene
// (measured; the check reports it), inside the 1 % a verdict requires.
constexpr int kRenders = 16;
constexpr int kSpp = 128;
// Seeds kFirstSeed .. kFirstSeed + kRenders − 1: Sobol-Burley is
// Owen-scrambled by the seed, so distinct seeds make independent renders.
constexpr int kFirstSeed = 1;
constexpr int kCyclesThreads = 2;

// Blender: FURNACE_BLENDER when set (used as given, so a wrong path fails
// loudly rather than skipping), else `blender` on PATH.
std::optional<fs::path> blender_binary() {
  const char* forced = std::getenv("FURNACE_BLENDER");
  if (forced && *forced) return fs::path(forced);
  return peer::find_on_path("blender");
}

std::string no_blender_message() {
  const char* path = std::getenv("PATH");
  return fmt::format("skipped: no Blender (set FURNACE_BLENDER; tried `blender` on PATH={})", path ? path : "");
}

using testing_support::CommandResult;

using peer::camel_case;
using peer::check_renders;
using peer::Diagnostics;
using peer::named;
using peer::quoted;
using peer::read_text;
using peer::run;
using peer::scene_file;

class CyclesPeer {
 protected:
  // Exports `scene_for_export` (its script edited by `edit_script`, if any),
  // renders it K times in one Blender process, checks the images against
  // `scene_file` at the depth a correct export of it needs, and returns
  // check's exit code.
  // The check runs in furnace's `none` convention (Cycles never divides
  // radiance by η′²; it matters only for glass) at the depth the export's
  // options render (check_max_depth), unless `convention` or `depth` say
  // otherwise (the controls).
  int render_and_check(const std::string& label, const fs::path& scene_file, const Scene& scene_for_export,
                       const CyclesOptions& options,
                       const std::function<std::string(const std::string&)>& edit_script = {},
                       int renders = kRenders, TransportConvention convention = TransportConvention::kNone,
                       std::optional<int> depth = std::nullopt) {
    const Scene scene = load_scene(scene_file);
    const int check_depth = depth.value_or(check_max_depth(scene, options.max_segments));
    const auto start = std::chrono::steady_clock::now();
    const fs::path script = dir_ / "scene.py";
    write_cycles(scene_for_export, options, script);
    if (edit_script) {
      const std::string edited = edit_script(read_text(script));
      std::ofstream(script) << edited;
    }
    const CommandResult r = run(fmt::format(
        "{} -b --factory-startup --python-exit-code 1 --python {} -- --seeds {}-{} --output {} --threads {}",
        quoted(*blender_), quoted(script), kFirstSeed, kFirstSeed + renders - 1,
        quoted(dir_ / "render_{seed}.exr"), kCyclesThreads));
    if (r.exit_code != 0) {
      ADD_FAILURE() << "Blender failed (exit " << r.exit_code << ") on " << script << ":\n" << r.output;
      return -1;
    }
    std::vector<fs::path> images;
    for (int i = 0; i < renders; ++i) images.push_back(dir_ / fmt::format("render_{}.exr", kFirstSeed + i));
    const peer::CheckRun check = check_renders(scene_file, check_depth, images, dir_ / "check.json", convention);
    last_ = check.numbers;
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("%s", check.output.c_str());
    std::printf("peer: cycles %s K=%d spp=%d check --max-depth %s --convention %s exit %d, worst pixel |t| %.2f, "
                "image-mean t %.2f (relative error %+.3g%%), detectable bias %.3g%%, wall %.1f s\n",
                label.c_str(), renders, options.spp, depth_name(check_depth).c_str(),
                transport_convention_name(convention).c_str(), check.exit_code,
                last_.worst_pixel_t, last_.image_mean_t, 100 * last_.image_mean_relative_error,
                100 * last_.detectable_relative_bias, seconds);
    return check.exit_code;
  }

  bool set_up(const std::string& name) {
    blender_ = blender_binary();
    if (!blender_) return false;
    dir_ = fs::temp_directory_path() / fmt::format("furnace_cycles_peer_{}_{}", ::getpid(), name);
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    return true;
  }
  void tear_down(bool passed) {
    if (dir_.empty()) return;
    if (passed) fs::remove_all(dir_);
    else std::printf("renders kept in %s\n", dir_.c_str());
  }

  std::optional<fs::path> blender_;
  fs::path dir_;
  Diagnostics last_;
};

// Scenes whose K renders alone would take most of the peer label's budget:
// enclosure_box_rho99's paths average 100 bounces, and its 16 renders of 128
// spp took 73 s on 2 threads (the rest of the label's scenes 3-10 s each).
// They run in cycles_peer_slow_tests (label slow), built from this file with
// FURNACE_PEER_COSTLY_SCENES=1.
const std::set<std::string> kCostlyScenes = {"enclosure_box_rho99"};

std::vector<std::string> exportable_scenes() {
  return peer::exportable_scenes([](const Scene& s) { return !cycles_refusal(s); }, kCostlyScenes,
                                 bool(FURNACE_PEER_COSTLY_SCENES));
}

class CyclesPeerScene : public CyclesPeer, public testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    if (!set_up(camel_case(GetParam()))) GTEST_SKIP() << no_blender_message();
  }
  void TearDown() override { tear_down(!HasFailure()); }
};

// What furnace finds in Cycles 3.4 with the export as it stands, each asserted
// to keep failing, so a change on either side is noticed; reported in
// docs/checking_cycles.md with its numbers.
const std::map<std::string, std::string> kKnownCyclesDefects = {
    {"near_contact",
     "Cycles 3.4 lets light reach receiver points under blockers 1e-5 and 1e-4 above them (black strips, a disk: "
     "up to 4.7x the reference; square lights that also hide part of the big light: |t| up to 279); image mean "
     "+5.5 %"},
    {"glass_sphere",
     "at unlimited depth the image mean agrees (t -0.36, detectable 0.013 %) but 9 of 256 pixels are 1e-4 to "
     "1.2e-3 too dark with a spread across the 16 seeds far below that: the same pixels with icospheres of 80 "
     "to 81 920 triangles, flat or smooth, 6 pixels with seeds 101-116, errors about 10 times smaller at 1024 "
     "spp, other pixels with progressive multi-jitter. An error falling as 1/spp and shared by every seed is "
     "what Cycles' sample 0, the same for every seed (docs/comparing.md), gives where one path's weight is far "
     "from the pixel's mean (1-spp samples here weigh 1.08 or 0.41)"},
    {"convex_furnace",
     "about 0.2 % of the camera samples of pixels crossed by the sphere's silhouette land anywhere in the pixel "
     "instead of within 0.01 px of its centre (the same with a flat 4096-gon, either filter or sampling pattern; "
     "none at straight edges): image mean -0.0012 %, t -5.39"},
};

TEST_P(CyclesPeerScene, PassesFurnaceCheck) {
  const fs::path file = scene_file(GetParam());
  CyclesOptions options;
  options.spp = kSpp;
  const auto known = kKnownCyclesDefects.find(GetParam());
  if (known != kKnownCyclesDefects.end()) {
    std::printf("known Cycles defect, expected to FAIL: %s\n", known->second.c_str());
    EXPECT_EQ(render_and_check(GetParam(), file, load_scene(file), options), 1);
    return;
  }
  EXPECT_EQ(render_and_check(GetParam(), file, load_scene(file), options), 0);
}

INSTANTIATE_TEST_SUITE_P(BuiltIn, CyclesPeerScene, testing::ValuesIn(exportable_scenes()),
                         [](const testing::TestParamInfo<std::string>& info) { return camel_case(info.param); });

#if !FURNACE_PEER_COSTLY_SCENES
// The oblique GGX scenes as Cycles 3.4 can render them: the built-in ones put
// a height-correlated strip beside each separable one (Cycles 3.4 has the
// separable form only: refused), so each peer scene is derived from a
// built-in one with every GGX surface separable (peer::derived_ggx_scene;
// albedo 0.8 kept: Color = albedo) and checked against its own exact
// reference. The normal-view GGX scenes (ggx_sky_strips, ggx_disk_occluder)
// are exportable as they are and run in CyclesPeerScene above.
std::vector<std::pair<std::string, std::string>> ggx_separable_scenes() {
  return {{"ggx_oblique_sky_60_sep", "ggx_oblique_sky_60"},
          {"ggx_oblique_sky_78_sep", "ggx_oblique_sky_78"},
          {"ggx_oblique_sphere_60_sep", "ggx_oblique_sphere_60"},
          {"ggx_oblique_sphere_78_sep", "ggx_oblique_sphere_78"}};
}

class CyclesPeerGgx : public CyclesPeer, public testing::TestWithParam<std::pair<std::string, std::string>> {
 protected:
  void SetUp() override {
    if (!set_up(camel_case(GetParam().first))) GTEST_SKIP() << no_blender_message();
  }
  void TearDown() override { tear_down(!HasFailure()); }
};

// What furnace finds in Cycles 3.4's GGX, asserted to keep failing
// (docs/findings.md): under a sky at oblique view the image is too dark by
// about 7e-5 (ggx_oblique_sky_60_sep: -7.0e-5, t -8.0 at 2048 spp; the
// BSDF-only renders of CyclesPeerGgxFinding below show it is the BSDF
// sampler's). At 128 spp that bias is below the check's resolution, so these
// scenes render 2048 spp.
const std::map<std::string, std::string> kKnownCyclesGgxDefects = {
    {"ggx_oblique_sky_60_sep", "Cycles 3.4's GGX under a sky at cos 0.5 renders about 7e-5 too dark"},
    {"ggx_oblique_sky_78_sep", "Cycles 3.4's GGX under a sky at cos 0.2 renders about 8e-5 too dark"},
};
constexpr int kGgxDefectSpp = 2048;

TEST_P(CyclesPeerGgx, PassesFurnaceCheck) {
  const auto& [name, builtin] = GetParam();
  const fs::path file = peer::derived_ggx_scene(builtin, name, dir_, "separable", std::nullopt);
  const Scene scene = load_scene(file);
  ASSERT_FALSE(cycles_refusal(scene)) << *cycles_refusal(scene);
  CyclesOptions options;
  options.spp = kSpp;
  const auto known = kKnownCyclesGgxDefects.find(name);
  if (known != kKnownCyclesGgxDefects.end()) {
    std::printf("known Cycles defect, expected to FAIL: %s\n", known->second.c_str());
    options.spp = kGgxDefectSpp;
    EXPECT_EQ(render_and_check(name, file, scene, options), 1);
    return;
  }
  EXPECT_EQ(render_and_check(name, file, scene, options), 0);
}

INSTANTIATE_TEST_SUITE_P(Derived, CyclesPeerGgx, testing::ValuesIn(ggx_separable_scenes()),
                         [](const testing::TestParamInfo<std::pair<std::string, std::string>>& info) {
                           return camel_case(info.param.first);
                         });

#endif

// The findings about Cycles 3.4's GGX (docs/findings.md), each with its
// asserted outcome, so that a Blender that changes shows up.
class CyclesPeerGgxFinding : public CyclesPeer, public testing::Test {
 protected:
  void SetUp() override {
    const std::string name = testing::UnitTest::GetInstance()->current_test_info()->name();
    if (!set_up("GgxFinding" + name)) GTEST_SKIP() << no_blender_message();
  }
  void TearDown() override { tear_down(!HasFailure()); }

  // The separable, albedo-1 variant of `builtin` under its sky with the
  // world not sampled as a light: the BSDF sampler alone carries the sky's
  // light. K = 16 renders of 8192 spp; returns check's exit code.
  int bsdf_only(const std::string& builtin) {
    const std::string name = builtin + "_sep_albedo1";
    const fs::path file = peer::derived_ggx_scene(builtin, name, dir_, "separable", 1.0);
    CyclesOptions options;
    options.spp = kBsdfOnlySpp;
    options.world_light_sampling = false;
    const Scene scene = load_scene(file);
    const int code = render_and_check(name + " (BSDF sampling only)", file, scene, options);
    std::printf("finding: %s, BSDF sampling only, K=%d spp=%d: image mean %+.3g relative (t %.2f), detectable "
                "bias %.3g\n",
                name.c_str(), kRenders, kBsdfOnlySpp, last_.image_mean_relative_error, last_.image_mean_t,
                last_.detectable_relative_bias);
    print_per_strip(scene);
    return code;
  }

  // Each strip's relative error and its t over the K renders: the scenes'
  // GGX strips are equal vertical bands across the image, left to right in
  // the order of the scene's objects (image right is +x in all three).
  void print_per_strip(const Scene& scene) {
    const std::vector<double> reference = analytic::global_reference_image(scene, kUnlimitedDepth);
    const int width = scene.camera.width_px, height = scene.camera.height_px;
    const int strips = int(scene.objects.size());
    std::vector<std::vector<double>> ratio(strips);  // per strip, per render: mean(image) / mean(reference)
    for (int i = 0; i < kRenders; ++i) {
      const exr::Image image = exr::read(dir_ / fmt::format("render_{}.exr", kFirstSeed + i), "Cycles render");
      std::vector<double> sum(strips, 0), ref(strips, 0);
      for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
          const size_t p = size_t(y) * width + x;
          const int k = x * strips / width;
          sum[k] += (double(image.floats.at("R")[p]) + image.floats.at("G")[p] + image.floats.at("B")[p]) / 3;
          ref[k] += reference[p];
        }
      for (int k = 0; k < strips; ++k) ratio[k].push_back(sum[k] / ref[k]);
    }
    for (int k = 0; k < strips; ++k) {
      double mean = 0, var = 0;
      for (double r : ratio[k]) mean += r / kRenders;
      for (double r : ratio[k]) var += (r - mean) * (r - mean) / (kRenders - 1);
      const double se = std::sqrt(var / kRenders);
      const Material& m = scene.objects[k].material;
      std::printf("finding: strip '%s' (alpha %g, %s): relative error %+.3g, t %.1f\n",
                  scene.objects[k].name.c_str(), std::get<Ggx>(m.bsdf).alpha,
                  microfacet_shadowing_name(std::get<Ggx>(m.bsdf).shadowing), mean - 1,
                  se > 0 ? (mean - 1) / se : 0.0);
    }
  }
  static constexpr int kBsdfOnlySpp = 8192;
};

#if FURNACE_PEER_COSTLY_SCENES
// Label slow (cycles_peer_slow_tests): 8192 spp renders, 19-29 s each.
// The oblique question: the BSDF sampler alone, at cos θo = 0.5 and 0.2, is
// measured too dark (-6.8e-5, t -36, and -7.7e-5, t -40; detectable 1.2e-5),
// the sign and size the approximate Heitz & d'Eon 2014 inverse CDF of Cycles
// 3.4 predicts (1e-5 to 4e-4).
TEST_F(CyclesPeerGgxFinding, ObliqueSkyBsdfSamplingIsBiasedAtCos05) { EXPECT_EQ(bsdf_only("ggx_oblique_sky_60"), 1); }
TEST_F(CyclesPeerGgxFinding, ObliqueSkyBsdfSamplingIsBiasedAtCos02) { EXPECT_EQ(bsdf_only("ggx_oblique_sky_78"), 1); }
// At normal view the same run finds a bias 8 times smaller and of the other
// sign (+0.9e-5, t 4.8, detectable 1.2e-5); with world light sampling on,
// the normal-view scene passes at 2048 spp (t 0.16).
TEST_F(CyclesPeerGgxFinding, NormalViewSkyBsdfSamplingIsBiasedByAbout1e5) {
  EXPECT_EQ(bsdf_only("ggx_sky_strips"), 1);
}

#else
// Energy conservation: Multiscatter GGX of Color ρ under a constant sky at
// normal view, the energy-conserving variant of the export, must reflect
// L = L_env·ρ. Checked against the same scene with Lambertian strips of
// albedo ρ (the same exact answer), and pixel by pixel: Cycles 3.4 renders
// every pixel of every render at L_env·ρ to float precision (its random walk
// gives every BSDF sample the weight ρ), so the deficit is 0, with no spread
// (furnace check needs a spread across images: it reports identical pixels
// as bad input, exit 2, when every pixel is constant).
TEST_F(CyclesPeerGgxFinding, MultiscatterGgxConservesEnergyExactlyUnderAConstantSky) {
  for (double albedo : {1.0, 0.8}) {
    const std::string name = fmt::format("ggx_sky_strips_albedo{}", albedo);
    const fs::path ggx = peer::derived_ggx_scene("ggx_sky_strips", name, dir_, std::nullopt, albedo);
    const fs::path lambertian =
        peer::derived_lambertian_scene("ggx_sky_strips", name + "_lambertian", dir_, albedo);
    const Scene scene = load_scene(ggx);
    CyclesOptions options;
    options.spp = 1024;
    options.energy_conserving_ggx = true;
    ASSERT_FALSE(cycles_refusal(scene, options)) << *cycles_refusal(scene, options);
    const int code = render_and_check("energy-conserving GGX " + name, lambertian, scene, options);
    EXPECT_NE(code, 1) << "furnace check found a deficit";
    double worst = 0;
    for (int i = 0; i < kRenders; ++i) {
      const exr::Image image = exr::read(dir_ / fmt::format("render_{}.exr", kFirstSeed + i), "Cycles render");
      for (const auto& [channel, values] : image.floats)
        if (channel == "R" || channel == "G" || channel == "B")
          for (float v : values) worst = std::max(worst, std::fabs(v / (scene.environment.radiance * albedo) - 1));
    }
    std::printf("finding: Multiscatter GGX, Color %g, K=%d spp=%d: largest |pixel / (L_env * albedo) - 1| %.3g\n",
                albedo, kRenders, options.spp, worst);
    // Cycles sums the spp samples of a pixel in float: rounding alone moves
    // the sum by up to spp·2⁻²⁴ relative (6.1e-5 at 1024 spp).
    EXPECT_LE(worst, options.spp * 0x1p-24);
  }
}
#endif

#if !FURNACE_PEER_COSTLY_SCENES
class CyclesPeerScript : public CyclesPeer, public testing::Test {
 protected:
  void SetUp() override {
    if (!set_up("Script")) GTEST_SKIP() << no_blender_message();
  }
  void TearDown() override { tear_down(!HasFailure()); }
};

// The script's own contract: bad arguments exit 2 with one line naming the
// argument, before anything is rendered or written.
TEST_F(CyclesPeerScript, BadArgumentsExitTwoAndWriteNothing) {
  const fs::path script = dir_ / "scene.py";
  write_cycles(load_scene(scene_file("rectangle_light")), {}, script);
  for (const std::string& args :
       {fmt::format("--seeds 5-1 --output {}", quoted(dir_ / "r_{seed}.exr")),
        fmt::format("--seeds 1-2 --output {}", quoted(dir_ / "r.exr")),
        fmt::format("--seed 1 --spp 0 --output {}", quoted(dir_ / "r.exr")),
        fmt::format("--seed 1 --output {}", quoted(dir_ / "missing" / "r.exr"))}) {
    const CommandResult r =
        run(fmt::format("{} -b --factory-startup --python-exit-code 1 --python {} -- {}", quoted(*blender_),
                        quoted(script), args));
    EXPECT_EQ(r.exit_code, 2) << args << ":\n" << r.output;
    EXPECT_NE(r.output.find("error: --"), std::string::npos) << args << ":\n" << r.output;
  }
  std::vector<std::string> left;
  for (const auto& e : fs::directory_iterator(dir_)) left.push_back(e.path().filename().string());
  EXPECT_EQ(left, std::vector<std::string>{"scene.py"});
}

// An export that is correct in every respect but one tessellation choice
// Cycles renders wrongly: expected to fail, its numbers printed.
struct Finding {
  std::string name;
  std::string scene;
  std::string what;
  std::function<void(CyclesOptions&)> choose;
};

void PrintTo(const Finding& f, std::ostream* os) { *os << f.name << " (" << f.scene << ")"; }

std::vector<Finding> findings() {
  return {
      {"RectangleLightAsTwoTriangles", "rectangle_light",
       "a rectangle light exported as its exact two triangles renders too dark (the 16x16 grid passes)",
       [](CyclesOptions& o) {
         o.emitter_grid = 1;
         o.spp = kSpp;
       }},
      {"SphereLight81920Triangles", "sphere_light",
       "a sphere light as an 81 920-triangle icosphere renders too dark at 512 spp",
       [](CyclesOptions& o) {
         o.sphere_subdivisions = 6;
         o.spp = 512;
       }},
  };
}

class CyclesPeerFinding : public CyclesPeer, public testing::TestWithParam<Finding> {
 protected:
  void SetUp() override {
    if (!set_up(GetParam().name)) GTEST_SKIP() << no_blender_message();
  }
  void TearDown() override { tear_down(!HasFailure()); }
};

TEST_P(CyclesPeerFinding, FailsFurnaceCheck) {
  const Finding& f = GetParam();
  const fs::path file = scene_file(f.scene);
  CyclesOptions options;
  f.choose(options);
  std::printf("known Cycles defect, expected to FAIL: %s\n", f.what.c_str());
  EXPECT_EQ(render_and_check(f.name + " (" + f.scene + ")", file, load_scene(file), options), 1);
  std::printf("finding: %s: image mean %+.3f %% (t %.2f), %d pixels fail, worst pixel |t| %.1f\n", f.name.c_str(),
              100 * last_.image_mean_relative_error, last_.image_mean_t, last_.failed_pixels, last_.worst_pixel_t);
}

INSTANTIATE_TEST_SUITE_P(Known, CyclesPeerFinding, testing::ValuesIn(findings()),
                         [](const testing::TestParamInfo<Finding>& info) { return info.param.name; });

// A deliberately wrong export: the scene as exported is altered, or its
// script, while the check compares with the unaltered scene.
struct Control {
  std::string name;
  std::string scene;
  std::function<void(Scene&)> break_scene;
  std::function<std::string(const std::string&)> break_script;
};

void PrintTo(const Control& c, std::ostream* os) { *os << c.name << " (" << c.scene << ")"; }

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  if (at == std::string::npos) throw std::runtime_error("the script has no '" + from + "'");
  return text.replace(at, from.size(), to);
}

std::vector<Control> controls() {
  return {
      {"LightRadiancePlusOnePercent", "disk_occluder",
       [](Scene& s) { named(s, "light").emitted_radiance *= 1.01; }, {}},
      // Every one-sided emitter of the scene emits from its back too, as
      // Cycles 3.4's Emission shader does without the Backfacing mix.
      {"TwoSidedEmission", "back_facing_emitters",
       [](Scene& s) {
         for (Object& o : s.objects)
           if (o.is_emitter()) o.two_sided = true;
       },
       {}},
      // Blender's default pixel filter, Blackman-Harris 1.5 px wide, instead of
      // pixel centres: it blurs the sharp edge of the disk light seen in the
      // mirror (on polygon_occluder's soft shadows it fails only narrowly,
      // image-mean t -3.38 against 3.29, so that scene is not the control).
      {"DefaultPixelFilter", "mirror_disk", [](Scene&) {},
       [](const std::string& script) {
         return replaced(script, "FILTER = ('BLACKMAN_HARRIS', 0.01)", "FILTER = ('BLACKMAN_HARRIS', 1.5)");
       }},
  };
}

class CyclesPeerControl : public CyclesPeer, public testing::TestWithParam<Control> {
 protected:
  void SetUp() override {
    if (!set_up(GetParam().name)) GTEST_SKIP() << no_blender_message();
  }
  void TearDown() override { tear_down(!HasFailure()); }
};

TEST_P(CyclesPeerControl, FailsFurnaceCheck) {
  const Control& c = GetParam();
  const fs::path file = scene_file(c.scene);
  Scene wrong = load_scene(file);
  c.break_scene(wrong);
  CyclesOptions options;
  options.spp = kSpp;
  EXPECT_EQ(render_and_check(c.name + " (" + c.scene + ")", file, wrong, options, c.break_script), 1);
}

INSTANTIATE_TEST_SUITE_P(Negative, CyclesPeerControl, testing::ValuesIn(controls()),
                         [](const testing::TestParamInfo<Control>& info) { return info.param.name; });

class CyclesPeerGgxControl : public CyclesPeer, public testing::Test {
 protected:
  void SetUp() override {
    const std::string name = testing::UnitTest::GetInstance()->current_test_info()->name();
    if (!set_up("GgxControl" + name)) GTEST_SKIP() << no_blender_message();
  }
  void TearDown() override { tear_down(!HasFailure()); }
};

// Roughness written as α instead of √α: Cycles then renders α² (strips of α
// 0.5 … 0.05 as 0.25 … 0.0025).
TEST_F(CyclesPeerGgxControl, RoughnessAlphaForSqrtAlphaFails) {
  const fs::path file = scene_file("ggx_sky_strips");
  CyclesOptions options;
  options.spp = kSpp;
  EXPECT_EQ(render_and_check("roughness = alpha (ggx_sky_strips)", file, load_scene(file), options,
                             [](const std::string& script) {
                               return replaced(script, "bsdf.inputs['Roughness'].default_value = o['ggx'][1]",
                                               "bsdf.inputs['Roughness'].default_value = o['ggx'][1] ** 2");
                             }),
            1);
}

// Beckmann left as the distribution (the default of Blender 3.x's Glossy and
// Glass nodes) where the scene asks for GGX: the strips' albedo under the sky
// differs. Rough glass itself is refused by the export, so this default is
// checked on the Glossy node.
TEST_F(CyclesPeerGgxControl, BeckmannForGgxFails) {
  const fs::path file = scene_file("ggx_sky_strips");
  CyclesOptions options;
  options.spp = kSpp;
  EXPECT_EQ(render_and_check("Beckmann for GGX (ggx_sky_strips)", file, load_scene(file), options,
                             [](std::string script) {
                               // Every strip's distribution, not the first only.
                               int strips = 0;
                               for (size_t at = script.find("('GGX', "); at != std::string::npos;
                                    at = script.find("('GGX', ", at), ++strips)
                                 script.replace(at, 8, "('BECKMANN', ");
                               if (strips != 5) throw std::runtime_error("expected the 5 GGX strips in the script");
                               return script;
                             }),
            1);
}

// Why height-correlated strips at oblique view are refused: Cycles'
// separable G2 rendered where the scene asks for the height-correlated one
// is seen.
TEST_F(CyclesPeerGgxControl, HeightCorrelatedObliqueSceneRenderedSeparableFails) {
  const fs::path rendered =
      peer::derived_ggx_scene("ggx_oblique_sky_78", "ggx_oblique_sky_78_sep", dir_, "separable", std::nullopt);
  const fs::path claimed =
      peer::derived_ggx_scene("ggx_oblique_sky_78", "ggx_oblique_sky_78_hc", dir_, "height_correlated", std::nullopt);
  ASSERT_TRUE(cycles_refusal(load_scene(claimed)));
  CyclesOptions options;
  options.spp = kSpp;
  EXPECT_EQ(render_and_check("separable render checked as height-correlated (ggx_oblique_sky_78)", claimed,
                             load_scene(rendered), options),
            1);
}

// Glass (smooth dielectrics: Glass BSDF SHARP). The single-interface
// scenes (glass_smooth_outside_60, _inside_60: total internal reflection,
// _inside_30) are exportable built-in scenes and run in CyclesPeerScene
// above, checked in the none convention; glass_sphere at unlimited depth
// too (a known finding). Here: the sphere at a depth limit where the
// truncation is visible, and the controls.
class CyclesPeerGlass : public CyclesPeer, public testing::Test {
 protected:
  void SetUp() override {
    const std::string name = testing::UnitTest::GetInstance()->current_test_info()->name();
    if (!set_up("Glass" + name)) GTEST_SKIP() << no_blender_message();
  }
  void TearDown() override { tear_down(!HasFailure()); }
  // glass_sphere rendered for `render_segments` (max_bounces = segments − 2),
  // its script edited by `edit`, checked at `check_segments`.
  int sphere(const std::string& label, int render_segments, int check_segments,
             const std::function<std::string(const std::string&)>& edit = {}) {
    const fs::path file = scene_file("glass_sphere");
    CyclesOptions options;
    options.spp = kSpp;
    options.max_segments = render_segments;
    return render_and_check(label + " (glass_sphere)", file, load_scene(file), options, edit, kRenders,
                            TransportConvention::kNone, check_segments);
  }
};

// 4 segments: at most one internal reflection, so the pixel is
// 1 − T·R² (the deficit T·R² ranges from 1.5e-3 at the centre to about 0.14
// near the silhouette); 3 and 5 segments differ by t 310 and −33.5.
constexpr int kGlassSphereSegments = 4;

TEST_F(CyclesPeerGlass, SphereAtFourSegmentsPasses) {
  EXPECT_EQ(sphere("depth-limited sphere", kGlassSphereSegments, kGlassSphereSegments), 0);
}

// Control: the export for one segment more (max_bounces 3, two internal
// reflections) checked against the 4-segment reference.
TEST_F(CyclesPeerGlass, DepthLimitOffByOneFails) {
  EXPECT_EQ(sphere("max_bounces for 5 segments checked at 4", kGlassSphereSegments + 1, kGlassSphereSegments), 1);
}

// Control: IOR 1.45 (the Blender 3.x node's default) rendered, checked as
// 1.5, at 3 segments (no internal reflection: the pixel is 1 − T·R, where
// the index shows most; at 4 segments it fails only narrowly, t 4.71
// against 3.29).
TEST_F(CyclesPeerGlass, Ior145CheckedAs15Fails) {
  EXPECT_EQ(sphere("IOR 1.45 checked as 1.5", kGlassSphereSegments - 1, kGlassSphereSegments - 1,
                   [](const std::string& script) {
                     return replaced(script, "'glass': ('SHARP', 1.5, 0.0)", "'glass': ('SHARP', 1.45, 0.0)");
                   }),
            1);
}

// Control: a Cycles render of the single quad checked in the radiance
// convention, whose reference is R + T/η² (0.494 at 60°) instead of 1.
TEST_F(CyclesPeerGlass, SingleInterfaceCheckedInTheRadianceConventionFails) {
  const fs::path file = scene_file("glass_smooth_outside_60");
  CyclesOptions options;
  options.spp = kSpp;
  EXPECT_EQ(render_and_check("checked in the radiance convention (glass_smooth_outside_60)", file, load_scene(file),
                             options, {}, kRenders, TransportConvention::kRadiance),
            1);
}
#endif

}  // namespace
}  // namespace furnace::exporter
