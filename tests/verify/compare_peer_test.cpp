// `furnace compare` on real renders (label peer), each verdict asserted:
//  - two seed sets of pbrt-v4 on disk_occluder → SAME (exit 0), and with
//    the light 1 % brighter on one side → DIFFERENT (its control);
//  - pbrt-v4 against furnace's own light_area renders, means only
//    (--no-variance-test: two renderers' noise differs) → SAME;
//  - furnace with and without --defect drop_light_cosine → DIFFERENT (exit 1),
//    and two seed sets of furnace → SAME (its control); needs no peer.
// pbrt-v4 is found as tests/export/pbrt_peer_test.cpp finds it: FURNACE_PBRT,
// else the shared peer build beside the repository, else `pbrt` on PATH;
// without it those tests say "skipped: no pbrt-v4 (set FURNACE_PBRT)".
//  - Blender Cycles with its two sampling patterns (Sobol-Burley, the
//    export's, and progressive multi-jitter) → SAME, and pbrt-v4 against
//    Cycles → SAME, both means only (--no-variance-test: other samplers);
//    Blender is found as FURNACE_BLENDER, else `blender` on PATH;
//  - Cycles' GGX against its Multiscatter GGX on ggx_disk_occluder →
//    DIFFERENT: single scattering loses energy that the multiple-scattering
//    walk keeps (means only).
//  - glass (issue 40): pbrt-v4 against Cycles on glass_sphere, at unlimited
//    depth and at 4 path segments → SAME (means only), and on the single
//    quad glass_smooth_outside_60 → DIFFERENT: pbrt-v4 divides transmitted
//    radiance by η′² (R + T/η² = 0.494), Cycles does not (exactly 1);
//  - a production-style pbrt-v4 scene that furnace did not export (issue 41:
//    a small bright sphere light, a triangle-mesh floor, bilinear patches,
//    coated-diffuse spheres, pixel jitter on, 48×48 at 32 spp, finite
//    negative values in its RGB film): two seed sets → SAME, 16-bit against
//    32-bit output → SAME, the light 1 % brighter → DIFFERENT, the floor's
//    reflectance 0.8 → 0.78 → DIFFERENT; with the light moved into view
//    and the film cropped around it, 64 spp against 4096 spp of the same
//    sampler → not DIFFERENT (a pixel beside the light whose 8 × 64 samples
//    all missed it is held by the rare-event guard), and the light 10 %
//    dimmer at 1024 spp on both sides → DIFFERENT (its control);
//  - samplers (issue 41): pixel jitter on, pbrt-v4's halton (whose seed
//    does not move the sub-pixel positions) against zsobol → DIFFERENT, two
//    halton seed sets → SAME (the trap), zsobol against independent → SAME.
// Each prints K, spp, verdict, image-mean t, the detectable difference and
// its wall time (renders and comparison).
#include <gtest/gtest.h>

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/scene.h"
#include "export/cycles.h"
#include "export/pbrt_v4.h"
#include "tests/export/peer_support.h"

