// Test helpers: deterministic samples and their running moments.
#pragma once

#include <cmath>
#include <cstdint>

#include "core/running_moments.h"
#include "renderer/rng.h"
#include "stats/statistics.h"

namespace furnace::stats::testing_support {

// The running central moments the renderer keeps per pixel (their agreement
// with two-pass moments is tested in tests/core), with the summary the
// statistics take.
struct Moments : RunningMoments {
  SampleSummary summary() const { return {count, mean, sample_variance()}; }
};

// N draws of a transformed uniform variate from one fixed stream.
template <class Transform>
Moments draw(uint64_t seed, uint64_t stream, uint64_t n, const Transform& transform) {
  Rng rng(seed, stream, 0);
  Moments m;
  for (uint64_t i = 0; i < n; ++i) m.add(transform(rng.next_double()));
  return m;
}

// Exp(1): mean 1, variance 1, μ4 = 9 (a skewed, moderately heavy-tailed estimator).
inline double exponential(double u) { return -std::log1p(-u); }
// U[0,1): mean 1/2, variance 1/12, μ4 = 1/80.
inline double uniform(double u) { return u; }

}  // namespace furnace::stats::testing_support
