// Convergence reports: error against samples and against time, per scene and
// strategy, written as CSV (for plotting) and Markdown (for reading).
#pragma once

#include <string>
#include <vector>

#include "verify/harness.h"

namespace furnace::verify {

struct ConvergencePoint {
  int spp = 0;
  double seconds = 0;        // render wall time at this spp
  double rmse = 0;           // √(mean over pixels of (estimate − reference)²)
  double relative_rmse = 0;  // rmse / mean of the reference
};

struct ConvergenceSeries {
  std::string scene;
  std::string strategy;
  std::vector<ConvergencePoint> points;
  // Least-squares slope of log(rmse) against log(spp): −1/2 for an unbiased
  // Monte Carlo estimator with finite variance; a flatter slope means bias
  // (error stops falling) or infinite variance.
  double slope = 0;
  // Work-normalised efficiency at the largest spp: 1/(relative MSE · seconds);
  // higher is better, comparable across strategies of one scene.
  double efficiency = 0;
  // Extrapolated from the largest spp along N^(−1/2): seconds to reach 1 % relative RMSE.
  double seconds_to_one_percent = 0;
};

// Renders each case at spp = min_spp, 2·min_spp, ... ≤ max_spp (each spp an
// independent render with the case's seed) and measures the error against the
// case's exact reference.
ConvergenceSeries measure_convergence(const Case& c, int min_spp, int max_spp);

// Writes <dir>/convergence.csv and <dir>/convergence.md (via temporary files
// and rename, so a failed run leaves the previous report intact).
void write_convergence_report(const std::vector<ConvergenceSeries>& series, const std::string& dir,
                              const std::string& command_line);

}  // namespace furnace::verify
