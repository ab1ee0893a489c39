// Calibration of the statistical tests themselves (label `slow`): over
// kTrials independent seeds, a test at level kTestAlpha must reject a true
// hypothesis at rate ≈ kTestAlpha (false alarms), and a mean shifted by the
// reported detectable bias (and a sampler off by the chi-square's reported
// detectable effect) at rate ≈ kDefaultPower (power). Each measured rate
// is compared with its nominal value by an exact two-sided binomial test
// (Boost binomial) at kCalibrationAlpha.
//
// Seeds are fixed (kFirstSeed, kFirstSeed + 1, ...), so the verdicts are fixed too.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <string>

#include <boost/math/distributions/normal.hpp>

#include "renderer/rng.h"
#include "renderer/sampling.h"
#include "tests/stats/sample_moments.h"
#include "stats/chi2.h"
#include "stats/statistics.h"

namespace furnace::stats {
namespace {

using testing_support::draw;
using testing_support::exponential;
using testing_support::Moments;
using testing_support::uniform;

// 1000 trials resolve a false-alarm rate of 0.05 to about ±0.014 (95 %).
constexpr size_t kTrials = 1000;
constexpr uint64_t kFirstSeed = 0xca11b000;
// Level of the tests under calibration: large, so that kTrials trials see
// ~20 false alarms and a rate off by a factor 2 is resolved.
constexpr double kTestAlpha = 0.05;
// Level of each binomial calibration check (9 checks: family ≈ 0.9 %).
constexpr double kCalibrationAlpha = 1e-3;

void report(const std::string& what, const RejectionRate& r) {
  std::cout << "  " << what << ": " << r.rejections << "/" << r.trials << " = " << r.rate << " (nominal "
            << r.expected_rate << ", 95% CI [" << r.ci_low << ", " << r.ci_high << "], binomial p "
            << r.binomial_p_value << ")\n";
  testing::Test::RecordProperty(what + "_rate", std::to_string(r.rate));
  testing::Test::RecordProperty(what + "_binomial_p", std::to_string(r.binomial_p_value));
}

// Exp(1) samples, N = 1000 per trial, true mean 1.
TEST(Calibration, MeanTestFalseAlarmRate) {
  const RejectionRate r = measure_rejection_rate(
      [](uint64_t seed) {
        const Moments m = draw(seed, 1, 1000, exponential);
        return !mean_test(m.count, m.mean, m.sample_variance(), 1.0, kTestAlpha).pass;
      },
      kTrials, kTestAlpha, kFirstSeed);
  report("mean_test_false_alarm", r);
  EXPECT_GE(r.binomial_p_value, kCalibrationAlpha);
}

// U[0,1) samples, N = 1000 per trial, tested against 1/2 − δ where
// δ = (t_{1−α/2} + t_{power})·σ/√N with the true σ² = 1/12: the rejection
// rate must match the power the test claims.
TEST(Calibration, MeanTestPowerAtDetectableBias) {
  constexpr uint64_t kN = 1000;
  const double sigma = std::sqrt(1.0 / 12.0);
  // The claimed detectable bias at the true σ (the mean and s² passed here only fix SE).
  const double delta = mean_test(kN, 0.5, sigma * sigma, 0.5, kTestAlpha).detectable_bias;
  const RejectionRate r = measure_rejection_rate(
      [delta](uint64_t seed) {
        const Moments m = draw(seed, 2, kN, uniform);
        return !mean_test(m.count, m.mean, m.sample_variance(), 0.5 - delta, kTestAlpha).pass;
      },
      kTrials, kDefaultPower, kFirstSeed);
  report("mean_test_power", r);
  EXPECT_GE(r.binomial_p_value, kCalibrationAlpha);
}

// U[0,1) (light tails) and Exp(1) (μ4 = 9σ⁴), N = 10 000 per trial.
TEST(Calibration, VarianceTestFalseAlarmRate) {
  const RejectionRate light = measure_rejection_rate(
      [](uint64_t seed) {
        const Moments m = draw(seed, 3, 10000, uniform);
        return !variance_test(m, 1.0 / 12.0, kTestAlpha).pass;
      },
      kTrials, kTestAlpha, kFirstSeed);
  report("variance_test_uniform_false_alarm", light);
  EXPECT_GE(light.binomial_p_value, kCalibrationAlpha);
  const RejectionRate heavy = measure_rejection_rate(
      [](uint64_t seed) {
        const Moments m = draw(seed, 4, 10000, exponential);
        return !variance_test(m, 1.0, kTestAlpha).pass;
      },
      kTrials, kTestAlpha, kFirstSeed);
  report("variance_test_exponential_false_alarm", heavy);
  EXPECT_GE(heavy.binomial_p_value, kCalibrationAlpha);
}

// Exp(1), N = 2000, vs U[0,2), N = 500: equal means, unequal variances and sizes.
TEST(Calibration, WelchFalseAlarmRate) {
  const RejectionRate r = measure_rejection_rate(
      [](uint64_t seed) {
        const SampleSummary a = draw(seed, 5, 2000, exponential).summary();
        const SampleSummary b = draw(seed, 6, 500, [](double u) { return 2 * u; }).summary();
        return !comparison_test(a, b, kTestAlpha).pass;
      },
      kTrials, kTestAlpha, kFirstSeed);
  report("welch_false_alarm", r);
  EXPECT_GE(r.binomial_p_value, kCalibrationAlpha);
}

// Cosine-hemisphere samples (renderer warp), N = 100 000 per trial, 21×10 cells.
TEST(Calibration, Chi2FalseAlarmRate) {
  const DirectionalChi2 chi2(cosine_hemisphere_pdf, SphericalGrid::hemisphere(10));
  const RejectionRate r = measure_rejection_rate(
      [&chi2](uint64_t seed) {
        Rng rng(seed, 7, 0);
        std::vector<Vec3> samples(100000);
        for (Vec3& w : samples) {
          const double u1 = rng.next_double();
          w = sample_cosine_hemisphere(u1, rng.next_double());
        }
        return !chi2.test(samples, kTestAlpha, 1).pass;
      },
      kTrials, kTestAlpha, kFirstSeed);
  report("chi2_false_alarm", r);
  EXPECT_GE(r.binomial_p_value, kCalibrationAlpha);
}

// A strongly skewed estimator (log-normal, σ = 1.5: skewness ≈ 33, so
// Cochran's rule asks N > ~28 000) at N = 1000: the t-test's α is then only
// approximate. Either its false-alarm rate is still consistent with α, or
// the skewness check must have flagged most trials; the rate is reported.
TEST(Calibration, SkewedEstimatorIsFlaggedByCochranRule) {
  constexpr double kSigma = 1.5;
  const double true_mean = std::exp(kSigma * kSigma / 2);
  size_t flagged = 0;
  const RejectionRate r = measure_rejection_rate(
      [&](uint64_t seed) {
        const Moments m = draw(seed, 10, 1000, [](double u) {
          // u ∈ [0, 1): shift off 0, where the normal quantile is −∞.
          const double z = boost::math::quantile(boost::math::normal_distribution<double>(), 0.5 * 0x1.0p-53 + u);
          return std::exp(kSigma * z);
        });
        const MeanTestResult t = mean_test(m, true_mean, kTestAlpha);
        if (!t.clt_adequate) ++flagged;
        return !t.pass;
      },
      kTrials, kTestAlpha, kFirstSeed);
  report("skewed_mean_test_false_alarm", r);
  std::cout << "  trials flagged by Cochran's rule: " << flagged << "/" << kTrials << "\n";
  testing::Test::RecordProperty("skewed_flagged", std::to_string(flagged));
  EXPECT_TRUE(r.binomial_p_value >= kCalibrationAlpha || flagged > kTrials / 2);
}

// Two-sample chi-square: Malley vs inversion cosine samples, N = 100 000
// each per trial, 21×10 cells.
TEST(Calibration, TwoSampleChi2FalseAlarmRate) {
  const SphericalGrid grid = SphericalGrid::hemisphere(10);
  const RejectionRate r = measure_rejection_rate(
      [&grid](uint64_t seed) {
        Rng rng(seed, 9, 0);
        std::vector<Vec3> a(100000), b(100000);
        for (size_t i = 0; i < a.size(); ++i) {
          const double u1 = rng.next_double(), u2 = rng.next_double(), u3 = rng.next_double(), u4 = rng.next_double();
          a[i] = sample_cosine_hemisphere_malley(u1, u2);
          b[i] = sample_cosine_hemisphere(u3, u4);
        }
        return !chi2_two_sample(direction_histogram(a, grid).counts, direction_histogram(b, grid).counts, kTestAlpha)
                    .pass;
      },
      kTrials, kTestAlpha, kFirstSeed);
  report("two_sample_chi2_false_alarm", r);
  EXPECT_GE(r.binomial_p_value, kCalibrationAlpha);
}

// Power of the chi-square: samples from the mixture (1 − ε)·cosine + ε·uniform
// on the hemisphere, tested against the cosine pdf. The mixture's effect is
// w = ε·w₁ (w₁ the effect of pure uniform samples), so ε = w_detectable/w₁
// puts it exactly at the reported detectable effect: the rejection rate must
// be the claimed power. N = 100 000 per trial, 21×10 cells.
TEST(Calibration, Chi2PowerAtDetectableEffect) {
  constexpr size_t kN = 100000;
  const SphericalGrid grid = SphericalGrid::hemisphere(10);
  const DirectionalChi2 chi2(cosine_hemisphere_pdf, grid);
  const std::vector<double>& p = chi2.cell_probabilities();
  const std::vector<double> q = DirectionalChi2(uniform_hemisphere_pdf, grid).cell_probabilities();  // a copy: the temporary dies here
  double w1_squared = 0;
  for (size_t i = 0; i < p.size(); ++i) w1_squared += (q[i] - p[i]) * (q[i] - p[i]) / p[i];
  // Closed form: w₁² = Σ q²/p − 1 over rows; row j (t ∈ [j, j+1]/10) has
  // q = 1/10 and p = (19 − 2j)/100, so w₁² = Σ_{j<10} 1/(2j + 1) − 1.
  double w1_squared_exact = -1;
  for (int j = 0; j < grid.t_bins; ++j) w1_squared_exact += 1.0 / (2 * j + 1);
  ASSERT_NEAR(w1_squared, w1_squared_exact, 1e-9);
  // The detectable effect depends only on N, the pooled dof and α: read it from any sample set.
  std::vector<Vec3> probe(kN, Vec3(0, 0, 1));
  const double w_detectable = chi2.test(probe, kTestAlpha, 1).detectable_effect;
  const double epsilon = w_detectable / std::sqrt(w1_squared);
  std::cout << "  detectable w = " << w_detectable << ", mixture weight of uniform samples = " << epsilon << "\n";
  const RejectionRate r = measure_rejection_rate(
      [&](uint64_t seed) {
        Rng rng(seed, 8, 0);
        std::vector<Vec3> samples(kN);
        for (Vec3& w : samples) {
          const bool uniform_sample = rng.next_double() < epsilon;
          const double u1 = rng.next_double();
          const double u2 = rng.next_double();
          w = uniform_sample ? sample_uniform_hemisphere(u1, u2) : sample_cosine_hemisphere(u1, u2);
        }
        return !chi2.test(samples, kTestAlpha, 1).pass;
      },
      kTrials, kDefaultPower, kFirstSeed);
  report("chi2_power", r);
  EXPECT_GE(r.binomial_p_value, kCalibrationAlpha);
}

}  // namespace
}  // namespace furnace::stats
