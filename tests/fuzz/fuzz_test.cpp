// The fuzz test: bad input never crashes, hangs or passes unnoticed.
//
// Deterministic mutations (tests/fuzz/mutations.h, seed kFuzzSeed) of every
// built-in scene and of the command lines of every subcommand:
//  - every mutation of every scene (about 33000) runs in this process
//    through parse_scene, render() (3×3 pixels, 2 spp, one strategy per case
//    in turn), the exact references and one second moment: each either
//    works, with finite references, or throws furnace::Error with one
//    sentence (the CLI's exit 2); any other exception fails the test, a
//    crash names the case on stderr before the process dies, and a case
//    running over kCaseTimeLimit ends the process naming it;
//  - kCliSceneCases scene mutations (sampled with kFuzzSeed) and kCommandLineCases mutated
//    command lines run through the real `furnace` binary under `timeout`
//    (kCaseTimeLimit): the exit code must be 0, 1 or 2 (3 for check), an
//    exit 2 prints exactly one line on stderr naming the scene file or the
//    option, and bad input or a crash leaves no file behind (every output
//    goes to an empty directory of its own, which must stay empty);
//  - tests/fuzz/corpus/: every case that ever crashed or hung, run the same
//    way as regression tests (one CTest test each).
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <ostream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "analytic/global.h"
#include "analytic/moments.h"
#include "analytic/reference.h"
#include "core/error.h"
#include "core/scene.h"
#include "core/strategy.h"
#include "renderer/render.h"
#include "tests/command.h"
#include "tests/fuzz/mutations.h"
#include "tests/test_names.h"

namespace furnace::fuzz {
namespace {

namespace fs = std::filesystem;
using testing_support::run_command;

constexpr uint64_t kFuzzSeed = 0xf0221e5eed;  // fixed: the same cases every run
// Every scene yields several hundred mutations (16 number tokens per number
// alone); fewer means the mutator lost an operator.
constexpr size_t kMinMutationsPerScene = 300;
constexpr size_t kCliSceneCases = 160;
constexpr size_t kCommandLineCases = 160;
// A case that takes longer is a hang: every case here is a few pixels at a
// few samples, a few seconds at most (a one-seed `sweep` of one strategy over
// the suite, ~3 s in Release).
constexpr int kReleaseCaseTimeLimit = 30;
// AddressSanitizer + UBSan (scripts/sanitize.sh) run furnace ~5-15x slower
// (the one-seed sweep above exceeded 30 s there), so an instrumented build
// scales the limit: still a bound that catches a hang, not a failure on time
// alone. Detected from the compiler's own macro, so a plain `ctest` in the
// sanitizer build directory gets it too.
#if defined(__SANITIZE_ADDRESS__)
constexpr int kSanitizerSlowdown = 10;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr int kSanitizerSlowdown = 10;
#else
constexpr int kSanitizerSlowdown = 1;
#endif
#else
constexpr int kSanitizerSlowdown = 1;
#endif
constexpr int kCaseTimeLimit = kReleaseCaseTimeLimit * kSanitizerSlowdown;
constexpr size_t kMaxFailingCasesShown = 20;  // then the in-process run stops
constexpr int kSmallImage = 3;  // in-process renders: at most 3×3 pixels
constexpr int kSpp = 2;
constexpr int kMaxDepth = 3;    // path tracers: camera segment + two bounces

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::vector<fs::path> builtin_scenes() {
  std::vector<fs::path> paths;
  for (const auto& entry : fs::directory_iterator(FURNACE_SCENE_DIR))
    if (entry.path().extension() == ".json") paths.push_back(entry.path());
  std::sort(paths.begin(), paths.end());
  return paths;
}

std::vector<SceneMutation> all_scene_mutations() {
  std::vector<SceneMutation> all;
  for (const fs::path& path : builtin_scenes())
    for (SceneMutation& m : scene_mutations(path.stem().string(), read_file(path))) all.push_back(std::move(m));
  return all;
}

// A scratch directory per test process (environment maps copied in, so the
// scene files written there find theirs), removed at the end.
class ScratchDir {
 public:
  ScratchDir() : dir_(fs::temp_directory_path() / ("furnace_fuzz_" + std::to_string(::getpid()))) {
    fs::create_directories(dir_);
    for (const auto& entry : fs::directory_iterator(FURNACE_SCENE_DIR))
      if (entry.path().extension() == ".exr") fs::copy_file(entry.path(), dir_ / entry.path().filename());
  }
  ~ScratchDir() { fs::remove_all(dir_); }
  const fs::path& path() const { return dir_; }