namespace furnace {
namespace {

namespace fs = std::filesystem;
using exporter::peer::quoted;
using exporter::peer::read_text;
using exporter::peer::run;

// Renders per side and samples per pixel: eight 256-spp renders of
// disk_occluder detect about 0.5 % (docs/comparing.md).
constexpr int kRenders = 8;
constexpr int kSpp = 256;
// Named seeds: side A 1 ... K, side B 101 ... 100 + K.
constexpr int kFirstSeedA = 1;
constexpr int kFirstSeedB = 101;
constexpr const char* kScene = "disk_occluder";

std::optional<fs::path> pbrt_binary() {
  const char* forced = std::getenv("FURNACE_PBRT");
  if (forced && *forced) return fs::path(forced);
  const fs::path shared = fs::path(FURNACE_SCENE_DIR).parent_path().parent_path() / "shared/peers/pbrt-v4/pbrt";
  if (exporter::peer::is_executable_file(shared)) return shared;
  return exporter::peer::find_on_path("pbrt");
}

std::optional<fs::path> blender_binary() {
  const char* forced = std::getenv("FURNACE_BLENDER");
  if (forced && *forced) return fs::path(forced);
  return exporter::peer::find_on_path("blender");
}

// The export script's sampling-pattern line, and progressive multi-jitter's
// name for it (Blender 3.x).
constexpr const char* kSobolBurleyLine = "cy.sampling_pattern = 'SOBOL'";
constexpr const char* kPmjLine = "cy.sampling_pattern = 'PROGRESSIVE_MULTI_JITTER'";

class ComparePeer : public testing::Test {
 protected:
  void SetUp() override {
    const auto* info = testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / fmt::format("furnace_compare_peer_{}_{}", ::getpid(), info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    start_ = std::chrono::steady_clock::now();
  }
  void TearDown() override {
    const std::chrono::duration<double> wall = std::chrono::steady_clock::now() - start_;
    std::printf("wall time %.1f s (renders and comparison)\n", wall.count());
    if (!HasFailure())
      fs::remove_all(dir_);
    else
      std::printf("renders kept in %s\n", dir_.c_str());
  }

  fs::path scene_file() const { return fs::path(FURNACE_SCENE_DIR) / (std::string(kScene) + ".json"); }

  // K furnace renders (light_area) with seeds first_seed ...; `defect` "none" or a defect name.
  std::vector<fs::path> furnace_renders(const std::string& name, int first_seed, const std::string& defect) {
    std::vector<fs::path> images;
    for (int i = 0; i < kRenders; ++i) {
      const fs::path image = dir_ / fmt::format("{}_{}.exr", name, i);
      const auto r =
          run(fmt::format("{} render --scene {} --strategy light_area --spp {} --seed {} --threads 2 "
                          "--defect {} --output {}",
                          FURNACE_CLI, quoted(scene_file()), kSpp, first_seed + i, defect, quoted(image)));
      EXPECT_EQ(r.exit_code, 0) << r.output;
      images.push_back(image);
    }
    return images;
  }

  // K pbrt-v4 renders of the exported scene with seeds first_seed ...
  // `light_gain` scales the light's emitted radiance in the export.
  std::vector<fs::path> pbrt_renders(const fs::path& pbrt, const std::string& name, int first_seed,
                                     double light_gain = 1) {
    exporter::PbrtV4Options options;
    options.spp = kSpp;
    Scene scene = load_scene(scene_file());
    exporter::peer::named(scene, "light").emitted_radiance *= light_gain;
    return pbrt_renders_of(pbrt, scene, options, name, first_seed);
  }
  // The same for `scene` exported with `options`.
  std::vector<fs::path> pbrt_renders_of(const fs::path& pbrt, const Scene& scene,
                                        const exporter::PbrtV4Options& options, const std::string& name,
                                        int first_seed) {
    const fs::path pbrt_file = dir_ / (name + ".pbrt");
    exporter::write_pbrt_v4(scene, options, pbrt_file);
    return pbrt_renders_of_file(pbrt, pbrt_file, name, first_seed);
  }
  // K pbrt-v4 renders of the scene file `pbrt_file` with seeds first_seed ...
  std::vector<fs::path> pbrt_renders_of_file(const fs::path& pbrt, const fs::path& pbrt_file,
                                             const std::string& name, int first_seed, int renders = kRenders) {
    std::vector<fs::path> images;
    for (int i = 0; i < renders; ++i) {
      const fs::path image = dir_ / fmt::format("{}_{}.exr", name, i);
      const auto r = run(fmt::format("{} --quiet --nthreads 2 --seed {} --outfile {} {}", quoted(pbrt), first_seed + i,
                                     quoted(image), quoted(pbrt_file)));
      EXPECT_EQ(r.exit_code, 0) << r.output;
      images.push_back(image);
    }
    return images;
  }

  // K Cycles renders of the exported scene with seeds first_seed ..., in one
  // Blender process; `pmj` switches the sampling pattern to progressive
  // multi-jitter.
  std::vector<fs::path> cycles_renders(const fs::path& blender, const std::string& name, int first_seed, bool pmj) {
    exporter::CyclesOptions options;
    options.spp = kSpp;
    return cycles_renders_of(blender, load_scene(scene_file()), options, name, first_seed,
                             pmj ? std::function<void(std::string&)>([](std::string& text) {
                               const size_t at = text.find(kSobolBurleyLine);
                               EXPECT_NE(at, std::string::npos)
                                   << "the Cycles export no longer sets " << kSobolBurleyLine;
                               if (at != std::string::npos)
                                 text.replace(at, std::string(kSobolBurleyLine).size(), kPmjLine);
                             })
                                 : std::function<void(std::string&)>());
  }
  // The same for `scene` exported with `options`, the script's text passed
  // through `edit` when given.
  std::vector<fs::path> cycles_renders_of(const fs::path& blender, const Scene& scene,
                                          const exporter::CyclesOptions& options, const std::string& name,
                                          int first_seed, const std::function<void(std::string&)>& edit = {}) {
    const fs::path script = dir_ / (name + ".py");
    exporter::write_cycles(scene, options, script);
    if (edit) {
      std::string text = read_text(script);
      edit(text);
      std::ofstream(script) << text;
    }
    const auto r = run(fmt::format(
        "{} -b --factory-startup --python-exit-code 1 --python {} -- --seeds {}-{} "
        "--output {} --threads 2",
        quoted(blender), quoted(script), first_seed, first_seed + kRenders - 1, quoted(dir_ / (name + "_{seed}.exr"))));
    EXPECT_EQ(r.exit_code, 0) << r.output;
    std::vector<fs::path> images;
    for (int i = 0; i < kRenders; ++i) images.push_back(dir_ / fmt::format("{}_{}.exr", name, first_seed + i));
    return images;
  }

  // `furnace compare` of the two sets; prints the demonstration's numbers
  // (`scene` and `spp` name what was rendered) and keeps the JSON report in
  // report_.
  int compare(const std::string& label, const std::vector<fs::path>& a, const std::vector<fs::path>& b,
              const std::string& extra = "", const std::string& scene = kScene, int spp = kSpp) {
    std::string args;
    for (const fs::path& p : a) args += " --a " + quoted(p);
    for (const fs::path& p : b) args += " --b " + quoted(p);
    const fs::path json_file = dir_ / "compare.json";
    const auto r = run(fmt::format("{} compare{} {} --json {}", FURNACE_CLI, args, extra, quoted(json_file)));
    std::printf("%s", r.output.c_str());
    report_ = nlohmann::json::parse(read_text(json_file), nullptr, false);
    const nlohmann::json& j = report_;
    if (!j.is_discarded() && j.contains("channels")) {
      const nlohmann::json& m = j["channels"][0]["image_mean"];
      std::printf(
          "demonstration: %s, %s, K=%d per side, spp=%d: %s (exit %d), image-mean t %.3f, detectable "
          "difference %.3g%%\n",
          scene.c_str(), label.c_str(), int(a.size()), spp, j["verdict"].get<std::string>().c_str(), r.exit_code,
          m["t"].is_number() ? m["t"].get<double>() : NAN,
          100 * (m["detectable_relative_difference"].is_number() ? m["detectable_relative_difference"].get<double>()
                                                                 : NAN));
    }
    return r.exit_code;
  }

  fs::path dir_;
  nlohmann::json report_;  // the last comparison's --json
  std::chrono::steady_clock::time_point start_;
};

TEST_F(ComparePeer, PbrtTwoSeedSetsAreSame) {
  const auto pbrt = pbrt_binary();
  if (!pbrt) GTEST_SKIP() << "skipped: no pbrt-v4 (set FURNACE_PBRT)";
  EXPECT_EQ(compare("pbrt-v4 seeds 1-8 vs 101-108", pbrt_renders(*pbrt, "a", kFirstSeedA),
                    pbrt_renders(*pbrt, "b", kFirstSeedB)),
            0);
}

// Negative control of the pbrt-v4 demonstration: the light 1 % brighter in
// side A's export (above the 0.38 % it detects) → DIFFERENT.
TEST_F(ComparePeer, PbrtWithTheLightOnePercentBrighterIsDifferent) {
  const auto pbrt = pbrt_binary();
  if (!pbrt) GTEST_SKIP() << "skipped: no pbrt-v4 (set FURNACE_PBRT)";
  EXPECT_EQ(compare("pbrt-v4 light x1.01 vs x1", pbrt_renders(*pbrt, "a", kFirstSeedA, 1.01),
                    pbrt_renders(*pbrt, "b", kFirstSeedB)),
            1);
}

TEST_F(ComparePeer, PbrtAgainstFurnaceMeansAreSame) {
  const auto pbrt = pbrt_binary();
  if (!pbrt) GTEST_SKIP() << "skipped: no pbrt-v4 (set FURNACE_PBRT)";
  EXPECT_EQ(compare("pbrt-v4 vs furnace light_area, --no-variance-test", pbrt_renders(*pbrt, "pbrt", kFirstSeedA),
                    furnace_renders("furnace", kFirstSeedB, "none"), "--no-variance-test"),
            0);
}

TEST_F(ComparePeer, CyclesSobolBurleyAgainstPmjIsSame) {
  const auto blender = blender_binary();
  if (!blender) GTEST_SKIP() << "skipped: no Blender (set FURNACE_BLENDER)";
  EXPECT_EQ(compare("Cycles progressive multi-jitter vs Sobol-Burley, --no-variance-test",
                    cycles_renders(*blender, "pmj", kFirstSeedA, true),
                    cycles_renders(*blender, "sobol", kFirstSeedB, false), "--no-variance-test"),
            0);
}

TEST_F(ComparePeer, PbrtAgainstCyclesIsSame) {
  const auto pbrt = pbrt_binary();
  const auto blender = blender_binary();
  if (!pbrt) GTEST_SKIP() << "skipped: no pbrt-v4 (set FURNACE_PBRT)";
  if (!blender) GTEST_SKIP() << "skipped: no Blender (set FURNACE_BLENDER)";
  EXPECT_EQ(compare("pbrt-v4 vs Cycles (Sobol-Burley), --no-variance-test", pbrt_renders(*pbrt, "pbrt", kFirstSeedA),
                    cycles_renders(*blender, "cycles", kFirstSeedB, false), "--no-variance-test"),
            0);
}

TEST_F(ComparePeer, CyclesGgxAgainstMultiscatterGgxIsDifferent) {
  const auto blender = blender_binary();
  if (!blender) GTEST_SKIP() << "skipped: no Blender (set FURNACE_BLENDER)";
  // ggx_disk_occluder (GGX plane under a disk light and its occluder): under
  // a constant sky alone Multiscatter GGX renders the same value at every
  // seed, and identical images are bad input. The exporter writes
  // Multiscatter only where it has an exact answer (a constant sky), so here
  // the script's distribution is switched by text.
  const Scene scene = load_scene(fs::path(FURNACE_SCENE_DIR) / "ggx_disk_occluder.json");
  exporter::CyclesOptions options;
  options.spp = kSpp;
  const auto multiscatter = [](std::string& text) {
    const std::string single = "('GGX', ";
    int switched = 0;
    for (size_t at = text.find(single); at != std::string::npos; at = text.find(single, at))
      text.replace(at, single.size(), "('MULTI_GGX', "), ++switched;
    EXPECT_GT(switched, 0) << "the Cycles export no longer writes ('GGX', roughness)";
  };
  EXPECT_EQ(compare("ggx_disk_occluder: Cycles GGX vs Multiscatter GGX, --no-variance-test",
                    cycles_renders_of(*blender, scene, options, "ggx", kFirstSeedA),
                    cycles_renders_of(*blender, scene, options, "multiscatter", kFirstSeedB, multiscatter),
                    "--no-variance-test"),
            1);
}

TEST_F(ComparePeer, FurnaceTwoSeedSetsAreSame) {
  EXPECT_EQ(compare("furnace seeds 1-8 vs 101-108", furnace_renders("a", kFirstSeedA, "none"),
                    furnace_renders("b", kFirstSeedB, "none")),
            0);
}

TEST_F(ComparePeer, FurnaceWithADefectIsDifferent) {
  EXPECT_EQ(compare("furnace --defect drop_light_cosine vs without",
                    furnace_renders("a", kFirstSeedA, "drop_light_cosine"), furnace_renders("b", kFirstSeedB, "none")),
            1);
}

// Glass (issue 40, part 5). pbrt-v4 renders furnace's dielectric in the
// radiance convention (transmitted radiance divided by η′²), Cycles 3.4's
// Glass BSDF Sharp in the none convention (never divided). Seen from outside
// a closed glass ball the two agree: the factors of entering and leaving
// cancel, so the ball is L_env at unlimited depth, and at a depth limit both
// renderers match furnace's truncated reference (tests/export: their
// SphereAtFourSegments tests). A single glass quad with the environment on
// both sides does not: R + T/η² = 0.494 at 60° in pbrt-v4, exactly 1 in
// Cycles. Different renderers: means only (--no-variance-test).
class ComparePeerGlass : public ComparePeer {
 protected:
  // Exit code of compare of K pbrt-v4 renders (seeds 1 ...) against K Cycles
  // renders (seeds 101 ...) of built-in `scene_name`, both exported for
  // `max_segments` path segments. Needs both peers (have_peers()).
  int pbrt_against_cycles(const std::string& label, const std::string& scene_name, int max_segments) {
    const fs::path pbrt = *pbrt_binary();
    const fs::path blender = *blender_binary();
    const Scene scene = load_scene(fs::path(FURNACE_SCENE_DIR) / (scene_name + ".json"));
    exporter::PbrtV4Options pbrt_options;
    pbrt_options.spp = kSpp;
    pbrt_options.max_segments = max_segments;
    exporter::CyclesOptions cycles_options;
    cycles_options.spp = kSpp;
    cycles_options.max_segments = max_segments;
    return compare(label, pbrt_renders_of(pbrt, scene, pbrt_options, "pbrt", kFirstSeedA),
                   cycles_renders_of(blender, scene, cycles_options, "cycles", kFirstSeedB), "--no-variance-test",
                   scene_name);
  }
  bool have_peers() const { return pbrt_binary() && blender_binary(); }
};

// At unlimited depth every pixel is L_env in both conventions. Cycles' 9
// pixels that are off by 1e-4 to 1.2e-3 here (docs/checking_cycles.md,
// "Glass scenes") are far below what a pixel test against pbrt-v4 can see:
// pbrt's wavelength sampling gives each of its pixels about 1 % of noise per
// render (median detectable pixel difference 8.6 %, 70 times the largest of
// those errors), so the comparison is SAME.
TEST_F(ComparePeerGlass, PbrtAgainstCyclesOnTheGlassSphereIsSame) {
  if (!have_peers()) GTEST_SKIP() << "skipped: needs pbrt-v4 (FURNACE_PBRT) and Blender (FURNACE_BLENDER)";
  EXPECT_EQ(pbrt_against_cycles("pbrt-v4 vs Cycles, unlimited depth, --no-variance-test", "glass_sphere",
                                kUnlimitedDepth),
            0);
}

// At 4 segments (at most one internal reflection) the ball is darker than
// L_env by T·R² (0.15 % at its centre, up to 25 % at the silhouette), the
// same in both renderers.
TEST_F(ComparePeerGlass, PbrtAgainstCyclesOnTheGlassSphereAtFourSegmentsIsSame) {
  if (!have_peers()) GTEST_SKIP() << "skipped: needs pbrt-v4 (FURNACE_PBRT) and Blender (FURNACE_BLENDER)";
  EXPECT_EQ(pbrt_against_cycles("pbrt-v4 vs Cycles, 4 segments, --no-variance-test", "glass_sphere", 4), 0);
}

// The transport conventions: pbrt-v4's quad is R + T/η² = 0.494, Cycles'
// exactly 1.
TEST_F(ComparePeerGlass, PbrtAgainstCyclesOnASingleGlassQuadIsDifferent) {
  if (!have_peers()) GTEST_SKIP() << "skipped: needs pbrt-v4 (FURNACE_PBRT) and Blender (FURNACE_BLENDER)";
  EXPECT_EQ(pbrt_against_cycles("pbrt-v4 (radiance convention) vs Cycles (none), --no-variance-test",
                                "glass_smooth_outside_60", kUnlimitedDepth),
            1);
}

// A production-style scene that furnace did not export and has no reference
// for (issue 41, part 5): compare is all there is. A small bright sphere
// light (radius 0.06, radiance 2000, outside the frame), a triangle-mesh
// floor, a blue bilinear-patch wall, a red coated-diffuse sphere and a green
// coated-diffuse bilinear patch (rough coats, roughness 0.15 and 0.3); a
// perspective camera with pixel jitter on (pbrt's default Gaussian filter),
// pbrt's `path` integrator, the `independent` sampler (every decision, the
// sub-pixel position included, re-randomised by --seed: docs/comparing.md).
// The saturated colours make pbrt's RGB film write small finite negative
// values (about 10 in 8 renders), which compare uses as data.
constexpr int kProductionSpp = 32;
constexpr int kProductionResolution = 48;
constexpr const char* kProductionScene = "production (pbrt-v4 text)";

// The scene's text: the light's emission scaled by `light_scale`, the
// floor's reflectance `floor_reflectance`, the film written as 16-bit half
// floats (pbrt-v4's default) when `half_float`, else 32-bit floats. With
// `light_in_view` the light is moved down into the view (0.7 units) and the
// film cropped to the 24 × 16 pixels around it, where it covers about one
// pixel: a pixel beside it is hit only by the rare camera samples the
// filter's tail sends onto the light, a 2000-radiance contribution.
std::string production_scene(double light_scale, double floor_reflectance, bool half_float,
                             int spp = kProductionSpp, bool light_in_view = false) {
  return fmt::format(R"(LookAt 0 1.6 5  0 0.5 0  0 1 0
Camera "perspective" "float fov" 38
Sampler "independent" "integer pixelsamples" {spp}
Integrator "path" "integer maxdepth" 5
Film "rgb" "integer xresolution" {res} "integer yresolution" {res} "bool savefp16" {fp16}
  "string filename" "production.exr" {crop}
WorldBegin
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [2000 2000 2000] "float scale" {light_scale}
  Material "diffuse" "rgb reflectance" [0 0 0]
  Translate 0.8 {light_y} 0.6
  Shape "sphere" "float radius" 0.06
AttributeEnd
AttributeBegin
  Material "diffuse" "rgb reflectance" [{rho} {rho} {rho}]
  Shape "trianglemesh" "point3 P" [-6 0 -6  6 0 -6  6 0 6  -6 0 6] "integer indices" [0 2 1  0 3 2]
AttributeEnd
AttributeBegin
  Material "diffuse" "rgb reflectance" [0.15 0.25 0.7]
  Shape "bilinearmesh" "point3 P" [-6 0 -2.5  6 0 -2.5  -6 5 -2.5  6 5 -2.5]
AttributeEnd
AttributeBegin
  Material "coateddiffuse" "rgb reflectance" [0.7 0.15 0.1] "float roughness" 0.15 "bool remaproughness" false
  Translate -0.5 0.6 0
  Shape "sphere" "float radius" 0.6
AttributeEnd
AttributeBegin
  Material "coateddiffuse" "rgb reflectance" [0.2 0.6 0.2] "float roughness" 0.3 "bool remaproughness" false
  Shape "bilinearmesh" "point3 P" [0.4 0 0.8  1.4 0 0.2  0.5 1.1 0.6  1.3 0.9 0.0]
AttributeEnd
)",
                     fmt::arg("spp", spp), fmt::arg("res", kProductionResolution),
                     fmt::arg("crop", light_in_view ? R"("float cropwindow" [0 0.5 0 0.3333])" : ""),
                     fmt::arg("light_y", light_in_view ? 1.9 : 2.6),
                     fmt::arg("fp16", half_float ? "true" : "false"), fmt::arg("light_scale", light_scale),
                     fmt::arg("rho", floor_reflectance));
}

class ComparePeerProduction : public ComparePeer {
 protected:
  void SetUp() override {
    ComparePeer::SetUp();
    pbrt_ = pbrt_binary();
  }
  // K renders (seeds first_seed ...) of production_scene(...).
  std::vector<fs::path> renders(const std::string& name, int first_seed, double light_scale = 1,
                                double floor_reflectance = kFloorReflectance, bool half_float = false,
                                int spp = kProductionSpp, bool light_in_view = false) {
    const fs::path file = dir_ / (name + ".pbrt");
    std::ofstream(file) << production_scene(light_scale, floor_reflectance, half_float, spp, light_in_view);
    return pbrt_renders_of_file(*pbrt_, file, name, first_seed);
  }
  int compare_production(const std::string& label, const std::vector<fs::path>& a, const std::vector<fs::path>& b) {
    return compare(label, a, b, "", kProductionScene, kProductionSpp);
  }
  // Finite negative values in the last comparison's side ("a" or "b").
  int negative_values(const std::string& side) const {
    const nlohmann::json& n = report_[side]["negative_values"]["values"];
    return n.is_number_integer() ? n.get<int>() : 0;
  }
  static constexpr double kFloorReflectance = 0.8;
  std::optional<fs::path> pbrt_;
};

TEST_F(ComparePeerProduction, TwoSeedSetsAreSame) {
  if (!pbrt_) GTEST_SKIP() << "skipped: no pbrt-v4 (set FURNACE_PBRT)";
  EXPECT_EQ(compare_production("seeds 1-8 vs 101-108", renders("a", kFirstSeedA), renders("b", kFirstSeedB)), 0);
  // The negative values that once stopped compare (exit 2) are present and
  // used as data.
  EXPECT_GT(negative_values("a") + negative_values("b"), 0);
}

// pbrt-v4's default output, 16-bit half floats, against 32-bit floats: the
// rounding (a relative step of 2⁻¹¹) is far below the pixels' noise.
TEST_F(ComparePeerProduction, HalfFloatAgainstFloatIsSame) {
  if (!pbrt_) GTEST_SKIP() << "skipped: no pbrt-v4 (set FURNACE_PBRT)";
  EXPECT_EQ(compare_production("16-bit half (seeds 1-8) vs 32-bit float (101-108)",
                               renders("half", kFirstSeedA, 1, kFloorReflectance, true),
                               renders("float", kFirstSeedB)),
            0);
  EXPECT_EQ(report_["a"]["half_float"], true);
  EXPECT_EQ(report_["b"]["half_float"], false);
}

// The light 1 % brighter on side A: the whole image is 1 % brighter (all its
// light comes from that light), above the 0.6 % the comparison detects.
TEST_F(ComparePeerProduction, LightOnePercentBrighterIsDifferent) {
  if (!pbrt_) GTEST_SKIP() << "skipped: no pbrt-v4 (set FURNACE_PBRT)";
  EXPECT_EQ(compare_production("light x1.01 vs x1", renders("a", kFirstSeedA, 1.01), renders("b", kFirstSeedB)), 1);
}

// A material change: the floor (the largest surface) reflects 0.78 instead of 0.8 on side A.
TEST_F(ComparePeerProduction, FloorReflectanceChangeIsDifferent) {
  if (!pbrt_) GTEST_SKIP() << "skipped: no pbrt-v4 (set FURNACE_PBRT)";
  EXPECT_EQ(compare_production("floor reflectance 0.78 vs 0.8", renders("a", kFirstSeedA, 1, 0.78),
                               renders("b", kFirstSeedB)),
            1);
}

// The rare event of issue 41 on a real render: the crop around the light in
// view, 8 renders at 64 spp (seeds 1-8) against 8 at 4096 (101-108), the
// same sampler. Pixel (9, 1), beside the light, has a plain Welch t of -13.2
// against its critical 11.1 (all 8 × 64 samples of side A missed the light)
// and was a false DIFFERENT before the rare-event guard; it is held now, and
// the comparison is not DIFFERENT (INCONCLUSIVE: the image mean, carried by
// the light's few pixels, also lacks the power for 1 %). The renders are
// pbrt-v4's deterministic ones for the standard seeds of these tests.
TEST_F(ComparePeerProduction, AMissedLightBesideItIsHeldNotDifferent) {
  if (!pbrt_) GTEST_SKIP() << "skipped: no pbrt-v4 (set FURNACE_PBRT)";
  const int exit = compare(
      "light in view, 64 spp vs 4096 spp",
      renders("low", kFirstSeedA, 1, kFloorReflectance, false, 64, true),
      renders("high", kFirstSeedB, 1, kFloorReflectance, false, 4096, true), "--no-variance-test", kProductionScene, 64);
  EXPECT_NE(exit, 1);
  const nlohmann::json& pixels = report_["channels"][0]["pixels"];
  std::printf("rare-event guard on the real scene: %d pixels held, %d untested for repeating values, %d rejected\n",
              pixels["held"].get<int>(), pixels["few_values"].get<int>(), pixels["failures"].get<int>());
  EXPECT_GE(pixels["held"].get<int>(), 1);
}

// Negative control: the light 10 % dimmer on side A, both sides at 1024 spp
// (16 times side A's samples above, where a pixel beside the light has had
// its hits): DIFFERENT, and nothing held by the guard.
TEST_F(ComparePeerProduction, ADimmerLightInViewIsDifferentAtEnoughSpp) {
  if (!pbrt_) GTEST_SKIP() << "skipped: no pbrt-v4 (set FURNACE_PBRT)";
  EXPECT_EQ(compare("light in view x0.9 vs x1, 1024 spp",
                    renders("dim", kFirstSeedA, 0.9, kFloorReflectance, false, 1024, true),
                    renders("high", kFirstSeedB, 1, kFloorReflectance, false, 1024, true), "--no-variance-test",
                    kProductionScene, 1024),
            1);
  EXPECT_EQ(report_["channels"][0]["pixels"]["held"], 0);
}

// Issue 41: renders of a sampler whose seed leaves the sub-pixel positions
// alone are not independent (docs/comparing.md, "What independent renders
// require"). mirror_disk (the disk light seen in a mirror: one sharp
// circular edge; otherwise only pbrt's wavelengths are random), exported at
// 16 spp, then rendered with pixel jitter on (the export's
// `disablepixeljitter` line removed) and the sampler replaced; 16 renders per
// side, seeds 1-16 against 101-116, means only (--no-variance-test: other
// samplers). halton's renders share one anti-aliasing error on the edge that
// their spread does not hold: against zsobol (which re-randomises the
// positions) DIFFERENT, while two halton seed sets agree (the trap: SAME);
// zsobol against independent, both re-randomising, SAME (the control).
constexpr int kSamplerRenders = 16;
constexpr int kSamplerSpp = 16;

class ComparePeerSamplers : public ComparePeer {
 protected:
  void SetUp() override {
    ComparePeer::SetUp();
    pbrt_ = pbrt_binary();
  }
  std::vector<fs::path> jittered(const std::string& sampler, int first_seed) {
    exporter::PbrtV4Options options;
    options.spp = kSamplerSpp;
    const fs::path base = dir_ / (sampler + "_export.pbrt");
    exporter::write_pbrt_v4(load_scene(fs::path(FURNACE_SCENE_DIR) / "mirror_disk.json"), options, base);
    std::string out;
    bool jitter_line = false, sampler_line = false;
    std::istringstream in(read_text(base));
    for (std::string line; std::getline(in, line);) {
      if (line.rfind("Option \"disablepixeljitter\"", 0) == 0) {
        jitter_line = true;
        continue;
      }
      if (line.rfind("Sampler ", 0) == 0) {
        sampler_line = true;
        line = fmt::format("Sampler \"{}\" \"integer pixelsamples\" {}", sampler, kSamplerSpp);
      }
      out += line + "\n";
    }
    EXPECT_TRUE(jitter_line && sampler_line) << "the pbrt-v4 export's Option or Sampler line changed";
    const fs::path file = dir_ / (sampler + ".pbrt");
    std::ofstream(file) << out;
    return pbrt_renders_of_file(*pbrt_, file, fmt::format("{}_{}", sampler, first_seed), first_seed, kSamplerRenders);
  }
  int compare_samplers(const std::string& a, const std::string& b) {
    return compare(fmt::format("pixel jitter on, {} (seeds 1-16) vs {} (101-116)", a, b), jittered(a, kFirstSeedA),
                   jittered(b, kFirstSeedB), "--no-variance-test", "mirror_disk", kSamplerSpp);
  }
  std::optional<fs::path> pbrt_;
};

TEST_F(ComparePeerSamplers, HaltonAgainstZsobolIsDifferent) {
  if (!pbrt_) GTEST_SKIP() << "skipped: no pbrt-v4 (set FURNACE_PBRT)";
  EXPECT_EQ(compare_samplers("halton", "zsobol"), 1);
}

TEST_F(ComparePeerSamplers, HaltonSeedSetsAreSame) {
  if (!pbrt_) GTEST_SKIP() << "skipped: no pbrt-v4 (set FURNACE_PBRT)";
  EXPECT_EQ(compare_samplers("halton", "halton"), 0);
}

TEST_F(ComparePeerSamplers, ZsobolAgainstIndependentIsSame) {
  if (!pbrt_) GTEST_SKIP() << "skipped: no pbrt-v4 (set FURNACE_PBRT)";
  EXPECT_EQ(compare_samplers("zsobol", "independent"), 0);
}

}  // namespace
}  // namespace furnace
