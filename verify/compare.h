// Two-sample comparison of renders: `furnace compare` tests whether two sets
// of OpenEXR renders of the same scene (side A, e.g. a renderer after a
// change; side B, its stored reference set) have the same expected image,
// and states how large a difference it could have seen. No exact reference
// is needed, so it works on any scene and any renderer.
//
// Each side is K ≥ 2 independent renders (different seeds), or one furnace
// EXR with variance and N channels. Per side, each quantity below is a
// stats::MeanEstimate (mean, variance of that mean, d.o.f.):
//  - K renders: the mean over the K images of the quantity computed on each
//    image, its spread²/K, K − 1 d.o.f. Computing a tile's or the image's
//    mean on each image first keeps any correlation between pixels (a wide
//    pixel filter) inside the spread.
//  - one furnace EXR: a pixel's mean with s²/N and N − 1 d.o.f.; a tile's or
//    the image's mean over its pixels with Σ(s²/N)/n² and the
//    Welch–Satterthwaite d.o.f. of that sum (pixels taken as independent).
//
// Tests (all two-sided, each channel tested separately):
//  - image mean: Welch's t of A − B, Welch–Satterthwaite d.o.f. when both
//    sides have the same d.o.f., else the smaller side's (Hsu's conservative
//    choice: see compare.cpp for the measured reason);
//  - tiles (tile × tile pixels, default 8; edge tiles are smaller): Welch's
//    t of each tile mean, which finds a localised shift that single pixels
//    are too noisy to see (a 1 % shift in one 8×8 tile moves the tile mean by
//    1 % but each of its pixels only by 1 %/their noise);
//  - pixels: Welch's t of each pixel;
//  - variance: the ratio of the summed per-pixel variances of one render,
//    R = Σ v_A / Σ v_B (v: a pixel's variance across the K renders, or s²/N
//    of a furnace EXR), as a z-test of log R with the delta-method standard
//    error from the normal-theory Var(s²) = 2σ⁴/ν of each pixel (the pixel
//    values of a render are means over its samples, close to normal); pixels
//    are taken as independent. The same mean with more noise (a sampler that
//    got worse) fails only this test, reported separately.
// Finite negative values (a spectral renderer's RGB film) are data: every
// test uses them as they are, and the result counts them per side.
// Pixels whose values repeat (has_few_distinct_values: a quasi-Monte Carlo
// render, a discrete estimate such as k light hits of 16 samples, or 16-bit
// half floats whose rounding step exceeds the pixel's noise), or
// that are constant on each side at different values (all K renders of side
// A hit the light 0 times, all of B once), are not pixel-tested: their
// spread says nothing of their error. The tile and image tests still see
// them, and there a zero spread on both sides demands exact agreement.
//
// Rare-event guard (image mean, tiles, pixels). A side whose samples all
// missed a rare large contribution (none of 8 × 64 samples of a pixel hit a
// small light that 8 × 4096 samples of the other side did) has a mean that is
// low and a spread that is low with it, so its Welch t explodes although the
// renderer is right; no test on that side's values alone can tell, since a
// non-negative estimator of mean μ may put all of it on an event no sample
// met. The other side's noise can: if the event is real, its variance shows
// there. So the side with the lower mean is taken to have at least the
// variance per sample that the higher side shows, at the lower confidence
// bound of its spread (spread_lower_bound_factor at kSpreadConfidence):
//   v_low ← max(v_low, b²·v_high·n_high/n_low),
// n a side's samples behind the estimate (K × the spp its files state, or a
// furnace EXR's N; a side whose files state no spp is taken at the other
// side's, which the report says). A test rejects only with the floored
// variance; when the plain Welch t would have rejected and the floored one
// does not, the test is *held*: not judged, counted, and the comparison is
// INCONCLUSIVE (unless another test rejects) with the spp factor at which
// both sides would find that difference with power 0.9. Where the two
// sides' noise per sample is alike (one renderer, two seed sets) the floor
// seldom binds: the guard costs power where the lower side is the quieter
// one per sample, its spread below b times the other's (0.76 at ν = 7),
// and the detectable differences below use the larger of the two directions'
// floored standard errors. The same floor makes a side that shares an error
// across its renders (a sampler whose seed leaves the sub-pixel positions
// alone, see docs/comparing.md) less able to show it where it is the lower
// side: those pixels are held, not passed.
//
// Levels. The family-wise α is split by Šidák among the four families
// (kCompareFamilies), and within each family by Šidák over its tests
// (channels × tiles, channels × pixels, channels for the image mean and the
// variance). Šidák holds for two-sided tests of correlated normal statistics
// (Šidák 1967), so the overlap of tiles, pixels and image is covered.
//
// Power (at stats::kReportedPower, 0.9): the smallest relative difference of
// the image mean detected, λ·f·SE/|mean_B| with λ from the noncentral t at the
// Welch d.o.f. and f = spread_upper_bound_factor (verify/image_statistics.h,
// the same rule as `furnace check`); the same for the median tile and the median
// pixel; and the smallest variance ratio detected, exp((z_{1−α/2} + z_0.9)·SE)
// of log R.
//
// Verdict:
//  - DIFFERENT (exit 1): any test rejects (names which: mean, tiles, pixels,
//    variance); wins over INCONCLUSIVE;
//  - INCONCLUSIVE (exit 3): nothing rejects but the rare-event guard held a
//    test (names which, and the spp factor that would find it);
//  - SAME (exit 0): nothing rejects and, in every channel, the image-mean
//    test detects a relative difference of max_detectable_difference;
//  - INCONCLUSIVE (exit 3): nothing rejects but that power is missing; the
//    advice says how many renders per side (at the current spp), or what spp
//    factor (at the current K), would reach it.
#pragma once

