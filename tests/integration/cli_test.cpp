// The furnace CLI: bad input gives one sentence naming the file, field and
// value, a non-zero exit, and no output file.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "tests/command.h"
#include "core/exr.h"
#include "core/scene.h"
#include "verify/harness.h"
#include "stats/statistics.h"

namespace {

using Result = furnace::testing_support::CommandResult;

// The furnace CLI with `args`; output is stdout and stderr.
Result run_cli(const std::string& args) {
  return furnace::testing_support::run_command(std::string(FURNACE_CLI) + " " + args + " 2>&1");
}

std::filesystem::path temp_dir() {
  auto dir = std::filesystem::temp_directory_path() / ("furnace_cli_test_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return dir;
}

TEST(Cli, BadSceneFieldIsNamedAndNothingIsWritten) {
  const auto dir = temp_dir();
  const auto scene = dir / "bad.json";
  std::ifstream in(std::string(FURNACE_SCENE_DIR) + "/disk_occluder.json");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string from = "\"radius\": 0.75";
  text.replace(text.find(from), from.size(), "\"radius\": -0.75");
  std::ofstream(scene) << text;
  const auto out = dir / "out.exr";
  const Result r = run_cli("render --scene " + scene.string() + " --output " + out.string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("bad.json"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("objects[1].shape.radius"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("-0.75"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(out));
  std::filesystem::remove_all(dir);
}

TEST(Cli, UnknownStrategyIsNamed) {
  const Result r = run_cli("verify --strategy uniform_hemisphre --spp 4");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("uniform_hemisphre"), std::string::npos) << r.output;
}

TEST(Cli, UnknownLightSelectionIsNamed) {
  const Result r = run_cli("verify --scene " + std::string(FURNACE_SCENE_DIR) + "/point_light.json --light-selection flux --spp 4");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  // CLI11's IsMember names the option, the value and the accepted names.
  EXPECT_NE(r.output.find("--light-selection: flux not in {power,uniform}"), std::string::npos) << r.output;
}

TEST(Cli, PointLightSceneSkipsBlindStrategiesAndPassesUnderPowerSelection) {
  const Result r = run_cli("verify --scene " + std::string(FURNACE_SCENE_DIR) +
                           "/point_and_area.json --light-selection power --spp 256 --strategy light_solid_angle mis_one_sample");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  const Result all = run_cli("verify --scene " + std::string(FURNACE_SCENE_DIR) + "/point_light.json --spp 128");
  EXPECT_EQ(all.exit_code, 0) << all.output;
  EXPECT_EQ(all.output.find("uniform_hemisphere"), std::string::npos) << all.output;
}

// verify's exit-code contract at low spp: a rejection it cannot support
// there (path_mis has no variance model; a quarter of its calibrated spp) is
// INCONCLUSIVE, exit 3, naming the spp; the same defect under light_area
// (exact variance) is FAIL, exit 1.
TEST(Cli, VerifyIsInconclusiveWhereItCannotJudgeAndFailsWhereItCan) {
  const std::string scene = std::string(FURNACE_SCENE_DIR) + "/disk_occluder.json";
  const int calibrated = furnace::verify::min_calibrated_spp(furnace::Strategy::kPathMis);
  const std::string spp = std::to_string(calibrated / 4);
  const Result low = run_cli("verify --scene " + scene + " --strategy path_mis --defect skip_shadow_ray --spp " + spp);
  EXPECT_EQ(low.exit_code, 3) << low.output;
  EXPECT_NE(low.output.find("verdict: INCONCLUSIVE"), std::string::npos) << low.output;
  EXPECT_NE(low.output.find("rerun at " + std::to_string(calibrated) + " spp or more"), std::string::npos)
      << low.output;
  const Result exact =
      run_cli("verify --scene " + scene + " --strategy light_area --defect skip_shadow_ray --spp " + spp);
  EXPECT_EQ(exact.exit_code, 1) << exact.output;
  EXPECT_NE(exact.output.find("verdict: FAIL"), std::string::npos) << exact.output;
}

TEST(Cli, MissingSceneFileIsNamed) {
  const Result r = run_cli("verify --scene /no/such/scene.json");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("/no/such/scene.json"), std::string::npos) << r.output;
}

TEST(Cli, BadNumberIsRejected) {
  const Result r = run_cli("verify --spp -3");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("spp"), std::string::npos) << r.output;
}

// Every kind of argument error exits 2 with one line on stderr naming the
// option (or word) at fault, whatever CLI11's own code for it, before any work.
TEST(Cli, EveryArgumentErrorIsOneLineNamingTheOptionAndExitsTwo) {
  const auto dir = temp_dir();
  const std::string scene = std::string(FURNACE_SCENE_DIR) + "/disk_occluder.json";
  const std::string afile = (dir / "afile").string();
  std::ofstream(afile) << "x";
  const std::string missing = (dir / "missing").string();
  const std::string images = " --image " + (dir / "a.exr").string() + " --image " + (dir / "b.exr").string();
  const std::string check = "check --scene " + scene + images;
  const std::string analytic = "analytic --scene " + scene;
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"verify --bogus", "--bogus"},                                   // unknown option
      {"verify --spp", "--spp"},                                       // missing value
      {"render --scene " + scene + " extra", "extra"},                 // extra positional
      {"verify --spp abc", "--spp"},                                   // wrong type
      {"verify --spp 1e3", "--spp"},
      {"verify --spp 1", "--spp"},                                     // out of range
      {"render --scene " + scene + " --spp 0", "--spp"},
      {"verify --max-depth 3", "--max-depth"},                         // needs --scene
      {"frobnicate", "frobnicate"},                                    // unknown subcommand
      {"", "subcommand"},                                              // no subcommand
      {"verify --alpha nan", "--alpha"},
      {"verify --alpha 0", "--alpha"},
      {"verify --alpha 0.7", "--alpha"},
      {check + " --alpha nan", "--alpha"},
      {check + " --max-detectable-bias inf", "--max-detectable-bias"},
      {check + " --max-detectable-bias 0", "--max-detectable-bias"},
      {check + " --channels hsv", "--channels"},
      {check + " --zmap " + afile + "/z.exr", "--zmap"},
      {check + " --json " + missing + "/j.json", "--json"},
      {analytic + " --point 0,0,0 --normal 0,0,1 --albedo nan", "--albedo"},
      {analytic + " --point 0,0,0 --normal 0,0,1 --albedo 1.5", "--albedo"},
      {analytic + " --point 0,nan,0 --normal 0,0,1", "--point"},
      {analytic + " --point 0,0,0 --normal 0,0,inf", "--normal"},
      {analytic + " --point 0,0 --normal 0,0,1", "--point"},
      {analytic + " --point 0,0,0 --normal 0,0,1 --view 0,0", "--view"},
      {analytic + " --point 0,0,0 --normal 0,0,1 --view 0,nan,1", "--view"},
      {"sweep --suite-scene no_such_scene --seeds 2", "--suite-scene"},
      {"sweep --suite-scene sphere_light --seeds 2", "--suite all"},  // an extended scene, default suite
      {"verify --suite quick", "--suite"},
      {"verify --suite extended --scene " + scene, "--suite"},       // excludes --scene
      {"report --suite bogus", "--suite"},
      {"verify --seed -1", "--seed"},
      {"verify --seed 18446744073709551616", "--seed"},
      {"render --scene " + scene + " --seed 1.5", "--seed"},
      {"verify --threads 1e9", "--threads"},
      {"render --scene " + scene + " --threads -1", "--threads"},
      {"render --scene " + scene + " --roulette-depth 0", "--roulette-depth"},
      {"render --scene " + scene + " --max-depth 0", "--max-depth"},
      {"render --scene " + scene + " --output " + missing + "/out.exr", "--output"},
      {"render --scene " + scene + " --output " + dir.string(), "--output"},
      {"export --scene " + scene + " --format pbrt-v4 -o " + missing + "/x.pbrt", "--output"},
      {"export --scene " + scene + " --format pbrt-v4 --spp 0 -o x.pbrt", "--spp"},
      {"export --scene " + scene + " --format pbrt-v4 --seed -1 -o x.pbrt", "--seed"},
      {"report --min-spp 1", "--min-spp"},
      {"report --max-spp 99999999999", "--max-spp"},
      {"report --seed -1", "--seed"},
      {"report --output-dir " + afile + "/sub", "--output-dir"},
      {"report --output-dir ''", "--output-dir"},
      {"sweep --case-alpha nan", "--case-alpha"},
      {"sweep --seeds 0", "--seeds"},
      {"sweep --spp 1", "--spp"},
  };
  for (const auto& [args, name] : cases) {
    const Result r = run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << args << ": " << r.output;
    EXPECT_EQ(r.output.rfind("furnace: error: ", 0), 0u) << args << ": " << r.output;
    EXPECT_NE(r.output.find(name), std::string::npos) << args << ": " << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << args << ": " << r.output;
  }
  EXPECT_FALSE(std::filesystem::exists(missing));
  EXPECT_TRUE(std::filesystem::is_regular_file(afile));
  std::filesystem::remove_all(dir);
}

