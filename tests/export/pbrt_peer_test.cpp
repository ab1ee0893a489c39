// The pbrt-v4 peer test: pbrt renders every built-in scene the exporter can
// express, K times with distinct seeds, and `furnace check` must pass each
// (exit 0); deliberately wrong exports rendered the same way must fail it
// (exit 1), proving the check can tell. The scenes too costly for the peer
// label's budget are tested by a second build of this file (label slow).
// Finds pbrt-v4 as pbrt_binary() says; without one every test reports
// "skipped: no pbrt-v4 (set FURNACE_PBRT; tried …)" and none fails.
//
// Each test prints one line: scene, K, spp, check's exit code, the worst
// per-pixel |t| and the image-mean t, the image-mean bias the check detects
// (from its output), and the test's wall time.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <functional>
#include <regex>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "tests/command.h"
#include "tests/export/peer_support.h"
#include "core/exr.h"
#include "core/scene.h"
#include "export/pbrt_v4.h"

namespace furnace::exporter {
namespace {

namespace fs = std::filesystem;

// Renders per scene and samples per pixel: with them the image-mean bias the
// check detects stays at or below 0.5 % on every built-in scene (measured;
// the check reports it), well inside the 1 % the check requires for a verdict.
constexpr int kRenders = 16;
constexpr int kSpp = 256;
// Seeds kFirstSeed, kFirstSeed + 1, ...: pbrt's independent sampler draws
// from (pixel, seed) alone, so distinct seeds make independent renders.
constexpr int kFirstSeed = 1;
// Every correct export traces unlimited depth; check compares with the
// reference check_max_depth() names: furnace's unlimited-depth global
// illumination (--max-depth unlimited), or direct lighting (2 segments) where
// light reaches the eye after at most one bounce and the two agree.
constexpr int kPbrtThreads = 2;

// The pbrt-v4 binary: FURNACE_PBRT when set (used as given, so a wrong path
// fails loudly rather than skipping), else the shared peer build next to the
// repository (../shared/peers/pbrt-v4/pbrt), else `pbrt` on PATH.
std::optional<fs::path> pbrt_binary() {
  const char* forced = std::getenv("FURNACE_PBRT");
  if (forced && *forced) return fs::path(forced);
  const fs::path shared = fs::path(FURNACE_SCENE_DIR).parent_path().parent_path() / "shared/peers/pbrt-v4/pbrt";
  if (peer::is_executable_file(shared)) return shared;
  return peer::find_on_path("pbrt");
}

// The skip message: what was looked for, so a user can tell why.
std::string no_pbrt_message() {
  return fmt::format("skipped: no pbrt-v4 (set FURNACE_PBRT; tried {} and `pbrt` on PATH)",
                     (fs::path(FURNACE_SCENE_DIR).parent_path().parent_path() / "shared/peers/pbrt-v4/pbrt").string());
}

using peer::camel_case;
using peer::check_renders;
using peer::Diagnostics;
using peer::named;
using peer::quoted;
using peer::read_text;
using peer::run;
using peer::scene_file;
using testing_support::CommandResult;

// Rewrites an EXR mirrored left to right, every channel (and attribute) kept.
void flip_horizontally(const fs::path& path) {
  exr::Image image = exr::read(path, "pbrt render");
  const size_t w = size_t(image.width);
  for (auto& [name, values] : image.floats)
    for (size_t row = 0; row < values.size(); row += w) std::reverse(values.begin() + row, values.begin() + row + w);
  exr::write(path, image, "mirrored pbrt render");
}

// How a peer render is checked: against the reference of `segments` path
// segments (unlimited when unset), in the transport convention
// `convention` (pbrt-v4 renders the radiance one).
struct CheckAs {
  std::optional<int> segments;
  TransportConvention convention = TransportConvention::kRadiance;
};

class PbrtPeer {
 protected:
  // Exports `scene_for_export`, renders it K times, checks the images
  // against `scene_file` at the depth a correct export of it needs (of
  // `check_as.segments` path segments; unlimited when unset) in the
  // transport convention `check_as.convention`, and returns check's exit
  // code; `flip` mirrors every image first. `edit`, when given, rewrites the
  // exported text before pbrt reads it.
  int render_and_check(const std::string& label, const fs::path& scene_file, const Scene& scene_for_export,
                       const PbrtV4Options& options, bool flip,
                       const std::function<std::string(const std::string&)>& edit = {}, CheckAs check_as = {}) {
    const Scene scene = load_scene(scene_file);
    PbrtV4Options correct;
    correct.spp = options.spp;
    if (check_as.segments) correct.max_segments = *check_as.segments;
    const int check_depth = check_max_depth(scene, correct);
    const auto start = std::chrono::steady_clock::now();
    const fs::path pbrt_file = dir_ / "scene.pbrt";
    write_pbrt_v4(scene_for_export, options, pbrt_file);
    if (edit) {
      const std::string edited = edit(read_text(pbrt_file));
      std::ofstream(pbrt_file) << edited;
    }
    std::vector<fs::path> images;
    for (int i = 0; i < kRenders; ++i) {
      const fs::path image = dir_ / fmt::format("render_{}.exr", i);
      const CommandResult r = run(fmt::format("{} --quiet --nthreads {} --seed {} --outfile {} {}", quoted(*pbrt_),
                                              kPbrtThreads, kFirstSeed + i, quoted(image), quoted(pbrt_file)));
      if (r.exit_code != 0) {
        ADD_FAILURE() << "pbrt failed (exit " << r.exit_code << ") on " << pbrt_file << ":\n" << r.output;
        return -1;
      }
      if (flip) flip_horizontally(image);
      images.push_back(image);
    }
    const peer::CheckRun check = check_renders(scene_file, check_depth, images, dir_ / "check.json", check_as.convention);
    last_ = check.numbers;
    const Diagnostics& d = check.numbers;
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("%s", check.output.c_str());
    std::printf("peer: %s K=%d spp=%d check --max-depth %s --convention %s exit %d, worst pixel |t| %.2f, "
                "image-mean t %.2f (relative error %+.3g%%), detectable bias %.3g%%, wall %.1f s\n",
                label.c_str(), kRenders, options.spp, depth_name(check_depth).c_str(),
                transport_convention_name(check_as.convention).c_str(), check.exit_code, d.worst_pixel_t,
                d.image_mean_t, 100 * d.image_mean_relative_error, 100 * d.detectable_relative_bias, seconds);
    return check.exit_code;
  }

