#include "cli/sweep_command.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <set>
#include <string>

#include <fmt/format.h>

#include "cli/cases.h"
#include "cli/cli_options.h"
#include "cli/progress.h"
#include "core/error.h"
#include "stats/statistics.h"
#include "verify/harness.h"

namespace furnace::cli {

CLI::App* add_sweep_command(CLI::App& app, SweepCommandOptions& o) {
  CLI::App* command =
      app.add_subcommand("sweep", "Measure the false-alarm rate of the verification over many seeds (slow)");
  add_strategies_option(command, o.strategies);
  add_suite_option(command, o.suite);
  command->add_option("--suite-scene", o.scenes,
                      "Only the --suite's cases of these scenes (file name without .json, repeatable; default: "
                      "all)")
      ->type_name("NAME");
  command->add_option("--seeds", o.seeds, "Seeds per case")->capture_default_str()->transform(integer_in(1, 100000));
  command->add_option("--spp", o.spp, spp_help())->capture_default_str()->transform(integer_in(2, kMaxSpp));
  command->add_option("--case-alpha", o.case_alpha, "False-alarm level of each case")
      ->capture_default_str()->check(number_in(1e-6, 0.5));
  add_threads_option(command, o.threads);
  set_contract_footer(command, "sweep exits 1 when some case rejects significantly more often than --case-alpha.");
  return command;
}

int run_sweep(const SweepCommandOptions& o) {
  std::vector<verify::Case> cases = suite_cases(verify::builtin_suite(o.suite, o.spp, 0, o.threads), o.strategies);
  if (!o.scenes.empty()) {
    const auto stem = [](const verify::Case& c) { return std::filesystem::path(c.scene_path).stem().string(); };
    std::set<std::string> known, anywhere;
    for (const verify::Case& c : verify::builtin_suite(o.suite, o.spp, 0, o.threads)) known.insert(stem(c));
    for (const verify::Case& c : verify::builtin_suite(verify::Suite::kAll, o.spp, 0, o.threads))
      anywhere.insert(stem(c));
    for (const std::string& name : o.scenes)
      if (!known.count(name)) {
        if (anywhere.count(name))
          throw Error(fmt::format("option --suite-scene: '{}' is no scene of the {} suite; add --suite all.", name,
                                  verify::suite_name(o.suite)));
        std::string list;
        for (const std::string& k : anywhere) list += (list.empty() ? "" : ", ") + k;
        throw Error(fmt::format("option --suite-scene: '{}' is no scene of the built-in suites (accepted: {}).",
                                name, list));
      }
    std::vector<verify::Case> kept;
    for (const verify::Case& c : cases)
      if (std::find(o.scenes.begin(), o.scenes.end(), stem(c)) != o.scenes.end()) kept.push_back(c);
    cases = kept;
  }
  if (cases.empty()) throw Error("no sweep case matches the given --suite-scene and --strategy options.");
  const std::string warning = verify::low_spp_warning(cases);
  if (!warning.empty()) std::fprintf(stderr, "furnace: warning: %s\n", warning.c_str());
  fmt::print("false-alarm sweep: {} cases x {} seeds at {} spp, per-case alpha {}\n", cases.size(), o.seeds, o.spp,
             o.case_alpha);
  fmt::print("{:<22} {:<24} {:>10} {:>8} {:>19} {:>10}\n", "scene", "strategy", "rejected", "rate", "95% CI",
             "binom p");
  size_t total_rejections = 0, total_trials = 0;
  bool calibrated = true;
  verify::Progress progress("sweep", cases.size() * size_t(o.seeds));
  for (const verify::Case& base : cases) {
    // The case at seeds 1 … seeds, run together (run_cases: the analytic
    // values once for all seeds, several seeds at a time).
    std::vector<verify::Case> runs(size_t(o.seeds), base);
    for (size_t i = 0; i < runs.size(); ++i) runs[i].options.seed = 1 + i;
    const std::vector<verify::Verdict> verdicts =
        verify::run_cases(runs, o.case_alpha, o.threads, [&] { progress.step(); });
    const stats::RejectionRate rate = stats::measure_rejection_rate(
        [&](uint64_t seed) { return !verdicts[seed - 1].pass; }, size_t(o.seeds), o.case_alpha, 1);
    total_rejections += rate.rejections;
    total_trials += rate.trials;
    // Too many false alarms is the failure that matters (one-sided reading of
    // the two-sided exact test): a significant excess at 1 %.
    const bool excess = rate.rate > o.case_alpha && rate.binomial_p_value < 0.01;
    calibrated = calibrated && !excess;
    progress.clear();
    fmt::print("{:<22} {:<24} {:>5}/{:<4} {:>8.4f} [{:.4f}, {:.4f}] {:>10.3g}{}\n", verdicts.front().scene,
               verdicts.front().strategy, rate.rejections, rate.trials, rate.rate, rate.ci_low, rate.ci_high,
               rate.binomial_p_value, excess ? "  EXCESS" : "");
  }
  progress.finish();
  const double p_all = stats::binomial_two_sided_p_value(total_rejections, total_trials, o.case_alpha);
  fmt::print("all cases: {}/{} rejected, rate {:.4f} against alpha {} (binomial p {:.3g})\n", total_rejections,
             total_trials, double(total_rejections) / double(total_trials), o.case_alpha, p_all);
  std::puts(calibrated ? "calibration: OK (no case rejects significantly more often than alpha)"
                       : "calibration: FAIL (some case rejects significantly more often than alpha)");
  return calibrated ? kExitPass : kExitFail;
}

}  // namespace furnace::cli
