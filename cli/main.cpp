// The `furnace` command line. Each subcommand is one file (cli/*_command.h):
// its options struct, bound by CLI11 to its flags, and the function that runs
// it. Here: the contract every subcommand obeys (cli/cli_options.h), parsing
// and dispatch. An argument error is one line on stderr and exit 2, before
// any work; bad input found later (furnace::Error) likewise.
#include <cstdio>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli/analytic_command.h"
#include "cli/check_command.h"
#include "cli/compare_command.h"
#include "cli/cli_options.h"
#include "cli/export_command.h"
#include "cli/render_command.h"
#include "cli/report_command.h"
#include "cli/sweep_command.h"
#include "cli/verify_command.h"
#include "core/error.h"
#include "core/provenance.h"

int main(int argc, char** argv) {
  using namespace furnace;
  CLI::App app{"furnace: deterministic verification of Monte Carlo rendering against exact references"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "furnace " + furnace_version());
  app.footer(cli::kExitContract);

  cli::RenderCommandOptions render;
  cli::VerifyCommandOptions verify;
  cli::ReportCommandOptions report;
  cli::AnalyticCommandOptions analytic;
  cli::CheckCommandOptions check;
  cli::CompareCommandOptions compare;
  cli::ExportCommandOptions export_options;
  cli::SweepCommandOptions sweep;
  verify.command_line = report.command_line = cli::command_line_text(argc, argv);
  // In the order --help lists them, each with the function that runs it.
  const std::vector<std::pair<CLI::App*, std::function<int()>>> subcommands = {
      {cli::add_render_command(app, render), [&] { return cli::run_render(render); }},
      {cli::add_verify_command(app, verify), [&] { return cli::run_verify(verify); }},
      {cli::add_report_command(app, report), [&] { return cli::run_report(report); }},
      {cli::add_analytic_command(app, analytic), [&] { return cli::run_analytic(analytic); }},
      {cli::add_check_command(app, check), [&] { return cli::run_check(check); }},
      {cli::add_compare_command(app, compare), [&] { return cli::run_compare(compare); }},
      {cli::add_export_command(app, export_options), [&] { return cli::run_export(export_options); }},
      {cli::add_sweep_command(app, sweep), [&] { return cli::run_sweep(sweep); }},
  };

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version exit 0; every argument error is bad input (2),
    // one line on stderr, whatever CLI11's own code for it.
    if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return app.exit(e);
    std::fprintf(stderr, "furnace: error: %s\n", cli::parse_error_message(app, e).c_str());
    return cli::kExitBadInput;
  }
  try {
    for (const auto& [command, run] : subcommands)
      if (*command) return run();
  } catch (const Error& e) {
    std::fprintf(stderr, "furnace: error: %s\n", e.what());
    return cli::kExitBadInput;
  }
  return cli::kExitPass;
}
