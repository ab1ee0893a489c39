// Convergence reports: error against samples and against time, per scene and
// strategy, written as CSV (for plotting) and Markdown (for reading), and as
// report.json, the data from which scripts/plot_report.py draws the HTML
// report's plots and images (verify/report_html.h runs it).
#pragma once

#include <cstdint>
#include <functional>
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
  // The strategy as the verify table names it (case_label, verify/suite.h):
  // "light_area", "path_mis/inf", "path_mis/d4", "light_area@power" (the
  // built-in suite runs some scenes under both selections).
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
// case's exact reference. `largest`, when given, receives the render at the
// largest spp and `reference` the per-pixel reference.
ConvergenceSeries measure_convergence(const Case& c, int min_spp, int max_spp, Image* largest = nullptr,
                                      std::vector<double>* reference = nullptr);

// Writes <dir>/convergence.csv and <dir>/convergence.md (via temporary files
// and rename, so a failed run leaves the previous report intact).
void write_convergence_report(const std::vector<ConvergenceSeries>& series, const std::string& dir,
                              const std::string& command_line);

// One render shown on the HTML report: its per-pixel mean and per-sample
// variance (the t map is (mean − reference)/√(variance/spp)).
struct ReportRender {
  int spp = 0;
  double seconds = 0;
  std::vector<double> mean, variance;
};
ReportRender report_render(const Image& image, int spp);

// Everything the HTML report shows of one case: its convergence series, its
// reference and two renders, one at the largest spp (equal spp across the
// scene's strategies) and one at equal time (the spp that fits the scene's
// time budget, below).
struct ReportCase {
  ConvergenceSeries series;
  int width = 0, height = 0;
  std::vector<double> reference;
  ReportRender equal_spp, equal_time;
  double time_budget = 0;  // seconds: the equal-time budget of the case's scene
};

// The equal-time render's spp: the spp a render taking `seconds_at_max` at
// `max_spp` reaches in `budget` seconds at the same rate, in [1, max_spp].
int equal_time_spp(double budget, double seconds_at_max, int max_spp);

// Measures every case (convergence series, equal-spp render) and then, per
// scene, renders each case once more at equal time: the scene's budget is the
// smallest time any of its cases took at max_spp, so no case exceeds max_spp.
// `on_case` is called after each case's convergence series (progress output).
std::vector<ReportCase> measure_report(const std::vector<Case>& cases, int min_spp, int max_spp,
                                       const std::function<void(const ReportCase&)>& on_case);

}  // namespace furnace::verify