  bool set_up(const std::string& name) {
    pbrt_ = pbrt_binary();
    if (!pbrt_) return false;
    dir_ = fs::temp_directory_path() / fmt::format("furnace_pbrt_peer_{}_{}", ::getpid(), name);
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    return true;
  }
  void tear_down(bool passed) {
    if (dir_.empty()) return;
    if (passed) fs::remove_all(dir_);
    else std::printf("renders kept in %s\n", dir_.c_str());
  }

  std::optional<fs::path> pbrt_;
  fs::path dir_;
  Diagnostics last_;
};

// Scenes whose K renders alone would overrun the peer label's budget (10
// minutes on 2 cores): enclosure_box_rho99's paths average 100 bounces, and
// its 16 renders of 256 spp took 308-330 CPU-s (the rest of the label
// together 183). They run in pbrt_peer_slow_tests (label slow) instead, built
// from this file with FURNACE_PEER_COSTLY_SCENES=1.
const std::set<std::string> kCostlyScenes = {"enclosure_box_rho99"};

// The exportable built-in scenes of this binary: the costly ones or the rest.
std::vector<std::string> exportable_scenes() {
  return peer::exportable_scenes([](const Scene& s) { return !pbrt_v4_refusal(s); }, kCostlyScenes,
                                 bool(FURNACE_PEER_COSTLY_SCENES));
}

class PbrtPeerScene : public PbrtPeer, public testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    if (!set_up(camel_case(GetParam()))) GTEST_SKIP() << no_pbrt_message();
  }
  void TearDown() override { tear_down(!HasFailure()); }
};

