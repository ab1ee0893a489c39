// The tests that verify a rendered image against its exact reference, pixel
// by pixel and as a whole, from each pixel's running moments:
//  - which pixels a mean test is valid for (Cochran's skewness rule, the
//    constant-pixel rule) and Hall's skewness-corrected statistic that tests
//    them;
//  - the zero-variance image (every pixel constant: exact sampling), which
//    must match its reference exactly everywhere;
//  - the image-mean z test and the aggregate variance test over all pixels.
// A caller shares its family-wise α among the P pixel tests and the image
// tests (Šidák) and passes the per-test level to each.
#pragma once

#include <vector>

#include "core/running_moments.h"
#include "stats/statistics.h"

namespace furnace::stats {

// Hall's skewness-removing transformation of the studentised mean (Hall
// 1992, "On the removal of skewness by transformation", JRSS B 54:221–228):
// with T = (ȳ − μ)/s and the sample skewness γ, the statistic
//   √N·(T + γT²/3 + γ²T³/27 + γ/(6N))
// is monotone in T and normal to O(1/N) instead of O(1/√N). Rendering
// estimators are skewed (rare hits on small lights or blockers), and the
// plain t overstates the far tails the Šidák level reaches: simulated on
// Bernoulli(0.03) samples at N = 1024, the plain t rejected 1.2e-3 at
// nominal 1e-4, the transformed statistic 2e-5 (and 6e-5 vs 2.5e-4 at p = 0.1).
// Needs s > 0 (else ±inf or NaN).
double hall_statistic(const RunningMoments& m, double reference);

// True if the pixel's spread is float round-off of a constant estimate
// (s ≤ kZeroVarianceRelTolerance·|mean|, e.g. the white furnace's exact 1
// summed in different orders). Also true for fewer than 2 samples (s = 0).
bool round_off_only(const RunningMoments& m);

// True if every pixel is round_off_only: the estimator samples exactly, so
// every pixel must equal its reference and the image mean's standard error
// is round-off. True for an empty image.
bool zero_variance_image(const std::vector<RunningMoments>& pixels);

// Bernstein's inequality for a mean that falls short (Bernstein 1924; e.g.
// Boucheron, Lugosi & Massart 2013, "Concentration Inequalities", thm 2.10):
// for N independent samples Yⱼ ≥ 0 with means μⱼ ≤ b and average variance
// v̄ = ΣVar(Yⱼ)/N, the variables μⱼ − Yⱼ are bounded above by b, so
//   P(Ȳ ≤ μ̄ − d) ≤ exp(−E),   E = N·d² / (2·v̄ + 2·b·d/3),
// whatever the samples' skewness and however few they are. Every rendering
// estimator is ≥ 0 for a correct renderer, and verify knows v̄ exactly where
// the analytic second moment is modelled, so a deficit tested this way cannot
// be a rare contribution that a run happened to miss (the sample variance
// shrinks with the miss and inflates a t statistic; the exact one does not).
// The exponent E for a deficit d > 0 (0 for d ≤ 0).
double bernstein_exponent(double n, double deficit, double mean_variance, double bound);
// The deficit d at which E = ln(1/q): the one-sided critical deficit at level q.
double bernstein_deficit(double n, double mean_variance, double bound, double q);

// Why a pixel was or was not mean-tested.
enum class PixelStatus {
  kTested,
  // Cochran's rule fails (clt_adequate): its mean is too skewed to be normal.
  kSkewed,
  // Constant samples that miss the reference in an image that is not zero
  // variance: a rare outcome (a blocker hit with p ≪ 1/N) simply never
  // occurred; its skewness is unbounded, so it is untested like kSkewed.
  kConstantMiss,
};

struct PixelTestResult {
  PixelStatus status = PixelStatus::kTested;
  // Filled when status is kTested or kConstantMiss. For a pixel that is not
  // round_off_only, statistic and pass are Hall's against test.threshold;
  // a round_off_only pixel takes mean_test's zero-variance branch.
  MeanTestResult test;
  bool tested() const { return status == PixelStatus::kTested; }
};

// One pixel's mean test at the per-test level alpha: skewed pixels are not
// tested; a round_off_only pixel must match exactly (zero-variance branch)
// and, unless `zero_variance_image`, is left untested when it does not;
// every other pixel gets Hall's statistic against Student's t quantile.
//
// With the estimator's exact variance σ² > 0 per sample (`exact_variance`;
// negative when unknown):
//  - a pixel below its reference is tested by Bernstein's bound instead, at
//    level α/2, valid at any N and any skewness, so it is never left
//    untested as skewed: it rejects when exp(−E) < α/2 with N samples,
//    v̄ = σ² and b = the reference. Its statistic is reported on the t scale,
//    −t_{1−α/2}·√(E / ln(2/α)), so that |statistic| > threshold exactly when
//    the bound rejects;
//  - a pixel above its reference is rejected only when Hall's statistic and
//    z = (ȳ − μ)/(σ/√N) both exceed the threshold (the statistic is the
//    smaller). A rare contribution below the mean (a blocker hit with
//    p ≪ 1/N) that the run missed shrinks the sample variance and inflates
//    t, while z stays near √(N·p); a rare large value that did occur
//    inflates z, while it inflates the sample variance too and holds the
//    studentised t down. A constant pixel above its reference is tested by
//    z alone; a pixel that fails the skewness rule is still untested there.
// The detectable bias is then the larger of the two sides': Bernstein's
// critical deficit plus z_power·σ/√N, and (t_{1−α/2} + t_power)·s/√N.
PixelTestResult pixel_mean_test(const RunningMoments& m, double reference, double alpha, bool zero_variance_image,
                                double power = kDefaultPower, double exact_variance = -1);

// The image-mean test: the mean over P pixels of the pixel estimates against
// the mean of the references, a z test with standard error √(Σ vᵢ)/P from the
// variances of the pixel means vᵢ = s²ᵢ/Nᵢ. An `exact` image (a zero-variance
// image) has a standard error of round-off and is tested with SE = 0:
// relative agreement within kZeroVarianceRelTolerance.
struct ImageMeanTestResult {
  double image_mean = 0;
  double reference_mean = 0;
  ZTestResult test;
};
// Sizes must match and be nonzero. With `exact_variances` (each pixel's
// exact variance per sample, every pixel of N = `samples_per_pixel`
// samples) an image mean below its reference is tested by Bernstein's bound
// over all P·N samples (v̄ the mean of the exact variances, b the largest
// reference), reported on the z scale as the pixels' is on the t scale; an
// image mean above it is rejected only when the z tests on the sample and on
// the exact variances both reject.
ImageMeanTestResult image_mean_test(const std::vector<double>& pixel_means,
                                    const std::vector<double>& variances_of_mean,
                                    const std::vector<double>& references, double alpha, bool exact,
                                    double power = kDefaultPower, const std::vector<double>& exact_variances = {},
                                    uint64_t samples_per_pixel = 0);

// The aggregate variance test: Σ s²ᵢ against the predicted Σ σ²ᵢ, a z test
// with standard error √(Σ Var s²ᵢ), each term from a pixel's variance_test.
// Per-pixel variance tests are anti-conservative for skewed estimators at
// the spp of a verification run (the false-alarm sweep measured 3/10
// rejections at 256 spp where α = 0.05 allowed 0.5); their sum over all
// pixels is close to normal. It takes every pixel: selecting pixels by their
// sample moments (the skewness rule) would bias Σ s².
//
// In a zero-variance image the sample variances are round-off and their z
// means nothing: the statistic is 0 and the test passes only if the
// predicted standard deviation is within the same tolerance,
// Σ σ²ᵢ ≤ kZeroVarianceRelTolerance²·Σ referenceᵢ² (exact sampling, or a far
// light's cone where cos θ is constant to 1e-12); else the estimator is
// constant where it should vary.
struct AggregateVarianceTestResult {
  double sum_sample_variance = 0;     // Σ s²ᵢ
  double sum_predicted_variance = 0;  // Σ σ²ᵢ
  double statistic = 0;               // (Σ s² − Σ σ²)/SE; 0 in a zero-variance image
  double threshold = 0;               // z_{1−α/2}
  // Smallest relative error of Σ s² detected with `power`; +inf when Σ σ² = 0.
  double detectable_relative_error = 0;
  bool zero_variance_image = false;
  bool pass = false;
  std::string message;
};
// pixels[i] is the variance test of pixel i; sizes must match.
AggregateVarianceTestResult aggregate_variance_test(const std::vector<VarianceTestResult>& pixels,
                                                    const std::vector<double>& references, double alpha,
                                                    bool zero_variance_image, double power = kDefaultPower);

}  // namespace furnace::stats
