// The mean test of a caller's Monte Carlo estimator against an exact
// reference, for a renderer's own test suite (furnace::stats in the
// installed package). The reference usually comes from furnace::analytic
// (analytic/reference.h: the irradiance at a point, the radiance along a
// ray; analytic/global.h: the closed forms of whole scenes).
//
// It is the per-pixel test of `furnace verify` (pixel_tests.h) applied to one
// estimator: Hall's skewness-corrected t against Student's t quantile, the
// zero-variance branch for a constant estimator (which must then match the
// reference exactly), and Cochran's rule, under which a mean too skewed for
// the normal approximation is left untested (inconclusive) instead of
// judged with a wrong α.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>

#include "core/running_moments.h"
#include "stats/statistics.h"
#include "stats/uniform_stream.h"

namespace furnace::stats {

// One sample of the estimator; it draws as many uniforms as it needs.
using Estimator = std::function<double(UniformStream& u)>;

struct EstimatorTestOptions {
  size_t samples = 100'000;
  uint64_t seed = kDefaultTestSeed;
  double alpha_family = 0.01;  // false-alarm probability of the caller's whole family of tests
  size_t n_tests = 1;          // tests in that family: each runs at the Šidák level
  double power = kDefaultPower;
};

enum class Verdict { kPass, kFail, kInconclusive };
const char* verdict_name(Verdict v);  // "PASS", "FAIL", "INCONCLUSIVE"

struct EstimatorMeanTestResult {
  Verdict verdict = Verdict::kFail;
  // count, mean, reference, standard_error, statistic (Hall's, or 0 in the
  // zero-variance branch), dof, p_value, alpha (the per-test level),
  // threshold, detectable_bias and detectable_relative_bias (the smallest
  // bias rejected with probability `power`), zero_variance, skewness,
  // clt_adequate (statistics.h).
  MeanTestResult test;
  size_t nonfinite = 0;  // samples that were NaN or ±inf: any fails the test
  uint64_t seed = 0;
  double alpha_family = 0;
  size_t n_tests = 0;
  double power = 0;
  std::string correction;  // e.g. "Sidak over 1 test at family alpha 0.01"
  std::string message;     // why it failed or was inconclusive, else the statistic used
  bool pass() const { return verdict == Verdict::kPass; }
};

// Draws options.samples values of `estimator` from the seeded stream and
// tests whether their mean is `reference`. Throws std::invalid_argument for
// samples < 2, alpha_family outside (0, 1), n_tests < 1 or a reference that
// is not finite.
EstimatorMeanTestResult estimator_mean_test(const Estimator& estimator, double reference,
                                            const EstimatorTestOptions& options = {});

// The same test of moments the caller accumulated (core/running_moments.h),
// e.g. from an estimator that owns its random numbers; options.samples and
// options.seed are not used.
EstimatorMeanTestResult estimator_mean_test(const RunningMoments& moments, double reference,
                                            const EstimatorTestOptions& options = {});

// One paragraph with every number of the result.
std::string describe(const EstimatorMeanTestResult& result);

}  // namespace furnace::stats