// Known pbrt-v4 defects that the suite finds, each diagnosed and asserted to
// keep failing, so a change on either side is noticed; reported in
// docs/checking_pbrt.md with its numbers.
//   near_contact: pbrt-v4 5f7a6068 loses hits on long, thin triangles close
//   to the ray origin: its conservative "t > 0" bound grows with the
//   triangle's extent across the ray and exceeds t (re-evaluated for shadow
//   rays under the 1e-4 strip: 21.9 % rejected, deltaT up to 0.02 against t
//   = 1e-4; see docs/checking_pbrt.md). The scene's black strips (2e-5 × 1.2 to 2e-3 × 1.2, aspect
//   600 to 60000) are exported as two triangles each; pbrt lets light through
//   them and is brighter than the reference under the strip 1e-4 above the
//   receiver (column 9: 0.095 against 0.0594, |t| 21.2) and the strip at 1e-3
//   (column 15), with the same pixels failing at ×100 scale (the loss depends
//   on shape, not size). The same strips cut into pieces of aspect <= 100
//   pass (PbrtPeerDiagnosis below: worst |t| 3.73, image-mean t -0.84), as do the strips written as pbrt
//   "bilinearmesh" patches (tried by hand).
const std::map<std::string, std::string> kKnownPbrtDefects = {
    {"near_contact", "pbrt-v4 lets light through the long, thin triangles of the occluding strips"}};

TEST_P(PbrtPeerScene, PassesFurnaceCheck) {
  const fs::path file = scene_file(GetParam());
  PbrtV4Options options;
  options.spp = kSpp;
  const auto known = kKnownPbrtDefects.find(GetParam());
  if (known != kKnownPbrtDefects.end()) {
    std::printf("known pbrt-v4 defect, expected to FAIL: %s\n", known->second.c_str());
    EXPECT_EQ(render_and_check(GetParam(), file, load_scene(file), options, false), 1);
    return;
  }
  EXPECT_EQ(render_and_check(GetParam(), file, load_scene(file), options, false), 0);
}

INSTANTIATE_TEST_SUITE_P(BuiltIn, PbrtPeerScene, testing::ValuesIn(exportable_scenes()),
                         [](const testing::TestParamInfo<std::string>& info) { return camel_case(info.param); });

#if !FURNACE_PEER_COSTLY_SCENES
// The GGX scenes as pbrt-v4 can render them. The built-in GGX scenes have
// albedo 0.8 (pbrt's conductor has no constant factor: refused) and their
// oblique ones put a separable strip beside each height-correlated one
// (pbrt has no separable form: refused), so each peer scene is derived from a
// built-in one by changing only its GGX materials (peer::derived_ggx_scene),
// written to the test's directory, and checked against its own exact
// reference. The normal-view scenes keep both forms: there they are equal,
// and the export writes pbrt's height-correlated G2 for each.
struct GgxPeerScene {
  std::string name;      // the derived scene's name (and the test's)
  std::string builtin;   // the built-in scene it is derived from
  std::optional<std::string> shadowing;  // every GGX object's form, or unchanged
};

void PrintTo(const GgxPeerScene& g, std::ostream* os) { *os << g.name; }

std::vector<GgxPeerScene> ggx_peer_scenes() {
  return {
      {"ggx_sky_strips_albedo1", "ggx_sky_strips", std::nullopt},
      {"ggx_disk_occluder_albedo1", "ggx_disk_occluder", std::nullopt},
      {"ggx_oblique_sky_60_hc_albedo1", "ggx_oblique_sky_60", "height_correlated"},
      {"ggx_oblique_sky_78_hc_albedo1", "ggx_oblique_sky_78", "height_correlated"},
      {"ggx_oblique_sphere_60_hc_albedo1", "ggx_oblique_sphere_60", "height_correlated"},
      {"ggx_oblique_sphere_78_hc_albedo1", "ggx_oblique_sphere_78", "height_correlated"},
  };
}

class PbrtPeerGgx : public PbrtPeer, public testing::TestWithParam<GgxPeerScene> {
 protected:
  void SetUp() override {
    if (!set_up(camel_case(GetParam().name))) GTEST_SKIP() << no_pbrt_message();
  }
  void TearDown() override { tear_down(!HasFailure()); }
};

TEST_P(PbrtPeerGgx, PassesFurnaceCheck) {
  const GgxPeerScene& g = GetParam();
  const fs::path file = peer::derived_ggx_scene(g.builtin, g.name, dir_, g.shadowing, 1.0);
  const Scene scene = load_scene(file);
  ASSERT_FALSE(pbrt_v4_refusal(scene)) << *pbrt_v4_refusal(scene);
  PbrtV4Options options;
  options.spp = kSpp;
  EXPECT_EQ(render_and_check(g.name, file, scene, options, false), 0);
}

