#include "verify/check.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <utility>

#include <fmt/format.h>

#include "analytic/glass.h"
#include "analytic/global.h"
#include "analytic/reference.h"
#include "core/error.h"
#include "core/provenance.h"
#include "stats/statistics.h"
#include "stats/test_design.h"
#include "verify/image_statistics.h"

namespace furnace::verify {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// The advice searches image counts up to this many.
constexpr int kMaxAdvisedImages = 1000000;
// Direct lighting, as a path length: the camera segment and one bounce.
constexpr int kDirectLightingSegments = 2;

std::string without_final_period(std::string s) {
  while (!s.empty() && (s.back() == '.' || s.back() == ' ')) s.pop_back();
  return s;
}

// The t of a failed zero-spread test is ±inf (the sign of the error).
double signed_statistic(const stats::MeanTestResult& t) {
  if (!t.zero_variance) return t.statistic;
  if (t.pass) return 0;
  return t.mean >= t.reference ? kInf : -kInf;
}

// Noncentralities per d.o.f. (one root solve each; pixels share a few d.o.f.).
class DetectableCache {
 public:
  explicit DetectableCache(double alpha) : alpha_(alpha) {}
  // Relative bias detected with power kReportedPower by the test of a mean
  // over `count` values of spread `sd` (d.o.f. count − 1, or `dof` when given)
  // against `reference`; the spread enters at its upper confidence bound.
  double relative(double count, double sd, double reference, double dof) {
    auto [at, fresh] = factor_.try_emplace(dof, 0.0);
    if (fresh)
      at->second = detectable_noncentrality(dof, alpha_, stats::kReportedPower) *
                   spread_upper_bound_factor(dof, kSpreadConfidence);
    if (sd == 0) return 0;
    return reference > 0 ? at->second * sd / std::sqrt(count) / reference : kInf;
  }

