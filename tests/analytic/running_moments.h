// Running central moments of a simulated estimator (Terriberry's one-pass
// update), shared by the analytic tests that check predicted second moments
// against a direct Monte Carlo written in the test.
#pragma once

#include <algorithm>
#include <cmath>

namespace furnace::analytic::testing_support {

struct RunningMoments {
  double n = 0, mean = 0, m2 = 0, m3 = 0, m4 = 0;
  void add(double y) {
    const double n1 = n;
    n += 1;
    const double delta = y - mean, dn = delta / n, dn2 = dn * dn, t1 = delta * dn * n1;
    mean += dn;
    m4 += t1 * dn2 * (n * n - 3 * n + 3) + 6 * dn2 * m2 - 4 * dn * m3;
    m3 += t1 * dn * (n - 2) - 3 * dn * m2;
    m2 += t1;
  }
  double sample_variance() const { return m2 / (n - 1); }
  double mean_standard_error() const { return std::sqrt(sample_variance() / n); }
  // Var(s²) ≈ (μ4 − σ⁴)/N for large N.
  double variance_standard_error() const {
    const double s2 = sample_variance();
    return std::sqrt(std::fmax(m4 / n - s2 * s2, 0.0) / n);
  }
};

}  // namespace furnace::analytic::testing_support
