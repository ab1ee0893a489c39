// Running central moments of a stream of values: count, mean and the sums of
// squared, cubed and fourth-power deviations from the mean, updated one value
// at a time (Terriberry's one-pass extension of Welford's update). The result
// depends only on the order of the values, so a pixel accumulated in sample
// order is the same whatever thread renders it.
#pragma once

#include <cmath>
#include <cstdint>

namespace furnace {

struct RunningMoments {
  uint64_t count = 0;
  double mean = 0;
  double m2 = 0;  // Σ (y − mean)²
  double m3 = 0;  // Σ (y − mean)³
  double m4 = 0;  // Σ (y − mean)⁴

  void add(double y) {
    const double n1 = double(count);
    ++count;
    const double n = double(count);
    const double delta = y - mean;
    const double delta_n = delta / n;
    const double delta_n2 = delta_n * delta_n;
    const double term1 = delta * delta_n * n1;
    mean += delta_n;
    // M4 and M3 first: they use the old M2 and M3.
    m4 += term1 * delta_n2 * (n * n - 3 * n + 3) + 6 * delta_n2 * m2 - 4 * delta_n * m3;
    m3 += term1 * delta_n * (n - 2) - 3 * delta_n * m2;
    m2 += term1;
  }

  // Unbiased sample variance s² = m2/(n − 1); 0 when n < 2.
  double sample_variance() const { return count > 1 ? m2 / double(count - 1) : 0.0; }
  // Standard error of the mean, √(s²/n); 0 when n < 2.
  double mean_standard_error() const { return count > 1 ? std::sqrt(sample_variance() / double(count)) : 0.0; }
};

}  // namespace furnace
