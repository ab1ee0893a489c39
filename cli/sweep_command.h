// `furnace sweep`: the false-alarm rate of the verification, measured over
// many seeds. Exits 1 when some case rejects significantly more often than
// its level.
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "core/strategy.h"
#include "verify/suite.h"

namespace furnace::cli {

struct SweepCommandOptions {
  std::vector<Strategy> strategies;  // empty: all
  std::vector<std::string> scenes;   // built-in scene names (file stem); empty: all
  verify::Suite suite = verify::Suite::kDefault;
  int seeds = 50;
  int spp = 1024;
  double case_alpha = 0.05;
  int threads = 0;
};

// Adds `sweep` to `app`, its options bound to `options`.
CLI::App* add_sweep_command(CLI::App& app, SweepCommandOptions& options);

// Every selected case of the built-in suite (narrowed to `scenes` and
// `strategies`; a name that is no built-in suite scene is bad input) rerun over seeds 1 … seeds at
// the per-case level case_alpha; each case's observed rejection rate is
// compared with case_alpha by an exact binomial test. The per-case tests are
// Šidák-corrected over pixels and partly positively correlated, so the true
// rate may sit below case_alpha but must not exceed it. Returns 0 when no
// case is in excess, else 1.
int run_sweep(const SweepCommandOptions& options);

}  // namespace furnace::cli
