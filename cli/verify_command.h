// `furnace verify`: render the built-in suite (or --scene files) and test
// each case against its exact reference; the verdict table on stdout, its
// JSON and HTML twins on request. Exits 1 when any case fails.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "core/strategy.h"
#include "verify/suite.h"
#include "stats/test_design.h"

namespace furnace::cli {

struct VerifyCommandOptions {
  std::vector<std::string> scenes;   // empty: the built-in suite
  verify::Suite suite = verify::Suite::kDefault;  // without --scene
  std::vector<Strategy> strategies;  // empty: all (--scene files: every direct strategy that sees their lights)
  Defect defect = Defect::kNone;
  int spp = 4096;
  uint64_t seed = 20261125;
  int threads = 0;
  double alpha = stats::kDefaultFamilyAlpha;
  int max_depth = kUnlimitedDepth;  // --scene files only; the suite sets its own
  // Empty: the built-in suite's own choice per case (it runs some scenes
  // under both), uniform for --scene files.
  std::optional<LightSelection> light_selection;
  TransportConvention convention = TransportConvention::kRadiance;
  std::string json_path, html_dir;  // empty: not asked for
  std::string command_line;         // recorded in the HTML page
};

// Adds `verify` to `app`, its options bound to `options`.
CLI::App* add_verify_command(CLI::App& app, VerifyCommandOptions& options);

// Runs the cases; returns 0 when every case passes, else 1. Bad input throws
// furnace::Error before any rendering.
int run_verify(const VerifyCommandOptions& options);

}  // namespace furnace::cli
