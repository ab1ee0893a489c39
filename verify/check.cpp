#include "verify/check.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>

#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/non_central_t.hpp>
#include <boost/math/distributions/normal.hpp>
#include <boost/math/distributions/students_t.hpp>
#include <boost/math/tools/roots.hpp>
#include <fmt/format.h>

#include "analytic/global.h"
#include "analytic/reference.h"
#include "core/error.h"
#include "core/provenance.h"
#include "verify/harness.h"
#include "stats/statistics.h"

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

// Bits of the noncentrality the root finder resolves (λ to ~1e-9 relative).
constexpr int kNoncentralityBits = 30;

// Two-sided level-α rejection probability of the t-test with `dof` d.o.f.
// when the statistic is noncentral t with noncentrality λ.
double t_test_power(double dof, double critical_t, double lambda) {
  const boost::math::non_central_t_distribution<double> t(dof, lambda);
  return boost::math::cdf(boost::math::complement(t, critical_t)) + boost::math::cdf(t, -critical_t);
}

}  // namespace

namespace {

// detectable_noncentrality's root solve (about 1–10 ms; a check needs a few,
// and the simulation of its power thousands).
double solve_detectable_noncentrality(double dof, double alpha, double power) {
  const boost::math::normal_distribution<double> normal;
  if (!std::isfinite(dof))  // z-test: the far tail's share of the power is below 1e-9 at the levels used
    return boost::math::quantile(boost::math::complement(normal, alpha / 2)) +
           boost::math::quantile(boost::math::complement(normal, 1 - power));
  const boost::math::students_t_distribution<double> student(dof);
  const double critical_t = boost::math::quantile(boost::math::complement(student, alpha / 2));
  try {
    // The additive (t_{1−α/2} + t_power) is a lower bound: start there, double until the power is reached.
    double low = 0, high = critical_t + boost::math::quantile(boost::math::complement(student, 1 - power));
    while (t_test_power(dof, critical_t, high) < power) low = high, high *= 2;
    std::uintmax_t iterations = 200;
    const auto root = boost::math::tools::toms748_solve(
        [&](double lambda) { return t_test_power(dof, critical_t, lambda) - power; }, low, high,
        boost::math::tools::eps_tolerance<double>(kNoncentralityBits), iterations);
    return 0.5 * (root.first + root.second);
  } catch (const std::exception&) {
    // Boost's series overflow at one d.o.f. and per-pixel levels (critical t
    // ~1e5). There the statistic (Z + λ)/|W| exceeds t essentially when
    // |W| < λ/t (Z is negligible next to λ), so power = 2Φ(λ/t) − 1.
    return critical_t * boost::math::quantile(normal, (1 + power) / 2);
  }
}

}  // namespace

double detectable_noncentrality(double dof, double alpha, double power) {
  // Memoised: the same few (d.o.f., level) pairs recur in every check of a process.
  static std::mutex mutex;
  static std::map<std::array<double, 3>, double> solved;
  const std::array<double, 3> key = {dof, alpha, power};
  {
    const std::lock_guard<std::mutex> lock(mutex);
    if (const auto it = solved.find(key); it != solved.end()) return it->second;
  }
  const double lambda = solve_detectable_noncentrality(dof, alpha, power);
  const std::lock_guard<std::mutex> lock(mutex);
  return solved.emplace(key, lambda).first->second;
}

bool has_few_distinct_values(std::vector<double> values) {
  const size_t k = values.size();
  if (k < size_t(kFewValuesMinImages)) return false;
  std::sort(values.begin(), values.end());
  const size_t distinct = size_t(std::unique(values.begin(), values.end()) - values.begin());
  return distinct > 1 && distinct * kFewValuesDivisor <= k;
}

double floored_variance(double sample_variance, double mean) {
  if (sample_variance == 0) return 0;
  const double floor = stats::kZeroVarianceRelTolerance * std::fabs(mean);
  return std::max(sample_variance, floor * floor);
}

int smallest_sufficient_count(const std::function<bool(int)>& enough, int max_count) {
  if (enough(2)) return 2;
  int low = 2, high = 4;  // enough(low) is false; doubling until enough(high)
  while (!enough(high)) {
    if (high >= max_count) return 0;
    low = high;
    high = std::min(2 * high, max_count);
  }
  while (high - low > 1) {
    const int mid = low + (high - low) / 2;
    (enough(mid) ? high : low) = mid;
  }
  return high;
}

double spread_upper_bound_factor(double dof, double confidence) {
  if (!std::isfinite(dof)) return 1.0;
  const boost::math::chi_squared_distribution<double> chi2(dof);
  return std::sqrt(dof / boost::math::quantile(chi2, 1 - confidence));
}

