// The cases verify, report and sweep run: the built-in suite's, or each
// --scene file's, narrowed to the --strategy names; and the --spp help that
// states where the suite's α is calibrated.
#pragma once

#include <string>
#include <vector>

#include "core/strategy.h"
#include <CLI/CLI.hpp>

#include "verify/harness.h"
#include "verify/suite.h"

namespace furnace::cli {

// --suite default|extended|all: which built-in suite (verify/suite.h) a
// command runs when no scene file is given.
CLI::Option* add_suite_option(CLI::App* command, verify::Suite& suite);

// The cases of `suite` whose strategy is among `strategies` (all of them
// when it is empty).
std::vector<verify::Case> suite_cases(const std::vector<verify::Case>& suite, const std::vector<Strategy>& strategies);

// The cases of --scene files: each file with `strategies`, or by default
// every direct strategy that can see its lights (none that misses its point
// lights). Each file is loaded first, so a bad one fails (furnace::Error)
// before any rendering. Options other than the strategy are the caller's.
std::vector<verify::Case> scene_file_cases(const std::vector<std::string>& scenes,
                                           const std::vector<Strategy>& strategies);

// --spp's help for verify and sweep: the variance test's minimum and the
// range of the strategies' calibrated spp.
std::string spp_help();

// "uniform_hemisphere 128, cosine_hemisphere 128, ...": each strategy's
// verify::min_calibrated_spp, in table order.
std::string calibrated_spp_list();

}  // namespace furnace::cli