 private:
  double alpha_;
  std::map<double, double> factor_;
};

// Smallest K ≥ 2 whose across-images test would report a detectable bias of
// at most `target` if the images' means had the spread `sd` (0: none up to
// kMaxAdvisedImages).
int images_needed(DetectableCache& cache, double sd, double reference_mean, double target) {
  return smallest_sufficient_count([&](int k) { return cache.relative(k, sd, reference_mean, k - 1) <= target; },
                                   kMaxAdvisedImages);
}

// The images' samples per pixel: the spp their headers state (furnace's,
// pbrt-v4's or Blender's attribute) when every image states the same, else
// the median N of a furnace EXR, else 0 (unknown).
double known_spp(const std::vector<ForeignImage>& images) {
  const std::string first = images[0].stated_spp;
  bool same = !first.empty();
  for (const ForeignImage& img : images) same = same && img.stated_spp == first;
  if (same) return std::stod(first);
  if (!images[0].count.empty()) return stats::median(images[0].count);
  return 0;
}

// Throws furnace::Error unless the images carry error bars: K ≥ 2 renders,
// or one furnace EXR with N ≥ 2 at every one of its n pixels.
void require_error_bars(const std::vector<ForeignImage>& images, size_t n) {
  if (images.size() > 1) return;
  if (!images[0].has_variance())
    throw Error(fmt::format("checking needs at least two independent renders (different seeds) to estimate the "
                            "error bars, or one furnace EXR with variance and N channels; '{}' alone has neither.",
                            images[0].path));
  for (size_t i = 0; i < n; ++i)
    if (images[0].count[i] < 2)
      throw Error(fmt::format("image '{}' has N = {} samples at pixel ({}, {}); one image alone needs at least 2 "
                              "per pixel to estimate its variance.",
                              images[0].path, images[0].count[i], i % size_t(images[0].width),
                              i / size_t(images[0].width)));
}

// One tested channel of the K images (or of the one furnace EXR), per pixel
// and summed over the pixels.
struct ChannelPixels {
  std::vector<double> means;      // the mean over the images
  std::vector<double> variances;  // of one value (floored_variance): across the images, or the EXR's s²
  std::vector<double> counts;     // K, or the EXR's N
  std::vector<bool> few_values;   // has_few_distinct_values (K renders only)
  std::vector<double> image_means;  // per image: the mean over its pixels
  double image_mean = 0;            // of the averaged image
  double sum_variance_of_mean = 0;  // Σ variance/count over the pixels
  double sum_squared_error = 0;     // Σ (mean − reference)² over the pixels
  bool all_constant = true;         // every pixel without spread: a zero-variance render
};

ChannelPixels channel_pixels(const std::vector<ForeignImage>& images, size_t c, const std::vector<double>& reference) {
  const size_t n = reference.size();
  const size_t k = images.size();
  const bool furnace_variance = k == 1;
  ChannelPixels p;
  p.means.resize(n);
  p.variances.resize(n);
  p.counts.resize(n);
  p.few_values.assign(n, false);
  p.image_means.assign(k, 0.0);
  std::vector<double> pixel_values(k);
  for (size_t i = 0; i < n; ++i) {
    double mean = 0;
    for (const ForeignImage& img : images) mean += img.value[c][i];
    mean /= double(k);
    for (size_t j = 0; j < k; ++j) p.image_means[j] += images[j].value[c][i];
    if (furnace_variance) {
      p.counts[i] = images[0].count[i];
      p.variances[i] = floored_variance(images[0].variance[c][i], mean);
    } else {
      double m2 = 0;
      for (const ForeignImage& img : images) m2 += (img.value[c][i] - mean) * (img.value[c][i] - mean);
      p.counts[i] = double(k);
      p.variances[i] = floored_variance(m2 / double(k - 1), mean);
      for (size_t j = 0; j < k; ++j) pixel_values[j] = images[j].value[c][i];
      p.few_values[i] = has_few_distinct_values(pixel_values);
    }
    p.means[i] = mean;
    p.all_constant = p.all_constant && p.variances[i] == 0;
    p.sum_variance_of_mean += p.variances[i] / p.counts[i];
    p.sum_squared_error += (mean - reference[i]) * (mean - reference[i]);
    p.image_mean += mean;
  }
  p.image_mean /= double(n);
  for (double& m : p.image_means) m /= double(n);
  return p;
}

// A pixel that may be listed among the worst.
struct Candidate {
  size_t pixel, channel;
  double value, t;
  bool untested;
};

// The pixel tests of channel c at level alpha_pixel: each pixel's t into
// pixel_t and `candidates`, the failures, untested pixels and pixel power
// into cc.
void test_pixels(const ChannelPixels& p, const std::vector<double>& reference, size_t c, double alpha_pixel,
                 DetectableCache& pixel_power, ChannelCheck& cc, std::vector<double>& pixel_t,
                 std::vector<Candidate>& candidates) {
  std::vector<double> detectable, thresholds, dofs;
  for (size_t i = 0; i < reference.size(); ++i) {
    const stats::MeanTestResult t = stats::mean_test(uint64_t(p.counts[i]), p.means[i], p.variances[i], reference[i],
                                                     alpha_pixel, stats::kReportedPower);
    pixel_t[i] = signed_statistic(t);
    if (p.few_values[i]) {
      ++cc.pixels_few_values;
      candidates.push_back({i, c, p.means[i], pixel_t[i], true});
      continue;
    }
    // Constant across every sample yet off the reference, in a render that
    // is not zero-variance: a rare contribution (p ≪ 1/samples) was never
    // sampled. Its skewness is unbounded, so like verify's harness the
    // pixel is untested and left to the image-mean test.
    const bool untested = t.zero_variance && !t.pass && !p.all_constant;
    if (untested) ++cc.pixels_untested;
    else if (!t.pass) ++cc.pixel_failures;
    candidates.push_back({i, c, p.means[i], pixel_t[i], untested});
    if (!t.zero_variance) {
      thresholds.push_back(t.threshold);
      dofs.push_back(t.dof);
    }
    if (reference[i] > 0)
      detectable.push_back(
          pixel_power.relative(p.counts[i], std::sqrt(p.variances[i]), reference[i], p.counts[i] - 1));
  }
  cc.median_pixel_detectable_relative_bias = detectable.empty() ? kInf : stats::median(std::move(detectable));
  cc.pixel_threshold = thresholds.empty() ? 0.0 : stats::median(thresholds);
  cc.pixel_dof = dofs.empty() ? 0.0 : stats::median(dofs);
}

// The image-mean test of one channel at level alpha_mean: a z-test with the
// summed pixel variances (one furnace EXR), else a t-test of the K image
// means. Fills cc's image-mean fields; returns the standard deviation of one
// image's mean, which the advice scales.
double test_image_mean(const ChannelPixels& p, double reference_mean, double alpha_mean, DetectableCache& mean_power,
                       ChannelCheck& cc) {
  const size_t n = p.means.size();
  const size_t k = p.image_means.size();
  if (k == 1) {
    const double sd_image_mean = p.all_constant ? 0.0 : std::sqrt(p.sum_variance_of_mean) / double(n);
    const stats::ZTestResult z =
        stats::z_test(cc.image_mean, reference_mean, sd_image_mean, alpha_mean, stats::kReportedPower);
    cc.standard_error = z.standard_error;
    cc.statistic = z.statistic;
    cc.threshold = z.threshold;
    cc.dof = kInf;
    cc.detectable_relative_bias = mean_power.relative(1, sd_image_mean, reference_mean, kInf);
    cc.image_mean_pass = z.pass;
    return sd_image_mean;
  }
  double m2 = 0;
  for (double m : p.image_means) m2 += (m - cc.image_mean) * (m - cc.image_mean);
  const double s2 = floored_variance(m2 / double(k - 1), cc.image_mean);
  const double sd_image_mean = std::sqrt(s2);
  const stats::MeanTestResult t =
      stats::mean_test(k, cc.image_mean, s2, reference_mean, alpha_mean, stats::kReportedPower);
  cc.standard_error = t.standard_error;
  cc.statistic = signed_statistic(t);
  cc.threshold = t.threshold;
  cc.dof = t.dof;
  cc.detectable_relative_bias = mean_power.relative(double(k), sd_image_mean, reference_mean, double(k - 1));
  cc.image_mean_pass = t.pass;
  return sd_image_mean;
}

// The advice's bounds over the channels whose image-mean test lacks power
// (CheckAdvice): the same test with more images or samples.
struct AdviceBounds {
  double images = 0, spp_factor_current = 0, spp_factor_advised = 0;
  bool beyond = false;  // some channel needs more than kMaxAdvisedImages images
};

void bound_advice(DetectableCache& mean_power, const ChannelCheck& cc, double sd_image_mean, double target,
                  int advised_k, AdviceBounds& b) {
  const int needed = images_needed(mean_power, sd_image_mean, cc.reference_mean, target);
  b.beyond = b.beyond || needed == 0;
  b.images = std::max(b.images, double(needed));
  const double at_current = cc.detectable_relative_bias / target;
  const double at_advised = mean_power.relative(advised_k, sd_image_mean, cc.reference_mean, advised_k - 1) / target;
  b.spp_factor_current = std::max(b.spp_factor_current, at_current * at_current);
  b.spp_factor_advised = std::max(b.spp_factor_advised, at_advised * at_advised);
}

// The worst pixels: largest |t| first (a failed zero-spread pixel is ±inf).
std::vector<WorstPixel> worst_pixels(std::vector<Candidate> candidates, const std::vector<ForeignImage>& images,
                                     const std::vector<double>& reference) {
  const size_t shown = std::min(candidates.size(), size_t(kWorstPixelsShown));
  std::partial_sort(candidates.begin(), candidates.begin() + shown, candidates.end(),
                    [](const Candidate& a, const Candidate& b) { return std::fabs(a.t) > std::fabs(b.t); });
  std::vector<WorstPixel> worst;
  for (size_t w = 0; w < shown; ++w) {
    const Candidate& cand = candidates[w];
    worst.push_back({int(cand.pixel % size_t(images[0].width)), int(cand.pixel / size_t(images[0].width)),
                     images[0].channels[cand.channel], cand.value, reference[cand.pixel], cand.t, cand.untested});
  }
  return worst;
}

}  // namespace

