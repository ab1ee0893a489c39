// The `furnace` command line's contract and the CLI11 validators every
// numeric and output option uses, so that each subcommand parses alike.
//
// Exit codes, every subcommand (kExitContract is the text --help prints):
//   0 pass, 1 fail, 2 bad input (every argument-parsing error included:
//   unknown option or subcommand, missing or extra value, wrong type, out of
//   range, missing requirement), 3 inconclusive (check only).
// An argument error is one line on stderr, "furnace: error: --option: why",
// naming the option and the value.
//
// The validators parse the option's text once, completely, in decimal, and
// reject what CLI11's own conversion would accept silently: NaN and ±inf for
// numbers (CLI::Range lets NaN through), "-1" or 2^64 for a seed (strtoull
// wraps both to 2^64 − 1), "010" (octal 8 to strtoll). An accepted integer is
// rewritten in canonical decimal so CLI11's conversion reads the same value.
#pragma once

#include <cstdint>
#include <string>

#include <CLI/CLI.hpp>

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

// Creates `dir` (and its parents) or throws furnace::Error naming `option`
// and the reason; call before any work whose result goes there.
void create_output_directory(const std::string& dir, const std::string& option);

// The one-line message for a CLI11 parse error (without the "furnace: error: "
// prefix): CLI11's text, except that a missing subcommand names the unknown
// word given instead (`remaining`) or lists the subcommands.
std::string parse_error_message(const CLI::App& app, const CLI::Error& e);

}  // namespace furnace::cli
