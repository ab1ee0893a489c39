#include "verify/check.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <optional>
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
  int width = 0;                    // of the images, for naming pixels
};

ChannelPixels channel_pixels(const std::vector<ForeignImage>& images, size_t c, const std::vector<double>& reference) {
  const size_t n = reference.size();
  const size_t k = images.size();
  const bool furnace_variance = k == 1;
  ChannelPixels p;
  p.width = images[0].width;
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
  bool held = false;
};

// One mean estimate as the rare-event guard sees it: its variance of the
// mean, its d.o.f. and the samples behind it.
struct Estimate {
  double mean = 0, variance_of_mean = 0, dof = 0, samples = 0;
};

// The guard images' side of one tested channel, and the spp per render each
// side is taken at (0: a furnace EXR, whose N counts the samples).
struct GuardSide {
  const ChannelPixels* pixels = nullptr;  // null: no guard
  double checked_spp = 0, guard_spp = 0;
  Estimate image_mean;  // the guard images' image mean
};

// The samples behind a pixel's mean: K × spp, or a furnace EXR's N.
double pixel_samples(const ChannelPixels& p, size_t i, double spp) { return spp > 0 ? p.counts[i] * spp : p.counts[i]; }

Estimate pixel_estimate(const ChannelPixels& p, size_t i, double spp) {
  return {p.means[i], p.variances[i] / p.counts[i], p.counts[i] - 1, pixel_samples(p, i, spp)};
}

// The mean of the samples behind each pixel's mean (the image mean's).
double mean_samples(const ChannelPixels& p, double spp) {
  double sum = 0;
  for (size_t i = 0; i < p.counts.size(); ++i) sum += pixel_samples(p, i, spp);
  return sum / double(p.counts.size());
}

// The test of `checked` against `reference` under the rare-event guard
// (check.h): below the reference, its variance of the mean floored at the
// guard's variance per sample, at the lower confidence bound of its spread,
// over the checked samples; the floored term carries the guard's d.o.f.
struct GuardedTest {
  double statistic = 0, dof = 0;
  bool rejects = false;
};

GuardedTest guarded_test(const Estimate& checked, const Estimate& guard, double reference, double alpha) {
  GuardedTest g;
  double v = checked.variance_of_mean;
  g.dof = checked.dof;
  if (checked.mean < reference && guard.variance_of_mean > 0 && checked.samples > 0) {
    const double floor =
        rare_event_variance_floor(guard.variance_of_mean, guard.dof, guard.samples, checked.samples);
    if (floor > v) {
      v = floor;
      g.dof = guard.dof;
    }
  }
  if (v <= 0) {
    g.statistic = checked.mean == reference ? 0 : (checked.mean < reference ? -kInf : kInf);
    g.rejects = g.statistic != 0;
    return g;
  }
  g.statistic = (checked.mean - reference) / std::sqrt(v);
  g.rejects = std::fabs(g.statistic) > critical_statistic(g.dof, alpha);
  return g;
}

// Records a held test when it is the worst held so far by |t|: its plain
// and guarded statistics, and the spp factor at which the guarded t reaches
// the noncentrality found with power kReportedPower (n × f divides the
// floored variance by f, so t grows as √f).
void note_held(CheckGuard& guard, const std::string& what, const std::string& channel, double plain_t,
               const GuardedTest& g, double alpha) {
  if (!guard.worst_held.empty() && std::fabs(plain_t) <= std::fabs(guard.worst_held_t)) return;
  guard.worst_held = what;
  guard.worst_held_channel = channel;
  guard.worst_held_t = plain_t;
  guard.worst_held_guarded_t = g.statistic;
  guard.worst_held_threshold = critical_statistic(g.dof, alpha);
  guard.worst_held_spp_factor = held_spp_factor(g.statistic, g.dof, alpha, stats::kReportedPower);
}

