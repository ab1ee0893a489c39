// The `furnace` command line's contract and the CLI11 validators every
// numeric and output option uses, so that each subcommand parses alike.
//
// Exit codes, every subcommand (kExitContract is the text --help prints):
//   0 pass, 1 fail, 2 bad input (every argument-parsing error included:
//   unknown option or subcommand, missing or extra value, wrong type, out of
//   range, missing requirement), 3 inconclusive (check, compare, verify).
// An argument error is one line on stderr, "furnace: error: --option: why",
// naming the option and the value.
//
// The validators parse the option's text once, completely, in decimal, and
// reject what CLI11's own conversion would accept silently: NaN and ±inf for
// numbers (CLI::Range lets NaN through), "-1" or 2^64 for a seed (strtoull
// wraps both to 2^64 − 1), "010" (octal 8 to strtoll). An accepted integer is
// rewritten in canonical decimal so CLI11's conversion reads the same value:
// bind integer_in and seed_value with transform(), never check(), which runs
// a validator on a copy of the text and drops the rewrite.
#pragma once

#include <cstdint>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

#include "core/strategy.h"

namespace furnace::cli {

inline constexpr int kExitPass = 0;
inline constexpr int kExitFail = 1;
inline constexpr int kExitBadInput = 2;
inline constexpr int kExitInconclusive = 3;
extern const char* const kExitContract;

// A decimal integer in [lo, hi].
CLI::Validator integer_in(int64_t lo, int64_t hi);
// A decimal integer in [0, 2^64 − 1] (random seeds).
CLI::Validator seed_value();

// A finite number in the interval from lo to hi; each end is included unless
// its `open_*` flag says otherwise (e.g. α in (0, 0.5]).
enum class End { kClosed, kOpen };
CLI::Validator number_in(double lo, double hi, End low_end = End::kClosed, End high_end = End::kClosed);
// Any finite number (each coordinate of --point, --normal).
CLI::Validator finite_number();

// An output file path that can be written now: not empty, not a directory,
// its directory exists and is a writable directory. `stdout_dash` also
// accepts "-" (standard output). Checked at parse time, before any work.
CLI::Validator output_file(bool stdout_dash = false);
// An output directory that exists (or can be created: the nearest existing
// ancestor is a writable directory, and no component is a file).
CLI::Validator output_directory();

// A name of one vocabulary (`names`, in the order --help lists them) stored
// in the option's enum variable: the name is looked up here, once, and CLI11
// is handed the enumerator's number, which it converts into the enum.
// Anything else, a number included, is refused in CLI11's IsMember words:
// "power3 not in {power,uniform}". Bind it with transform(), as integer_in.
template <typename Enum>
CLI::Validator enum_by_name(std::vector<std::pair<std::string, Enum>> names) {
  static_assert(std::is_enum_v<Enum>);
  std::string set;
  for (const auto& [name, value] : names) set += (set.empty() ? "{" : ",") + name;
  set += "}";
  return CLI::Validator(
      [names, set](std::string& text) -> std::string {
        for (const auto& [name, value] : names)
          if (name == text) {
            text = std::to_string(static_cast<std::underlying_type_t<Enum>>(value));
            return "";
          }
        return text + " not in " + set;
      },
      set);
}
// The vocabularies of core/strategy.h, from their tables: strategies and
// defects in table order, light selections by name (as --help always listed
// them).
CLI::Validator strategy_by_name();
CLI::Validator defect_by_name();
CLI::Validator light_selection_by_name();
// --convention radiance|none (core/strategy.h's TransportConvention), default shown.
CLI::Option* add_convention_option(CLI::App* command, TransportConvention& convention);

// Upper bounds of the integer options: 2^24 spp keeps spp × pixels × path
// length far inside 64-bit counters; 1024 threads is beyond any machine the
// tests run on while still catching a mistyped number.
inline constexpr int kMaxSpp = 1 << 24;
inline constexpr int kMaxThreads = 1024;
// α of a whole run, in [1e-12, 0.5]: at least 1e-12 so that its Šidák share
// of one test among ~10⁵ (cases × pixels) is still a representable level.
CLI::Validator family_alpha();

// Makes `option` a --max-depth, the same for render, verify, check and
// export: the longest path in segments (the camera segment counts as 1; 2 is
// direct lighting), a number >= 1 or the word "unlimited" (kUnlimitedDepth).
CLI::Option* max_depth_option(CLI::Option* option);

// Options several subcommands share, worded and checked alike:
// --threads N ("Worker threads (0: all)"), --seed S ("Random seed") and
// --strategy NAME... ("Strategy name(s); default: all"), the first two
// showing their default.
CLI::Option* add_threads_option(CLI::App* command, int& threads);
CLI::Option* add_seed_option(CLI::App* command, uint64_t& seed);
CLI::Option* add_strategies_option(CLI::App* command, std::vector<Strategy>& strategies);

// Ends `command`'s --help with `footer` (if any), then the exit-code contract.
void set_contract_footer(CLI::App* command, const std::string& footer = "");

// "furnace ARG1 ARG2 ...", as the reports record the run.
std::string command_line_text(int argc, char** argv);

// Creates `dir` (and its parents) or throws furnace::Error naming `option`
// and the reason; call before any work whose result goes there.
void create_output_directory(const std::string& dir, const std::string& option);

// The one-line message for a CLI11 parse error (without the "furnace: error: "
// prefix): CLI11's text, except that a missing subcommand names the unknown
// word given instead (`remaining`) or lists the subcommands.
std::string parse_error_message(const CLI::App& app, const CLI::Error& e);

}  // namespace furnace::cli
