// The hypothesis tests of stats/statistics.h on distributions whose moments
// are known exactly: correct references pass, references shifted by more than
// the reported detectable bias fail (negative controls), and the family-wise
// corrections are computed to full precision.
//
// Every sample set comes from a fixed named seed and stream, so each verdict
// is fixed: a test that passes today fails only when the code changes.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <limits>
#include <string>

#include <boost/math/distributions/normal.hpp>
#include <boost/math/distributions/students_t.hpp>

#include "tests/stats/sample_moments.h"
#include "stats/statistics.h"

namespace furnace::stats {
namespace {

using testing_support::draw;
using testing_support::exponential;
using testing_support::Moments;
using testing_support::uniform;

constexpr uint64_t kSeed = 0x57a7157c5;  // fixed: verdicts are reproducible
// Per-test level of the tests below (no family: each is a separate claim).
constexpr double kAlpha = 1e-3;
constexpr uint64_t kSamples = 100000;
// Shift of the negative controls, in units of the detectable bias: at 1.5 δ
// the power is ≈ 0.999, so the control tests the power claim, not luck.
constexpr double kControlShift = 1.5;

// Exact moments of the test distributions.
constexpr double kUniformMean = 0.5, kUniformVariance = 1.0 / 12.0;
constexpr double kExponentialMean = 1.0, kExponentialVariance = 1.0;

void report(const std::string& key, double value) {
  testing::Test::RecordProperty(key, std::to_string(value));
  std::cout << "  " << key << " = " << value << "\n";
}

// --- family-wise corrections -------------------------------------------------

TEST(Sidak, SingleTestKeepsAlpha) {
  EXPECT_DOUBLE_EQ(sidak_alpha(0.05, 1), 0.05);
  EXPECT_DOUBLE_EQ(bonferroni_alpha(0.05, 1), 0.05);
}

TEST(Sidak, FamilyRateIsRestoredAndExceedsBonferroni) {
  for (double alpha : {0.1, 0.01, 1e-4}) {
    for (size_t n : {size_t(2), size_t(1024), size_t(1) << 30}) {
      const double a = sidak_alpha(alpha, n);
      // 1 − (1 − a)^n back to α, again through log1p/expm1 (independent of the forward formula's rounding).
      const double family = -std::expm1(double(n) * std::log1p(-a));
      EXPECT_NEAR(family, alpha, 64 * std::numeric_limits<double>::epsilon() * alpha) << alpha << " " << n;
      EXPECT_GE(a, bonferroni_alpha(alpha, n));
      // Šidák and Bonferroni agree to first order: a = α/n·(1 + O(α)).
      EXPECT_LT(a / bonferroni_alpha(alpha, n) - 1, alpha);
    }
  }
}

TEST(Sidak, TinyLevelsKeepTheirDigits) {
  // The naive 1 − pow(1 − α, 1/n) loses every digit here; the series
  // −log(1 − α)/n − … is exact to double precision at n = 1e12.
  const double alpha = 1e-3;
  const size_t n = size_t(1e12);
  const double series = -std::log1p(-alpha) / double(n);
  EXPECT_NEAR(sidak_alpha(alpha, n), series, 4 * std::numeric_limits<double>::epsilon() * series);
}

TEST(Sidak, RejectsBadArguments) {
  EXPECT_THROW(sidak_alpha(0.0, 3), std::invalid_argument);
  EXPECT_THROW(sidak_alpha(1.0, 3), std::invalid_argument);
  EXPECT_THROW(sidak_alpha(0.05, 0), std::invalid_argument);
}

// --- mean test ---------------------------------------------------------------

// N = kSamples, α = kAlpha, uncorrected (one test per case).
TEST(MeanTest, UniformPassesAtTrueMeanFailsBeyondDetectableBias) {
  const Moments m = draw(kSeed, 1, kSamples, uniform);
  const MeanTestResult ok = mean_test(m.count, m.mean, m.sample_variance(), kUniformMean, kAlpha);
  report("uniform_detectable_relative_bias", ok.detectable_relative_bias);
  EXPECT_TRUE(ok.pass) << ok.message;
  EXPECT_GT(ok.p_value, kAlpha);
  for (double sign : {-1.0, 1.0}) {
    const double shifted = kUniformMean + sign * kControlShift * ok.detectable_bias;
    const MeanTestResult bad = mean_test(m.count, m.mean, m.sample_variance(), shifted, kAlpha);
    EXPECT_FALSE(bad.pass) << "shift " << sign * kControlShift << " detectable biases went undetected";
  }
}

// N = kSamples, α = kAlpha: a skewed estimator.
TEST(MeanTest, ExponentialPassesAtTrueMeanFailsBeyondDetectableBias) {
  const Moments m = draw(kSeed, 2, kSamples, exponential);
  const MeanTestResult ok = mean_test(m.count, m.mean, m.sample_variance(), kExponentialMean, kAlpha);
  report("exponential_detectable_relative_bias", ok.detectable_relative_bias);
  EXPECT_TRUE(ok.pass) << ok.message;
  const MeanTestResult bad =
      mean_test(m.count, m.mean, m.sample_variance(), kExponentialMean * (1 + kControlShift * ok.detectable_relative_bias), kAlpha);
  EXPECT_FALSE(bad.pass);
}

TEST(MeanTest, DetectableBiasIsQuantileSumTimesStandardError) {
  // Small N, where Student's t and the normal differ visibly.
  const uint64_t n = 8;
  const double variance = 2.0, alpha = 0.05, power = 0.9;
  const MeanTestResult r = mean_test(n, 1.0, variance, 1.0, alpha, power);
  const boost::math::students_t_distribution<double> t(double(n - 1));
  const double expected = (boost::math::quantile(t, 1 - alpha / 2) + boost::math::quantile(t, power)) *
                          std::sqrt(variance / double(n));
  EXPECT_NEAR(r.detectable_bias, expected, 1e-12 * expected);
  EXPECT_NEAR(r.threshold, boost::math::quantile(t, 1 - alpha / 2), 1e-12);
  EXPECT_GT(r.threshold, boost::math::quantile(boost::math::normal_distribution<double>(), 1 - alpha / 2));
}

TEST(MeanTest, LargeCountEqualsZTest) {
  const uint64_t n = uint64_t(1) << 40;
  const MeanTestResult t = mean_test(n, 1.001, 1.0, 1.0, kAlpha);
  const ZTestResult z = z_test(1.001, 1.0, std::sqrt(1.0 / double(n)), kAlpha);
  EXPECT_NEAR(t.threshold, z.threshold, 1e-9);
  EXPECT_NEAR(t.statistic, z.statistic, 1e-9 * std::fabs(z.statistic));
  EXPECT_NEAR(t.detectable_bias, z.detectable_bias, 1e-9 * z.detectable_bias);
}

TEST(MeanTest, ZeroVarianceRequiresExactAgreement) {
  const double reference = 0.731;
  const MeanTestResult same = mean_test(64, reference * (1 + 0.5 * kZeroVarianceRelTolerance), 0.0, reference, kAlpha);
  EXPECT_TRUE(same.pass) << same.message;
  EXPECT_TRUE(same.zero_variance);
  const MeanTestResult off = mean_test(64, reference * (1 + 2 * kZeroVarianceRelTolerance), 0.0, reference, kAlpha);
  EXPECT_FALSE(off.pass);
  EXPECT_TRUE(off.zero_variance);
  EXPECT_FALSE(off.message.empty());
  // A zero reference admits only an exact zero.
  EXPECT_TRUE(mean_test(64, 0.0, 0.0, 0.0, kAlpha).pass);
  EXPECT_FALSE(mean_test(64, 1e-300, 0.0, 0.0, kAlpha).pass);
}

TEST(MeanTest, DegenerateInputsFail) {
  EXPECT_FALSE(mean_test(1, 0.5, 0.0, 0.5, kAlpha).pass);
  EXPECT_FALSE(mean_test(0, 0.0, 0.0, 0.0, kAlpha).pass);
  EXPECT_FALSE(mean_test(100, std::nan(""), 1.0, 0.5, kAlpha).pass);
  EXPECT_FALSE(mean_test(100, 0.5, std::numeric_limits<double>::infinity(), 0.5, kAlpha).pass);
  EXPECT_THROW(mean_test(100, 0.5, 1.0, 0.5, 0.0), std::invalid_argument);
}

// Exp(1) has skewness exactly 2: Cochran's rule asks N > 25·4 = 100.
TEST(MeanTest, SkewnessAndCochranRule) {
  const Moments large = draw(kSeed, 9, kSamples, exponential);
  const MeanTestResult r = mean_test(large, kExponentialMean, kAlpha);
  EXPECT_NEAR(r.skewness, 2.0, 0.1);
  EXPECT_TRUE(r.clt_adequate);
  EXPECT_TRUE(r.pass) << r.message;
  // Same verdict and numbers as the (count, mean, variance) overload.
  const MeanTestResult plain = mean_test(large.count, large.mean, large.sample_variance(), kExponentialMean, kAlpha);
  EXPECT_EQ(r.statistic, plain.statistic);
  EXPECT_EQ(r.detectable_bias, plain.detectable_bias);
  const Moments small = draw(kSeed, 10, 40, exponential);
  const MeanTestResult few = mean_test(small, kExponentialMean, kAlpha);
  EXPECT_FALSE(few.clt_adequate) << "skewness " << few.skewness;
  EXPECT_NE(few.message.find("Cochran"), std::string::npos) << few.message;
}

// --- variance test -----------------------------------------------------------

// N = kSamples, α = kAlpha.
TEST(VarianceTest, UniformPassesAtTrueVarianceFailsBeyondDetectableError) {
  const Moments m = draw(kSeed, 3, kSamples, uniform);
  const VarianceTestResult ok = variance_test(m, kUniformVariance, kAlpha);
  report("uniform_detectable_relative_variance_error", ok.detectable_relative_error);
  EXPECT_TRUE(ok.pass) << ok.message;
  for (double sign : {-1.0, 1.0}) {
    const double wrong = kUniformVariance * (1 + sign * kControlShift * ok.detectable_relative_error);
    EXPECT_FALSE(variance_test(m, wrong, kAlpha).pass) << "sign " << sign;
  }
}

// N = kSamples, α = kAlpha. The SE of s² uses μ4 = 9 σ⁴ here (vs 1.8 σ⁴ for the uniform).
TEST(VarianceTest, ExponentialPassesAtTrueVarianceFailsBeyondDetectableError) {
  const Moments m = draw(kSeed, 4, kSamples, exponential);
  const VarianceTestResult ok = variance_test(m, kExponentialVariance, kAlpha);
  report("exponential_detectable_relative_variance_error", ok.detectable_relative_error);
  EXPECT_TRUE(ok.pass) << ok.message;
  // SE(s²)/σ² → √((μ4/σ⁴ − 1)/N) = √(8/N) for Exp(1).
  EXPECT_NEAR(ok.standard_error, std::sqrt(8.0 / double(kSamples)), 0.1 * std::sqrt(8.0 / double(kSamples)));
  EXPECT_FALSE(variance_test(m, kExponentialVariance * (1 + kControlShift * ok.detectable_relative_error), kAlpha).pass);
}

// The stated detectable variance error δ solves δ/(1 + δ) = k: the statistic
// at a true variance (1 + δ)σ², whose estimated SE grows by (1 + δ) too, then
// has the mean (z_α + z_power) that gives the stated power. Beyond k = 1 no
// variance excess is detectable.
TEST(VarianceTest, DetectableErrorAccountsForTheStandardErrorGrowingWithTheVariance) {
  for (double k : {1e-4, 0.01, 0.1, 0.5, 0.9}) {
    const double delta = detectable_relative_variance_error(k);
    EXPECT_GT(delta, k) << "k " << k;
    EXPECT_NEAR(delta / (1 + delta), k, 4 * std::numeric_limits<double>::epsilon()) << "k " << k;
  }
  EXPECT_TRUE(std::isinf(detectable_relative_variance_error(1.0)));
  EXPECT_TRUE(std::isinf(detectable_relative_variance_error(std::numeric_limits<double>::infinity())));
  EXPECT_TRUE(std::isinf(detectable_relative_variance_error(std::nan(""))));
}

TEST(VarianceTest, ZeroPredictedVariance) {
  Moments exact;
  for (int i = 0; i < 200; ++i) exact.add(0.25);
  EXPECT_TRUE(variance_test(exact, 0.0, kAlpha).pass);
  EXPECT_FALSE(variance_test(exact, 0.01, kAlpha).pass);  // nonzero predicted, none observed
  const Moments noisy = draw(kSeed, 5, 200, uniform);
  EXPECT_FALSE(variance_test(noisy, 0.0, kAlpha).pass);
}

TEST(VarianceTest, TooFewSamplesFail) {
  const Moments m = draw(kSeed, 6, kMinVarianceTestSamples - 1, uniform);
  const VarianceTestResult r = variance_test(m, kUniformVariance, kAlpha);
  EXPECT_FALSE(r.pass);
  EXPECT_FALSE(r.message.empty());
}

// --- many mean tests ---------------------------------------------------------

// 256 "pixels" of 4096 samples, family-wise α = 0.01 with Šidák over 256.
TEST(MeanTests, PixelsPassAndOneBiasedPixelIsFound) {
  constexpr size_t kPixels = 256;
  constexpr uint64_t kPerPixel = 4096;
  constexpr double kFamilyAlpha = 0.01;
  std::vector<SampleSummary> pixels;
  std::vector<double> references;
  for (size_t p = 0; p < kPixels; ++p) {
    const double scale = 0.5 + double(p) / kPixels;  // pixel p has mean `scale`
    pixels.push_back(draw(kSeed, 100 + p, kPerPixel, [&](double u) { return scale * exponential(u); }).summary());
    references.push_back(scale);
  }
  const MeanTestSummary ok = mean_tests(pixels, references, kFamilyAlpha);
  report("median_pixel_detectable_relative_bias", ok.median_detectable_relative_bias);
  EXPECT_EQ(ok.failures, 0u) << "worst |t| " << ok.worst_abs_statistic;
  EXPECT_TRUE(ok.pass);
  EXPECT_DOUBLE_EQ(ok.alpha_each, sidak_alpha(kFamilyAlpha, kPixels));

  constexpr size_t kBiased = 77;
  const MeanTestResult single = mean_test(pixels[kBiased].count, pixels[kBiased].mean,
                                          pixels[kBiased].sample_variance, references[kBiased], ok.alpha_each);
  references[kBiased] *= 1 + kControlShift * single.detectable_relative_bias;
  const MeanTestSummary bad = mean_tests(pixels, references, kFamilyAlpha);
  EXPECT_EQ(bad.failures, 1u);
  EXPECT_EQ(bad.worst_index, kBiased);
  EXPECT_FALSE(bad.pass);
}

// --- Welch comparison --------------------------------------------------------

// Two estimators of the mean 1 with different variances (Exp(1) and a
// uniform on [0, 2)), 50 000 and 20 000 samples, α = kAlpha.
TEST(ComparisonTest, EqualMeansPassShiftedFail) {
  const SampleSummary a = draw(kSeed, 7, 50000, exponential).summary();
  const SampleSummary b = draw(kSeed, 8, 20000, [](double u) { return 2 * u; }).summary();
  const ComparisonTestResult ok = comparison_test(a, b, kAlpha);
  report("welch_detectable_relative_difference", ok.detectable_relative_difference);
  EXPECT_TRUE(ok.pass) << ok.message;
  EXPECT_GT(ok.dof, 20000.0);
  SampleSummary shifted = b;
  shifted.mean += kControlShift * ok.detectable_difference;
  EXPECT_FALSE(comparison_test(a, shifted, kAlpha).pass);
}

TEST(ComparisonTest, ZeroVarianceBothSides) {
  EXPECT_TRUE(comparison_test({10, 2.0, 0.0}, {20, 2.0, 0.0}, kAlpha).pass);
  EXPECT_FALSE(comparison_test({10, 2.0, 0.0}, {20, 2.1, 0.0}, kAlpha).pass);
}

// --- calibration helpers -----------------------------------------------------

TEST(Binomial, TwoSidedPValue) {
  EXPECT_NEAR(binomial_two_sided_p_value(50, 100, 0.5), 1.0, 1e-12);
  EXPECT_LT(binomial_two_sided_p_value(0, 1000, 0.05), 1e-20);
  EXPECT_LT(binomial_two_sided_p_value(100, 1000, 0.05), 1e-6);
  EXPECT_GT(binomial_two_sided_p_value(52, 1000, 0.05), 0.5);
}

TEST(RejectionRate, CountsAndBracketsTheRate) {
  // A fake test that rejects every 20th seed: rate 0.05 exactly.
  const RejectionRate r = measure_rejection_rate([](uint64_t seed) { return seed % 20 == 0; }, 400, 0.05);
  EXPECT_EQ(r.rejections, 20u);
  EXPECT_DOUBLE_EQ(r.rate, 0.05);
  EXPECT_LT(r.ci_low, 0.05);
  EXPECT_GT(r.ci_high, 0.05);
  EXPECT_GT(r.binomial_p_value, 0.5);
}

}  // namespace
}  // namespace furnace::stats

