// The analytic side of the cases: per-pixel references and predicted
// variances, computed once and shared between cases.
#pragma once

#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "core/scene.h"
#include "verify/suite.h"

namespace furnace::verify {

// The reference a case's render must converge to, per pixel centre; a
// non-finite value is bad input (require_finite_reference).
std::vector<double> reference_for(const Scene& scene, const RenderOptions& options);

// Throws furnace::Error naming the scene file, the pixel and the value if any
// per-pixel reference (row-major, the scene camera's width) is not finite: a
// scene whose exact answer overflows double precision cannot be verified.
void require_finite_reference(const std::vector<double>& reference, const Scene& scene);

// The analytic side of cases (per-pixel references and predicted
// variances), computed once per scene file and kept for every later case
// that needs the same values: the direct-lighting strategies of a scene share
// one reference, the path tracers one per max_depth, and a strategy's
// variances (under one light selection) do not depend on the seed or spp, so
// a sweep over seeds computes them once. A value is a pure function of the
// scene file and those keys, so a run's results are the same with or without
// the cache. Thread-safe: concurrent cases may share one (two cases that
// miss the same key at once both compute it; the values are equal).
class AnalyticCache {
 public:
  // reference_for(scene, options), from the cache when this scene file's was computed before.
  const std::vector<double>& reference(const Case& c, const Scene& scene);
  // The predicted per-pixel variances E[Y²] − E[Y]² of c's strategy, or empty
  // when analytic/ does not model them on this scene (see run_case).
  const std::vector<double>& predicted_variance(const Case& c, const Scene& scene,
                                                const std::vector<double>& reference);

 private:
  std::mutex mutex_;  // guards the maps; values are computed outside it
  // std::map: references to its values stay valid as keys are added.
  std::map<std::string, std::vector<double>> references_;
  std::map<std::string, std::vector<double>> variances_;
};

}  // namespace furnace::verify