#include <string>
#include <vector>

#include "stats/statistics.h"
#include "verify/check_image.h"

namespace furnace::verify {

// Default of --max-detectable-difference: SAME needs the image-mean test to
// catch a 1 % difference of the mean with probability 0.9.
inline constexpr double kDefaultMaxDetectableDifference = 0.01;
// Default of --tile: 8 × 8 pixels, the size of a small local defect (a
// texture tile, a light's footprint) while still holding 64 pixels, so that
// a tile mean's noise is 1/8 of a pixel's.
inline constexpr int kDefaultTileSize = 8;
// The four test families sharing the family-wise α (Šidák): image mean,
// tiles, pixels, variance (three without the variance test).
inline constexpr int kCompareFamilies = 4;

enum class CompareVerdict { kSame, kDifferent, kInconclusive };
std::string verdict_name(CompareVerdict v);  // "SAME", "DIFFERENT", "INCONCLUSIVE"
int exit_code(CompareVerdict v);             // 0, 1, 3 (2 is bad input, thrown as furnace::Error)

// One side: K ≥ 2 renders, or one furnace EXR.
struct CompareSide {
  std::vector<ForeignImage> images;
  bool furnace_variance() const { return images.size() == 1; }
};

// The tests of one channel ("gray", or "R", "G", "B").
struct ChannelComparison {
  std::string channel;
  // Image mean.
  stats::MeanEstimate mean_a, mean_b;
  double statistic = 0, threshold = 0, dof = 0, alpha = 0;
  double detectable_relative_difference = 0;  // of the image mean, relative to |mean_b|, power 0.9
  bool image_mean_pass = true;
  bool image_mean_held = false;  // Welch t rejected, the rare-event guard did not
  double guarded_statistic = 0;  // the difference over the guard's standard error
  // Tiles.
  int tiles = 0, tile_failures = 0, tiles_held = 0;
  double tile_alpha = 0;
  double worst_tile_t = 0;                                // largest |t| (signed)
  int worst_tile_x = 0, worst_tile_y = 0;                 // its top-left pixel
  double worst_tile_threshold = 0;                        // critical |t| at the worst tile's d.o.f.
  double tile_threshold = 0;                              // critical |t| at the median tile's d.o.f.
  double median_tile_detectable_relative_difference = 0;  // over tiles with mean_b > 0
  // Pixels.
  int pixel_failures = 0;
  int pixels_held = 0;        // Welch t rejected, the rare-event guard did not
  int pixels_few_values = 0;  // repeating or constant-apart values: not tested (see the header)
  double pixel_alpha = 0;
  double worst_pixel_t = 0;
  int worst_pixel_x = 0, worst_pixel_y = 0;
  double worst_pixel_threshold = 0;  // critical |t| at the worst tested pixel's d.o.f.
  double median_pixel_detectable_relative_difference = 0;  // over pixels with mean_b > 0
  // The held test of largest |t| (image mean, tile or pixel), when any.
  std::string worst_held;      // "image mean", "tile (x, y)" or "pixel (x, y)"; empty: none held
  double worst_held_t = 0;     // its Welch t
  double worst_held_guarded_t = 0;
  double worst_held_threshold = 0;
  double worst_held_spp_factor = 0;  // both sides at this factor × their spp judge a difference of its size
  // Variance (not run when the comparison leaves it out: variance_tested false).
  bool variance_tested = true;
  double sum_variance_a = 0, sum_variance_b = 0;  // Σ over pixels of one render's pixel variance
  double variance_ratio = 1;                      // sum_variance_a / sum_variance_b
  double log_ratio_standard_error = 0;
  double variance_statistic = 0;  // log R / SE; ±inf when one side has no spread at all
  double variance_threshold = 0;  // z_{1−α/2}
  double variance_alpha = 0;
  double detectable_variance_ratio = 0;  // exp((z_{1−α/2} + z_0.9)·SE), ≥ 1
  bool variance_pass = true;
};

// How many renders or samples would give the image-mean test its power: K
// renders per side at the current spp, assuming each side's render-to-render
// spread of the image mean is the observed one (a furnace EXR counts as one
// render), or the current K at spp × factor (spread falling as 1/√spp).
struct CompareAdvice {
  bool needed = false;
  int renders_per_side = 0;                     // 0: more than 10⁶
  double spp_factor = 0;                        // at the current K on both sides
  double current_spp_a = 0, current_spp_b = 0;  // from provenance or N; 0 if unknown
};

struct CompareResult {
  int images_a = 0, images_b = 0;
  // Finite negative values on each side: data, used as is (a spectral
  // renderer's RGB film holds small ones); counted for the report.
  NegativeValues negative_a, negative_b;
  // A side stores its radiance as 16-bit half floats: its repeating pixel
  // values are half-float rounding, not a quasi-Monte Carlo pattern.
  bool half_float_a = false, half_float_b = false;
  int width = 0, height = 0, tile_size = 0;
  std::string method_a, method_b;  // "K renders" or "furnace variance"
  double alpha = 0, max_detectable_difference = 0;
  int families = kCompareFamilies;  // sharing alpha: 4, or 3 without the variance test
  std::vector<ChannelComparison> channels;
  std::vector<std::vector<double>> pixel_t;         // [channel][pixel], for --zmap
  std::vector<std::vector<double>> mean_a, mean_b;  // [channel][pixel]: each side's mean image, for --html
  int tiles_x = 0, tiles_y = 0;
  std::vector<std::vector<double>> tile_t;    // [channel][tile], row-major over tiles_x × tiles_y
  std::vector<double> pixel_threshold;        // per channel: critical |t| of the median pixel
  double detectable_relative_difference = 0;  // largest over channels
  bool image_mean_has_power = false;
  // Which families rejected, in the order mean, tiles, pixels, variance.
  std::vector<std::string> rejected;
  // Which families the rare-event guard held (mean, tiles, pixels).
  std::vector<std::string> held;
  // The spp per render the guard took for each side (0: a furnace EXR, its
  // N per pixel), and, when a side's files state none, what was assumed.
  double guard_spp_a = 0, guard_spp_b = 0;
  std::string guard_assumption;
  CompareAdvice advice;
  CompareVerdict verdict = CompareVerdict::kDifferent;
};

// Throws furnace::Error (one sentence naming the file and value) for input
// the tests cannot use: a side without images; one image on a side without
// variance channels, or with N < 2 somewhere; images of different
// resolutions or from different channels (R, G, B against Y); two images
// with identical pixels (one render given twice, on one side or both).
void validate_compare_input(const CompareSide& a, const CompareSide& b);

// Runs every test; validates first (validate_compare_input). Without
// `test_variance` (two renderers or samplers, whose noise legitimately
// differs) only the means are compared, the α shared by three families.
CompareResult compare_renders(const CompareSide& a, const CompareSide& b, double alpha,
                              double max_detectable_difference, int tile_size = kDefaultTileSize,
                              bool test_variance = true);

}  // namespace furnace::verify