TEST(Cli, HelpAndVersionExitZeroAndHelpStatesTheExitCodes) {
  const Result help = run_cli("--help");
  EXPECT_EQ(help.exit_code, 0) << help.output;
  EXPECT_NE(help.output.find("0 pass, 1 fail, 2 bad input"), std::string::npos) << help.output;
  EXPECT_NE(help.output.find("3 inconclusive"), std::string::npos) << help.output;
  for (const char* sub : {"render", "verify", "analytic", "check", "compare", "export", "report", "sweep"}) {
    const Result r = run_cli(std::string(sub) + " --help");
    EXPECT_EQ(r.exit_code, 0) << sub;
    EXPECT_NE(r.output.find("2 bad input"), std::string::npos) << sub << ": " << r.output;
  }
  EXPECT_EQ(run_cli("--version").exit_code, 0);
}

// Below stats::kMinVarianceTestSamples the variance test cannot run: it is
// skipped and named, the case passes on its mean tests; below the strategy's
// verify::min_calibrated_spp a warning says the stated alpha is not
// calibrated there (light_area: 31 is below its 32).
TEST(Cli, TooFewSamplesSkipTheVarianceTestLoudlyAndTheCasePasses) {
  ASSERT_EQ(furnace::verify::min_calibrated_spp(furnace::Strategy::kLightArea), 32);
  const Result r = run_cli("verify --scene " + std::string(FURNACE_SCENE_DIR) +
                           "/disk_occluder.json --strategy light_area --spp 31");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("variance: skipped (31 samples per pixel, the variance test needs at least 100)"),
            std::string::npos) << r.output;
  EXPECT_NE(r.output.find("skipped: the variance test of 1 case(s)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("warning: 31 spp is below"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("verdict: PASS"), std::string::npos) << r.output;
  // Not a terminal: no progress line.
  EXPECT_EQ(r.output.find('\r'), std::string::npos) << r.output;
}

// The low-spp warning is per strategy: a case warns exactly when its spp is
// below its own strategy's measured threshold, and the warning names those
// strategies only, each with its threshold.
TEST(Cli, LowSppWarningNamesEachStrategyBelowItsCalibratedSpp) {
  using furnace::verify::Case;
  const auto case_at = [](furnace::Strategy strategy, int spp) {
    Case c;
    c.options.strategy = strategy;
    c.options.spp = spp;
    return c;
  };
  for (const furnace::StrategyInfo& info : furnace::kStrategyTable) {
    const int threshold = furnace::verify::min_calibrated_spp(info.strategy);
    EXPECT_GE(threshold, 32) << info.name;  // the smallest spp the calibration sweeps measured
    EXPECT_EQ(furnace::verify::low_spp_warning({case_at(info.strategy, threshold)}), "") << info.name;
    const std::string below = furnace::verify::low_spp_warning({case_at(info.strategy, threshold - 1)});
    EXPECT_NE(below.find(std::to_string(threshold - 1) + " spp is below"), std::string::npos) << below;
    EXPECT_NE(below.find(std::string(info.name) + " (" + std::to_string(threshold) + ")"), std::string::npos)
        << below;
  }
  // A mixed run: only the strategy below its threshold is named.
  const furnace::Strategy low = furnace::Strategy::kLightArea, other = furnace::Strategy::kCosineHemisphere;
  const int spp = furnace::verify::min_calibrated_spp(low) - 1;
  const std::string mixed = furnace::verify::low_spp_warning(
      {case_at(low, spp), case_at(other, std::max(spp, furnace::verify::min_calibrated_spp(other)))});
  EXPECT_NE(mixed.find("light_area"), std::string::npos) << mixed;
  EXPECT_EQ(mixed.find("cosine_hemisphere"), std::string::npos) << mixed;
  EXPECT_LE(furnace::verify::lowest_min_calibrated_spp(), furnace::verify::highest_min_calibrated_spp());
}

// Non-finite samples (the nan_sample control: one sample in 1024 is NaN)
// fail a render unless --allow-nonfinite, and fail a verification case.
TEST(Cli, NonFiniteSamplesFailRenderAndVerify) {
  const auto dir = temp_dir();
  const std::string scene = std::string(FURNACE_SCENE_DIR) + "/disk_occluder.json";
  const std::string out = (dir / "nan.exr").string();
  const Result render = run_cli("render --scene " + scene + " --spp 4 --defect nan_sample --output " + out);
  EXPECT_EQ(render.exit_code, 1) << render.output;
  EXPECT_NE(render.output.find("4 of 4096 samples were not finite"), std::string::npos) << render.output;
  const Result allowed =
      run_cli("render --scene " + scene + " --spp 4 --defect nan_sample --allow-nonfinite --output " + out);
  EXPECT_EQ(allowed.exit_code, 0) << allowed.output;
  const Result clean = run_cli("render --scene " + scene + " --spp 4 --output " + out);
  EXPECT_EQ(clean.exit_code, 0) << clean.output;
  const Result verify = run_cli("verify --scene " + scene + " --strategy light_area --spp 128 --defect nan_sample");
  EXPECT_EQ(verify.exit_code, 1) << verify.output;
  EXPECT_NE(verify.output.find("non-finite samples: 128"), std::string::npos) << verify.output;
  std::filesystem::remove_all(dir);
}

// A scene whose exact answer overflows double precision is bad input, named,
// in every command that needs the reference.
TEST(Cli, NonFiniteReferenceIsBadInput) {
  const auto dir = temp_dir();
  const auto scene = dir / "huge_sky.json";
  std::ifstream in(std::string(FURNACE_SCENE_DIR) + "/environment_blocker.json");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string from = "\"radiance\": 1.5";
  text.replace(text.find(from), from.size(), "\"radiance\": 1e308");
  std::ofstream(scene) << text;
  for (const std::string& args :
       {"verify --scene " + scene.string() + " --strategy light_area --spp 4",
        "analytic --scene " + scene.string() + " --point 1.5,1.5,0 --normal 0,0,1",
        "check --scene " + scene.string() + " --image " + (dir / "a.exr").string() + " --image " +
            (dir / "b.exr").string()}) {
    const Result r = run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << args << ": " << r.output;
    EXPECT_NE(r.output.find("huge_sky.json"), std::string::npos) << args << ": " << r.output;
  }
  std::filesystem::remove_all(dir);
}

// Integers are decimal: CLI11's own conversion (strtoll, base 0) would read
// "010" as octal 8; the validators hand it the canonical "10".
TEST(Cli, LeadingZerosAreDecimal) {
  const auto dir = temp_dir();
  const Result r = run_cli("render --scene " + std::string(FURNACE_SCENE_DIR) + "/disk_occluder.json --spp 010 --threads 1 " +
                           "--output " + (dir / "zeros.exr").string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("10 spp"), std::string::npos) << r.output;
  std::filesystem::remove_all(dir);
}

// A hemisphere strategy cannot see what glass transmits: refused with the
// object's name (exit 2), never a silently dark image.
TEST(Cli, HemisphereStrategyIsRefusedOnGlass) {
  const auto dir = temp_dir();
  const Result r = run_cli("render --scene " + std::string(FURNACE_SCENE_DIR) +
                           "/glass_smooth_outside_60.json --strategy uniform_hemisphere --spp 4 --output " +
                           (dir / "glass.exr").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("dielectric object 'interface'"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "glass.exr"));
  std::filesystem::remove_all(dir);
}

// --convention on render and check: renders of an open glass interface in
// the none convention (Cycles') pass check in that convention and fail in
// the radiance convention (pbrt-v4's), which divides what is transmitted by
// η² (E_R + E_T against E_R + E_T/2.25 here: 0.88 against 0.44).
TEST(Cli, ConventionOfRenderAndCheckMustAgree) {
  const auto dir = temp_dir();
  const std::string scene = std::string(FURNACE_SCENE_DIR) + "/glass_rough_outside_60.json";
  std::string images;
  for (int seed = 1; seed <= 4; ++seed) {
    const std::string out = (dir / ("none" + std::to_string(seed) + ".exr")).string();
    const Result r = run_cli("render --scene " + scene + " --strategy bsdf --convention none --spp 1024 --seed " +
                             std::to_string(seed) + " --output " + out);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    images += " " + out;
  }
  const Result same = run_cli("check --scene " + scene + " --convention none --image" + images);
  EXPECT_EQ(same.exit_code, 0) << same.output;
  EXPECT_EQ(same.output.find("transport convention"), std::string::npos) << same.output;
  const Result other = run_cli("check --scene " + scene + " --convention radiance --image" + images);
  EXPECT_EQ(other.exit_code, 1) << other.output;
  // The images' provenance names their convention: check warns of the mismatch.
  EXPECT_NE(other.output.find("rendered in the 'none' transport convention, but the reference is checked in "
                              "'radiance'"),
            std::string::npos)
      << other.output;
  const Result bad = run_cli("check --scene " + scene + " --convention importance --image" + images);
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_NE(bad.output.find("radiance"), std::string::npos) << bad.output;
  std::filesystem::remove_all(dir);
}

// `furnace analytic --view` through the binary: the separable α = 1 GGX
// strip of ggx_oblique_sky_78 under the sky of radiance 1 has the closed-form
// directional albedo 2(1 − ln 2)ρ/(1 + μo) at any view (analytic/ggx.cpp);
// an explicit view at μo = 0.6 gives it, the camera's own direction given
// explicitly gives the default's answer, and (negative control) the μo = 0.6
// value is not what the camera's μo = 0.2 gives.
TEST(Cli, AnalyticViewOptionAgainstAClosedForm) {
  const std::string base = "analytic --scene " + std::string(FURNACE_SCENE_DIR) +
                           "/ggx_oblique_sky_78.json --point -0.75,0,0 --normal 0,0,1 --estimator bsdf --json";
  const auto radiance_of = [](const Result& r) {
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return nlohmann::json::parse(r.output)["radiance"].get<double>();
  };
  const double rho = 0.8, mu = 0.6;
  const double closed_form = 2 * (1 - std::log(2.0)) * rho / (1 + mu);
  const double at_06 = radiance_of(run_cli(base + " --view 0,-0.8,0.6"));
  EXPECT_NEAR(at_06, closed_form, 1e-12 * closed_form);
  const furnace::Scene scene = furnace::load_scene(std::string(FURNACE_SCENE_DIR) + "/ggx_oblique_sky_78.json");
  const furnace::Vec3 v = -scene.camera.forward;
  const double camera = radiance_of(run_cli(base));
  EXPECT_EQ(radiance_of(run_cli(base + fmt::format(" --view {:.17g},{:.17g},{:.17g}", v.x, v.y, v.z))), camera);
  EXPECT_GT(std::fabs(camera - closed_form), 1e-2 * closed_form);
  EXPECT_NEAR(camera, 2 * (1 - std::log(2.0)) * rho / (1 + v.z), 1e-12 * camera);
}

TEST(Cli, InjectedDefectMakesVerifyFail) {
  const Result r = run_cli("verify --strategy light_area --defect drop_light_cosine --spp 256");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("verdict: FAIL"), std::string::npos) << r.output;
}

}  // namespace

