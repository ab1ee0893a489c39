// `furnace check`'s power, proven by simulation (issue: "test the judge's own
// numbers"). check states, for the image-mean test of K images, the smallest
// relative bias it detects with probability 0.9:
//     d = λ(ν) · f(ν) · s / √K / mean(reference),   ν = K − 1,
// λ the noncentrality of the two-sided t-test at the test's level, f the
// upper confidence factor on the spread (kSpreadConfidence) and s the
// observed spread of the K image means. Each part is measured here on
// synthetic image sets whose noise is known exactly (Gaussian, per pixel and
// channel, fixed named seeds), through check_images itself:
//  1. power: at the bias check claims for the TRUE spread (its statement
//     with s replaced by σ and f divided out: λ(ν)·σ/√K) the image-mean test
//     rejects in 90 % of trials, a two-sided binomial test that tells 0.9
//     from 0.8;
//  2. coverage: σ ≤ f(ν)·s in 90 % of trials;
//  3. false alarms: unbiased sets FAIL in at most α of trials (one-sided);
//  4. the advice: the K' images (or the spp factor) it names, at the spread
//     it assumes, reach the target (recomputed with independent arithmetic)
//     and detect a bias of the target in at least 90 % of trials.
// For K = 2, 4, 8, 16 and both channel modes. Negative controls: a power
// computed with ν = K instead of K − 1 (λ and f) is rejected by tests 1 and 2.
// Each binomial test runs at kTestAlpha = 1 − (1 − 0.01)^(1/m), Šidák over
// the m tests of its TEST (the seeds are fixed: a given build passes or
// fails every run). The slow label repeats 1–3 with 4000 trials.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include <boost/math/distributions/binomial.hpp>

#include "stats/statistics.h"
#include "verify/check.h"
#include "verify/check_image.h"
#include "verify/image_statistics.h"

