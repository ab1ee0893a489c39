// Test helpers: deterministic samples and their running moments, written
// independently of renderer/render.h so the statistics are tested against
// their own accumulator.
#pragma once

#include <cmath>
#include <cstdint>

#include "renderer/rng.h"
#include "verify/statistics.h"

namespace furnace::stats::testing_support {

// Welford / Terriberry running central moments (count, mean, m2, m4).
struct Moments {
  uint64_t count = 0;
  double mean = 0, m2 = 0, m3 = 0, m4 = 0;

  void add(double y) {
    const double n1 = double(count);
    ++count;
    const double n = double(count);
    const double delta = y - mean;
    const double delta_n = delta / n;
    const double delta_n2 = delta_n * delta_n;
    const double term1 = delta * delta_n * n1;
    mean += delta_n;
    m4 += term1 * delta_n2 * (n * n - 3 * n + 3) + 6 * delta_n2 * m2 - 4 * delta_n * m3;
    m3 += term1 * delta_n * (n - 2) - 3 * delta_n * m2;
    m2 += term1;
  }
  double sample_variance() const { return count > 1 ? m2 / double(count - 1) : 0.0; }
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
