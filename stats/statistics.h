// Hypothesis tests that compare Monte Carlo estimates with exact references.
//
// Every test here takes its quantiles from Boost.Math (never typed in), runs at
// a per-test level α that the caller derives from a family-wise level by the
// Šidák (or Bonferroni) correction, and reports its power: the smallest bias
// it detects with probability kDefaultPower (the "minimum detectable effect").
// Inputs are plain numbers (count, mean) or running central moments
// (core/running_moments.h), so this file does not depend on renderer/.
//
// Models: Subr & Arvo 2007 (hypothesis tests for Monte Carlo estimators),
// Nori's ttest, Mitsuba's test_renders. Ideas only.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/running_moments.h"

namespace furnace::stats {

// Power at which detectable effects are quoted: the bias a test catches with
// probability 1 − β. β = 0.1 (power 0.9) is the usual design power in
// experiment planning; at power 0.5 the detectable bias would be just the
// critical value times the standard error, which a real bias of that size
// escapes half the time.
inline constexpr double kDefaultBeta = 0.1;
inline constexpr double kDefaultPower = 1.0 - kDefaultBeta;

// A zero-variance estimator (e.g. cone sampling of an unoccluded sphere light)
// must reproduce the reference exactly, up to float geometry: Embree hits are
// within ~2 float steps of the exact distance, and the hit point enters the
// estimate through squared distances, cosines and a solid angle,
// each multiplying the relative error by a small factor. 64 float epsilons
// (7.6e-6) covers that chain with margin, yet is far below any bias a
// statistical test at realistic sample counts could resolve.
inline constexpr double kZeroVarianceRelTolerance = 64 * 1.1920928955078125e-7;  // 64 · FLT_EPSILON

// ---------------------------------------------------------------------------
// Family-wise corrections: the per-test level that keeps the probability of
// any false alarm among n independent tests at alpha_family.

// Šidák: 1 − (1 − α)^(1/n), computed as −expm1(log1p(−α)/n) so that tiny
// per-test levels (α/n ~ 1e-9) keep all their digits.
double sidak_alpha(double alpha_family, size_t n_tests);
// Bonferroni: α/n. Valid without independence; slightly conservative.
double bonferroni_alpha(double alpha_family, size_t n_tests);

// Upper quantile of the standard normal: the z with P(Z > z) = q, from
// Boost. A two-sided test at level α compares |z| with normal_upper_quantile(α/2).
double normal_upper_quantile(double q);

// ---------------------------------------------------------------------------
// One-sample mean test: is the true mean of an estimator equal to the
// reference? Student's t with N − 1 degrees of freedom (the z-test for large
// N), two-sided.

struct MeanTestResult {
  uint64_t count = 0;
  double mean = 0;
  double reference = 0;
  double standard_error = 0;   // s/√N
  double statistic = 0;        // t = (mean − reference)/SE; 0 in the zero-variance branch
  double dof = 0;              // N − 1
  double p_value = 0;          // two-sided
  double alpha = 0;            // the per-test level used
  double threshold = 0;        // |t| above this fails: t_{1−α/2, N−1}
  // Smallest |bias| rejected with probability `power`:
  // δ = (t_{1−α/2} + t_{power}) · SE (the far tail's contribution neglected).
  double detectable_bias = 0;
  double detectable_relative_bias = 0;  // δ/|reference|; +inf when reference == 0
  bool zero_variance = false;  // s = 0: exact agreement within kZeroVarianceRelTolerance required
  bool pass = false;
  std::string message;         // one sentence: why it failed, or the zero-variance branch taken
  // Filled only by the RunningMoments overload (below): sample skewness and Cochran's rule.
  double skewness = 0;
  bool clt_adequate = true;
};

// count: N samples; mean, sample_variance: their mean and unbiased variance
// s² = Σ(y − ȳ)²/(N − 1); alpha: per-test level in (0, 1).
// Fails (pass = false, message says why) when N < 2, an input is not finite,
// or s = 0 and the mean differs from the reference by more than
// kZeroVarianceRelTolerance·|reference| (exact equality when reference == 0).
MeanTestResult mean_test(uint64_t count, double mean, double sample_variance, double reference, double alpha,
                         double power = kDefaultPower);

// Normal (z) test of an estimate with a known or already-aggregated standard
// error, e.g. the mean of an image over its pixels. Same zero-SE rule.
struct ZTestResult {
  double statistic = 0;
  double p_value = 0;
  double alpha = 0;
  double threshold = 0;                 // z_{1−α/2}
  double standard_error = 0;
  double detectable_bias = 0;           // (z_{1−α/2} + z_{power})·SE
  double detectable_relative_bias = 0;  // δ/|reference|; +inf when reference == 0
  bool zero_variance = false;
  bool pass = false;
  std::string message;
};
ZTestResult z_test(double estimate, double reference, double standard_error, double alpha,
                   double power = kDefaultPower);

// ---------------------------------------------------------------------------
// Variance test: is the estimator's true variance the predicted σ² (from an
// analytic second moment, σ² = E[Y²] − E[Y]²)?
//
// s² = m2/(N − 1). Its standard error comes from the fourth central moment
// (Cramér): Var(s²) ≈ (μ4 − (N−3)/(N−1)·σ⁴)/N, with the plug-in estimates
// μ4 ≈ m4/N and σ⁴ ≈ s⁴; with these the bracket is provably > 0 whenever
// m2 > 0. The statistic (s² − σ²)/SE is compared with the normal
// distribution. Asymptotic: the estimate of μ4 is itself noisy, so heavy
// tails make the test optimistic; require at least kMinVarianceTestSamples.

// Below this the normal approximation of s² and the plug-in μ4 are poor.
inline constexpr uint64_t kMinVarianceTestSamples = 100;

// The estimated Var(s²) above, (m4/N − (N−3)/(N−1)·s⁴)/N, clamped at 0;
// 0 when N < 2.
double sample_variance_variance(const RunningMoments& m);

// The smallest relative variance error δ a variance test detects with its
// power, from k = (z_{1−α/2} + z_power)·SE/σ² (SE estimated from the samples).
// Under a true variance (1 + δ)·σ² the estimated SE of s² grows by (1 + δ)
// too (same kurtosis), so the statistic's mean is only δ/(1 + δ)·σ²/SE:
// power is reached at δ/(1 + δ) = k, δ = k/(1 − k) for a variance too large,
// the harder of the two directions (too small needs k/(1 + k)). ∞ for k ≥ 1.
double detectable_relative_variance_error(double k);

struct VarianceTestResult {
  uint64_t count = 0;
  double sample_variance = 0;     // s²
  double predicted_variance = 0;  // σ²
  double standard_error = 0;      // SE of s²
  double statistic = 0;           // (s² − σ²)/SE
  double p_value = 0;
  double alpha = 0;
  double threshold = 0;           // z_{1−α/2}
  // Smallest relative variance error |s² − σ²|/σ² detected with `power`.
  double detectable_relative_error = 0;
  bool zero_variance = false;     // σ² == 0 predicted: s must be ≤ kZeroVarianceRelTolerance·|mean|
  bool pass = false;
  std::string message;
};
VarianceTestResult variance_test(const RunningMoments& m, double predicted_variance, double alpha,
                                 double power = kDefaultPower);

// ---------------------------------------------------------------------------
// Is the t-test's normal approximation of the mean trustworthy? A skewed
// estimator (rare large values: a small light found by hemisphere sampling)
// needs many samples before its mean is normal. Cochran's rule (Cochran 1977,
// Sampling Techniques §2.15; Boos & Hughes-Oliver 2000): N ≥ 25·G1², G1 the
// sample skewness. A hemisphere sample that rarely hits a small light is
// nearly Bernoulli with small p, skewness ≈ 1/√p.
inline constexpr double kCochranSkewnessFactor = 25;

// Sample skewness G1 = (m3/N)/(m2/N)^{3/2}; 0 when m2 == 0 or N == 0.
double sample_skewness(const RunningMoments& m);
// N ≥ kCochranSkewnessFactor·G1² (true when G1 is not a number). A false
// answer does not fail a mean test by itself: it says the test's α is
// approximate (pixel_tests.h leaves such pixels untested).
bool clt_adequate(const RunningMoments& m);

// The mean test from running moments: s² = m2/(N − 1); fills skewness and
// clt_adequate in the result (message notes a failed check).
MeanTestResult mean_test(const RunningMoments& m, double reference, double alpha, double power = kDefaultPower);

// Median of the values (the upper median for an even count); 0 when empty.
double median(std::vector<double> values);

// ---------------------------------------------------------------------------
// Many mean tests at once (e.g. every pixel), each at the Šidák level that
// keeps the family-wise false-alarm probability at alpha_family.

struct SampleSummary {
  uint64_t count = 0;
  double mean = 0;
  double sample_variance = 0;  // unbiased
};

struct MeanTestSummary {
  size_t tests = 0;
  double alpha_family = 0;
  double alpha_each = 0;
  size_t failures = 0;
  double worst_abs_statistic = 0;  // largest |t| (zero-variance tests count as 0 unless they fail: +inf)
  size_t worst_index = 0;
  // Median over tests with a nonzero reference of the detectable relative bias.
  double median_detectable_relative_bias = 0;
  bool pass = false;  // no failures
};

// summaries[i] is tested against references[i]; sizes must match.
MeanTestSummary mean_tests(const std::vector<SampleSummary>& summaries, const std::vector<double>& references,
                           double alpha_family, double power = kDefaultPower);

// ---------------------------------------------------------------------------
// Welch's t-test: do two independent estimators (e.g. Russian roulette on and
// off) have the same mean? Unequal variances, Welch–Satterthwaite d.o.f.

// An estimate of a mean with the variance of that estimate and its degrees
// of freedom: a sample mean (s²/N, N − 1), the mean of K independent renders
// (spread²/K, K − 1), or a sum of such terms with Welch–Satterthwaite d.o.f.
// dof = +inf: a known variance (the normal distribution).
struct MeanEstimate {
  double mean = 0;
  double variance_of_mean = 0;
  double dof = 0;
};

// Welch's statistic of a − b: difference, SE = √(v_a + v_b), t = difference/SE
// (±inf or 0 when SE = 0, as the difference is nonzero or not) and the
// Welch–Satterthwaite d.o.f. (v_a + v_b)²/(v_a²/ν_a + v_b²/ν_b), where a side
// with v = 0 contributes nothing (+inf when both ν are +inf).
struct WelchStatistic {
  double difference = 0, standard_error = 0, statistic = 0, dof = 0;
};
WelchStatistic welch_statistic(const MeanEstimate& a, const MeanEstimate& b);

struct ComparisonTestResult {
  double difference = 0;      // mean_a − mean_b
  double standard_error = 0;  // √(s_a²/N_a + s_b²/N_b)
  double statistic = 0;
  double dof = 0;
  double p_value = 0;
  double alpha = 0;
  double threshold = 0;
  double detectable_difference = 0;           // with `power`
  double detectable_relative_difference = 0;  // relative to |mean_b|
  bool zero_variance = false;
  bool pass = false;
  std::string message;
};
ComparisonTestResult comparison_test(const SampleSummary& a, const SampleSummary& b, double alpha,
                                     double power = kDefaultPower);
// comparison_test of two mean estimates (comparison_test is welch_test of
// {mean, s²/N, N − 1}); the quantiles are Student's t at the Welch d.o.f.,
// normal for +inf. Both dof must be ≥ 1 (or +inf), else pass = false.
ComparisonTestResult welch_test(const MeanEstimate& a, const MeanEstimate& b, double alpha,
                                double power = kDefaultPower);

// ---------------------------------------------------------------------------
// Calibration: the empirical false-alarm (or rejection) rate of a test.
//
// `rejects(seed)` runs one complete test on data generated from `seed` and
// returns true if it rejected. Seeds first_seed, first_seed + 1, ... are used.
// The observed count is compared with Binomial(trials, expected_rate) by a
// two-sided test (twice the smaller tail, capped at 1).
struct RejectionRate {
  size_t trials = 0;
  size_t rejections = 0;
  double rate = 0;
  double expected_rate = 0;
  double ci_low = 0, ci_high = 0;  // Clopper–Pearson interval at ci_level
  double ci_level = 0;
  double binomial_p_value = 0;     // H0: rate == expected_rate
};
RejectionRate measure_rejection_rate(const std::function<bool(uint64_t seed)>& rejects, size_t trials,
                                     double expected_rate, uint64_t first_seed = 1, double ci_level = 0.95);
// Two-sided exact binomial p-value of k successes in n trials at rate p.
double binomial_two_sided_p_value(size_t k, size_t n, double p);

}  // namespace furnace::stats
