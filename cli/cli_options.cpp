#include "cli/cli_options.h"

#include <unistd.h>

#include <charconv>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <optional>
#include <system_error>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/error.h"

namespace furnace::cli {

const char* const kExitContract =
    "Exit codes (every subcommand): 0 pass, 1 fail, 2 bad input (any argument error, scene files, images, output "
    "paths; one line on stderr), 3 inconclusive (check, compare: no test rejects but the test lacks the stated "
    "power, or a rare-event guard (compare's, check --guard) held a test; verify: a case rejected where its spp "
    "cannot support the rejection, and none failed).";

namespace {

namespace fs = std::filesystem;

// The whole of `text` as a base-10 integer of type T (no sign for unsigned
// T, no leading '+', no spaces); empty on anything else or out of T's range.
template <typename T>
std::optional<T> parse_decimal(const std::string& text) {
  T value{};
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, value, 10);
  if (text.empty() || ec != std::errc() || ptr != end) return std::nullopt;
  return value;
}

std::string interval_text(double lo, double hi, End low_end, End high_end) {
  return fmt::format("{}{:g}, {:g}{}", low_end == End::kOpen ? "(" : "[", lo, hi, high_end == End::kOpen ? ")" : "]");
}

// The nearest existing ancestor of `path` (itself if it exists); empty when
// none can be examined or a relative path's every component is new (the
// working directory is then the one to examine).
fs::path nearest_existing(fs::path path) {
  std::error_code ec;
  while (!path.empty() && !fs::exists(fs::symlink_status(path, ec))) {
    const fs::path parent = path.parent_path();
    if (parent == path) break;  // a root that does not exist
    path = parent;
  }
  return path;
}

// Empty if `dir` is an existing directory this process can create files in;
// else the reason, one clause.
std::string writable_directory_problem(const fs::path& dir) {
  std::error_code ec;
  if (!fs::exists(dir, ec)) return fmt::format("directory '{}' does not exist", dir.string());
  if (!fs::is_directory(dir, ec)) return fmt::format("'{}' is not a directory", dir.string());
  if (::access(dir.c_str(), W_OK | X_OK) != 0) return fmt::format("directory '{}' is not writable", dir.string());
  return "";
}

}  // namespace

CLI::Validator integer_in(int64_t lo, int64_t hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        const std::optional<int64_t> value = parse_decimal<int64_t>(text);
        if (!value || *value < lo || *value > hi)
          return fmt::format("must be a decimal integer in [{}, {}], got '{}'", lo, hi, text);
        text = std::to_string(*value);  // canonical decimal: CLI11's strtoll reads "010" as octal
        return "";
      },
      fmt::format("[{}, {}]", lo, hi));
}

CLI::Validator seed_value() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        const std::optional<uint64_t> value = parse_decimal<uint64_t>(text);
        if (!value)
          return fmt::format("must be a decimal integer in [0, {}], got '{}'", std::numeric_limits<uint64_t>::max(),
                             text);
        text = std::to_string(*value);
        return "";
      },
      "[0, 2^64-1]");
}

CLI::Validator number_in(double lo, double hi, End low_end, End high_end) {
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        double value = 0;
        // CLI11's own conversion, so the value checked is the value stored.
        const bool converted = CLI::detail::lexical_cast(text, value);
        const bool inside = converted && std::isfinite(value) &&
                            (low_end == End::kOpen ? value > lo : value >= lo) &&
                            (high_end == End::kOpen ? value < hi : value <= hi);
        if (!inside)
          return fmt::format("must be a finite number in {}, got '{}'", interval_text(lo, hi, low_end, high_end), text);
        return "";
      },
      interval_text(lo, hi, low_end, high_end));
}

CLI::Validator finite_number() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        double value = 0;
        if (!CLI::detail::lexical_cast(text, value) || !std::isfinite(value))
          return fmt::format("must be finite numbers, got '{}'", text);
        return "";
      },
      "FINITE");
}

CLI::Validator output_file(bool stdout_dash) {
  return CLI::Validator(
      [stdout_dash](std::string& text) -> std::string {
        if (stdout_dash && text == "-") return "";
        if (text.empty()) return "the output file name is empty";
        const fs::path path(text);
        std::error_code ec;
        if (fs::is_directory(path, ec)) return fmt::format("'{}' is a directory, not a file", text);
        const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
        const std::string problem = writable_directory_problem(dir);
        if (!problem.empty()) return fmt::format("cannot write '{}': {}", text, problem);
        return "";
      },
      "FILE");
}