namespace furnace::verify {
namespace {

constexpr uint64_t kPowerSeed = 20261204;  // named seed of every synthetic set
constexpr int kSide = 8;                   // 8×8 pixels
constexpr int kPixels = kSide * kSide;
constexpr double kPixelNoise = 0.05;       // relative per-pixel, per-channel standard deviation
constexpr double kAlpha = 0.01;            // check's family-wise α
constexpr double kTarget = 0.01;           // --max-detectable-bias
constexpr double kPower = 0.9;             // kReportedPower
constexpr double kFamilyAlpha = 0.01;      // of each TEST's binomial tests
const int kImageCounts[] = {2, 4, 8, 16};
const ChannelMode kModes[] = {ChannelMode::kGray, ChannelMode::kRgb};

bool slow_run() { return std::getenv("FURNACE_CHECK_POWER_SLOW") != nullptr; }
size_t trials() { return slow_run() ? 4000 : 400; }

std::vector<double> reference() {
  std::vector<double> r(kPixels);
  for (int p = 0; p < kPixels; ++p) r[size_t(p)] = 0.5 + double(p % kSide) / kSide + double(p / kSide) / (2 * kSide);
  return r;
}
double reference_mean() {
  double sum = 0;
  for (double v : reference()) sum += v;
  return sum / kPixels;
}
// The true standard deviation of one image's mean, per channel: independent
// pixels of standard deviation noise·r_p.
double image_mean_sd(double noise) {
  double sum = 0;
  for (double v : reference()) sum += (noise * v) * (noise * v);
  return std::sqrt(sum) / kPixels;
}

// K images of the reference times (1 + bias + noise·z), z standard normal per
// pixel and channel: the bias shifts the mean and leaves the spread as it is
// (the spread the statement is made for).
std::vector<ForeignImage> synthetic(int k, double bias, double noise, ChannelMode mode, uint64_t seed) {
  const std::vector<double> ref = reference();
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> z;
  std::vector<ForeignImage> images(static_cast<size_t>(k));
  for (int j = 0; j < k; ++j) {
    ForeignImage& im = images[size_t(j)];
    im.path = "synthetic_" + std::to_string(j) + ".exr";
    im.width = im.height = kSide;
    im.channels = mode == ChannelMode::kGray ? std::vector<std::string>{"gray"} : std::vector<std::string>{"R", "G", "B"};
    im.value.assign(im.channels.size(), std::vector<double>(kPixels));
    for (auto& plane : im.value)
      for (int p = 0; p < kPixels; ++p) plane[size_t(p)] = ref[size_t(p)] * (1 + bias + noise * z(rng));
  }
  return images;
}

// The first channel's image-mean test (the others, in rgb mode, are
// independent copies: any of three rejects with power 1 − 0.1³).
bool image_mean_rejects(const CheckResult& r) { return !r.channels.front().image_mean_pass; }

uint64_t config_seed(int k, ChannelMode mode, int part) {
  return kPowerSeed + uint64_t(k) * 1000003 + (mode == ChannelMode::kRgb ? 500009 : 0) + uint64_t(part) * 100000007;
}

double sidak(double family, int tests) { return 1 - std::pow(1 - family, 1.0 / tests); }

// What one configuration's check says of its image-mean test (from one
// unbiased set: λ, f and the level do not depend on the data).
struct Statement {
  double alpha = 0;  // per-test level of the image-mean test
  double claimed_true_spread_bias = 0;  // d·(σ/√K)/(f(K−1)·SE): λ_used·f_used/f(K−1)·σ/√K/mean
};
Statement statement(int k, ChannelMode mode) {
  const CheckResult r =
      check_images(synthetic(k, 0, kPixelNoise, mode, config_seed(k, mode, 9)), reference(), kAlpha, kTarget);
  const ChannelCheck& c = r.channels.front();
  const double f = spread_upper_bound_factor(double(k - 1), kSpreadConfidence);
  const double sigma_se = image_mean_sd(kPixelNoise) / std::sqrt(double(k));
  return {c.alpha, c.detectable_relative_bias * c.reference_mean / c.standard_error * sigma_se / f / reference_mean()};
}

// Rejections of the image-mean test over `n` sets of K images with `bias`.
stats::RejectionRate power_at(int k, ChannelMode mode, double bias, double noise, double expected, int part) {
  return stats::measure_rejection_rate(
      [&](uint64_t seed) {
        return image_mean_rejects(check_images(synthetic(k, bias, noise, mode, seed), reference(), kAlpha, kTarget));
      },
      trials(), expected, config_seed(k, mode, part));
}

std::string mode_name(ChannelMode m) { return channel_mode_name(m); }

// 1. The power at the bias check claims for the true spread is 0.9.
TEST(CheckPower, RejectsInNinetyPercentAtTheStatedBias) {
  const int tests = int(std::size(kImageCounts) * std::size(kModes));
  const double level = sidak(kFamilyAlpha, tests);
  for (const int k : kImageCounts)
    for (const ChannelMode mode : kModes) {
      const Statement s = statement(k, mode);
      const stats::RejectionRate r = power_at(k, mode, s.claimed_true_spread_bias, kPixelNoise, kPower, 1);
      std::printf("power K=%2d %-4s: stated bias at the true spread %.4f%%: %zu/%zu rejected (%.3f, 95%% CI "
                  "[%.3f, %.3f]), binomial p %.3g vs 0.9 (level %.2g)\n",
                  k, mode_name(mode).c_str(), 100 * s.claimed_true_spread_bias, r.rejections, r.trials, r.rate,
                  r.ci_low, r.ci_high, r.binomial_p_value, level);
      EXPECT_GT(r.binomial_p_value, level) << "K=" << k << " " << mode_name(mode) << ": power " << r.rate;
    }
}

// The power of this test itself: the rejection count below which 0.9 is
// refused, and the probability that a true power of 0.8 stays above it.
TEST(CheckPower, BinomialTestTellsNinetyFromEighty) {
  const size_t n = trials();
  const double level = sidak(kFamilyAlpha, int(std::size(kImageCounts) * std::size(kModes)));
  const boost::math::binomial_distribution<double> at90(double(n), 0.9), at80(double(n), 0.8);
  // Largest count c with P(X ≤ c | 0.9) ≤ level/2: counts at or below it are refused.
  double c = boost::math::quantile(at90, level / 2);
  while (c > 0 && boost::math::cdf(at90, c) > level / 2) c -= 1;
  const double missed = 1 - boost::math::cdf(at80, c);
  std::printf("%zu trials: a power of 0.9 is refused at %.0f rejections or fewer; a true power of 0.8 passes with "
              "probability %.2g\n", n, c, missed);
  EXPECT_LT(missed, 0.01);
}

// 2. σ ≤ f(ν)·s in 90 % of sets of K images (ν = K − 1).
double coverage_rate(int k, double dof_used, uint64_t seed, stats::RejectionRate* out) {
  const double f = spread_upper_bound_factor(dof_used, kSpreadConfidence);
  *out = stats::measure_rejection_rate(
      [&](uint64_t s) {
        std::mt19937_64 rng(s);
        std::normal_distribution<double> z;
        std::vector<double> x(static_cast<size_t>(k));
        double mean = 0;
        for (double& v : x) mean += (v = z(rng));
        mean /= k;
        double m2 = 0;
        for (double v : x) m2 += (v - mean) * (v - mean);
        return 1.0 <= f * std::sqrt(m2 / (k - 1));  // "rejection" = covered
      },
      trials(), kSpreadConfidence, seed);
  return out->rate;
}

TEST(CheckPower, SpreadBoundCoversNinetyPercent) {
  const double level = sidak(kFamilyAlpha, int(std::size(kImageCounts)));
  for (const int k : kImageCounts) {
    stats::RejectionRate r;
    coverage_rate(k, double(k - 1), kPowerSeed + uint64_t(k), &r);
    std::printf("spread bound K=%2d: f=%.3f covers sigma in %zu/%zu (%.3f), binomial p %.3g\n", k,
                spread_upper_bound_factor(double(k - 1), kSpreadConfidence), r.rejections, r.trials, r.rate,
                r.binomial_p_value);
    EXPECT_GT(r.binomial_p_value, level) << "K=" << k;
  }
}

// 3. Unbiased sets: FAIL (any test: image mean or pixels) in at most α.
TEST(CheckPower, FalseAlarmsStayWithinAlpha) {
  const int tests = int(std::size(kImageCounts) * std::size(kModes));
  const double level = sidak(kFamilyAlpha, tests);
  for (const int k : kImageCounts)
    for (const ChannelMode mode : kModes) {
      const stats::RejectionRate r = stats::measure_rejection_rate(
          [&](uint64_t seed) {
            return check_images(synthetic(k, 0, kPixelNoise, mode, seed), reference(), kAlpha, kTarget).verdict ==
                   CheckVerdict::kFail;
          },
          trials(), kAlpha, config_seed(k, mode, 2));
      const boost::math::binomial_distribution<double> b(double(r.trials), kAlpha);
      const double p_upper = r.rejections == 0 ? 1.0 : boost::math::cdf(boost::math::complement(b, double(r.rejections - 1)));
      std::printf("false alarms K=%2d %-4s: %zu/%zu (%.4f) at alpha %.2g, one-sided p %.3g\n", k,
                  mode_name(mode).c_str(), r.rejections, r.trials, r.rate, kAlpha, p_upper);
      EXPECT_GT(p_upper, level) << "K=" << k << " " << mode_name(mode);
    }
}

// 4. The advice. From two images (INCONCLUSIVE at the 1 % target), check
// names K' images at the current spp and an spp factor at K = 2 and at
// kAdvisedImages. Recomputed here from λ and f with ν = K' − 1 and from the
// observed spread; then, at the spread it assumes (σ = the observed s), K'
// images and the factors detect a bias of the target in ≥ 90 % of trials.
TEST(CheckPower, AdviceReachesThePowerItPromises) {
  const double level = sidak(kFamilyAlpha, 3 * int(std::size(kModes)));
  for (const ChannelMode mode : kModes) {
    const double noise = 4 * kPixelNoise;  // the advice is needed: ~2.5 % image-mean spread
    const CheckResult pilot =
        check_images(synthetic(2, 0, noise, mode, config_seed(2, mode, 3)), reference(), kAlpha, kTarget);
    ASSERT_TRUE(pilot.advice.needed) << mode_name(mode);
    // The assumed spread: the largest channel's observed s (the advice covers every channel).
    double s = 0, alpha = 0;
    for (const ChannelCheck& c : pilot.channels)
      if (c.standard_error * std::sqrt(2.0) / c.reference_mean > s) s = c.standard_error * std::sqrt(2.0) / c.reference_mean,
                                                                    alpha = c.alpha;
    auto stated = [&](int k) {
      const double dof = double(k - 1);
      return detectable_noncentrality(dof, alpha, kPower) * spread_upper_bound_factor(dof, kSpreadConfidence) * s /
             std::sqrt(double(k));
    };
    const int kp = pilot.advice.images_at_current_spp;
    ASSERT_GT(kp, 2);
    EXPECT_LE(stated(kp), kTarget * (1 + 1e-12)) << mode_name(mode) << " K'=" << kp;
    EXPECT_GT(stated(kp - 1), kTarget) << mode_name(mode) << " K'=" << kp;
    const double factor_current = std::pow(stated(2) / kTarget, 2);
    const double factor_advised = std::pow(stated(kAdvisedImages) / kTarget, 2);
    EXPECT_NEAR(pilot.advice.spp_factor_at_current_images / factor_current, 1, 1e-9) << mode_name(mode);
    EXPECT_NEAR(pilot.advice.spp_factor_at_advised_images / factor_advised, 1, 1e-9) << mode_name(mode);
    // By simulation, at the assumed spread: per-pixel noise scaled so one image's mean has sd s (relative).
    const double assumed_noise = s * reference_mean() / image_mean_sd(1.0);
    struct Plan {
      const char* what;
      int k;
      double spp_factor;
    };
    const Plan plans[] = {{"K' images", kp, 1.0},
                          {"2 images at the spp factor", 2, pilot.advice.spp_factor_at_current_images},
                          {"kAdvisedImages at the spp factor", kAdvisedImages, pilot.advice.spp_factor_at_advised_images}};
    int part = 4;
    for (const Plan& plan : plans) {
      const stats::RejectionRate r =
          power_at(plan.k, mode, kTarget, assumed_noise / std::sqrt(plan.spp_factor), kPower, part++);
      const boost::math::binomial_distribution<double> b(double(r.trials), kPower);
      const double p_lower = boost::math::cdf(b, double(r.rejections));
      std::printf("advice %-4s: %s (K=%d, spp x%.3g): a %.0f%% bias detected in %zu/%zu (%.3f), one-sided p vs 0.9 "
                  "%.3g\n", mode_name(mode).c_str(), plan.what, plan.k, plan.spp_factor, 100 * kTarget, r.rejections,
                  r.trials, r.rate, p_lower);
      EXPECT_GT(p_lower, level) << mode_name(mode) << ": " << plan.what;
    }
  }
}

// Negative controls: a power computed with ν = K (not K − 1), in λ and in f,
// states a bias the test does not detect with probability 0.9, and a spread
// bound that does not cover 90 %: the binomial tests above refuse both (K = 2
// and 4, where one d.o.f. matters; at K ≥ 8 the change is too small for 400
// trials to see, 0.9 against about 0.87).
TEST(CheckPower, NegativeControlWrongDegreesOfFreedomIsRefused) {
  const double level = sidak(kFamilyAlpha, int(std::size(kImageCounts) * std::size(kModes)));
  for (const int k : {2, 4}) {
    const ChannelMode mode = ChannelMode::kGray;
    const Statement s = statement(k, mode);
    const double wrong = s.claimed_true_spread_bias * detectable_noncentrality(double(k), s.alpha, kPower) /
                         detectable_noncentrality(double(k - 1), s.alpha, kPower);
    const stats::RejectionRate r = power_at(k, mode, wrong, kPixelNoise, kPower, 1);
    std::printf("control K=%d: power with nu = K: %zu/%zu (%.3f), binomial p %.3g\n", k, r.rejections, r.trials, r.rate,
                r.binomial_p_value);
    EXPECT_LT(r.binomial_p_value, level) << "K=" << k << ": the wrong d.o.f. went unnoticed, power " << r.rate;
    stats::RejectionRate c;
    coverage_rate(k, double(k), kPowerSeed + uint64_t(k), &c);
    std::printf("control K=%d: spread bound with nu = K covers %.3f, binomial p %.3g\n", k, c.rate, c.binomial_p_value);
    EXPECT_LT(c.binomial_p_value, sidak(kFamilyAlpha, int(std::size(kImageCounts)))) << "K=" << k;
  }
}

}  // namespace
}  // namespace furnace::verify