INSTANTIATE_TEST_SUITE_P(Derived, PbrtPeerGgx, testing::ValuesIn(ggx_peer_scenes()),
                         [](const testing::TestParamInfo<GgxPeerScene>& info) { return camel_case(info.param.name); });

class PbrtPeerGgxSmooth : public PbrtPeer, public testing::Test {
 protected:
  void SetUp() override {
    if (!set_up("GgxSmooth")) GTEST_SKIP() << no_pbrt_message();
  }
  void TearDown() override { tear_down(!HasFailure()); }
};

// The near-specular end of furnace's α range, down to its lower limit 1e-3
// (pbrt renders α < 1e-3 as a mirror; NaNs near roughness 0 were pbrt-v4
// #283): ggx_sky_strips with α 0.001, 0.002, 0.005, 0.01, 0.02, albedo 1.
TEST_F(PbrtPeerGgxSmooth, NearSpecularStripsPassFurnaceCheck) {
  const fs::path file = peer::derived_strips_with_alphas({0.001, 0.002, 0.005, 0.01, 0.02}, "ggx_sky_strips_smooth", dir_);
  const Scene scene = load_scene(file);
  ASSERT_FALSE(pbrt_v4_refusal(scene)) << *pbrt_v4_refusal(scene);
  PbrtV4Options options;
  options.spp = kSpp;
  EXPECT_EQ(render_and_check("ggx_sky_strips_smooth", file, scene, options, false), 0);
}

class PbrtPeerGgxControl : public PbrtPeer, public testing::Test {
 protected:
  void SetUp() override {
    const std::string name = testing::UnitTest::GetInstance()->current_test_info()->name();
    if (!set_up("GgxControl" + name)) GTEST_SKIP() << no_pbrt_message();
  }
  void TearDown() override { tear_down(!HasFailure()); }
};

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  size_t count = 0;
  for (size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()), ++count)
    text.replace(at, from.size(), to);
  if (count == 0) throw std::runtime_error("the exported text has no '" + from + "'");
  return text;
}

// pbrt's default remaproughness true reads "roughness" r as α = √r: the
// strips of α 0.5 … 0.05 render as α 0.71 … 0.22.
TEST_F(PbrtPeerGgxControl, RemapRoughnessTrueFails) {
  const fs::path file = peer::derived_ggx_scene("ggx_sky_strips", "ggx_sky_strips_albedo1", dir_, std::nullopt, 1.0);
  PbrtV4Options options;
  options.spp = kSpp;
  EXPECT_EQ(render_and_check("remaproughness true (ggx_sky_strips_albedo1)", file, load_scene(file), options, false,
                             [](const std::string& text) {
                               return replaced(text, "\"bool remaproughness\" false", "\"bool remaproughness\" true");
                             }),
            1);
}

// The albedo-1 export checked against the same scene with albedo 0.99: a
// 1 % error in the reflection must be seen.
TEST_F(PbrtPeerGgxControl, Albedo099For1Fails) {
  const fs::path rendered =
      peer::derived_ggx_scene("ggx_sky_strips", "ggx_sky_strips_albedo1", dir_, std::nullopt, 1.0);
  const fs::path claimed =
      peer::derived_ggx_scene("ggx_sky_strips", "ggx_sky_strips_albedo099", dir_, std::nullopt, 0.99);
  PbrtV4Options options;
  options.spp = kSpp;
  EXPECT_EQ(render_and_check("albedo 1 checked as 0.99 (ggx_sky_strips)", claimed, load_scene(rendered), options,
                             false),
            1);
}

// Why separable strips at oblique view are refused: pbrt's height-correlated
// G2 rendered where the scene asks for the separable one is seen (the forms
// differ by up to 20 % in directional albedo at α = 1, cos θo = 0.2).
TEST_F(PbrtPeerGgxControl, SeparableObliqueSceneRenderedHeightCorrelatedFails) {
  const fs::path rendered =
      peer::derived_ggx_scene("ggx_oblique_sky_78", "ggx_oblique_sky_78_hc_albedo1", dir_, "height_correlated", 1.0);
  const fs::path claimed =
      peer::derived_ggx_scene("ggx_oblique_sky_78", "ggx_oblique_sky_78_sep_albedo1", dir_, "separable", 1.0);
  ASSERT_TRUE(pbrt_v4_refusal(load_scene(claimed)));
  PbrtV4Options options;
  options.spp = kSpp;
  EXPECT_EQ(render_and_check("height-correlated render checked as separable (ggx_oblique_sky_78)", claimed,
                             load_scene(rendered), options, false),
            1);
}