CheckReference check_reference(const Scene& scene, std::optional<int> max_depth, TransportConvention convention) {
  CheckReference r;
  if (analytic::has_dielectric(scene)) r.convention = transport_convention_name(convention);
  const int depth = max_depth.value_or(kUnlimitedDepth);
  try {
    r.values = analytic::global_reference_image(scene, depth, convention);
    r.global = true;
    r.max_segments = depth;
    r.description = fmt::format("global illumination, max depth {}", depth_name(depth));
    return r;
  } catch (const Error& e) {
    if (max_depth && *max_depth != kDirectLightingSegments)
      throw Error(fmt::format("{}, so --max-depth {} cannot be checked; only direct lighting (--max-depth 2) can.",
                              without_final_period(e.what()), depth_name(*max_depth)));
    r.note = e.what();
  }
  r.values = analytic::reference_image(scene);
  r.global = false;
  r.max_segments = kDirectLightingSegments;
  r.description = "direct lighting (emission + one bounce: max depth 2)";
  return r;
}

std::string verdict_name(CheckVerdict v) {
  switch (v) {
    case CheckVerdict::kPass: return "PASS";
    case CheckVerdict::kFail: return "FAIL";
    case CheckVerdict::kInconclusive: return "INCONCLUSIVE";
  }
  return "?";
}

