// Reference checking of other renderers' images: `furnace check` compares
// OpenEXR renders of one of our scenes, made by any renderer, against the
// scene's exact reference, and states how large a bias it could have seen.
//
// Error bars. A single image carries none, so the test needs either
//  - K ≥ 2 independent renders (different seeds): per pixel, the mean over
//    the K images is t-tested with the spread across them (Student t, K − 1
//    d.o.f.), and so is the image mean (the K image means are independent); or
//  - one furnace EXR (variance and N channels): per pixel a t-test with the
//    stored per-sample variance (N − 1 d.o.f.), and a z-test of the image mean
//    with standard error √(Σ s²/N)/P. The EXR holds no third moment, so the
//    pixel tests lack verify's skewness correction (Hall's transformation) and
//    are somewhat anti-conservative for strongly skewed estimators: one of
//    seven single 1024–2048-spp path_mis renders of enclosure_box failed one
//    pixel of 256 at |t| 4.49 against 4.28. K ≥ 2 renders are t-tested on
//    per-image means, which are much closer to normal.
//
// Levels. The family-wise α is split in two halves (kImageMeanAlphaShare):
// one for the image-mean test(s), one shared by the P pixel tests (per
// tested channel), each half divided by the Šidák correction over its own
// tests. The image-mean test decides PASS, so it must not pay for the 1024
// pixel tests: at K = 8 its critical t falls from 11.6 to 4.0.
//
// Power. The detectable bias is λ·σ⁺/√K: λ the noncentrality at which the
// two-sided t-test (K − 1 d.o.f.) rejects with probability stats::kReportedPower,
// from Boost's noncentral t (the usual additive t_{1−α/2} + t_{0.9} gives only
// power 0.69 at one d.o.f.), and σ⁺ the spread's upper confidence bound
// (kSpreadConfidence, verify/image_statistics.h). The same for each pixel,
// with its own spread.
//
// Verdict.
//  - FAIL (exit 1): any test rejects. A test with little power that still
//    rejects has found a bias, so FAIL wins over INCONCLUSIVE.
//  - INCONCLUSIVE (exit 3): nothing rejects, but the smallest relative bias
//    of the image mean detected with power kReportedPower (0.9) exceeds
//    max_detectable_bias (in any tested channel).
//  - PASS (exit 0): nothing rejects and the image-mean test has that power.
// The per-pixel tests' power is reported (median detectable pixel bias) but
// does not gate PASS: a pixel sees a thousandth of the samples of the image.
//
// Rare-event guard (optional: guard images, the CLI's --guard). Images whose
// samples all missed a rare, large contribution (a small light that 8 × 64
// samples of a pixel never hit) have a mean below the reference and a spread
// that is small with it, so t explodes although the renderer is right. No
// test on these images alone can tell: a non-negative estimator of mean μ may
// put all of μ on an event no sample met, and the exact reference says
// nothing of the checked renderer's estimator (a floor taken from furnace's
// own estimators silenced a real Cycles finding: docs/checking.md). Renders
// of the same renderer and settings at a high spp (K' ≥ 2 other seeds, or one
// furnace EXR) can: if the event is real, their spread shows it. So a test
// whose mean is below the reference has its variance of the mean floored at
// the guard's variance per sample, at the lower confidence bound of its
// spread (spread_lower_bound_factor at kSpreadConfidence), over the checked
// samples: v ← max(v, b²·v_guard·n_guard/n), n the samples behind each
// estimate (K × the spp the files state, or a furnace EXR's N; a side whose
// files state none is taken at the other's, which the report says). The
// floored term carries the guard's d.o.f. A test that rejects only without
// the floor is *held*: counted, not judged, and the verdict is INCONCLUSIVE
// (unless another test rejects) with the spp factor at which these images
// would find a bias of that size with power kReportedPower. The guard
// images are not themselves checked (check them with their own call), and
// a guard set that missed the event as well leaves the floor low: the test
// still fails.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/scene.h"
#include "verify/check_image.h"