// The microfacet scenes pbrt-v4 renders only in their height-correlated
// form: each built-in rough-glass or conductor-Fresnel scene seen obliquely
// puts a separable strip beside the height-correlated ones (refused), so the
// peer scene is the built-in one with every rough material height-correlated
// (peer::derived_scene), checked against its own exact reference.
// glass_rough_disk_inside_hc lights the strips from a disk inside the glass:
// pbrt's light sampling and MIS through a rough transmission, where the 2021
// class (f and pdf both missing η′², pbrt-v4 dfa11074) is seen.
struct MicrofacetPeerScene {
  std::string builtin;  // the derived scene is <builtin>_hc
  std::string type;     // the material type made height-correlated
};

void PrintTo(const MicrofacetPeerScene& m, std::ostream* os) { *os << m.builtin << "_hc"; }

std::vector<MicrofacetPeerScene> microfacet_peer_scenes() {
  return {{"glass_rough_outside_60", "dielectric"},
          {"glass_rough_inside_45", "dielectric"},
          {"glass_rough_disk_inside", "dielectric"},
          {"conductor_fresnel_sky_60", "ggx"},
          {"conductor_fresnel_sphere_60", "ggx"}};
}

fs::path height_correlated_scene(const std::string& builtin, const std::string& type, const fs::path& dir) {
  return peer::derived_scene(builtin, builtin + "_hc", dir, type, [](nlohmann::json& m) {
    if (m.contains("alpha")) m["shadowing"] = "height_correlated";
  });
}

class PbrtPeerMicrofacet : public PbrtPeer, public testing::TestWithParam<MicrofacetPeerScene> {
 protected:
  void SetUp() override {
    if (!set_up(camel_case(GetParam().builtin + "_hc"))) GTEST_SKIP() << no_pbrt_message();
  }
  void TearDown() override { tear_down(!HasFailure()); }
};

TEST_P(PbrtPeerMicrofacet, PassesFurnaceCheck) {
  const MicrofacetPeerScene& m = GetParam();
  const fs::path file = height_correlated_scene(m.builtin, m.type, dir_);
  const Scene scene = load_scene(file);
  ASSERT_FALSE(pbrt_v4_refusal(scene)) << *pbrt_v4_refusal(scene);
  ASSERT_TRUE(pbrt_v4_refusal(load_scene(scene_file(m.builtin))));  // the built-in one is refused
  PbrtV4Options options;
  options.spp = kSpp;
  EXPECT_EQ(render_and_check(m.builtin + "_hc", file, scene, options, false), 0);
}

INSTANTIATE_TEST_SUITE_P(Derived, PbrtPeerMicrofacet, testing::ValuesIn(microfacet_peer_scenes()),
                         [](const testing::TestParamInfo<MicrofacetPeerScene>& info) {
                           return camel_case(info.param.builtin + "_hc");
                         });

class PbrtPeerGlass : public PbrtPeer, public testing::Test {
 protected:
  void SetUp() override {
    const std::string name = testing::UnitTest::GetInstance()->current_test_info()->name();
    if (!set_up("Glass" + name)) GTEST_SKIP() << no_pbrt_message();
  }
  void TearDown() override { tear_down(!HasFailure()); }
};

// The smooth glass sphere at a depth limit: 4 path segments (maxdepth 3)
// allow K = 1 internal reflection, a pixel-centre answer of 1 − T·R^(K+1)
// (furnace's 4-segment reference), darker than L_env by up to 25 % at the
// silhouette pixels. pbrt-v4's K = maxdepth − 2 is confirmed by the pass
// here and by the off-by-one controls below.
TEST_F(PbrtPeerGlass, SphereAtFourSegmentsPassesFurnaceCheck) {
  const fs::path file = scene_file("glass_sphere");
  PbrtV4Options options;
  options.spp = kSpp;
  options.max_segments = 4;
  EXPECT_EQ(render_and_check("glass_sphere at 4 segments", file, load_scene(file), options, false, {}, {4}), 0);
}