// The quantiles are memoised per thread (the last few arguments): every value
// must equal Boost's for the same arguments, whatever was asked before it,
// including after its entry was evicted by more distinct arguments than the
// memo holds.
TEST(Quantiles, MemoisedValuesEqualBoostsInAnyOrder) {
  const double levels[] = {0.5e-6, 0.1, 0.025, 1e-9, 0.3, 0.1, 0.5e-6, 0.2, 1e-9, 0.025, 0.1};
  const double dofs[] = {4095, 127, 4095, 9, 1e6};
  size_t checked = 0;
  for (int round = 0; round < 3; ++round)
    for (double dof : dofs)
      for (double q : levels) {
        const furnace::stats::MeanTestResult r = furnace::stats::mean_test(uint64_t(dof) + 1, 0.1, 1.0, 0.0, 2 * q, 0.9);
        const double expected = boost::math::quantile(
            boost::math::complement(boost::math::students_t_distribution<double>(dof), q));
        EXPECT_EQ(r.threshold, expected) << "dof " << dof << ", q " << q;
        EXPECT_EQ(furnace::stats::normal_upper_quantile(q),
                  boost::math::quantile(boost::math::complement(boost::math::normal_distribution<double>(), q)));
        ++checked;
      }
  // Negative control: a neighbouring level's quantile is not the same number,
  // so a memo answering for the wrong key would be seen.
  EXPECT_NE(furnace::stats::normal_upper_quantile(0.1), furnace::stats::normal_upper_quantile(std::nextafter(0.1, 1.0)));
  std::printf("%zu (dof, level) pairs: memoised quantiles equal Boost's bit for bit\n", checked);
}