namespace furnace::verify {

// Default of --max-detectable-bias: PASS needs the image-mean test to catch a
// 1 % bias of the mean with probability 0.9.
inline constexpr double kDefaultMaxDetectableBias = 0.01;
// Share of the family-wise α given to the image-mean test(s); the pixel
// tests share the rest (see above).
inline constexpr double kImageMeanAlphaShare = 0.5;
// Pixels listed as the worst (largest |t|).
inline constexpr int kWorstPixelsShown = 5;
// The image count the advice quotes the spp for when K is smaller: with 7
// d.o.f. the t quantiles are within ~45 % of the normal ones at these levels,
// while K = 2 (1 d.o.f.) needs a critical t of ~127 even at α/2.
inline constexpr int kAdvisedImages = 8;

// The exact answer the images are compared with.
struct CheckReference {
  std::vector<double> values;   // per pixel centre, row-major
  bool global = false;          // analytic::global_reference_image, else analytic::reference_image
  int max_segments = 0;         // path length in segments (2 for direct lighting)
  std::string description;      // e.g. "global illumination, unlimited depth"
  std::string note;             // why direct lighting was chosen, when it was
  // The transport convention the reference assumes, for a scene with a
  // dielectric ("radiance" or "none"); empty where nothing depends on it.
  std::string convention;
};

// The reference for `max_depth` segments (the CLI's --max-depth; empty: not
// given). Not given: the full global-illumination answer (unlimited depth)
// when analytic::global_reference_image has one for the scene, else direct
// lighting. Given: the global answer at that depth; where the scene has no
// closed form, depth 2 is direct lighting (emission + one bounce, the same
// quantity), and any other depth is bad input (furnace::Error).
// `convention`: the checked renderer's transport convention (what a scene
// with a dielectric depends on).
CheckReference check_reference(const Scene& scene, std::optional<int> max_depth,
                               TransportConvention convention = TransportConvention::kRadiance);

enum class CheckVerdict { kPass, kFail, kInconclusive };
std::string verdict_name(CheckVerdict v);  // "PASS", "FAIL", "INCONCLUSIVE"
int exit_code(CheckVerdict v);             // 0, 1, 3 (2 is bad input, thrown as furnace::Error)

// The tests of one tested channel ("gray", or "R", "G", "B").
struct ChannelCheck {
  std::string channel;
  // Image-mean test.
  double image_mean = 0, reference_mean = 0;
  double standard_error = 0;  // of the image mean
  double statistic = 0;       // t (K ≥ 2) or z (one furnace EXR)
  double threshold = 0;       // critical |statistic|
  double dof = 0;             // K − 1; +inf for the z-test
  double alpha = 0;           // per-test level
  double detectable_relative_bias = 0;  // at power kReportedPower
  bool image_mean_pass = false;
  // Pixel tests.
  int pixel_failures = 0;
  // Constant across all samples (no spread at all) yet off the reference,
  // while other pixels vary: a rare contribution never sampled (verify's
  // harness rule). Not tested; the image-mean test still sees them.
  int pixels_untested = 0;
  // The rare-event guard (above): the image-mean test held, its statistic
  // with the floored variance, and the pixel tests it held.
  bool image_mean_held = false;
  double guarded_statistic = 0;
  int pixels_held = 0;
  // K ≥ 4 values taking at most K/2 distinct values (pixels_few_values): a
  // quasi-Monte Carlo or quantised render, whose values repeat to the bit.
  // Independent renders with continuous noise essentially never tie, so the
  // spread of such a pixel says nothing about its error (15 of 16 equal
  // values give a spread near zero and an exploding t). Not tested, and left
  // out of the median detectable pixel bias; the image-mean test still sees
  // them.
  int pixels_few_values = 0;
  double pixel_alpha = 0;
  double pixel_threshold = 0;  // critical |t| of the median pixel (they differ with N for one furnace EXR)
  double pixel_dof = 0;        // of the median pixel
  double median_pixel_detectable_relative_bias = 0;
  double relative_rmse = 0;    // of the (averaged) image against the reference, relative to the reference mean
};

struct WorstPixel {
  int x = 0, y = 0;
  std::string channel;
  double value = 0, reference = 0;
  double t = 0;  // ±inf: zero spread and not on the reference
  bool untested = false;  // see ChannelCheck::pixels_untested and pixels_few_values
  bool held = false;      // rejected, but held by the rare-event guard
};

// How many images or samples would give the image-mean test its power,
// assuming the true spread of an image's mean is the observed one, that it
// falls as 1/√spp (independent samples), and that the check of K images then
// reports λ(K − 1)·σ⁺(K − 1)/√K (the power rule above, with its own bound).
struct CheckAdvice {
  bool needed = false;
  int images_at_current_spp = 0;        // smallest K reaching the threshold at the current spp (0: beyond 10⁶)
  double spp_factor_at_current_images = 0;  // multiply each image's spp by this, keeping K images
  int advised_images = 0;               // max(K, kAdvisedImages)
  double spp_factor_at_advised_images = 0;  // multiply each image's spp by this with advised_images images
  double current_spp = 0;               // from the images' provenance or N channel; 0 if unknown
};

// The rare-event guard's inputs and what it held (guard_images = 0: none).
struct CheckGuard {
  int guard_images = 0;
  // The spp per render it took for the checked and the guard images (0: a
  // furnace EXR, whose N channel counts its samples per pixel), and what it
  // assumed for a side whose files state none.
  double checked_spp = 0, guard_spp = 0;
  std::string assumption;
  std::vector<std::string> held;  // the families it held: "mean", "pixels"
  // The held test of largest |t|, when any.
  std::string worst_held;  // "image mean" or "pixel (x, y)"; empty: none held
  std::string worst_held_channel;
  double worst_held_t = 0, worst_held_guarded_t = 0, worst_held_threshold = 0;
  double worst_held_spp_factor = 0;  // these images at this factor × their spp judge a bias of its size
};

struct CheckResult {
  int images = 0;
  // Finite negative values in the images: used as is in every test, and
  // counted, since the reference is non-negative (a spectral renderer's RGB
  // film holds small ones; large or many ones are a bias the tests may find).
  NegativeValues negative;
  bool half_float = false;  // some image stores its radiance as 16-bit half floats
  int pixels = 0;
  std::string method;  // "across-images t" or "furnace variance"
  double alpha = 0;
  double max_detectable_bias = 0;
  std::vector<ChannelCheck> channels;
  std::vector<WorstPixel> worst_pixels;
  // Per tested channel, per pixel: the test statistic (for --zmap).
  std::vector<std::vector<double>> pixel_t;
  double detectable_relative_bias = 0;  // the largest over the tested channels
  bool image_mean_has_power = false;    // detectable_relative_bias ≤ max_detectable_bias
  bool pixels_have_power = false;       // every channel's median detectable pixel bias ≤ max_detectable_bias
  CheckAdvice advice;
  CheckGuard guard;
  // Some test rejected below the reference without a guard: the report
  // points to --guard (a rare event the images missed looks the same).
  bool rejected_below_unguarded = false;
  CheckVerdict verdict = CheckVerdict::kFail;
};

// Throws furnace::Error for input the tests cannot use (one image without
// variance channels, one furnace EXR with N < 2 somewhere), in `images` or
// in `guard` (the rare-event guard's images; empty: no guard).
CheckResult check_images(const std::vector<ForeignImage>& images, const std::vector<double>& reference, double alpha,
                         double max_detectable_bias, const std::vector<ForeignImage>& guard = {});

}  // namespace furnace::verify