// The same render checked against the 3- and 5-segment references: a
// depth mapping off by one either way is seen.
TEST_F(PbrtPeerGlass, SphereDepthOffByOneFails) {
  const fs::path file = scene_file("glass_sphere");
  PbrtV4Options options;
  options.spp = kSpp;
  options.max_segments = 4;
  EXPECT_EQ(render_and_check("glass_sphere at 4 segments checked at 5", file, load_scene(file), options, false, {},
                             {5}),
            1);
  options.max_segments = 5;
  EXPECT_EQ(render_and_check("glass_sphere at 5 segments checked at 4", file, load_scene(file), options, false, {},
                             {4}),
            1);
}

// η 1.45 (Blender's default IOR) rendered where the scene says 1.5: the
// single interface at 60° reflects and transmits R + T/η² = 0.518 instead
// of 0.494.
TEST_F(PbrtPeerGlass, Eta145CheckedAs15Fails) {
  const fs::path file = scene_file("glass_smooth_outside_60");
  PbrtV4Options options;
  options.spp = kSpp;
  EXPECT_EQ(render_and_check("eta 1.45 checked as 1.5 (glass_smooth_outside_60)", file, load_scene(file), options,
                             false,
                             [](const std::string& text) {
                               return replaced(text, "\"float eta\" 1.5", "\"float eta\" 1.45");
                             }),
            1);
}

// pbrt-v4 renders the radiance convention: checked in the none convention
// (Cycles'), the single interface's R + T/η² (0.494) is not 1.
TEST_F(PbrtPeerGlass, RadianceRenderCheckedInTheNoneConventionFails) {
  const fs::path file = scene_file("glass_smooth_outside_60");
  PbrtV4Options options;
  options.spp = kSpp;
  EXPECT_EQ(render_and_check("radiance render checked as none (glass_smooth_outside_60)", file, load_scene(file),
                             options, false, {}, {std::nullopt, TransportConvention::kNone}),
            1);
}

// remaproughness left true on rough glass lit from inside: α 0.1 … 1 render
// as 0.32 … 1, and the disk's light spreads wider.
TEST_F(PbrtPeerGlass, RemapRoughnessTrueOnGlassFails) {
  const fs::path file = height_correlated_scene("glass_rough_disk_inside", "dielectric", dir_);
  PbrtV4Options options;
  options.spp = kSpp;
  EXPECT_EQ(render_and_check("remaproughness true (glass_rough_disk_inside_hc)", file, load_scene(file), options,
                             false,
                             [](const std::string& text) {
                               return replaced(text, "\"bool remaproughness\" false", "\"bool remaproughness\" true");
                             }),
            1);
}

// The conductor's Fresnel matters: the gold strips (n + ik = 0.2 + 3.4i)
// rendered with F ≡ 1 (η + ik = i, the export of a GGX object without
// Fresnel), checked against gold.
TEST_F(PbrtPeerGlass, ConductorFresnelOneCheckedAsGoldFails) {
  const fs::path file = height_correlated_scene("conductor_fresnel_sky_60", "ggx", dir_);
  PbrtV4Options options;
  options.spp = kSpp;
  EXPECT_EQ(render_and_check("F = 1 checked as gold (conductor_fresnel_sky_60_hc)", file, load_scene(file), options,
                             false,
                             [](const std::string& text) {
                               return replaced(replaced(text, "\"spectrum eta\" [300 0.2 900 0.2]",
                                                        "\"spectrum eta\" [300 0 900 0]"),
                                               "\"spectrum k\" [300 3.4 900 3.4]", "\"spectrum k\" [300 1 900 1]");
                             }),
            1);
}

// A deliberately wrong export: the scene as exported is altered, or the
// renders are, while the check compares with the unaltered scene.
struct Control {
  std::string name;
  std::string scene;
  std::function<void(Scene&, PbrtV4Options&)> break_export;
  bool mirror_images = false;
};

void PrintTo(const Control& c, std::ostream* os) { *os << c.name << " (" << c.scene << ")"; }