namespace {

// `furnace check` on our own renders treated as a foreign renderer's: K
// independent correct renders pass when the test has power, and are
// INCONCLUSIVE (exit 3) when it has not; renders with a known defect fail; bad
// images are bad input (exit 2) named with file, pixel and value.
class CheckCommand : public testing::Test {
 protected:
  void SetUp() override { dir_ = temp_dir(); }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string render(const std::string& scene, int seed, const std::string& defect, int spp = 256,
                     const std::string& strategy = "light_area") {
    const std::string out = (dir_ / ("r" + std::to_string(seed) + defect + strategy + ".exr")).string();
    const Result r = run_cli("render --scene " + scene + " --strategy " + strategy + " --spp " + std::to_string(spp) +
                             " --seed " + std::to_string(seed) + " --defect " + defect + " --output " + out);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return out;
  }
  std::string images(const std::string& scene, int k, int spp = 256) {
    std::string args;
    for (int seed = 1; seed <= k; ++seed) args += " --image " + render(scene, seed, "none", spp);
    return args;
  }
  std::filesystem::path dir_;
};

const std::string kDisk = std::string(FURNACE_SCENE_DIR) + "/disk_occluder.json";

// PASS needs power. At 64 spp eight renders detect only ~1.1 %
// (INCONCLUSIVE); at 256 spp ~0.5 %.
TEST_F(CheckCommand, IndependentCorrectRendersPass) {
  const Result r = run_cli("check --scene " + kDisk + images(kDisk, 8));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("verdict: PASS"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("has power"), std::string::npos) << r.output;
}

TEST_F(CheckCommand, TwoRendersAreInconclusiveAndSayWhatWouldSuffice) {
  const Result r = run_cli("check --scene " + kDisk + images(kDisk, 2));
  EXPECT_EQ(r.exit_code, 3) << r.output;
  EXPECT_NE(r.output.find("verdict: INCONCLUSIVE"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("images at 256 spp"), std::string::npos) << r.output;
}

TEST_F(CheckCommand, NanImageIsBadInputAndANegativeImageIsCounted) {
  // NaN radiance is bad input (a finite negative value is data since issue
  // 41: an all −1 image is read, fails against the reference, and is counted).
  furnace::exr::Image nan_image, minus_one;
  nan_image.width = nan_image.height = minus_one.width = minus_one.height = 32;
  for (const char* c : {"R", "G", "B"}) nan_image.floats[c].assign(32 * 32, std::numeric_limits<float>::quiet_NaN());
  for (const char* c : {"R", "G", "B"}) minus_one.floats[c].assign(32 * 32, -1.0f);
  const std::string bad = (dir_ / "nan.exr").string(), negative = (dir_ / "minus_one.exr").string();
  furnace::exr::write(bad, nan_image);
  furnace::exr::write(negative, minus_one);
  const std::string json = (dir_ / "bad.json").string();
  const Result r = run_cli("check --scene " + kDisk + " --image " + render(kDisk, 1, "none") + " --image " + bad +
                           " --json " + json);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(bad), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("(0, 0)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("nan"), std::string::npos) << r.output;
  std::ifstream in(json);
  const auto j = nlohmann::json::parse(in);
  EXPECT_EQ(j.at("exit_code"), 2);
  EXPECT_EQ(j.at("verdict"), "BAD INPUT");
  const std::string counted_json = (dir_ / "negative.json").string();
  const Result counted = run_cli("check --scene " + kDisk + " --image " + render(kDisk, 1, "none") + " --image " +
                                 negative + " --json " + counted_json);
  // Read and tested as is: two images (1 d.o.f., critical t 127) cannot
  // reject even an all −1 image, and lack power, so INCONCLUSIVE, not bad input.
  EXPECT_EQ(counted.exit_code, 3) << counted.output;
  EXPECT_NE(counted.output.find("negative values (the images): 3072 in 1 of 2 image(s)"), std::string::npos)
      << counted.output;
  std::ifstream counted_in(counted_json);
  EXPECT_EQ(nlohmann::json::parse(counted_in).at("negative_values").at("values"), 3 * 32 * 32);
}

TEST_F(CheckCommand, SameImageTwiceIsBadInputNamingBoth) {
  const std::string a = render(kDisk, 1, "none");
  const std::string copy = (dir_ / "copy.exr").string();
  std::filesystem::copy_file(a, copy);
  const Result r = run_cli("check --scene " + kDisk + " --image " + a + " --image " + copy);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(a), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(copy), std::string::npos) << r.output;
}

TEST_F(CheckCommand, ImagesOfAnotherSceneAreWarnedAbout) {
  const std::string other = std::string(FURNACE_SCENE_DIR) + "/polygon_occluder.json";  // 32x32 like kDisk
  const Result r = run_cli("check --scene " + kDisk + images(other, 2));
  EXPECT_NE(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("warning"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("'polygon_occluder'"), std::string::npos) << r.output;
}

// A closed enclosure is checked against its full global illumination by
// default (against direct lighting a path tracer fails); --max-depth 2
// asks for direct lighting, which a path tracer without a depth limit must
// fail. The ρ = 0.5 box: shorter paths than enclosure_box, so eight 256-spp
// renders take 2 s and detect ~0.3 %.
TEST_F(CheckCommand, PathTracedEnclosurePassesAgainstUnlimitedDepthByDefault) {
  const std::string box = std::string(FURNACE_SCENE_DIR) + "/enclosure_box_rho5.json";
  std::string args;
  for (int seed = 1; seed <= 8; ++seed) args += " --image " + render(box, seed, "none", 256, "path_mis");
  const Result r = run_cli("check --scene " + box + args);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("max depth unlimited"), std::string::npos) << r.output;
  const Result direct = run_cli("check --scene " + box + args + " --max-depth 2");
  EXPECT_EQ(direct.exit_code, 1) << direct.output;
  EXPECT_NE(direct.output.find("warning"), std::string::npos) << direct.output;
}

// The closed albedo-1 enclosure has infinite radiance at unlimited depth:
// check refuses it as bad input (the rule verify applies and render refuses
// with, core/path_length.h), naming the depth in words.
TEST_F(CheckCommand, InfiniteAnswerAtTheRequestedDepthIsBadInput) {
  std::ifstream in(std::string(FURNACE_SCENE_DIR) + "/enclosure_sphere.json");
  nlohmann::json j = nlohmann::json::parse(in);
  j["objects"][0]["material"]["albedo"] = 1;
  const auto scene = dir_ / "white_enclosure.json";
  std::ofstream(scene) << j.dump();
  const std::string images = " --image " + render(kDisk, 1, "none", 4) + " --image " + render(kDisk, 2, "none", 4);
  const Result r = run_cli("check --scene " + scene.string() + images + " --max-depth unlimited");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("infinite radiance"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("--max-depth unlimited cannot be checked"), std::string::npos) << r.output;
  const Result rendered = run_cli("render --scene " + scene.string() + " --strategy path_mis --spp 1 --output " +
                                  (dir_ / "white.exr").string());
  EXPECT_EQ(rendered.exit_code, 2) << rendered.output;
  EXPECT_NE(rendered.output.find("white_enclosure.json"), std::string::npos) << rendered.output;
  EXPECT_FALSE(std::filesystem::exists(dir_ / "white.exr"));
}

TEST_F(CheckCommand, JsonHoldsTheVerdictAndZmapTheT) {
  const std::string json = (dir_ / "check.json").string(), zmap = (dir_ / "z.exr").string();
  const Result r = run_cli("check --scene " + kDisk + images(kDisk, 8) + " --json " + json + " --zmap " + zmap);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  std::ifstream in(json);
  const auto j = nlohmann::json::parse(in);
  EXPECT_EQ(j.at("verdict"), "PASS");
  EXPECT_EQ(j.at("exit_code"), 0);
  EXPECT_EQ(j.at("image_count"), 8);
  EXPECT_LE(j.at("detectable_relative_bias").get<double>(), j.at("max_detectable_bias").get<double>());
  EXPECT_EQ(j.at("worst_pixels").size(), 5u);
  const furnace::exr::Image z = furnace::exr::read(zmap);
  EXPECT_EQ(z.width, 32);
  EXPECT_TRUE(z.has_channel("Y"));
  // "-": the JSON on stdout, parseable on its own.
  const std::string cmd = std::string(FURNACE_CLI) + " check --scene " + kDisk + images(kDisk, 2) + " --json - 2>/dev/null";
  const Result stdout_json = furnace::testing_support::run_command(cmd);
  EXPECT_EQ(stdout_json.exit_code, 3);
  EXPECT_EQ(nlohmann::json::parse(stdout_json.output).at("verdict"), "INCONCLUSIVE");
}

TEST(CliMaxDepth, AcceptsUnlimitedAndRejectsOtherWords) {
  const auto dir = temp_dir();
  const std::string out = (dir / "depth.exr").string();
  const std::string scene = std::string(FURNACE_SCENE_DIR) + "/enclosure_box.json";
  const Result unlimited =
      run_cli("render --scene " + scene + " --strategy path_mis --spp 2 --max-depth unlimited --output " + out);
  EXPECT_EQ(unlimited.exit_code, 0) << unlimited.output;
  EXPECT_EQ(furnace::exr::read(out).attribute("furnace.max_depth"), "unlimited");
  const Result four = run_cli("render --scene " + scene + " --strategy path_mis --spp 2 --max-depth 4 --output " + out);
  EXPECT_EQ(four.exit_code, 0) << four.output;
  EXPECT_EQ(furnace::exr::read(out).attribute("furnace.max_depth"), "4");
  for (const char* bad : {"0", "infinite", "-3"}) {
    const Result r = run_cli("verify --scene " + scene + " --strategy path_mis --spp 4 --max-depth " + std::string(bad));
    EXPECT_NE(r.exit_code, 0) << bad << ": " << r.output;
    EXPECT_NE(r.output.find("max-depth"), std::string::npos) << bad << ": " << r.output;
  }
  std::filesystem::remove_all(dir);
}

TEST_F(CheckCommand, DefectiveRendersFail) {
  std::string args;
  for (int seed = 1; seed <= 8; ++seed) args += " --image " + render(kDisk, seed, "drop_light_cosine");
  const Result r = run_cli("check --scene " + kDisk + args);
  EXPECT_EQ(r.exit_code, 1) << r.output;
}

// The rare-event guard on real renders (examples/check_rare_event): a small
// bright sphere light beside a receiver lit by a large dim disk, rendered by
// uniform hemisphere sampling, which hits the sphere with probability ~2e-3
// per sample. Eight 16-spp renders miss it at most pixels and FAIL against
// the exact reference although the renderer is right; with eight 4096-spp
// renders of the same renderer as --guard those pixels are held and the
// verdict is INCONCLUSIVE (exit 3). Negative controls: a renderer that drops
// the light (the scene rendered without it), guarded by its own 4096-spp
// renders, still FAILs; a guard image that copies a checked one is bad input.
TEST_F(CheckCommand, RareEventGuardHoldsAMissedLightAndNotADroppedOne) {
  const std::string scene = std::string(FURNACE_EXAMPLE_DIR) + "/check_rare_event/rare_light.json";
  const auto set = [&](const std::string& scene_path, int first_seed, int spp) {
    std::string paths;
    for (int seed = first_seed; seed < first_seed + 8; ++seed)
      paths += " " + render(scene_path, seed, "none", spp, "uniform_hemisphere");
    return paths;
  };
  const std::string low = set(scene, 1, 16), guard = set(scene, 101, 4096);
  const Result unguarded = run_cli("check --scene " + scene + " --image" + low);
  EXPECT_EQ(unguarded.exit_code, 1) << unguarded.output;
  EXPECT_NE(unguarded.output.find("--guard IMAGE"), std::string::npos) << unguarded.output;
  const std::string json = (dir_ / "guarded.json").string();
  const Result guarded = run_cli("check --scene " + scene + " --image" + low + " --guard" + guard + " --json " + json);
  EXPECT_EQ(guarded.exit_code, 3) << guarded.output;
  EXPECT_NE(guarded.output.find("held (pixels): worst pixel"), std::string::npos) << guarded.output;
  EXPECT_NE(guarded.output.find("0/256 fail"), std::string::npos) << guarded.output;
  std::ifstream in(json);
  const auto j = nlohmann::json::parse(in);
  EXPECT_EQ(j.at("rare_event_guard").at("guard_spp"), 4096.0);
  EXPECT_GT(j.at("channels").at(0).at("pixels_held").get<int>(), 100);

  // The renderer that drops the light: the scene without it, same name.
  std::ifstream scene_in(scene);
  nlohmann::json dark = nlohmann::json::parse(scene_in);
  auto& objects = dark.at("objects");
  objects.erase(std::remove_if(objects.begin(), objects.end(),
                               [](const nlohmann::json& o) { return o.at("name") == "small_light"; }),
                objects.end());
  const std::string dark_scene = (dir_ / "rare_light_dropped.json").string();
  std::ofstream(dark_scene) << dark.dump();
  const Result dropped = run_cli("check --scene " + scene + " --image" + set(dark_scene, 201, 16) + " --guard" +
                                 set(dark_scene, 301, 4096));
  EXPECT_EQ(dropped.exit_code, 1) << dropped.output;
  EXPECT_NE(dropped.output.find("held: none"), std::string::npos) << dropped.output;

  const std::string first_low = low.substr(1, low.find(' ', 1) - 1);
  const Result copy = run_cli("check --scene " + scene + " --image" + low + " --guard " + first_low + guard);
  EXPECT_EQ(copy.exit_code, 2) << copy.output;
}

TEST_F(CheckCommand, WrongResolutionIsNamed) {
  const std::string other = std::string(FURNACE_SCENE_DIR) + "/white_furnace.json";  // 24x24, not 32x32
  const std::string a = render(other, 1, "none"), b = render(other, 2, "none");
  const Result r = run_cli("check --scene " + kDisk + " --image " + a + " --image " + b);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("camera.resolution"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(a), std::string::npos) << r.output;
}

}  // namespace