// The pixel tests of channel c at level alpha_pixel: each pixel's t into
// pixel_t and `candidates`, the failures, untested pixels and pixel power
// into cc. A pixel that rejects below the reference is tested again under
// the rare-event guard when there is one (held when that does not reject),
// and flags `rejected_below` when there is none.
void test_pixels(const ChannelPixels& p, const std::vector<double>& reference, size_t c, double alpha_pixel,
                 DetectableCache& pixel_power, const GuardSide& guard_side, CheckGuard& guard, bool& rejected_below,
                 ChannelCheck& cc, std::vector<double>& pixel_t, std::vector<Candidate>& candidates) {
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
    bool held = false;
    if (untested) {
      ++cc.pixels_untested;
    } else if (!t.pass) {
      const bool below = p.means[i] < reference[i];
      if (below && guard_side.pixels) {
        const GuardedTest g = guarded_test(pixel_estimate(p, i, guard_side.checked_spp),
                                           pixel_estimate(*guard_side.pixels, i, guard_side.guard_spp), reference[i],
                                           alpha_pixel);
        held = !g.rejects;
        if (held) {
          ++cc.pixels_held;
          note_held(guard, fmt::format("pixel ({}, {})", i % size_t(p.width), i / size_t(p.width)), cc.channel,
                    pixel_t[i], g, alpha_pixel);
        }
      }
      if (!held) ++cc.pixel_failures;
      rejected_below = rejected_below || (below && !guard_side.pixels);
    }
    candidates.push_back({i, c, p.means[i], pixel_t[i], untested, held});
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

// The image mean of K renders (or of one furnace EXR) as the rare-event
// guard sees it: the variance of the K images' means over K, K − 1 d.o.f.
// (the summed pixel variances, normal, for one EXR), K × spp samples (the
// mean N).
Estimate image_mean_estimate(const ChannelPixels& p, double spp) {
  const size_t n = p.means.size();
  const size_t k = p.image_means.size();
  if (k == 1) return {p.image_mean, p.all_constant ? 0.0 : p.sum_variance_of_mean / double(n * n), kInf,
                      mean_samples(p, spp)};
  double m2 = 0;
  for (double m : p.image_means) m2 += (m - p.image_mean) * (m - p.image_mean);
  return {p.image_mean, floored_variance(m2 / double(k - 1), p.image_mean) / double(k), double(k - 1),
          mean_samples(p, spp)};
}

// The image-mean test again under the rare-event guard, when it rejected
// below the reference (held when the guarded test does not reject).
void guard_image_mean(const ChannelPixels& p, const GuardSide& guard_side, double alpha_mean, CheckGuard& guard,
                      bool& rejected_below, ChannelCheck& cc) {
  if (cc.image_mean_pass || !(cc.image_mean < cc.reference_mean)) return;
  if (!guard_side.pixels) {
    rejected_below = true;
    return;
  }
  const GuardedTest g = guarded_test(image_mean_estimate(p, guard_side.checked_spp), guard_side.image_mean,
                                     cc.reference_mean, alpha_mean);
  cc.guarded_statistic = g.statistic;
  if (g.rejects) return;
  cc.image_mean_held = true;
  cc.image_mean_pass = true;  // not judged: held
  note_held(guard, "image mean", cc.channel, cc.statistic, g, alpha_mean);
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
                     images[0].channels[cand.channel], cand.value, reference[cand.pixel], cand.t, cand.untested,
                     cand.held});
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
                         double max_detectable_bias, const std::vector<ForeignImage>& guard_images) {
  FURNACE_CHECK(!images.empty());
  const size_t n = reference.size();
  const size_t k = images.size();
  const size_t channels = images[0].channels.size();
  for (const ForeignImage& img : images) FURNACE_CHECK(img.value.size() == channels && img.value[0].size() == n);
  for (const ForeignImage& img : guard_images)
    FURNACE_CHECK(img.value.size() == channels && img.value[0].size() == n);
  require_error_bars(images, n);
  if (!guard_images.empty()) require_error_bars(guard_images, n);

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
  r.guard.guard_images = int(guard_images.size());
  if (!guard_images.empty()) {
    const GuardSpp g = guard_spp(images, guard_images, "the images'", "the guard images'",
                                 "neither the images' nor the guard images'");
    r.guard.checked_spp = g.a;
    r.guard.guard_spp = g.b;
    r.guard.assumption = g.assumption;
  }
  for (size_t c = 0; c < channels; ++c) {
    const ChannelPixels pixels = channel_pixels(images, c, reference);
    std::optional<ChannelPixels> guard_pixels;
    GuardSide guard_side;
    if (!guard_images.empty()) {
      guard_pixels = channel_pixels(guard_images, c, reference);
      guard_side = {&*guard_pixels, r.guard.checked_spp, r.guard.guard_spp,
                    image_mean_estimate(*guard_pixels, r.guard.guard_spp)};
    }
    ChannelCheck cc;
    cc.channel = images[0].channels[c];
    cc.alpha = alpha_mean;
    cc.pixel_alpha = alpha_pixel;
    test_pixels(pixels, reference, c, alpha_pixel, pixel_power, guard_side, r.guard, r.rejected_below_unguarded, cc,
                r.pixel_t[c], candidates);
    cc.image_mean = pixels.image_mean;
    cc.reference_mean = reference_mean;
    cc.relative_rmse = std::sqrt(pixels.sum_squared_error / double(n)) / (reference_mean > 0 ? reference_mean : 1.0);
    const double sd_image_mean = test_image_mean(pixels, reference_mean, alpha_mean, mean_power, cc);
    guard_image_mean(pixels, guard_side, alpha_mean, r.guard, r.rejected_below_unguarded, cc);
    if (!(cc.detectable_relative_bias <= max_detectable_bias))
      bound_advice(mean_power, cc, sd_image_mean, max_detectable_bias, advised_k, advice);
    r.detectable_relative_bias = std::max(r.detectable_relative_bias, cc.detectable_relative_bias);
    r.channels.push_back(cc);
  }
  r.worst_pixels = worst_pixels(std::move(candidates), images, reference);

  r.image_mean_has_power = r.detectable_relative_bias <= max_detectable_bias;
  r.pixels_have_power = true;
  bool rejected = false, mean_held = false, pixel_held = false;
  for (const ChannelCheck& cc : r.channels) {
    r.pixels_have_power = r.pixels_have_power && cc.median_pixel_detectable_relative_bias <= max_detectable_bias;
    rejected = rejected || !cc.image_mean_pass || cc.pixel_failures > 0;
    mean_held = mean_held || cc.image_mean_held;
    pixel_held = pixel_held || cc.pixels_held > 0;
  }
  if (mean_held) r.guard.held.push_back("mean");
  if (pixel_held) r.guard.held.push_back("pixels");
  if (!r.image_mean_has_power) {
    r.advice.needed = true;
    r.advice.images_at_current_spp = advice.beyond ? 0 : int(advice.images);
    r.advice.advised_images = advised_k;
    r.advice.spp_factor_at_advised_images = advice.spp_factor_advised;
    r.advice.spp_factor_at_current_images = advice.spp_factor_current;
    r.advice.current_spp = images_spp(images);
  }
  r.verdict = rejected ? CheckVerdict::kFail
                       : (r.guard.held.empty() && r.image_mean_has_power ? CheckVerdict::kPass
                                                                         : CheckVerdict::kInconclusive);
  return r;
}

}  // namespace furnace::verify