int exit_code(CheckVerdict v) {
  switch (v) {
    case CheckVerdict::kPass: return 0;
    case CheckVerdict::kFail: return 1;
    case CheckVerdict::kInconclusive: return 3;
  }
  return 1;
}

CheckResult check_images(const std::vector<ForeignImage>& images, const std::vector<double>& reference, double alpha,
                         double max_detectable_bias) {
  FURNACE_CHECK(!images.empty());
  const size_t n = reference.size();
  const size_t k = images.size();
  const size_t channels = images[0].channels.size();
  for (const ForeignImage& img : images) FURNACE_CHECK(img.value.size() == channels && img.value[0].size() == n);
  require_error_bars(images, n);

  CheckResult r;
  r.images = int(k);
  r.negative = count_negative_values(images);
  r.half_float = any_half_float(images);
  r.pixels = int(n);
  r.method = k == 1 ? "furnace variance" : "across-images t";
  r.alpha = alpha;
  r.max_detectable_bias = max_detectable_bias;
  const double alpha_mean = stats::sidak_alpha(alpha * kImageMeanAlphaShare, channels);
  const double alpha_pixel = stats::sidak_alpha(alpha * (1 - kImageMeanAlphaShare), channels * n);
  double reference_mean = 0;
  for (double v : reference) reference_mean += v;
  reference_mean /= double(n);

  std::vector<Candidate> candidates;
  r.pixel_t.assign(channels, std::vector<double>(n, 0.0));
  DetectableCache mean_power(alpha_mean), pixel_power(alpha_pixel);
  AdviceBounds advice;
  const int advised_k = std::max(int(k), kAdvisedImages);
  for (size_t c = 0; c < channels; ++c) {
    const ChannelPixels pixels = channel_pixels(images, c, reference);
    ChannelCheck cc;
    cc.channel = images[0].channels[c];
    cc.alpha = alpha_mean;
    cc.pixel_alpha = alpha_pixel;
    test_pixels(pixels, reference, c, alpha_pixel, pixel_power, cc, r.pixel_t[c], candidates);
    cc.image_mean = pixels.image_mean;
    cc.reference_mean = reference_mean;
    cc.relative_rmse = std::sqrt(pixels.sum_squared_error / double(n)) / (reference_mean > 0 ? reference_mean : 1.0);
    const double sd_image_mean = test_image_mean(pixels, reference_mean, alpha_mean, mean_power, cc);
    if (!(cc.detectable_relative_bias <= max_detectable_bias))
      bound_advice(mean_power, cc, sd_image_mean, max_detectable_bias, advised_k, advice);
    r.detectable_relative_bias = std::max(r.detectable_relative_bias, cc.detectable_relative_bias);
    r.channels.push_back(cc);
  }
  r.worst_pixels = worst_pixels(std::move(candidates), images, reference);

  r.image_mean_has_power = r.detectable_relative_bias <= max_detectable_bias;
  r.pixels_have_power = true;
  bool rejected = false;
  for (const ChannelCheck& cc : r.channels) {
    r.pixels_have_power = r.pixels_have_power && cc.median_pixel_detectable_relative_bias <= max_detectable_bias;
    rejected = rejected || !cc.image_mean_pass || cc.pixel_failures > 0;
  }
  if (!r.image_mean_has_power) {
    r.advice.needed = true;
    r.advice.images_at_current_spp = advice.beyond ? 0 : int(advice.images);
    r.advice.advised_images = advised_k;
    r.advice.spp_factor_at_advised_images = advice.spp_factor_advised;
    r.advice.spp_factor_at_current_images = advice.spp_factor_current;
    r.advice.current_spp = known_spp(images);
  }
  r.verdict = rejected ? CheckVerdict::kFail
                       : (r.image_mean_has_power ? CheckVerdict::kPass : CheckVerdict::kInconclusive);
  return r;
}

}  // namespace furnace::verify
