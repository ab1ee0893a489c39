// `furnace report`: convergence of each case's error with spp and time,
// written as Markdown and CSV, and (unless --no-html) as report.json and an
// HTML page whose plots and images scripts/plot_report.py draws.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "core/strategy.h"
#include "verify/suite.h"

namespace furnace::cli {

struct ReportCommandOptions {
  std::vector<std::string> scenes;   // empty: the built-in suite
  verify::Suite suite = verify::Suite::kDefault;  // without --scene
  std::vector<Strategy> strategies;  // empty: all (--scene files: every direct strategy that sees their lights)
  int min_spp = 4, max_spp = 1024;
  uint64_t seed = 20261125;
  int threads = 0;
  std::string output_dir = "reports/generated";
  bool no_html = false;
  std::string command_line;  // recorded in the reports
};

// Adds `report` to `app`, its options bound to `options`.
CLI::App* add_report_command(CLI::App& app, ReportCommandOptions& options);

// Measures and writes the report; returns 0, or 1 when the plotting script
// fails. Bad input (no Python with matplotlib, no plotting script, a bad
// scene) throws furnace::Error before any rendering.
int run_report(const ReportCommandOptions& options);

}  // namespace furnace::cli
