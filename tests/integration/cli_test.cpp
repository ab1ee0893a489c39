// The furnace CLI: bad input gives one sentence naming the file, field and
// value, a non-zero exit, and no output file.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace {

struct Result {
  int exit_code;
  std::string output;  // stdout and stderr
};

Result run_cli(const std::string& args) {
  const std::string cmd = std::string(FURNACE_CLI) + " " + args + " 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return {-1, "popen failed"};
  std::string out;
  char buf[4096];
  while (size_t n = fread(buf, 1, sizeof buf, pipe)) out.append(buf, n);
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
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
  EXPECT_NE(r.output.find("light selection 'flux'"), std::string::npos) << r.output;
}

TEST(Cli, PointLightSceneSkipsBlindStrategiesAndPassesUnderPowerSelection) {
  const Result r = run_cli("verify --scene " + std::string(FURNACE_SCENE_DIR) +
                           "/point_and_area.json --light-selection power --spp 256 --strategy light_solid_angle mis_one_sample");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  const Result all = run_cli("verify --scene " + std::string(FURNACE_SCENE_DIR) + "/point_light.json --spp 128");
  EXPECT_EQ(all.exit_code, 0) << all.output;
  EXPECT_EQ(all.output.find("uniform_hemisphere"), std::string::npos) << all.output;
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

TEST(Cli, InjectedDefectMakesVerifyFail) {
  const Result r = run_cli("verify --strategy light_area --defect drop_light_cosine --spp 256");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("verdict: FAIL"), std::string::npos) << r.output;
}

}  // namespace

namespace {

// `furnace check` on our own renders treated as a foreign renderer's: K
// independent correct renders pass, renders with a known defect fail, and
// an image of the wrong resolution is rejected naming the field.
class CheckCommand : public testing::Test {
 protected:
  void SetUp() override { dir_ = temp_dir(); }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string render(const std::string& scene, int seed, const std::string& defect) {
    const std::string out = (dir_ / ("r" + std::to_string(seed) + defect + ".exr")).string();
    const Result r = run_cli("render --scene " + scene + " --strategy light_area --spp 64 --seed " +
                             std::to_string(seed) + " --defect " + defect + " --output " + out);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return out;
  }
  std::filesystem::path dir_;
};

const std::string kDisk = std::string(FURNACE_SCENE_DIR) + "/disk_occluder.json";

TEST_F(CheckCommand, IndependentCorrectRendersPass) {
  std::string args;
  for (int seed = 1; seed <= 8; ++seed) args += " --image " + render(kDisk, seed, "none");
  const Result r = run_cli("check --scene " + kDisk + args);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("verdict: PASS"), std::string::npos) << r.output;
}

TEST_F(CheckCommand, DefectiveRendersFail) {
  std::string args;
  for (int seed = 1; seed <= 8; ++seed) args += " --image " + render(kDisk, seed, "drop_light_cosine");
  const Result r = run_cli("check --scene " + kDisk + args);
  EXPECT_EQ(r.exit_code, 1) << r.output;
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
