// The command line's validators (cli/cli_options.h) and progress line
// (cli/progress.h): each validator on both sides of its bounds, on NaN,
// infinities, wrapped or octal integers, and on output paths that cannot be
// written.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include "core/error.h"
#include "cli/cli_options.h"
#include "cli/progress.h"

namespace furnace::cli {
namespace {

// The validator's verdict on `text`: empty when accepted; `text` becomes the
// string CLI11 then converts.
std::string check(const CLI::Validator& v, std::string& text) { return v(text); }
bool accepts(const CLI::Validator& v, std::string text) { return check(v, text).empty(); }

TEST(IntegerIn, AcceptsItsBoundsAndRejectsBeyondThem) {
  const CLI::Validator v = integer_in(2, 100);
  EXPECT_TRUE(accepts(v, "2"));
  EXPECT_TRUE(accepts(v, "100"));
  EXPECT_FALSE(accepts(v, "1"));
  EXPECT_FALSE(accepts(v, "101"));
  EXPECT_FALSE(accepts(v, "-3"));
}

TEST(IntegerIn, RejectsWhatIsNotADecimalIntegerAndNamesTheValue) {
  const CLI::Validator v = integer_in(0, 1 << 24);
  for (const char* bad : {"", "abc", "1e3", "2.5", "0x10", "+5", " 5", "5 ", "nan", "99999999999999999999"}) {
    std::string text = bad;
    const std::string message = check(v, text);
    EXPECT_FALSE(message.empty()) << bad;
    EXPECT_NE(message.find("'" + std::string(bad) + "'"), std::string::npos) << message;
  }
}

TEST(IntegerIn, RewritesLeadingZerosSoTheValueIsNotReadAsOctal) {
  std::string text = "010";
  EXPECT_TRUE(check(integer_in(0, 100), text).empty());
  EXPECT_EQ(text, "10");
}

TEST(SeedValue, TakesTheFullUnsignedRangeAndNothingThatWouldWrap) {
  const CLI::Validator v = seed_value();
  EXPECT_TRUE(accepts(v, "0"));
  EXPECT_TRUE(accepts(v, "18446744073709551615"));  // 2^64 − 1
  EXPECT_FALSE(accepts(v, "18446744073709551616"));  // 2^64: strtoull saturates to 2^64 − 1
  EXPECT_FALSE(accepts(v, "-1"));                    // strtoull wraps to 2^64 − 1
  EXPECT_FALSE(accepts(v, "1.5"));
  EXPECT_FALSE(accepts(v, ""));
}

TEST(NumberIn, RejectsNonFiniteValuesThatCliRangeLetsThrough) {
  const CLI::Validator v = number_in(1e-12, 0.5);
  EXPECT_TRUE(accepts(v, "0.01"));
  EXPECT_TRUE(accepts(v, "1e-12"));
  EXPECT_TRUE(accepts(v, "0.5"));
  for (const char* bad : {"nan", "NaN", "-nan", "inf", "-inf", "infinity", "1e400", "0.5000001", "1e-13", "0", "x", ""})
    EXPECT_FALSE(accepts(v, bad)) << bad;
}

TEST(NumberIn, OpenEndsExcludeTheirBound) {
  const CLI::Validator v = number_in(0, 1, End::kOpen);
  EXPECT_FALSE(accepts(v, "0"));
  EXPECT_TRUE(accepts(v, "1e-300"));
  EXPECT_TRUE(accepts(v, "1"));
  const CLI::Validator both = number_in(0, 1, End::kOpen, End::kOpen);
  EXPECT_FALSE(accepts(both, "1"));
  EXPECT_TRUE(accepts(both, "0.999"));
}

TEST(FiniteNumber, RejectsNanAndInfinity) {
  EXPECT_TRUE(accepts(finite_number(), "-1000"));
  EXPECT_TRUE(accepts(finite_number(), "1e300"));
  for (const char* bad : {"nan", "inf", "-inf", "1e999", "1,2", ""}) EXPECT_FALSE(accepts(finite_number(), bad)) << bad;
}

class OutputPaths : public testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() / ("furnace_cli_options_test_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
    std::ofstream(dir_ / "afile") << "x";
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::filesystem::path dir_;
};

TEST_F(OutputPaths, FileNeedsAnExistingWritableDirectory) {
  EXPECT_TRUE(accepts(output_file(), path("out.exr")));
  EXPECT_TRUE(accepts(output_file(), path("afile")));  // overwritten atomically
  EXPECT_FALSE(accepts(output_file(), path("missing/out.exr")));
  EXPECT_FALSE(accepts(output_file(), path("afile/out.exr")));
  EXPECT_FALSE(accepts(output_file(), dir_.string()));  // a directory
  EXPECT_FALSE(accepts(output_file(), ""));
  EXPECT_TRUE(accepts(output_file(true), "-"));
}

TEST_F(OutputPaths, DirectoryMayBeCreatedUnlessAFileIsInTheWay) {
  EXPECT_TRUE(accepts(output_directory(), dir_.string()));
  EXPECT_TRUE(accepts(output_directory(), path("new/deeper")));
  EXPECT_FALSE(accepts(output_directory(), path("afile")));
  EXPECT_FALSE(accepts(output_directory(), path("afile/sub")));
  EXPECT_FALSE(accepts(output_directory(), ""));
  create_output_directory(path("new/deeper"), "--output-dir");
  EXPECT_TRUE(std::filesystem::is_directory(path("new/deeper")));
  EXPECT_THROW(create_output_directory(path("afile/sub"), "--output-dir"), Error);
}

// A relative name whose every component is new (`--output-dir reports`)
// is created in the working directory: accepted there, refused where the
// working directory cannot be written.
TEST_F(OutputPaths, RelativeNewDirectoryIsCreatedInTheWorkingDirectory) {
  const std::filesystem::path before = std::filesystem::current_path();
  std::filesystem::current_path(dir_);
  EXPECT_TRUE(accepts(output_directory(), "fresh"));
  EXPECT_TRUE(accepts(output_directory(), "fresh/deeper"));
  EXPECT_TRUE(accepts(output_file(), "out.exr"));
  EXPECT_FALSE(accepts(output_directory(), "afile/sub"));
  std::filesystem::create_directories(dir_ / "locked");
  std::filesystem::permissions(dir_ / "locked", std::filesystem::perms::owner_read | std::filesystem::perms::owner_exec);
  std::filesystem::current_path(dir_ / "locked");
  if (::geteuid() != 0) EXPECT_FALSE(accepts(output_directory(), "fresh"));  // root writes anywhere
  std::filesystem::current_path(before);
  std::filesystem::permissions(dir_ / "locked", std::filesystem::perms::owner_all);
}

TEST(ParseErrorMessage, NamesAnUnknownSubcommandOrListsThem) {
  CLI::App app{"t"};
  app.require_subcommand(1);
  app.add_subcommand("render", "");
  app.add_subcommand("verify", "");
  const auto message_for = [&](std::vector<std::string> args) {
    std::reverse(args.begin(), args.end());  // CLI11 takes them reversed
    try {
      app.parse(args);
    } catch (const CLI::ParseError& e) {
      return parse_error_message(app, e);
    }
    return std::string("parsed");
  };
  const std::string unknown = message_for({"frobnicate"});
  EXPECT_NE(unknown.find("unknown subcommand 'frobnicate'"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("render, verify"), std::string::npos) << unknown;
  app.clear();
  const std::string none = message_for({});
  EXPECT_NE(none.find("a subcommand is required"), std::string::npos) << none;
  EXPECT_EQ(none.find('\n'), std::string::npos) << none;
}

// Parses `args` (after the program name) into a fresh app built by `bind`;
// returns CLI11's message, or empty when parsing succeeded.
template <typename Bind>
std::string parse_with(Bind bind, std::vector<std::string> args) {
  CLI::App app{"t"};
  bind(app);
  std::reverse(args.begin(), args.end());  // CLI11 takes them reversed
  try {
    app.parse(args);
  } catch (const CLI::ParseError& e) {
    return e.what();
  }
  return "";
}

// The validator's text is what CLI11 converts: bound with transform(), a
// leading zero is decimal; bound with check() (the negative control), the
// rewrite is dropped and strtoll reads octal.
TEST(IntegerIn, BoundWithTransformTheOptionReadsDecimal) {
  int spp = 0;
  EXPECT_EQ(parse_with([&](CLI::App& app) { app.add_option("--spp", spp)->transform(integer_in(1, 100)); },
                       {"--spp", "010"}), "");
  EXPECT_EQ(spp, 10);
  EXPECT_EQ(parse_with([&](CLI::App& app) { app.add_option("--spp", spp)->check(integer_in(1, 100)); },
                       {"--spp", "010"}), "");
  EXPECT_EQ(spp, 8);
}

TEST(MaxDepthOption, TakesUnlimitedInAnyCaseAndCanonicalNumbers) {
  int depth = 0;
  const auto bind = [&](CLI::App& app) { max_depth_option(app.add_option("--max-depth", depth)); };
  EXPECT_EQ(parse_with(bind, {"--max-depth", "Unlimited"}), "");
  EXPECT_EQ(depth, kUnlimitedDepth);
  EXPECT_EQ(parse_with(bind, {"--max-depth", "010"}), "");
  EXPECT_EQ(depth, 10);
  for (const char* bad : {"0", "infinite", "-3", "2.5"})
    EXPECT_NE(parse_with(bind, {"--max-depth", bad}), "") << bad;
}

// Every name of each table parses to its own row's enumerator, once, in the
// option's enum variable.
TEST(EnumByName, EveryTableNameParsesToItsEnumerator) {
  for (const StrategyInfo& info : kStrategyTable) {
    Strategy s = Strategy(-1);
    EXPECT_EQ(parse_with([&](CLI::App& app) { app.add_option("--strategy", s)->transform(strategy_by_name()); },
                         {"--strategy", info.name}), "");
    EXPECT_EQ(s, info.strategy) << info.name;
  }
  for (const DefectInfo& info : kDefectTable) {
    Defect d = Defect(-1);
    EXPECT_EQ(parse_with([&](CLI::App& app) { app.add_option("--defect", d)->transform(defect_by_name()); },
                         {"--defect", info.name}), "");
    EXPECT_EQ(d, info.defect) << info.name;
  }
  for (const auto& [name, selection] : light_selection_names()) {
    LightSelection l = LightSelection(-1);
    EXPECT_EQ(parse_with([&](CLI::App& app) { app.add_option("--light-selection", l)->transform(light_selection_by_name()); },
                         {"--light-selection", name}), "");
    EXPECT_EQ(l, selection) << name;
  }
  std::vector<Strategy> several;
  EXPECT_EQ(parse_with([&](CLI::App& app) { app.add_option("--strategy", several)->transform(strategy_by_name()); },
                       {"--strategy", "bsdf", "--strategy", "path_mis"}), "");
  EXPECT_EQ(several, (std::vector<Strategy>{Strategy::kBsdf, Strategy::kPathMis}));
}

// Anything but a name is refused in IsMember's words, an enumerator's number
// included (CLI11's CheckedTransformer would take "2" for light_area).
TEST(EnumByName, RefusesOtherWordsAndNumbersNamingTheValueAndTheNames) {
  const auto message_for = [](const std::string& value) {
    LightSelection l = LightSelection::kUniform;
    return parse_with([&](CLI::App& app) { app.add_option("--light-selection", l)->transform(light_selection_by_name()); },
                      {"--light-selection", value});
  };
  EXPECT_NE(message_for("flux").find("--light-selection: flux not in {power,uniform}"), std::string::npos)
      << message_for("flux");
  for (const char* bad : {"1", "0", "Power", "", "power "}) EXPECT_NE(message_for(bad), "") << bad;
  Strategy s = Strategy::kLightArea;
  EXPECT_NE(parse_with([&](CLI::App& app) { app.add_option("--strategy", s)->transform(strategy_by_name()); },
                       {"--strategy", "2"}), "");
}

// --help lists the names in table order.
TEST(EnumByName, DescriptionListsTheNamesInTableOrder) {
  std::string expected = "{";
  for (const StrategyInfo& info : kStrategyTable) expected += std::string(expected.size() > 1 ? "," : "") + info.name;
  EXPECT_EQ(strategy_by_name().get_description(), expected + "}");
  EXPECT_EQ(light_selection_by_name().get_description(), "{power,uniform}");
}

}  // namespace
}  // namespace furnace::cli

namespace furnace::verify {
namespace {

TEST(Progress, LineCountsElapsedAndRemainingTime) {
  EXPECT_EQ(Progress::line("verify", 0, 10, 0), "verify: 0/10 done, 0 s elapsed");
  EXPECT_EQ(Progress::line("verify", 5, 20, 30), "verify: 5/20 done, 30 s elapsed, ~1.5 min left");
  EXPECT_EQ(Progress::line("sweep", 20, 20, 7200), "sweep: 20/20 done, 2.0 h elapsed");
}

}  // namespace
}  // namespace furnace::verify
