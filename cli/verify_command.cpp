#include "cli/verify_command.h"

#include <cstdio>

#include <fmt/format.h>

#include "cli/cases.h"
#include "cli/cli_options.h"
#include "cli/progress.h"
#include "core/error.h"
#include "stats/statistics.h"
#include "verify/harness.h"
#include "verify/verdict_export.h"

namespace furnace::cli {

CLI::App* add_verify_command(CLI::App& app, VerifyCommandOptions& o) {
  CLI::App* command =
      app.add_subcommand("verify", "Render the analytic scenes and test them against their exact references");
  CLI::Option* scene = command->add_option("--scene", o.scenes, "Scene file(s); default: the built-in suite");
  add_suite_option(command, o.suite)->excludes(scene);
  add_strategies_option(command, o.strategies);
  command
      ->add_option_function<LightSelection>(
          "--light-selection", [&o](const LightSelection& s) { o.light_selection = s; },
          "Light selection pmf, uniform or power, for every case (default: the built-in suite's own choice per "
          "case, uniform for --scene files)")
      ->transform(light_selection_by_name())->type_name("TEXT");
  add_convention_option(command, o.convention);
  command->add_option("--defect", o.defect, "Inject a negative-control defect (the run must then fail)")
      ->transform(defect_by_name())->type_name("TEXT")->default_str(defect_name(o.defect));
  command->add_option("--spp", o.spp, spp_help())->capture_default_str()->transform(integer_in(2, kMaxSpp));
  add_seed_option(command, o.seed);
  add_threads_option(command, o.threads);
  command->add_option("--alpha", o.alpha, "Family-wise false-alarm probability of the whole run")
      ->capture_default_str()->check(family_alpha());
  max_depth_option(command->add_option("--max-depth", o.max_depth,
                                       "Path tracers with --scene: longest path in segments, camera segment "
                                       "included, or 'unlimited' (default unlimited; the built-in suite sets its own)"))
      ->needs(scene);
  set_contract_footer(command, fmt::format("A test that cannot run (the variance test below {} spp) is skipped and "
                                           "named, never failed. Where a strategy's second moment is modelled (most "
                                           "direct-lighting cases) a mean below its reference is tested with the "
                                           "exact variance (Bernstein's bound), valid at any spp; elsewhere, below "
                                           "the strategy's calibrated spp ({}), a rejection makes the case "
                                           "INCONCLUSIVE (exit 3, naming the spp that would judge it), not FAIL.",
                                           stats::kMinVarianceTestSamples, calibrated_spp_list()));
  command->add_option("--json", o.json_path, "Also write every number of the verdict table as JSON to FILE")
      ->check(output_file().description(""))->type_name("FILE");
  command->add_option("--html", o.html_dir, "Also write the verdict table as DIR/index.html (failing cases first)")
      ->check(output_directory().description(""))->type_name("DIR");
  return command;
}

namespace {

// The run's cases, every option applied; bad --scene files throw here.
std::vector<verify::Case> verify_cases(const VerifyCommandOptions& o) {
  std::vector<verify::Case> cases;
  if (o.scenes.empty())
    for (verify::Case c : suite_cases(verify::builtin_suite(o.suite, o.spp, o.seed, o.threads), o.strategies)) {
      c.options.defect = o.defect;
      c.options.convention = o.convention;
      if (o.light_selection) c.options.light_selection = *o.light_selection;
      cases.push_back(c);
    }
  for (verify::Case c : scene_file_cases(o.scenes, o.strategies)) {
    c.options.light_selection = o.light_selection.value_or(LightSelection::kUniform);
    c.options.defect = o.defect;
    c.options.convention = o.convention;
    c.options.spp = o.spp;
    c.options.seed = o.seed;
    c.options.threads = o.threads;
    c.options.max_depth = o.max_depth;
    cases.push_back(c);
  }
  return cases;
}

}  // namespace

int run_verify(const VerifyCommandOptions& o) {
  const std::vector<verify::Case> cases = verify_cases(o);
  if (cases.empty()) throw Error("no verification case matches the given --scene and --strategy options.");
  // Šidák: the cases share the family-wise α equally.
  const double per_case_alpha = stats::sidak_alpha(o.alpha, cases.size());
  if (!o.html_dir.empty()) create_output_directory(o.html_dir, "--html");
  const std::string warning = verify::low_spp_warning(cases);
  if (!warning.empty()) std::fprintf(stderr, "furnace: warning: %s\n", warning.c_str());
  verify::Progress progress("verify", cases.size());
  const std::vector<verify::Verdict> verdicts =
      verify::run_cases(cases, per_case_alpha, o.threads, [&] { progress.step(); });
  progress.finish();
  std::fputs(verify::format_table(verdicts, o.alpha).c_str(), stdout);
  if (!o.json_path.empty()) verify::write_verdicts_json(verdicts, o.alpha, o.json_path);
  if (!o.html_dir.empty()) verify::write_verdicts_html(verdicts, o.alpha, o.command_line, o.html_dir);
  const verify::RunOutcome outcome = verify::run_outcome(verdicts);
  std::printf("verdict: %s\n", verify::run_outcome_word(outcome));
  switch (outcome) {
    case verify::RunOutcome::kPass: return kExitPass;
    case verify::RunOutcome::kInconclusive: return kExitInconclusive;
    case verify::RunOutcome::kFail: return kExitFail;
  }
  return kExitFail;
}

}  // namespace furnace::cli