CLI::Validator output_directory() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        if (text.empty()) return "the output directory name is empty";
        const fs::path existing = nearest_existing(fs::path(text));
        const std::string problem = writable_directory_problem(existing.empty() ? fs::path(".") : existing);
        if (!problem.empty()) return fmt::format("cannot create or write '{}': {}", text, problem);
        return "";
      },
      "DIR");
}

CLI::Validator strategy_by_name() {
  std::vector<std::pair<std::string, Strategy>> names;
  for (const StrategyInfo& info : kStrategyTable) names.emplace_back(info.name, info.strategy);
  return enum_by_name(names);
}

CLI::Validator defect_by_name() {
  std::vector<std::pair<std::string, Defect>> names;
  for (const DefectInfo& info : kDefectTable) names.emplace_back(info.name, info.defect);
  return enum_by_name(names);
}

CLI::Validator light_selection_by_name() {
  const std::map<std::string, LightSelection> by_name = light_selection_names();
  return enum_by_name(std::vector<std::pair<std::string, LightSelection>>(by_name.begin(), by_name.end()));
}

CLI::Option* add_convention_option(CLI::App* command, TransportConvention& convention) {
  const std::map<std::string, TransportConvention> by_name = transport_convention_names();
  return command
      ->add_option("--convention", convention,
                   "How radiance crossing a dielectric is transported: radiance (divided by η′² entering the denser "
                   "side: pbrt-v4, Mitsuba 3) or none (unscaled: Cycles)")
      ->transform(enum_by_name(std::vector<std::pair<std::string, TransportConvention>>(by_name.begin(), by_name.end())))
      ->type_name("radiance|none")
      ->default_str(transport_convention_name(convention));
}

CLI::Validator family_alpha() { return number_in(1e-12, 0.5); }

CLI::Option* max_depth_option(CLI::Option* option) {
  const std::map<std::string, int> words{{"unlimited", kUnlimitedDepth}};
  // transform() puts each validator first: the word is replaced by its
  // number, then the number checked and made canonical.
  return option->transform(integer_in(1, kUnlimitedDepth).description(""))
      ->transform(CLI::Transformer(words, CLI::ignore_case).description(""))
      ->type_name("SEGMENTS|unlimited");
}

CLI::Option* add_threads_option(CLI::App* command, int& threads) {
  return command->add_option("--threads", threads, "Worker threads (0: all)")
      ->capture_default_str()->transform(integer_in(0, kMaxThreads));
}

CLI::Option* add_seed_option(CLI::App* command, uint64_t& seed) {
  return command->add_option("--seed", seed, "Random seed")->capture_default_str()->transform(seed_value());
}

CLI::Option* add_strategies_option(CLI::App* command, std::vector<Strategy>& strategies) {
  return command->add_option("--strategy", strategies, "Strategy name(s); default: all")
      ->transform(strategy_by_name())->type_name("TEXT");
}

void set_contract_footer(CLI::App* command, const std::string& footer) {
  command->footer(footer.empty() ? std::string(kExitContract) : footer + "\n" + kExitContract);
}

std::string command_line_text(int argc, char** argv) {
  std::string text = "furnace";
  for (int i = 1; i < argc; ++i) text += std::string(" ") + argv[i];
  return text;
}

void create_output_directory(const std::string& dir, const std::string& option) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir))
    throw Error(fmt::format("option {}: cannot create the directory '{}' ({}).", option, dir,
                            ec ? ec.message() : "a file of that name exists"));
}

std::string parse_error_message(const CLI::App& app, const CLI::Error& e) {
  std::string message = e.what();
  if (dynamic_cast<const CLI::RequiredError*>(&e) && app.get_subcommands().empty()) {
    std::vector<std::string> names;
    for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) names.push_back(sub->get_name());
    const std::vector<std::string> rest = app.remaining();
    message = rest.empty() ? fmt::format("a subcommand is required, one of: {}", fmt::join(names, ", "))
                           : fmt::format("unknown subcommand '{}'; the subcommands are: {}", rest.front(),
                                         fmt::join(names, ", "));
  }
  return message + " (run with --help for more information)";
}

}  // namespace furnace::cli