 private:
  fs::path dir_;
};

// ---------------------------------------------------------------------------
// Crash reporting: the case being run, printed by a fatal signal's handler.

char g_current_case[4096];

void on_fatal_signal(int sig) {
  const char prefix[] = "\nfuzz: fatal signal while running case: ";
  ssize_t ignored = ::write(STDERR_FILENO, prefix, sizeof prefix - 1);
  ignored = ::write(STDERR_FILENO, g_current_case, std::strlen(g_current_case));
  ignored = ::write(STDERR_FILENO, "\n", 1);
  (void)ignored;
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

// When the current case began (steady clock, ns), for the watchdog.
std::atomic<int64_t> g_case_start_ns{0};

int64_t now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

// In-process cases cannot be interrupted: a watchdog thread ends the process,
// naming the case, when one runs longer than kCaseTimeLimit (a hang).
void start_watchdog() {
  static const bool started = [] {
    std::thread([] {
    for (;;) {
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
      const int64_t start = g_case_start_ns.load();
      if (start != 0 && now_ns() - start > int64_t(kCaseTimeLimit) * 1000000000) {
        std::fprintf(stderr, "\nfuzz: case exceeded the %d s time limit (a hang): %s\n", kCaseTimeLimit,
                     g_current_case);
        std::fflush(stderr);
        std::_Exit(1);
      }
    }
    }).detach();
    return true;
  }();
  (void)started;
}

void set_current_case(const std::string& description) {
  std::snprintf(g_current_case, sizeof g_current_case, "%s", description.c_str());
  g_case_start_ns.store(now_ns());
  static const bool installed = [] {
    for (int sig : {SIGABRT, SIGSEGV, SIGFPE, SIGBUS, SIGILL}) std::signal(sig, on_fatal_signal);
    return true;
  }();
  (void)installed;
}

// A furnace::Error message is one sentence on one line.
void expect_sentence(const std::string& message, const std::string& context) {
  EXPECT_FALSE(message.empty()) << context;
  EXPECT_EQ(message.find('\n'), std::string::npos) << context << ": " << message;
  EXPECT_TRUE(!message.empty() && (message.back() == '.' || message.back() == '?')) << context << ": " << message;
}

// ---------------------------------------------------------------------------
// In process.

struct InProcessTally {
  size_t refused = 0;   // parse_scene threw furnace::Error
  size_t accepted = 0;  // parsed; then rendered (or refused by render) and referenced
  double slowest_seconds = 0;
  std::string slowest;
};

// Runs one mutated scene text through the loader, the renderer and the
// references; `source` is where it claims to be (for its environment map).
void run_in_process(const std::string& text, const std::string& source, size_t index,
                    const std::string& description, InProcessTally& tally) {
  set_current_case(description);
  const auto start = std::chrono::steady_clock::now();
  Scene scene;
  try {
    scene = parse_scene(text, source);
  } catch (const Error& e) {
    ++tally.refused;
    expect_sentence(e.what(), description);
    EXPECT_NE(std::string(e.what()).find(source), std::string::npos) << description << ": " << e.what();
    return;
  } catch (const std::exception& e) {
    ADD_FAILURE() << description << ": parse_scene threw a non-furnace exception: " << e.what();
    return;
  }
  ++tally.accepted;
  scene.camera.width_px = std::min(scene.camera.width_px, kSmallImage);
  scene.camera.height_px = std::min(scene.camera.height_px, kSmallImage);
  // One strategy per case, in turn through the table.
  const Strategy strategy = kStrategyTable[index % kStrategyTable.size()].strategy;
  const LightSelection selection = index % 2 ? LightSelection::kPower : LightSelection::kUniform;
  const auto guarded = [&](const char* step, const auto& body) {
    try {
      body();
    } catch (const Error& e) {
      expect_sentence(e.what(), description + " (" + step + ")");
    } catch (const std::exception& e) {
      ADD_FAILURE() << description << ": " << step << " threw a non-furnace exception: " << e.what();
    }
  };
  guarded("render", [&] {
    RenderOptions options;
    options.strategy = strategy;
    options.light_selection = selection;
    options.spp = kSpp;
    options.seed = kFuzzSeed;
    options.threads = 1;
    options.max_depth = kMaxDepth;
    render(scene, options);
  });
  guarded("reference", [&] {
    for (double v : analytic::reference_image(scene))
      EXPECT_TRUE(std::isfinite(v)) << description << ": direct-lighting reference " << v;
  });
  guarded("global reference", [&] {
    for (double v : analytic::global_reference_image(scene, kMaxDepth))
      EXPECT_TRUE(std::isfinite(v)) << description << ": global reference " << v;
  });
  guarded("second moment", [&] {
    const double m2 = analytic::pixel_center_second_moment(strategy, scene, 0, 0, selection);
    EXPECT_FALSE(std::isnan(m2)) << description << ": second moment " << m2;
  });
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (seconds > tally.slowest_seconds) {
    tally.slowest_seconds = seconds;
    tally.slowest = description;
  }
}

// Every mutation of one built-in scene, in process (one test per scene, so a
// hang or crash in one scene's cases leaves the others' results).
class InProcessScene : public testing::TestWithParam<std::string> {};

TEST_P(InProcessScene, MutationsAreRefusedOrWork) {
  const auto start = std::chrono::steady_clock::now();
  const fs::path source = fs::path(FURNACE_SCENE_DIR) / (GetParam() + ".json");
  const std::vector<SceneMutation> cases = scene_mutations(GetParam(), read_file(source));
  InProcessTally tally;
  start_watchdog();
  const testing::TestResult& result = *testing::UnitTest::GetInstance()->current_test_info()->result();
  size_t failing_cases = 0;
  for (size_t i = 0; i < cases.size() && failing_cases < kMaxFailingCasesShown; ++i) {
    const int parts_before = result.total_part_count();
    run_in_process(cases[i].text, source.string(), i, cases[i].description, tally);
    if (result.total_part_count() != parts_before) ++failing_cases;
  }
  g_case_start_ns.store(0);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("in-process scene fuzz of %s: %zu cases: %zu refused, %zu accepted; %.1f s; slowest case %.3f s (%s); "
              "limit %d s per case\n",
              GetParam().c_str(), cases.size(), tally.refused, tally.accepted, seconds, tally.slowest_seconds,
              tally.slowest.c_str(), kCaseTimeLimit);
  EXPECT_GE(cases.size(), kMinMutationsPerScene);
}

std::vector<std::string> builtin_scene_names() {
  std::vector<std::string> names;
  for (const fs::path& p : builtin_scenes()) names.push_back(p.stem().string());
  return names;
}

INSTANTIATE_TEST_SUITE_P(Fuzz, InProcessScene, testing::ValuesIn(builtin_scene_names()),
                         [](const testing::TestParamInfo<std::string>& info) {
                           return testing_support::camel_case(info.param);
                         });

// ---------------------------------------------------------------------------
// Through the binary.

struct CliRun {
  int exit_code;
  std::string err;
  std::vector<std::string> left_behind;  // files in the output directory after the run
};

// Runs `furnace <args>` under `timeout` in `out_dir` (created empty), the
// place every output goes; stdout is discarded.
CliRun run_cli(const std::vector<std::string>& args, const fs::path& out_dir, const fs::path& scratch) {
  fs::create_directories(out_dir);
  const fs::path err_file = scratch / "stderr.txt";
  // Run inside out_dir, so that an output path a mutation made relative lands there too.
  std::string command = "cd " + shell_quote(out_dir.string()) + " && timeout -k 2 " + std::to_string(kCaseTimeLimit) +
                        " " + shell_quote(FURNACE_CLI);
  for (const std::string& a : args) command += " " + shell_quote(a);
  command += " >/dev/null 2>" + shell_quote(err_file.string());
  CliRun run{run_command(command).exit_code, read_file(err_file), {}};
  for (const auto& entry : fs::recursive_directory_iterator(out_dir)) {
    // check --json documents bad input with a complete report of verdict
    // "BAD INPUT" (cli/check_command.h): an answer, not a half-written output.
    if (entry.path().extension() == ".json" && read_file(entry.path()).find("\"BAD INPUT\"") != std::string::npos)
      continue;
    run.left_behind.push_back(entry.path().lexically_relative(out_dir).string());
  }
  fs::remove_all(out_dir);
  return run;
}

// The exit-code contract. `named`: what a one-line error must mention (any
// one of them).
void expect_contract(const CliRun& run, const std::vector<std::string>& named, const std::string& description,
                     bool check_command = false) {
  const bool known_code = run.exit_code == 0 || run.exit_code == 1 || run.exit_code == 2 ||
                          (check_command && run.exit_code == 3);
  EXPECT_TRUE(known_code) << description << ": exit code " << run.exit_code
                          << (run.exit_code == 124 ? " (timed out)" : "") << ", stderr:\n" << run.err;
  if (run.exit_code == 2) {
    // One error line; warnings ("furnace: warning: ...", e.g. of a low spp)
    // may precede it on lines of their own.
    std::vector<std::string> error_lines;
    std::istringstream lines(run.err);
    for (std::string line; std::getline(lines, line);)
      if (line.rfind("furnace: warning:", 0) != 0) error_lines.push_back(line);
    EXPECT_TRUE(error_lines.size() == 1 && !run.err.empty() && run.err.back() == '\n')
        << description << ": an error is one line on stderr, got:\n" << run.err;
    const std::string error = error_lines.empty() ? std::string() : error_lines.front();
    const bool names_it = std::any_of(named.begin(), named.end(), [&](const std::string& n) {
      return !n.empty() && error.find(n) != std::string::npos;
    });
    const bool nothing_to_name = std::all_of(named.begin(), named.end(), [](const std::string& n) { return n.empty(); });
    EXPECT_TRUE(names_it || nothing_to_name) << description << ": the error names none of the file or option ("
                                           << testing::PrintToString(named) << "): " << error;
  }
  // Exit 1 (fail) and 3 (inconclusive) are verdicts whose reports are wanted;
  // bad input and crashes leave nothing.
  if (run.exit_code != 0 && run.exit_code != 1 && run.exit_code != 3) {
    EXPECT_TRUE(run.left_behind.empty()) << description << ": exit " << run.exit_code << " left "
                                         << testing::PrintToString(run.left_behind);
  }
}

// The subcommand a scene case runs through, in turn: render (one strategy
// in turn), analytic, verify, export.
std::vector<std::string> scene_command(size_t index, const std::string& scene, const fs::path& out) {
  const Strategy strategy = kStrategyTable[(index / 4) % kStrategyTable.size()].strategy;
  switch (index % 4) {
    case 0:
      return {"render", "--scene", scene, "--strategy", strategy_name(strategy), "--spp", "2", "--threads", "1",
              "--max-depth", "3", "--output", (out / "out.exr").string()};
    case 1:
      return {"analytic", "--scene", scene, "--point", "0.1,0.2,0", "--normal", "0,0,1", "--json"};
    case 2:
      return {"verify", "--scene", scene, "--strategy", strategy_name(strategy), "--spp", "4", "--threads", "1",
              "--max-depth", "3"};
    default:
      return {"export", "--scene", scene, "--format", "pbrt-v4", "--spp", "4", "-o", (out / "out.pbrt").string()};
  }
}

TEST(Fuzz, SceneMutationsThroughTheCli) {
  const auto start = std::chrono::steady_clock::now();
  const ScratchDir scratch;
  const std::vector<SceneMutation> cases = sample(all_scene_mutations(), kCliSceneCases, 0, kFuzzSeed);
  ASSERT_EQ(cases.size(), kCliSceneCases);
  size_t by_code[4] = {0, 0, 0, 0};
  for (size_t i = 0; i < cases.size(); ++i) {
    const fs::path scene = scratch.path() / (cases[i].scene + ".json");
    std::ofstream(scene, std::ios::binary) << cases[i].text;
    const fs::path out = scratch.path() / "out";
    const std::vector<std::string> args = scene_command(i, scene.string(), out);
    const CliRun run = run_cli(args, out, scratch.path());
    expect_contract(run, {scene.string()}, cases[i].description + " [furnace " + args[0] + "]");
    if (run.exit_code >= 0 && run.exit_code <= 2) ++by_code[run.exit_code];
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("CLI scene fuzz: %zu cases: exit 0: %zu, exit 1: %zu, exit 2: %zu; %.1f s; limit %d s per case\n",
              cases.size(), by_code[0], by_code[1], by_code[2], seconds, kCaseTimeLimit);
}

// The base command lines: every subcommand with cheap, valid options; the
// options that bound the work are never dropped by a mutation.
struct BaseCommand {
  std::vector<std::string> args;
  std::vector<std::string> bounding;
};

std::vector<BaseCommand> base_commands(const fs::path& scratch, const fs::path& out) {
  const std::string scenes = FURNACE_SCENE_DIR;
  const std::string image_a = (scratch / "a.exr").string(), image_b = (scratch / "b.exr").string();
  return {
      {{"render", "--scene", scenes + "/disk_occluder.json", "--strategy", "light_area", "--spp", "2", "--seed", "7",
        "--threads", "1", "--max-depth", "2", "--roulette-depth", "3", "--light-selection", "power", "--output",
        (out / "out.exr").string()},
       {"--spp"}},
      {{"verify", "--scene", scenes + "/point_light_unoccluded.json", "--strategy", "light_area", "--spp", "4",
        "--seed", "7", "--threads", "1", "--alpha", "0.01", "--max-depth", "2", "--light-selection", "uniform"},
       {"--spp", "--scene"}},
      {{"analytic", "--scene", scenes + "/three_lights.json", "--point", "0.1,0.2,0", "--normal", "0,0,1", "--albedo",
        "0.5", "--json"},
       {}},
      {{"check", "--scene", scenes + "/disk_occluder.json", "--image", image_a, "--image", image_b, "--alpha", "0.01",
        "--max-depth", "2", "--max-detectable-bias", "0.01", "--channels", "gray", "--zmap", (out / "t.exr").string(),
        "--json", (out / "r.json").string()},
       {}},
      {{"compare", "--a", image_a, "--a", image_b, "--b", (scratch / "c.exr").string(), "--b",
        (scratch / "d.exr").string(), "--alpha", "0.01", "--max-detectable-difference", "0.01", "--tile", "4",
        "--channels", "gray", "--zmap", (out / "t.exr").string(), "--json", (out / "r.json").string()},
       {}},
      {{"export", "--scene", scenes + "/disk_occluder.json", "--format", "pbrt-v4", "--spp", "4", "--seed", "3",
        "--max-depth", "2", "-o", (out / "x.pbrt").string()},
       {}},
      {{"report", "--strategy", "light_area", "--min-spp", "2", "--max-spp", "2", "--seed", "1", "--threads", "1",
        "--output-dir", (out / "report").string(), "--no-html"},
       {"--strategy", "--max-spp", "--min-spp", "--no-html"}},
      {{"sweep", "--strategy", "light_area", "--seeds", "1", "--spp", "2", "--case-alpha", "0.05", "--threads", "1"},
       {"--strategy", "--seeds", "--spp"}},
  };
}

TEST(Fuzz, CommandLineMutations) {
  const auto start = std::chrono::steady_clock::now();
  const ScratchDir scratch;
  const fs::path out = scratch.path() / "out";
  // Four renders of disk_occluder for `check` and `compare` to read.
  for (const char* image : {"a.exr", "b.exr", "c.exr", "d.exr"}) {
    const CliRun made = run_cli({"render", "--scene", std::string(FURNACE_SCENE_DIR) + "/disk_occluder.json",
                                 "--spp", "4", "--seed", std::to_string(image[0] - 'a' + 1), "--threads", "1", "--output",
                                 (scratch.path() / image).string()},
                                out, scratch.path());
    ASSERT_EQ(made.exit_code, 0) << made.err;
  }
  std::vector<CommandLine> all;
  for (const BaseCommand& base : base_commands(scratch.path(), out)) {
    for (CommandLine& c : command_mutations(base.args, base.bounding)) all.push_back(std::move(c));
  }
  // A fixed sample, every base command in proportion.
  std::vector<CommandLine> cases;
  SplitMix64 rng(kFuzzSeed);
  for (size_t i = all.size(); i > 1; --i) std::swap(all[i - 1], all[rng.below(i)]);
  cases.assign(all.begin(), all.begin() + long(std::min(kCommandLineCases, all.size())));
  cases.push_back({"no arguments", {}, ""});
  size_t by_code[4] = {0, 0, 0, 0};
  for (const CommandLine& c : cases) {
    const CliRun run = run_cli(c.args, out, scratch.path());
    std::vector<std::string> named = {c.named};
    for (size_t i = 0; i + 1 < c.args.size(); ++i)
      if (c.args[i] == "--scene" || c.args[i] == "--image" || c.args[i] == "--a" || c.args[i] == "--b")
        // An empty file name is named as the messages quote it: ''.
        named.push_back(c.args[i + 1].empty() ? "''" : c.args[i + 1]);
    expect_contract(run, named, c.description, !c.args.empty() && (c.args[0] == "check" || c.args[0] == "compare"));
    if (run.exit_code >= 0 && run.exit_code <= 3) ++by_code[std::min(run.exit_code, 3)];
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("command-line fuzz: %zu cases (of %zu mutations): exit 0: %zu, exit 1: %zu, exit 2: %zu, exit 3: %zu; "
              "%.1f s; limit %d s per case\n", cases.size(), all.size(), by_code[0], by_code[1], by_code[2], by_code[3], seconds,
              kCaseTimeLimit);
}

// ---------------------------------------------------------------------------
// Long paths: the closed enclosures with albedo 1 and its near-1 neighbours,
// marked closed and (wrongly) open, at unlimited depth through every path
// tracer (core/path_length.h). A closed scene is refused when its bound on
// the expected path length, 3 + ρ/(1−ρ) segments with the default roulette,
// exceeds 1e5 (ρ ≥ 1 − 1e-5) or its answer is infinite (ρ = 1); an open one
// is rendered, and a path that reaches 2^20 segments ends the render as bad
// input. Every case ends well inside the time limit, with the exit-code
// contract; `report` and `export` refuse the albedo-1 enclosure too.

struct LongPathCase {
  double albedo;
  bool closed;
  std::vector<int> exit_codes;  // the ones allowed
};

std::string with_albedo(const std::string& text, double albedo, bool closed) {
  nlohmann::json j = nlohmann::json::parse(text);
  j["closed"] = closed;
  j["camera"]["resolution"] = {2, 2};
  for (auto& o : j["objects"])
    if (o.contains("material")) o["material"]["albedo"] = albedo;
  return j.dump();
}

TEST(Fuzz, LongPathsAreRefusedOrEndInTime) {
  const auto start = std::chrono::steady_clock::now();
  const ScratchDir scratch;
  const fs::path out = scratch.path() / "out";
  const std::vector<LongPathCase> cases = {
      {1, true, {2}},           {1 - 1e-6, true, {2}},     {1 - 1e-5, true, {2}},  {1 - 1e-4, true, {0}},
      {0.999, true, {0}},       {1, false, {2}},           {1 - 1e-6, false, {0, 2}}, {1 - 1e-5, false, {0, 2}},
      {1 - 1e-4, false, {0}},   {0.999, false, {0}},
  };
  std::vector<std::string> path_tracers;
  for (const StrategyInfo& info : kStrategyTable)
    if (is_path_tracer(info.strategy)) path_tracers.push_back(info.name);
  ASSERT_GE(path_tracers.size(), 2u);
  size_t runs = 0, refused = 0;
  for (const char* name : {"enclosure_sphere", "enclosure_box", "enclosure_blockers"}) {
    const std::string text = read_file(fs::path(FURNACE_SCENE_DIR) / (std::string(name) + ".json"));
    for (size_t i = 0; i < cases.size(); ++i) {
      const LongPathCase& c = cases[i];
      const fs::path scene = scratch.path() / fmt::format("{}_{}_{:.0e}.json", name, c.closed ? "closed" : "open",
                                                          1 - c.albedo);
      std::ofstream(scene, std::ios::binary) << with_albedo(text, c.albedo, c.closed);
      const std::string strategy = path_tracers[(i + runs) % path_tracers.size()];
      const std::string description = fmt::format("{} (albedo {}, {}) through {}", scene.filename().string(),
                                                  c.albedo, c.closed ? "closed" : "open", strategy);
      const CliRun run = run_cli({"render", "--scene", scene.string(), "--strategy", strategy, "--spp", "1",
                                  "--threads", "1", "--output", (out / "out.exr").string()},
                                 out, scratch.path());
      ++runs;
      refused += run.exit_code == 2;
      EXPECT_NE(std::find(c.exit_codes.begin(), c.exit_codes.end(), run.exit_code), c.exit_codes.end())
          << description << ": exit " << run.exit_code << ", stderr:\n" << run.err;
      expect_contract(run, {scene.string()}, description);
      if (c.albedo == 1 && c.closed)
        EXPECT_NE(run.err.find("infinite radiance"), std::string::npos) << description << ": " << run.err;
      if (c.albedo == 1 && c.closed) {
        for (const std::vector<std::string>& args : std::vector<std::vector<std::string>>{
                 {"report", "--scene", scene.string(), "--strategy", strategy, "--min-spp", "2", "--max-spp", "2",
                  "--threads", "1", "--no-html", "--output-dir", (out / "report").string()},
                 {"export", "--scene", scene.string(), "--format", "pbrt-v4", "-o", (out / "x.pbrt").string()},
                 {"export", "--scene", scene.string(), "--format", "cycles", "-o", (out / "x.py").string()}}) {
          const CliRun other = run_cli(args, out, scratch.path());
          ++runs;
          EXPECT_EQ(other.exit_code, 2) << description << " [furnace " << args[0] << "]: " << other.err;
          expect_contract(other, {scene.string()}, description + " [furnace " + args[0] + "]");
        }
      }
    }
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("long-path fuzz: %zu runs (%zu renders refused); %.1f s; limit %d s per case\n", runs, refused, seconds,
              kCaseTimeLimit);
}

// ---------------------------------------------------------------------------
// The corpus: every case that ever crashed or hung.

// A scene file of tests/fuzz/corpus/: run in process and through render,
// analytic and verify.
class CorpusScene : public testing::TestWithParam<std::string> {};

TEST_P(CorpusScene, NeitherCrashesNorHangs) {
  const fs::path original = fs::path(FURNACE_FUZZ_CORPUS) / (GetParam() + ".json");
  const ScratchDir scratch;
  const fs::path scene = scratch.path() / original.filename();
  fs::copy_file(original, scene);
  InProcessTally tally;
  start_watchdog();
  for (size_t index = 0; index < kStrategyTable.size(); ++index)
    run_in_process(read_file(scene), scene.string(), index, GetParam(), tally);
  g_case_start_ns.store(0);
  const fs::path out = scratch.path() / "out";
  for (size_t index = 0; index < 4; ++index) {
    const std::vector<std::string> args = scene_command(index, scene.string(), out);
    expect_contract(run_cli(args, out, scratch.path()), {scene.string()}, GetParam() + " [furnace " + args[0] + "]");
  }
}

std::vector<std::string> corpus_scenes() {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(FURNACE_FUZZ_CORPUS))
    if (entry.path().extension() == ".json") names.push_back(entry.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

INSTANTIATE_TEST_SUITE_P(FuzzCorpus, CorpusScene, testing::ValuesIn(corpus_scenes()),
                         [](const testing::TestParamInfo<std::string>& info) {
                           return testing_support::camel_case(info.param);
                         });

// A line of tests/fuzz/corpus/command_lines.txt: "name: arguments", with
// {scenes} the built-in scene directory and {out} an empty output directory
// (a file named 'file' is in it, for options given a file where a directory
// belongs); '#' starts a comment line.
struct CorpusCommand {
  std::string name;
  std::string arguments;
};

void PrintTo(const CorpusCommand& c, std::ostream* os) { *os << c.name; }

std::vector<CorpusCommand> corpus_commands() {
  std::vector<CorpusCommand> out;
  std::ifstream in(fs::path(FURNACE_FUZZ_CORPUS) / "command_lines.txt");
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    const size_t colon = line.find(": ");
    if (colon == std::string::npos) continue;
    out.push_back({line.substr(0, colon), line.substr(colon + 2)});
  }
  return out;
}

std::string substituted(std::string text, const std::string& from, const std::string& to) {
  for (size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
    text.replace(at, from.size(), to);
  return text;
}

class CorpusCommandLine : public testing::TestWithParam<CorpusCommand> {};

TEST_P(CorpusCommandLine, ObeysTheExitCodeContract) {
  const ScratchDir scratch;
  const fs::path out = scratch.path() / "out";
  fs::create_directories(out);
  std::ofstream(out / "file") << "a regular file\n";
  const std::string arguments =
      substituted(substituted(GetParam().arguments, "{scenes}", FURNACE_SCENE_DIR), "{out}", out.string());
  // Split on spaces; '' is an empty argument.
  std::vector<std::string> args;
  std::istringstream words(arguments);
  for (std::string w; words >> w;) args.push_back(w == "''" ? std::string() : w);
  const CliRun run = run_cli(args, out, scratch.path());
  // The pre-made file is the only thing allowed in the output directory.
  CliRun checked = run;
  checked.left_behind.erase(std::remove(checked.left_behind.begin(), checked.left_behind.end(), "file"),
                            checked.left_behind.end());
  std::vector<std::string> named;
  for (const std::string& a : args)
    if (a.rfind("--", 0) == 0 || a.find('/') != std::string::npos) named.push_back(a);
  expect_contract(checked, named, GetParam().name + " (" + arguments + ")", !args.empty() && args[0] == "check");
}

INSTANTIATE_TEST_SUITE_P(FuzzCorpus, CorpusCommandLine, testing::ValuesIn(corpus_commands()),
                         [](const testing::TestParamInfo<CorpusCommand>& info) {
                           return testing_support::camel_case(info.param.name);
                         });

}  // namespace
}  // namespace furnace::fuzz