std::vector<Control> controls() {
  return {
      {"LightRadiancePlusOnePercent", "disk_occluder",
       [](Scene& s, PbrtV4Options&) { named(s, "light").emitted_radiance *= 1.01; }},
      {"Albedo049For05", "disk_occluder",
       [](Scene& s, PbrtV4Options&) { named(s, "receiver").material.albedo = 0.49; }},
      // polygon_occluder's occluders are asymmetric left to right.
      {"MirroredImage", "polygon_occluder", [](Scene&, PbrtV4Options&) {}, true},
      // pbrt's own default maxdepth 5 (6 segments) keeps 1 − 0.5⁶ of the
      // radiance of an enclosure of albedo 0.5: 1.6 % too dark.
      {"EnclosureMaxDepthTooSmall", "enclosure_box_rho5",
       [](Scene&, PbrtV4Options& o) { o.max_segments = 6; }},
  };
}

class PbrtPeerControl : public PbrtPeer, public testing::TestWithParam<Control> {
 protected:
  void SetUp() override {
    if (!set_up(GetParam().name)) GTEST_SKIP() << no_pbrt_message();
  }
  void TearDown() override { tear_down(!HasFailure()); }
};

TEST_P(PbrtPeerControl, FailsFurnaceCheck) {
  const Control& c = GetParam();
  const fs::path file = scene_file(c.scene);
  Scene wrong = load_scene(file);
  PbrtV4Options options;
  options.spp = kSpp;
  c.break_export(wrong, options);
  EXPECT_EQ(render_and_check(c.name + " (" + c.scene + ")", file, wrong, options, c.mirror_images), 1);
}

INSTANTIATE_TEST_SUITE_P(Negative, PbrtPeerControl, testing::ValuesIn(controls()),
                         [](const testing::TestParamInfo<Control>& info) { return info.param.name; });

// Cuts every non-emitting rectangle whose sides differ by more than
// `max_aspect` into equal pieces along its long side, each of aspect at most
// `max_aspect`: the same surface, as triangles of bounded aspect.
Scene split_slivers(const Scene& scene, double max_aspect) {
  Scene out = scene;
  out.objects.clear();
  for (const Object& o : scene.objects) {
    const auto* r = std::get_if<Rectangle>(&o.shape);
    if (!r || o.is_emitter()) {
      out.objects.push_back(o);
      continue;
    }
    const bool u_long = length(r->edge_u) >= length(r->edge_v);
    const Vec3 long_edge = u_long ? r->edge_u : r->edge_v;
    const Vec3 short_edge = u_long ? r->edge_v : r->edge_u;
    const int pieces = int(std::ceil(length(long_edge) / (max_aspect * length(short_edge))));
    if (pieces <= 1) {
      out.objects.push_back(o);
      continue;
    }
    for (int k = 0; k < pieces; ++k) {
      Object piece = o;
      piece.name = fmt::format("{}_piece_{}", o.name, k);
      const Vec3 corner = r->corner + long_edge * (double(k) / pieces);
      const Vec3 step = long_edge * (1.0 / pieces);
      // Keep the rectangle's orientation (edge_u × edge_v) unchanged.
      piece.shape = u_long ? Rectangle{corner, step, short_edge} : Rectangle{corner, short_edge, step};
      out.objects.push_back(piece);
    }
  }
  return out;
}

class PbrtPeerDiagnosis : public PbrtPeer, public testing::Test {
 protected:
  void SetUp() override {
    if (!set_up("Diagnosis")) GTEST_SKIP() << no_pbrt_message();
  }
  void TearDown() override { tear_down(!HasFailure()); }
};

// near_contact's failure is pbrt's, not the export's or the reference's: the
// same strips cut into triangles of aspect <= 100 pass the same check.
TEST_F(PbrtPeerDiagnosis, NearContactPassesWithSliversSplit) {
  const fs::path file = scene_file("near_contact");
  const Scene split = split_slivers(load_scene(file), 100);
  std::printf("near_contact with its strips cut into %zu rectangles of aspect <= 100\n", split.objects.size());
  PbrtV4Options options;
  options.spp = kSpp;
  EXPECT_EQ(render_and_check("near_contact (slivers split)", file, split, options, false), 0);
}
#endif

}  // namespace
}  // namespace furnace::exporter