namespace {

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
      at->second = detectable_noncentrality(dof, alpha_, kReportedPower) * spread_upper_bound_factor(dof, kSpreadConfidence);
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

// The images' samples per pixel: the provenance's spp when every image
// states the same, else the median N of a furnace EXR, else 0 (unknown).
double known_spp(const std::vector<ForeignImage>& images) {
  const std::string first = images[0].provenance.spp;
  bool same = !first.empty();
  for (const ForeignImage& img : images) same = same && img.provenance.spp == first;
  if (same) return std::stod(first);
  if (!images[0].count.empty()) return stats::median(images[0].count);
  return 0;
}

}  // namespace

CheckReference check_reference(const Scene& scene, std::optional<int> max_depth) {
  CheckReference r;
  const int depth = max_depth.value_or(kUnlimitedDepth);
  try {
    r.values = analytic::global_reference_image(scene, depth);
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
  const bool furnace_variance = k == 1;
  if (furnace_variance && !images[0].has_variance())
    throw Error(fmt::format("checking needs at least two independent renders (different seeds) to estimate the "
                            "error bars, or one furnace EXR with variance and N channels; '{}' alone has neither.",
                            images[0].path));
  if (furnace_variance)
    for (size_t i = 0; i < n; ++i)
      if (images[0].count[i] < 2)
        throw Error(fmt::format("image '{}' has N = {} samples at pixel ({}, {}); one image alone needs at least 2 "
                                "per pixel to estimate its variance.",
                                images[0].path, images[0].count[i], i % size_t(images[0].width),
                                i / size_t(images[0].width)));

  CheckResult r;
  r.images = int(k);
  r.pixels = int(n);
  r.method = furnace_variance ? "furnace variance" : "across-images t";
  r.alpha = alpha;
  r.max_detectable_bias = max_detectable_bias;
  const double alpha_mean = stats::sidak_alpha(alpha * kImageMeanAlphaShare, channels);
  const double alpha_pixel = stats::sidak_alpha(alpha * (1 - kImageMeanAlphaShare), channels * n);
  double reference_mean = 0;
  for (double v : reference) reference_mean += v;
  reference_mean /= double(n);

  struct Candidate {
    size_t pixel, channel;
    double value, t;
    bool untested;
  };
  std::vector<Candidate> candidates;
  r.pixel_t.assign(channels, std::vector<double>(n, 0.0));
  DetectableCache mean_power(alpha_mean), pixel_power(alpha_pixel);
  double advice_images = 0, advice_factor_current = 0, advice_factor_advised = 0;
  bool advice_beyond = false;
  const int advised_k = std::max(int(k), kAdvisedImages);
  for (size_t c = 0; c < channels; ++c) {
    ChannelCheck cc;
    cc.channel = images[0].channels[c];
    cc.alpha = alpha_mean;
    cc.pixel_alpha = alpha_pixel;
    std::vector<double> image_means(k, 0.0), detectable, thresholds, dofs;
    std::vector<double> means(n), variances(n), counts(n), pixel_values(k);
    std::vector<bool> few_values(n, false);
    double sum_sq = 0, sum_variance_of_mean = 0;
    bool all_constant = true;  // every pixel without spread: a zero-variance render
    for (size_t i = 0; i < n; ++i) {
      double mean = 0;
      for (const ForeignImage& img : images) mean += img.value[c][i];
      mean /= double(k);
      for (size_t j = 0; j < k; ++j) image_means[j] += images[j].value[c][i];
      if (furnace_variance) {
        counts[i] = images[0].count[i];
        variances[i] = floored_variance(images[0].variance[c][i], mean);
      } else {
        double m2 = 0;
        for (const ForeignImage& img : images) m2 += (img.value[c][i] - mean) * (img.value[c][i] - mean);
        counts[i] = double(k);
        variances[i] = floored_variance(m2 / double(k - 1), mean);
        for (size_t j = 0; j < k; ++j) pixel_values[j] = images[j].value[c][i];
        few_values[i] = has_few_distinct_values(pixel_values);
      }
      means[i] = mean;
      all_constant = all_constant && variances[i] == 0;
      sum_variance_of_mean += variances[i] / counts[i];
      sum_sq += (mean - reference[i]) * (mean - reference[i]);
      cc.image_mean += mean;
    }
    for (size_t i = 0; i < n; ++i) {
      const stats::MeanTestResult t =
          stats::mean_test(uint64_t(counts[i]), means[i], variances[i], reference[i], alpha_pixel, kReportedPower);
      r.pixel_t[c][i] = signed_statistic(t);
      if (few_values[i]) {
        ++cc.pixels_few_values;
        candidates.push_back({i, c, means[i], r.pixel_t[c][i], true});
        continue;
      }
      // Constant across every sample yet off the reference, in a render that
      // is not zero-variance: a rare contribution (p ≪ 1/samples) was never
      // sampled. Its skewness is unbounded, so like verify's harness the
      // pixel is untested and left to the image-mean test.
      const bool untested = t.zero_variance && !t.pass && !all_constant;
      if (untested) ++cc.pixels_untested;
      else if (!t.pass) ++cc.pixel_failures;
      candidates.push_back({i, c, means[i], r.pixel_t[c][i], untested});
      if (!t.zero_variance) {
        thresholds.push_back(t.threshold);
        dofs.push_back(t.dof);
      }
      if (reference[i] > 0)
        detectable.push_back(pixel_power.relative(counts[i], std::sqrt(variances[i]), reference[i], counts[i] - 1));
    }
    cc.image_mean /= double(n);
    cc.reference_mean = reference_mean;
    cc.relative_rmse = std::sqrt(sum_sq / double(n)) / (reference_mean > 0 ? reference_mean : 1.0);
    cc.median_pixel_detectable_relative_bias = detectable.empty() ? kInf : stats::median(std::move(detectable));
    cc.pixel_threshold = thresholds.empty() ? 0.0 : stats::median(thresholds);
    cc.pixel_dof = dofs.empty() ? 0.0 : stats::median(dofs);

    double sd_image_mean = 0;  // standard deviation of one image's mean
    if (furnace_variance) {
      sd_image_mean = all_constant ? 0.0 : std::sqrt(sum_variance_of_mean) / double(n);
      const stats::ZTestResult z = stats::z_test(cc.image_mean, reference_mean, sd_image_mean, alpha_mean,
                                                 kReportedPower);
      cc.standard_error = z.standard_error;
      cc.statistic = z.statistic;
      cc.threshold = z.threshold;
      cc.dof = kInf;
      cc.detectable_relative_bias = mean_power.relative(1, sd_image_mean, reference_mean, kInf);
      cc.image_mean_pass = z.pass;
    } else {
      for (double& m : image_means) m /= double(n);
      double m2 = 0;
      for (double m : image_means) m2 += (m - cc.image_mean) * (m - cc.image_mean);
      const double s2 = floored_variance(m2 / double(k - 1), cc.image_mean);
      sd_image_mean = std::sqrt(s2);
      const stats::MeanTestResult t = stats::mean_test(k, cc.image_mean, s2, reference_mean, alpha_mean, kReportedPower);
      cc.standard_error = t.standard_error;
      cc.statistic = signed_statistic(t);
      cc.threshold = t.threshold;
      cc.dof = t.dof;
      cc.detectable_relative_bias = mean_power.relative(double(k), sd_image_mean, reference_mean, double(k - 1));
      cc.image_mean_pass = t.pass;
    }
    // Advice (CheckAdvice): the same image-mean test with more images or samples.
    if (!(cc.detectable_relative_bias <= max_detectable_bias)) {
      const int needed = images_needed(mean_power, sd_image_mean, reference_mean, max_detectable_bias);
      advice_beyond = advice_beyond || needed == 0;
      advice_images = std::max(advice_images, double(needed));
      const double at_current = cc.detectable_relative_bias / max_detectable_bias;
      const double at_advised =
          mean_power.relative(advised_k, sd_image_mean, reference_mean, advised_k - 1) / max_detectable_bias;
      advice_factor_current = std::max(advice_factor_current, at_current * at_current);
      advice_factor_advised = std::max(advice_factor_advised, at_advised * at_advised);
    }
    r.detectable_relative_bias = std::max(r.detectable_relative_bias, cc.detectable_relative_bias);
    r.channels.push_back(cc);
  }

  // The worst pixels: largest |t| first (a failed zero-spread pixel is ±inf).
  const size_t shown = std::min(candidates.size(), size_t(kWorstPixelsShown));
  std::partial_sort(candidates.begin(), candidates.begin() + shown, candidates.end(),
                    [](const Candidate& a, const Candidate& b) { return std::fabs(a.t) > std::fabs(b.t); });
  for (size_t w = 0; w < shown; ++w) {
    const Candidate& cand = candidates[w];
    r.worst_pixels.push_back({int(cand.pixel % size_t(images[0].width)), int(cand.pixel / size_t(images[0].width)),
                              images[0].channels[cand.channel], cand.value, reference[cand.pixel], cand.t,
                              cand.untested});
  }

  r.image_mean_has_power = r.detectable_relative_bias <= max_detectable_bias;
  r.pixels_have_power = true;
  bool rejected = false;
  for (const ChannelCheck& cc : r.channels) {
    r.pixels_have_power = r.pixels_have_power && cc.median_pixel_detectable_relative_bias <= max_detectable_bias;
    rejected = rejected || !cc.image_mean_pass || cc.pixel_failures > 0;
  }
  if (!r.image_mean_has_power) {
    r.advice.needed = true;
    r.advice.images_at_current_spp = advice_beyond ? 0 : int(advice_images);
    r.advice.advised_images = advised_k;
    r.advice.spp_factor_at_advised_images = advice_factor_advised;
    r.advice.spp_factor_at_current_images = advice_factor_current;
    r.advice.current_spp = known_spp(images);
  }
  r.verdict = rejected ? CheckVerdict::kFail
                       : (r.image_mean_has_power ? CheckVerdict::kPass : CheckVerdict::kInconclusive);
  return r;
}

}  // namespace furnace::verify
