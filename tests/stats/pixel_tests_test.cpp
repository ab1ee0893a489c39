// The per-pixel and image-wide tests of stats/pixel_tests.h on samples whose
// distribution is known exactly: correct references pass, references off by
// more than the reported detectable bias fail (negative controls), and each
// validity rule (Cochran's skewness rule, the constant-pixel rule, the
// zero-variance image) picks the pixels it documents.
//
// Every sample set comes from a fixed named seed and stream, so each verdict
// is fixed: a test that passes today fails only when the code changes.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
#include <stdexcept>
#include <vector>

#include <boost/math/distributions/binomial.hpp>
#include <boost/math/distributions/students_t.hpp>

#include "renderer/rng.h"
#include "tests/stats/sample_moments.h"
#include "stats/pixel_tests.h"
#include "stats/statistics.h"

namespace furnace::stats {
namespace {

using testing_support::draw;
using testing_support::exponential;
using testing_support::Moments;
using testing_support::uniform;

constexpr uint64_t kSeed = 0x91c5e7e5;  // fixed: verdicts are reproducible
// Per-test level of the single-pixel tests below (each a separate claim).
constexpr double kAlpha = 1e-3;
// Shift of the negative controls, in units of the detectable bias: at 1.5 δ
// the power is ≈ 0.999, so the control tests the power claim, not luck.
constexpr double kControlShift = 1.5;
// A pixel's spp in a verification run (furnace verify's default).
constexpr uint64_t kSpp = 4096;

// A pixel of n equal samples.
RunningMoments constant_pixel(double value, uint64_t n) {
  RunningMoments m;
  for (uint64_t i = 0; i < n; ++i) m.add(value);
  return m;
}

// Bernoulli(p) samples: the rare hit of a small light, skewness (1 − 2p)/√(p(1 − p)).
double bernoulli(double u, double p) { return u < p ? 1.0 : 0.0; }

// --- Hall's statistic ---------------------------------------------------------

// Symmetric samples (each value and its mirror about 1/2) have γ = 0: Hall's
// statistic is then Student's t itself.
TEST(HallStatistic, EqualsStudentTWithoutSkewness) {
  RunningMoments m;
  Rng rng(kSeed, 1, 0);
  for (int i = 0; i < 500; ++i) {
    const double u = rng.next_double();
    m.add(u);
    m.add(1 - u);
  }
  ASSERT_NEAR(sample_skewness(m), 0.0, 1e-12);
  const double reference = 0.49;
  const MeanTestResult t = mean_test(m.count, m.mean, m.sample_variance(), reference, kAlpha);
  EXPECT_NEAR(hall_statistic(m, reference), t.statistic, 1e-9 * std::fabs(t.statistic));
}

// On a right-skewed estimator the plain t has a heavy left tail (a sample
// mean below μ comes with a small s); Hall's transformation moves the two
// one-sided rejection rates towards their nominal 2.5 % each. Exp(1) at
// N = 20, 20 000 fixed-seed trials.
TEST(HallStatistic, BalancesTheTailsOfASkewedMean) {
  constexpr int kTrials = 20000;
  constexpr uint64_t kN = 20;
  const double tail = 0.025;
  const double critical = boost::math::quantile(
      boost::math::complement(boost::math::students_t_distribution<double>(double(kN - 1)), tail));
  int t_low = 0, t_high = 0, hall_low = 0, hall_high = 0;
  for (int trial = 0; trial < kTrials; ++trial) {
    const Moments m = draw(kSeed, 1000 + trial, kN, exponential);
    const double t = mean_test(m.count, m.mean, m.sample_variance(), 1.0, kAlpha).statistic;
    const double h = hall_statistic(m, 1.0);
    t_low += t < -critical;
    t_high += t > critical;
    hall_low += h < -critical;
    hall_high += h > critical;
  }
  const double expected = tail * kTrials;
  std::printf("  one-sided rejections of %d (nominal %.0f): t %d low / %d high, Hall %d low / %d high\n", kTrials,
              expected, t_low, t_high, hall_low, hall_high);
  EXPECT_LT(std::fabs(hall_low - expected), std::fabs(t_low - expected));
  EXPECT_LT(std::abs(hall_low - hall_high), std::abs(t_low - t_high));
}

// --- validity rules ------------------------------------------------------------

TEST(RoundOffOnly, ToleratesOnlyFloatNoise) {
  EXPECT_TRUE(round_off_only(constant_pixel(0.25, 64)));
  EXPECT_TRUE(round_off_only(RunningMoments{}));  // no samples: s = 0
  // Spread of ±δ·mean about the mean: s ≈ δ·mean.
  auto spread = [](double delta) {
    RunningMoments m;
    for (int i = 0; i < 64; ++i) m.add(0.25 * (1 + (i % 2 ? delta : -delta)));
    return m;
  };
  EXPECT_TRUE(round_off_only(spread(0.5 * kZeroVarianceRelTolerance)));
  EXPECT_FALSE(round_off_only(spread(2 * kZeroVarianceRelTolerance)));
  EXPECT_FALSE(round_off_only(draw(kSeed, 2, 64, uniform)));
}

TEST(ZeroVarianceImage, NeedsEveryPixelConstant) {
  std::vector<RunningMoments> pixels(16, constant_pixel(0.5, 64));
  EXPECT_TRUE(zero_variance_image(pixels));
  EXPECT_TRUE(zero_variance_image({}));
  pixels[7] = draw(kSeed, 3, 64, uniform);
  EXPECT_FALSE(zero_variance_image(pixels));
}

// Exp(1) has skewness 2: Cochran's rule asks N ≥ 25·4 = 100.
TEST(CltAdequate, FollowsCochransRule) {
  EXPECT_TRUE(clt_adequate(draw(kSeed, 4, 1000, exponential)));
  EXPECT_FALSE(clt_adequate(draw(kSeed, 5, 40, exponential)));
  // No spread, no skewness: adequate (a constant pixel is tested exactly instead).
  EXPECT_TRUE(clt_adequate(constant_pixel(1.0, 10)));
  // A skewness that is not a number does not hide a pixel from its test.
  RunningMoments nan;
  nan.count = 10;
  nan.m2 = 1;
  nan.m3 = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(clt_adequate(nan));
}

// --- one pixel's mean test -----------------------------------------------------

TEST(PixelMeanTest, UnbiasedPixelPassesShiftedReferenceFails) {
  const Moments m = draw(kSeed, 6, kSpp, exponential);
  const PixelTestResult ok = pixel_mean_test(m, 1.0, kAlpha, false);
  ASSERT_EQ(ok.status, PixelStatus::kTested);
  EXPECT_TRUE(ok.test.pass) << ok.test.message;
  EXPECT_EQ(ok.test.statistic, hall_statistic(m, 1.0));
  EXPECT_FALSE(ok.test.zero_variance);
  for (double sign : {-1.0, 1.0}) {
    const double shifted = 1.0 + sign * kControlShift * ok.test.detectable_bias;
    const PixelTestResult bad = pixel_mean_test(m, shifted, kAlpha, false);
    ASSERT_EQ(bad.status, PixelStatus::kTested);
    EXPECT_FALSE(bad.test.pass) << "shift " << sign * kControlShift << " detectable biases went undetected";
    EXPECT_FALSE(bad.test.message.empty());
    EXPECT_LT(bad.test.p_value, kAlpha);
  }
}

// A light hit with p = 0.002: skewness ≈ 22, Cochran asks N ≥ 12 500.
TEST(PixelMeanTest, SkewedPixelIsNotTested) {
  const Moments m = draw(kSeed, 7, kSpp, [](double u) { return bernoulli(u, 0.002); });
  ASSERT_GT(m.mean, 0.0);
  EXPECT_EQ(pixel_mean_test(m, 0.002, kAlpha, false).status, PixelStatus::kSkewed);
  // Even against a reference it visibly misses (negative control of the rule, not of the test).
  EXPECT_EQ(pixel_mean_test(m, 0.5, kAlpha, false).status, PixelStatus::kSkewed);
  // The same estimator at 20 times the samples satisfies the rule.
  const Moments many = draw(kSeed, 8, 20 * kSpp, [](double u) { return bernoulli(u, 0.002); });
  const PixelTestResult r = pixel_mean_test(many, 0.002, kAlpha, false);
  EXPECT_EQ(r.status, PixelStatus::kTested);
  EXPECT_TRUE(r.test.pass) << r.test.message;
}

TEST(PixelMeanTest, ConstantPixelMustMatchExactly) {
  const double reference = 0.731;
  const PixelTestResult same = pixel_mean_test(constant_pixel(reference, kSpp), reference, kAlpha, false);
  EXPECT_EQ(same.status, PixelStatus::kTested);
  EXPECT_TRUE(same.test.pass);
  EXPECT_TRUE(same.test.zero_variance);
  // Off by twice the tolerance: in a zero-variance image it fails ...
  const RunningMoments off = constant_pixel(reference * (1 + 2 * kZeroVarianceRelTolerance), kSpp);
  const PixelTestResult exact = pixel_mean_test(off, reference, kAlpha, true);
  EXPECT_EQ(exact.status, PixelStatus::kTested);
  EXPECT_FALSE(exact.test.pass);
  EXPECT_TRUE(exact.test.zero_variance);
  // ... elsewhere it is a rare event that never occurred, left untested.
  EXPECT_EQ(pixel_mean_test(off, reference, kAlpha, false).status, PixelStatus::kConstantMiss);
}

// --- the known-variance test below the reference (Bernstein) -------------------

TEST(Bernstein, CriticalDeficitSolvesTheExponent) {
  for (double n : {2.0, 256.0, 4096.0, 1e6})
    for (double variance : {0.0, 1e-6, 0.3, 50.0})
      for (double bound : {0.0, 0.2, 3.0})
        for (double q : {0.25, 1e-3, 1e-9}) {
          if (variance == 0 && bound == 0) continue;  // no deficit is possible
          const double d = bernstein_deficit(n, variance, bound, q);
          EXPECT_NEAR(bernstein_exponent(n, d, variance, bound), -std::log(q), 1e-9 * -std::log(q))
              << n << " " << variance << " " << bound << " " << q;
        }
  EXPECT_EQ(bernstein_exponent(100, 0, 1, 1), 0);
  EXPECT_EQ(bernstein_exponent(100, -0.5, 1, 1), 0);
}

// A pixel whose estimator is a faint background plus a rare large
// contribution: with probability p the sample is `spike`, else uniform on
// [0, 2·base). The point_and_area light_area@power pixel of issue 41 is of
// this kind (a rarely selected light of large weight).
struct RareEvent {
  double base, p, spike;
  double sample(double u1, double u2) const { return u1 < p ? spike : 2 * base * u2; }
  double mean() const { return p * spike + (1 - p) * base; }
  double second_moment() const { return p * spike * spike + (1 - p) * 4 * base * base / 3; }
  double variance() const { return second_moment() - mean() * mean(); }
};

Moments rare_pixel(const RareEvent& e, uint64_t stream, uint64_t n) {
  Rng rng(kSeed, stream, 0);
  Moments m;
  for (uint64_t i = 0; i < n; ++i) {
    const double u1 = rng.next_double();
    m.add(e.sample(u1, rng.next_double()));
  }
  return m;
}

// At 256 samples with p = 2e-3 (0.5 expected hits) most runs miss every
// spike: the mean sits low and so does the sample variance, and Hall's t
// rejects the correct reference; with the exact variance the same pixel
// passes. The first stream whose run missed every spike is taken.
TEST(PixelMeanTest, KnownVarianceDoesNotFailAMissedRareEvent) {
  const RareEvent e{0.2, 2e-3, 20};
  const uint64_t n = 256;
  Moments missed;
  for (uint64_t stream = 1000;; ++stream) {
    missed = rare_pixel(e, stream, n);
    if (missed.mean < 2 * e.base) break;  // no spike in this run
  }
  const PixelTestResult sample_only = pixel_mean_test(missed, e.mean(), kAlpha, false);
  ASSERT_EQ(sample_only.status, PixelStatus::kTested);
  EXPECT_FALSE(sample_only.test.pass) << "the sample-variance test no longer fails a missed rare event: "
                                      << sample_only.test.statistic;
  const PixelTestResult known = pixel_mean_test(missed, e.mean(), kAlpha, false, kDefaultPower, e.variance());
  EXPECT_EQ(known.status, PixelStatus::kTested);
  EXPECT_TRUE(known.test.pass) << known.test.message;
  EXPECT_LT(known.test.statistic, 0);
  EXPECT_DOUBLE_EQ(known.test.standard_error, std::sqrt(e.variance() / double(n)));
  std::printf("missed rare event at N = %llu: Hall's t %.2f (fails), known-variance statistic %.2f (critical %.2f)\n",
              static_cast<unsigned long long>(n), sample_only.test.statistic, known.test.statistic,
              known.test.threshold);
}

// Over 4000 runs of a pixel of N samples drawn by `pixel(stream, N)` for
// each N of `sizes`, the known-variance test at α = 0.05 must reject at most
// at rate α (a one-sided binomial test at 1e-3), and the sample-variance test
// on the same runs more than twice as often (the negative control).
void expect_level_held(const std::function<Moments(uint64_t, uint64_t)>& pixel, double mean, double variance,
                       std::initializer_list<uint64_t> sizes, uint64_t first_stream, const char* label) {
  const double alpha = 0.05;
  const int runs = 4000;
  for (uint64_t n : sizes) {
    int known_rejections = 0, sample_rejections = 0;
    for (int run = 0; run < runs; ++run) {
      const Moments m = pixel(first_stream + uint64_t(run), n);
      const PixelTestResult known = pixel_mean_test(m, mean, alpha, false, kDefaultPower, variance);
      known_rejections += known.tested() && !known.test.pass;
      const PixelTestResult sample = pixel_mean_test(m, mean, alpha, false);
      sample_rejections += sample.tested() && !sample.test.pass;
    }
    const boost::math::binomial_distribution<double> null(runs, alpha);
    // P(X ≥ k) under the level α: 1 for k = 0.
    const double p_known =
        known_rejections == 0 ? 1.0 : boost::math::cdf(boost::math::complement(null, known_rejections - 1));
    std::printf("%s, N = %llu: known variance rejects %d/%d (p %.3g), sample variance %d/%d, alpha %.2f\n", label,
                static_cast<unsigned long long>(n), known_rejections, runs, p_known, sample_rejections, runs, alpha);
    EXPECT_GE(p_known, 1e-3) << label << ": known-variance test above its level at N = " << n;
    EXPECT_GT(sample_rejections, 2 * alpha * runs) << label << ": negative control, the sample-variance test at N = "
                                                   << n;
  }
}

// The rare-event pixel at N = 64 … 1024 (0.1 to 2 expected spikes): at most
// α (Bernstein's bound is exact, not asymptotic, below the reference, and
// above it the studentised t must reject too, which a spike that occurred
// holds down).
TEST(PixelMeanTest, KnownVarianceHoldsItsLevelAtAnySpp) {
  const RareEvent e{0.2, 2e-3, 20};
  expect_level_held([&](uint64_t stream, uint64_t n) { return rare_pixel(e, stream, n); }, e.mean(), e.variance(),
                    {64, 256, 1024}, 10000, "rare event");
}

// A pixel with a rare blocker: with probability p the sample is 0 (the
// blocker hit), else `lit` times a uniform in [0.998, 1.002): left-skewed,
// like polygon_occluder's pixels near a thin blocker under light_solid_angle.
// A run that missed every blocker sits high with a small sample variance, and
// Hall's t rejects the correct reference; the exact variance's z does not.
struct RareBlocker {
  double lit, p;
  static constexpr double kLow = 0.998, kWidth = 0.004;
  double sample(double u1, double u2) const { return u1 < p ? 0.0 : lit * (kLow + kWidth * u2); }
  double mean() const { return (1 - p) * lit * (kLow + kWidth / 2); }
  double second_moment() const {
    return (1 - p) * lit * lit * (kLow * kLow + kLow * kWidth + kWidth * kWidth / 3);
  }
  double variance() const { return second_moment() - mean() * mean(); }
};

Moments blocker_pixel(const RareBlocker& b, uint64_t stream, uint64_t n, int* hits = nullptr) {
  Rng rng(kSeed, stream, 0);
  Moments m;
  for (uint64_t i = 0; i < n; ++i) {
    const double u1 = rng.next_double();
    const double y = b.sample(u1, rng.next_double());
    if (hits && y == 0) ++*hits;
    m.add(y);
  }
  return m;
}

TEST(PixelMeanTest, KnownVarianceDoesNotFailAMissedRareBlocker) {
  const RareBlocker b{0.2, 5e-3};
  const uint64_t n = 256;
  Moments missed;
  for (uint64_t stream = 2000;; ++stream) {
    int hits = 0;
    missed = blocker_pixel(b, stream, n, &hits);
    if (hits == 0) break;  // no blocker in this run
  }
  const PixelTestResult sample_only = pixel_mean_test(missed, b.mean(), kAlpha, false);
  ASSERT_EQ(sample_only.status, PixelStatus::kTested);
  EXPECT_FALSE(sample_only.test.pass) << "the sample-variance test no longer fails a missed rare blocker: "
                                      << sample_only.test.statistic;
  const PixelTestResult known = pixel_mean_test(missed, b.mean(), kAlpha, false, kDefaultPower, b.variance());
  ASSERT_EQ(known.status, PixelStatus::kTested);
  EXPECT_TRUE(known.test.pass) << known.test.message;
  std::printf("missed rare blocker at N = %llu: Hall's t %.2f, known-variance statistic %.2f (critical %.2f)\n",
              static_cast<unsigned long long>(n), sample_only.test.statistic, known.test.statistic,
              known.test.threshold);
}

// The level over 4000 runs of the rare-blocker pixel at N = 64 … 256 (0.3
// to 1.3 expected blocker hits), as for the rare event above; the
// sample-variance test on the same runs is the negative control.
TEST(PixelMeanTest, KnownVarianceHoldsItsLevelWithARareBlocker) {
  const RareBlocker b{0.2, 5e-3};
  expect_level_held([&](uint64_t stream, uint64_t n) { return blocker_pixel(b, stream, n); }, b.mean(), b.variance(),
                    {64, 128, 256}, 20000, "rare blocker");
}

// Power: a pixel whose reference is 1.5 reported detectable biases above
// its mean (the pixel reads low) fails, for a smooth estimator and for the
// rare-event one, and a pixel reading high keeps Hall's test.
TEST(PixelMeanTest, KnownVarianceDetectsTheBiasItReports) {
  const Moments smooth = draw(kSeed, 30, kSpp, exponential);
  const PixelTestResult ok = pixel_mean_test(smooth, 1.0, kAlpha, false, kDefaultPower, 1.0);
  EXPECT_TRUE(ok.test.pass) << ok.test.message;
  const double low = 1.0 + kControlShift * ok.test.detectable_bias;  // the pixel reads low against it
  const PixelTestResult bad = pixel_mean_test(smooth, low, kAlpha, false, kDefaultPower, 1.0);
  EXPECT_FALSE(bad.test.pass);
  EXPECT_LT(bad.test.statistic, -bad.test.threshold);
  EXPECT_NE(bad.test.message.find("Bernstein"), std::string::npos) << bad.test.message;
  const double high = 1.0 - kControlShift * ok.test.detectable_bias;  // reads high: Hall's t and the exact z
  const PixelTestResult above = pixel_mean_test(smooth, high, kAlpha, false, kDefaultPower, 1.0);
  EXPECT_FALSE(above.test.pass);
  const double exact_z = (smooth.mean - high) / std::sqrt(1.0 / double(smooth.count));
  EXPECT_EQ(above.test.statistic, std::min(hall_statistic(smooth, high), exact_z));
  // The detectable bias with the exact variance is at most 1.3 times the
  // sample-variance test's here (Bernstein's price for holding at any spp).
  const PixelTestResult sample_only = pixel_mean_test(smooth, 1.0, kAlpha, false);
  EXPECT_LE(ok.test.detectable_bias, 1.3 * sample_only.test.detectable_bias);
  EXPECT_GE(ok.test.detectable_bias, sample_only.test.detectable_bias);

  const RareEvent e{0.2, 2e-3, 20};
  const Moments rare = rare_pixel(e, 31, kSpp);
  const PixelTestResult rare_ok = pixel_mean_test(rare, e.mean(), kAlpha, false, kDefaultPower, e.variance());
  EXPECT_TRUE(rare_ok.test.pass) << rare_ok.test.message;
  const double rare_low = e.mean() + kControlShift * rare_ok.test.detectable_bias;
  EXPECT_FALSE(pixel_mean_test(rare, rare_low, kAlpha, false, kDefaultPower, e.variance()).test.pass);
}

// A constant pixel below its reference (every run of a rare positive
// contribution missed it) is tested by the bound when the variance is known,
// not left untested.
TEST(PixelMeanTest, KnownVarianceTestsAConstantPixelBelowItsReference) {
  const RareEvent e{0, 1e-3, 100};  // 0 or a spike: mean 0.1, variance ≈ 10
  const RunningMoments zeros = constant_pixel(0, 256);
  EXPECT_EQ(pixel_mean_test(zeros, e.mean(), kAlpha, false).status, PixelStatus::kConstantMiss);
  const PixelTestResult known = pixel_mean_test(zeros, e.mean(), kAlpha, false, kDefaultPower, e.variance());
  EXPECT_EQ(known.status, PixelStatus::kTested);
  EXPECT_TRUE(known.test.pass) << known.test.message;  // 0.26 expected spikes: missing them is likely
  // 40 000 samples (40 expected spikes) that all read 0: rejected.
  const PixelTestResult never = pixel_mean_test(constant_pixel(0, 40000), e.mean(), kAlpha, false, kDefaultPower,
                                                e.variance());
  EXPECT_FALSE(never.test.pass);
}

// --- image-mean test -----------------------------------------------------------

// 64 "pixels" of Exp(scale) samples, scale from 0.5 to 1.5.
struct Image {
  std::vector<double> means, variances_of_mean, references;
};
Image exponential_image(uint64_t first_stream) {
  Image image;
  for (int p = 0; p < 64; ++p) {
    const double scale = 0.5 + p / 63.0;
    const Moments m = draw(kSeed, first_stream + p, 1024, [&](double u) { return scale * exponential(u); });
    image.means.push_back(m.mean);
    image.variances_of_mean.push_back(m.sample_variance() / double(m.count));
    image.references.push_back(scale);
  }
  return image;
}

TEST(ImageMeanTest, UnbiasedImagePassesShiftedReferenceFails) {
  const Image image = exponential_image(100);
  const ImageMeanTestResult ok = image_mean_test(image.means, image.variances_of_mean, image.references, kAlpha, false);
  EXPECT_TRUE(ok.test.pass) << ok.test.message;
  double sum = 0, sum_reference = 0, sum_variance = 0;
  for (size_t i = 0; i < image.means.size(); ++i) {
    sum += image.means[i];
    sum_reference += image.references[i];
    sum_variance += image.variances_of_mean[i];
  }
  const double p = double(image.means.size());
  EXPECT_DOUBLE_EQ(ok.image_mean, sum / p);
  EXPECT_DOUBLE_EQ(ok.reference_mean, sum_reference / p);
  EXPECT_DOUBLE_EQ(ok.test.standard_error, std::sqrt(sum_variance) / p);
  // Negative control: every reference up by 1.5 detectable relative biases.
  std::vector<double> shifted = image.references;
  for (double& r : shifted) r *= 1 + kControlShift * ok.test.detectable_relative_bias;
  EXPECT_FALSE(image_mean_test(image.means, image.variances_of_mean, shifted, kAlpha, false).test.pass);
}

TEST(ImageMeanTest, ExactImageAllowsOnlyRoundOff) {
  const std::vector<double> references(16, 0.4), noise(16, 1e-6);
  std::vector<double> means(16, 0.4 * (1 + 0.5 * kZeroVarianceRelTolerance));
  const ImageMeanTestResult same = image_mean_test(means, noise, references, kAlpha, true);
  EXPECT_TRUE(same.test.pass);
  EXPECT_TRUE(same.test.zero_variance);
  for (double& m : means) m = 0.4 * (1 + 2 * kZeroVarianceRelTolerance);
  EXPECT_FALSE(image_mean_test(means, noise, references, kAlpha, true).test.pass);
  // Not exact: the same offset is far inside the noise.
  EXPECT_TRUE(image_mean_test(means, noise, references, kAlpha, false).test.pass);
}

// With exact variances an image mean below its reference is tested by
// Bernstein's bound over all samples; a shifted reference fails, and the
// reported detectable bias is at least the z test's.
TEST(ImageMeanTest, KnownVariancesTestTheImageMeanBelowItsReference) {
  const Image image = exponential_image(200);
  std::vector<double> exact_variances;
  for (double r : image.references) exact_variances.push_back(r * r);  // Exp(scale): variance scale²
  const ImageMeanTestResult sample_only =
      image_mean_test(image.means, image.variances_of_mean, image.references, kAlpha, false);
  const ImageMeanTestResult ok = image_mean_test(image.means, image.variances_of_mean, image.references, kAlpha,
                                                 false, kDefaultPower, exact_variances, 1024);
  EXPECT_TRUE(ok.test.pass) << ok.test.message;
  EXPECT_GE(ok.test.detectable_bias, sample_only.test.detectable_bias);
  std::vector<double> shifted = image.references;
  for (double& r : shifted) r *= 1 + kControlShift * ok.test.detectable_relative_bias;
  const ImageMeanTestResult bad = image_mean_test(image.means, image.variances_of_mean, shifted, kAlpha, false,
                                                  kDefaultPower, exact_variances, 1024);
  EXPECT_FALSE(bad.test.pass);
  EXPECT_NE(bad.test.message.find("Bernstein"), std::string::npos) << bad.test.message;
  EXPECT_THROW(image_mean_test(image.means, image.variances_of_mean, image.references, kAlpha, false, kDefaultPower,
                               {1.0}, 1024),
               std::invalid_argument);
}

TEST(ImageMeanTest, MismatchedSizesThrow) {
  EXPECT_THROW(image_mean_test({1.0}, {0.1, 0.1}, {1.0}, kAlpha, false), std::invalid_argument);
  EXPECT_THROW(image_mean_test({}, {}, {}, kAlpha, false), std::invalid_argument);
}

// --- aggregate variance test ---------------------------------------------------

// 256 pixels of 1024 uniform samples each: Σ s² against 256/12.
std::vector<VarianceTestResult> uniform_pixels(double predicted_variance) {
  std::vector<VarianceTestResult> pixels;
  for (int p = 0; p < 256; ++p)
    pixels.push_back(variance_test(draw(kSeed, 200 + p, 1024, uniform), predicted_variance, kAlpha));
  return pixels;
}

TEST(AggregateVarianceTest, TrueVariancePassesWrongVarianceFails) {
  const std::vector<double> references(256, 0.5);
  const std::vector<VarianceTestResult> pixels = uniform_pixels(1.0 / 12.0);
  const AggregateVarianceTestResult ok = aggregate_variance_test(pixels, references, kAlpha, false);
  EXPECT_TRUE(ok.pass) << ok.message;
  double sum_s2 = 0, sum_sigma2 = 0;
  for (const VarianceTestResult& v : pixels) {
    sum_s2 += v.sample_variance;
    sum_sigma2 += v.predicted_variance;
  }
  EXPECT_EQ(ok.sum_sample_variance, sum_s2);
  EXPECT_EQ(ok.sum_predicted_variance, sum_sigma2);
  for (double sign : {-1.0, 1.0}) {
    const double wrong = (1 + sign * kControlShift * ok.detectable_relative_error) / 12.0;
    const AggregateVarianceTestResult bad = aggregate_variance_test(uniform_pixels(wrong), references, kAlpha, false);
    EXPECT_FALSE(bad.pass) << "sign " << sign;
  }
}

TEST(AggregateVarianceTest, ZeroVarianceImageNeedsZeroPredictedVariance) {
  const std::vector<double> references(16, 0.3);
  std::vector<VarianceTestResult> pixels;
  for (int p = 0; p < 16; ++p) pixels.push_back(variance_test(constant_pixel(0.3, 256), 0.0, kAlpha));
  const AggregateVarianceTestResult ok = aggregate_variance_test(pixels, references, kAlpha, true);
  EXPECT_TRUE(ok.pass) << ok.message;
  EXPECT_TRUE(ok.zero_variance_image);
  EXPECT_EQ(ok.statistic, 0.0);
  // Negative control: the model predicts a spread the (constant) estimator lacks.
  pixels.clear();
  for (int p = 0; p < 16; ++p) pixels.push_back(variance_test(constant_pixel(0.3, 256), 1e-6, kAlpha));
  EXPECT_FALSE(aggregate_variance_test(pixels, references, kAlpha, true).pass);
}

TEST(AggregateVarianceTest, MismatchedSizesThrow) {
  EXPECT_THROW(aggregate_variance_test(uniform_pixels(1.0 / 12.0), {0.5}, kAlpha, false), std::invalid_argument);
}

}  // namespace
}  // namespace furnace::stats
