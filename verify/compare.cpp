#include "verify/compare.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <system_error>

#include <boost/math/distributions/students_t.hpp>
#include <fmt/format.h>

#include "core/error.h"
#include "stats/test_design.h"
#include "verify/image_statistics.h"

namespace furnace::verify {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// The advice searches render counts up to this many per side.
constexpr int kMaxAdvisedRenders = 1000000;

std::string pixel_name(size_t i, int width) { return fmt::format("({}, {})", i % size_t(width), i / size_t(width)); }

// A rectangle of pixels [x0, x1) × [y0, y1).
struct Region {
  int x0, y0, x1, y1;
  size_t pixels() const { return size_t(x1 - x0) * size_t(y1 - y0); }
};

// One channel of one side: the mean estimates of its pixels and regions,
// and each pixel's variance of one render for the variance test.
class SideChannel {
 public:
  // `spp`: the spp per render the rare-event guard takes for K renders
  // (unused for a furnace EXR, whose N channel counts its samples).
  SideChannel(const CompareSide& side, size_t channel, double spp) : side_(side), c_(channel), spp_(spp) {}

  int width() const { return side_.images[0].width; }
  size_t renders() const { return side_.images.size(); }
  double value(size_t image, size_t i) const { return side_.images[image].value[c_][i]; }

  stats::MeanEstimate pixel(size_t i) const {
    if (side_.furnace_variance()) {
      const ForeignImage& img = side_.images[0];
      const double mean = img.value[c_][i];
      return {mean, floored_variance(img.variance[c_][i], mean) / img.count[i], img.count[i] - 1};
    }
    const size_t k = renders();
    double mean = 0;
    for (size_t j = 0; j < k; ++j) mean += value(j, i);
    mean /= double(k);
    double m2 = 0;
    for (size_t j = 0; j < k; ++j) m2 += (value(j, i) - mean) * (value(j, i) - mean);
    return {mean, floored_variance(m2 / double(k - 1), mean) / double(k), double(k - 1)};
  }

  // The mean over the region: per render, then across renders (K renders);
  // or the mean of the pixel means with the summed variances (one EXR).
  stats::MeanEstimate region(const Region& r) const {
    const double n = double(r.pixels());
    if (side_.furnace_variance()) {
      double mean = 0, v = 0, v2_over_dof = 0;
      for (int y = r.y0; y < r.y1; ++y)
        for (int x = r.x0; x < r.x1; ++x) {
          const stats::MeanEstimate p = pixel(size_t(y) * size_t(width()) + size_t(x));
          mean += p.mean;
          v += p.variance_of_mean;
          v2_over_dof += p.variance_of_mean * p.variance_of_mean / p.dof;
        }
      const double dof = v2_over_dof > 0 ? v * v / v2_over_dof : kInf;
      return {mean / n, v / (n * n), dof};
    }
    const size_t k = renders();
    std::vector<double> means(k, 0.0);
    for (size_t j = 0; j < k; ++j) {
      for (int y = r.y0; y < r.y1; ++y)
        for (int x = r.x0; x < r.x1; ++x) means[j] += value(j, size_t(y) * size_t(width()) + size_t(x));
      means[j] /= n;
    }
    double mean = 0;
    for (double m : means) mean += m / double(k);
    double m2 = 0;
    for (double m : means) m2 += (m - mean) * (m - mean);
    return {mean, floored_variance(m2 / double(k - 1), mean) / double(k), double(k - 1)};
  }

  // One render's variance at pixel i (unfloored) and the normal-theory
  // estimate of that estimate's variance: 2σ⁴/ν, with σ⁴ estimated without
  // bias by s⁴·ν/(ν + 2).
  std::pair<double, double> render_variance(size_t i) const {
    if (side_.furnace_variance()) {
      const ForeignImage& img = side_.images[0];
      const double u = img.variance[c_][i] / img.count[i];
      return {u, 2 * u * u / (img.count[i] + 1)};
    }
    const size_t k = renders();
    double mean = 0;
    for (size_t j = 0; j < k; ++j) mean += value(j, i) / double(k);
    double m2 = 0;
    for (size_t j = 0; j < k; ++j) m2 += (value(j, i) - mean) * (value(j, i) - mean);
    const double s2 = m2 / double(k - 1);
    return {s2, 2 * s2 * s2 / double(k + 1)};
  }

  // The samples behind a pixel's or a region's mean, for the rare-event
  // guard: K × spp, or a furnace EXR's N (its mean over a region).
  double samples(size_t i) const {
    return side_.furnace_variance() ? side_.images[0].count[i] : double(renders()) * spp_;
  }
  double samples(const Region& r) const {
    if (!side_.furnace_variance()) return double(renders()) * spp_;
    double sum = 0;
    for (int y = r.y0; y < r.y1; ++y)
      for (int x = r.x0; x < r.x1; ++x) sum += samples(size_t(y) * size_t(width()) + size_t(x));
    return sum / double(r.pixels());
  }

  // True when the pixel's K values repeat (a quasi-Monte Carlo render).
  bool few_values(size_t i) const {
    if (side_.furnace_variance()) return false;
    std::vector<double> values(renders());
    for (size_t j = 0; j < renders(); ++j) values[j] = value(j, i);
    return has_few_distinct_values(std::move(values));
  }

 private:
  const CompareSide& side_;
  size_t c_;
  double spp_;
};

// λ·f at a d.o.f.: the noncentrality reaching power stats::kReportedPower
// times the spread's upper-bound factor (verify/image_statistics.h), cached
// per d.o.f.
class PowerFactor {
 public:
  explicit PowerFactor(double alpha) : alpha_(alpha) {}
  double operator()(double dof) {
    auto [at, fresh] = cache_.try_emplace(dof, 0.0);
    if (fresh)
      at->second = detectable_noncentrality(dof, alpha_, stats::kReportedPower) *
                   spread_upper_bound_factor(dof, kSpreadConfidence);
    return at->second;
  }

 private:
  double alpha_;
  std::map<double, double> cache_;
};

double relative(double difference, double mean_b) {
  if (difference == 0) return 0;
  return mean_b != 0 ? difference / std::fabs(mean_b) : kInf;
}

// Rejects a Welch statistic at the two-sided level alpha; `z_critical` (the
// normal quantile, never above Student's) skips the t distribution for the
// many statistics below it.
bool welch_rejects(const stats::WelchStatistic& w, double alpha, double z_critical) {
  if (w.standard_error == 0) return w.statistic != 0;
  const double t = std::fabs(w.statistic);
  if (t <= z_critical) return false;
  if (!std::isfinite(w.dof)) return true;
  const boost::math::students_t_distribution<double> student(w.dof);
  return 2 * boost::math::cdf(boost::math::complement(student, t)) < alpha;
}

// A zero-SE difference is exact agreement (round-off allowed) or ±inf.
//
// The d.o.f.: Welch–Satterthwaite when both sides have the same d.o.f. (K
// renders each, or furnace EXRs of equal N), else the smaller side's (Hsu's
// conservative choice). With unequal d.o.f. the Satterthwaite estimate is
// anti-conservative in the far tails the Šidák levels reach: when the
// few-d.o.f. side's spread comes out small by chance, the estimate follows
// the many-d.o.f. side. Measured on same-distribution synthetic pairs at
// α = 0.05: 2 renders against one furnace EXR falsely rejected 35 of 200 with
// the Satterthwaite d.o.f.
stats::WelchStatistic welch(const stats::MeanEstimate& a, const stats::MeanEstimate& b) {
  stats::WelchStatistic w = stats::welch_statistic(a, b);
  if (w.standard_error == 0 &&
      std::fabs(w.difference) <= stats::kZeroVarianceRelTolerance * std::max(std::fabs(a.mean), std::fabs(b.mean)))
    w.statistic = 0;
  if (w.standard_error > 0 && a.dof != b.dof) w.dof = std::min(a.dof, b.dof);
  return w;
}

// One test under the rare-event guard (compare.h): the plain Welch statistic,
// the one with the lower side's variance floored, and the standard error the
// detectable difference uses (the larger of the two directions' floored ones,
// as a true difference may go either way).
struct GuardedTest {
  stats::WelchStatistic plain, guarded;
  double power_standard_error = 0;
};

GuardedTest guarded_welch(const stats::MeanEstimate& a, double n_a, const stats::MeanEstimate& b, double n_b) {
  GuardedTest g;
  g.plain = g.guarded = welch(a, b);
  g.power_standard_error = g.plain.standard_error;
  if (g.plain.standard_error == 0) return g;
  // Each side as the lower one: its variance floored; the floored term
  // carries the d.o.f. of the side it came from.
  const auto floored = [](const stats::MeanEstimate& low, double n_low, const stats::MeanEstimate& high,
                          double n_high) {
    const double floor = rare_event_variance_floor(high.variance_of_mean, high.dof, n_high, n_low);
    return floor > low.variance_of_mean ? stats::MeanEstimate{low.mean, floor, high.dof} : low;
  };
  const stats::MeanEstimate a_low = floored(a, n_a, b, n_b), b_low = floored(b, n_b, a, n_a);
  const stats::WelchStatistic wa = welch(a_low, b), wb = welch(a, b_low);
  g.power_standard_error = std::max(wa.standard_error, wb.standard_error);
  g.guarded = g.plain.difference < 0 ? wa : wb;
  return g;
}

// Records a held test (plain t rejects, the guarded one does not) when it is
// the channel's worst so far by |t|.
void note_held(ChannelComparison& cc, const std::string& what, const GuardedTest& g, double alpha) {
  if (!cc.worst_held.empty() && std::fabs(g.plain.statistic) <= std::fabs(cc.worst_held_t)) return;
  cc.worst_held = what;
  cc.worst_held_t = g.plain.statistic;
  cc.worst_held_guarded_t = g.guarded.statistic;
  cc.worst_held_threshold = critical_statistic(g.guarded.dof, alpha);
  // Both sides' samples × f scale the guarded t by √f (for a difference that
  // stays): f brings it to the noncentrality found with power kReportedPower.
  cc.worst_held_spp_factor = held_spp_factor(g.guarded.statistic, g.guarded.dof, alpha, stats::kReportedPower);
}

// The spp per render the rare-event guard takes for each side, and what it
// assumed (guard_spp, check_image.h).
void guard_spp(const CompareSide& a, const CompareSide& b, CompareResult& r) {
  const GuardSpp g = verify::guard_spp(a.images, b.images, "side A's", "side B's", "neither side's");
  r.guard_spp_a = g.a;
  r.guard_spp_b = g.b;
  r.guard_assumption = g.assumption;
}

void test_image_mean(const SideChannel& a, const SideChannel& b, int width, int height, double alpha,
                     ChannelComparison& cc) {
  const Region whole{0, 0, width, height};
  cc.mean_a = a.region(whole);
  cc.mean_b = b.region(whole);
  cc.alpha = alpha;
  const GuardedTest g = guarded_welch(cc.mean_a, a.samples(whole), cc.mean_b, b.samples(whole));
  cc.dof = g.plain.dof;
  cc.statistic = g.plain.statistic;
  cc.guarded_statistic = g.guarded.statistic;
  cc.threshold = critical_statistic(g.plain.dof, alpha);
  const bool plain_rejects = std::fabs(g.plain.statistic) > cc.threshold;
  const bool guarded_rejects = std::fabs(g.guarded.statistic) > critical_statistic(g.guarded.dof, alpha);
  cc.image_mean_pass = !(plain_rejects && guarded_rejects);
  cc.image_mean_held = plain_rejects && !guarded_rejects;
  if (cc.image_mean_held) note_held(cc, "image mean", g, alpha);
  PowerFactor power(alpha);
  cc.detectable_relative_difference = relative(power(cc.dof) * g.power_standard_error, cc.mean_b.mean);
}

void test_tiles(const SideChannel& a, const SideChannel& b, int width, int height, int tile, double alpha,
                ChannelComparison& cc, std::vector<double>& tile_t) {
  cc.tile_alpha = alpha;
  const double z = stats::normal_upper_quantile(alpha / 2);
  std::vector<double> relative_se, dofs, all_dofs;
  double worst_dof = kInf;
  for (int y0 = 0; y0 < height; y0 += tile)
    for (int x0 = 0; x0 < width; x0 += tile) {
      const Region r{x0, y0, std::min(x0 + tile, width), std::min(y0 + tile, height)};
      const stats::MeanEstimate ea = a.region(r), eb = b.region(r);
      const GuardedTest g = guarded_welch(ea, a.samples(r), eb, b.samples(r));
      const stats::WelchStatistic& w = g.plain;
      tile_t.push_back(w.statistic);
      ++cc.tiles;
      if (welch_rejects(w, alpha, z)) {
        if (welch_rejects(g.guarded, alpha, z)) {
          ++cc.tile_failures;
        } else {
          ++cc.tiles_held;
          note_held(cc, fmt::format("tile ({}, {})", x0, y0), g, alpha);
        }
      }
      if (w.standard_error > 0) all_dofs.push_back(w.dof);
      if (std::fabs(w.statistic) > std::fabs(cc.worst_tile_t) || cc.tiles == 1) {
        cc.worst_tile_t = w.statistic;
        cc.worst_tile_x = x0;
        cc.worst_tile_y = y0;
        worst_dof = w.standard_error > 0 ? w.dof : kInf;
      }
      if (eb.mean > 0 && w.standard_error > 0) {
        relative_se.push_back(g.power_standard_error / eb.mean);
        dofs.push_back(w.dof);
      }
    }
  PowerFactor power(alpha);
  cc.median_tile_detectable_relative_difference =
      relative_se.empty() ? 0 : power(stats::median(dofs)) * stats::median(relative_se);
  cc.tile_threshold = critical_statistic(all_dofs.empty() ? kInf : stats::median(all_dofs), alpha);
  cc.worst_tile_threshold = critical_statistic(worst_dof, alpha);
}

void test_pixels(const SideChannel& a, const SideChannel& b, size_t n, double alpha, ChannelComparison& cc,
                 std::vector<double>& pixel_t, double& median_threshold) {
  cc.pixel_alpha = alpha;
  const double z = stats::normal_upper_quantile(alpha / 2);
  std::vector<double> relative_se, dofs;
  pixel_t.assign(n, 0.0);
  bool first = true;
  double worst_dof = kInf;
  for (size_t i = 0; i < n; ++i) {
    const stats::MeanEstimate ea = a.pixel(i), eb = b.pixel(i);
    const GuardedTest g = guarded_welch(ea, a.samples(i), eb, b.samples(i));
    const stats::WelchStatistic& w = g.plain;
    pixel_t[i] = w.statistic;
    // Constant on each side at different values (a Bernoulli-like pixel
    // whose K renders all hit k and k' times): the spread says nothing of
    // the error, as with repeating values; the tile and image tests see it.
    const bool constant_apart = w.standard_error == 0 && w.statistic != 0;
    if (constant_apart || a.few_values(i) || b.few_values(i)) {
      ++cc.pixels_few_values;
      continue;
    }
    if (welch_rejects(w, alpha, z)) {
      if (welch_rejects(g.guarded, alpha, z)) {
        ++cc.pixel_failures;
      } else {
        ++cc.pixels_held;
        note_held(cc, "pixel " + pixel_name(i, a.width()), g, alpha);
      }
    }
    if (first || std::fabs(w.statistic) > std::fabs(cc.worst_pixel_t)) {
      first = false;
      cc.worst_pixel_t = w.statistic;
      cc.worst_pixel_x = int(i % size_t(a.width()));
      cc.worst_pixel_y = int(i / size_t(a.width()));
      worst_dof = w.standard_error > 0 ? w.dof : kInf;
    }
    if (eb.mean > 0 && w.standard_error > 0) {
      relative_se.push_back(g.power_standard_error / eb.mean);
      dofs.push_back(w.dof);
    }
  }
  PowerFactor power(alpha);
  const double median_dof = dofs.empty() ? kInf : stats::median(dofs);
  cc.median_pixel_detectable_relative_difference =
      relative_se.empty() ? 0 : power(median_dof) * stats::median(relative_se);
  median_threshold = critical_statistic(median_dof, alpha);
  cc.worst_pixel_threshold = critical_statistic(worst_dof, alpha);
}

void test_variance_ratio(const SideChannel& a, const SideChannel& b, size_t n, double alpha, ChannelComparison& cc) {
  cc.variance_alpha = alpha;
  cc.variance_threshold = stats::normal_upper_quantile(alpha / 2);
  double var_sum_a = 0, var_sum_b = 0;
  for (size_t i = 0; i < n; ++i) {
    const auto [ua, va] = a.render_variance(i);
    const auto [ub, vb] = b.render_variance(i);
    cc.sum_variance_a += ua;
    cc.sum_variance_b += ub;
    var_sum_a += va;
    var_sum_b += vb;
  }
  const double sa = cc.sum_variance_a, sb = cc.sum_variance_b;
  const double z_power = stats::normal_upper_quantile(1 - stats::kReportedPower);
  if (sa == 0 || sb == 0) {  // a side without any spread: equal only if both have none
    cc.variance_ratio = sa == sb ? 1 : (sb == 0 ? kInf : 0);
    cc.variance_statistic = sa == sb ? 0 : (sb == 0 ? kInf : -kInf);
    cc.detectable_variance_ratio = sa == sb ? 1 : kInf;
    cc.variance_pass = sa == sb;
    return;
  }
  cc.variance_ratio = sa / sb;
  cc.log_ratio_standard_error = std::sqrt(var_sum_a / (sa * sa) + var_sum_b / (sb * sb));
  cc.variance_statistic = std::log(cc.variance_ratio) / cc.log_ratio_standard_error;
  cc.detectable_variance_ratio = std::exp((cc.variance_threshold + z_power) * cc.log_ratio_standard_error);
  cc.variance_pass = std::fabs(cc.variance_statistic) <= cc.variance_threshold;
}

// Standard deviation of one render's image mean on a side (a furnace EXR is one render).
double render_spread(const stats::MeanEstimate& e, size_t renders) {
  return std::sqrt(e.variance_of_mean * double(renders));
}

// Smallest k renders per side at which the image-mean test of the two
// observed spreads would reach `target` (0: none up to kMaxAdvisedRenders).
int renders_needed(PowerFactor& power, double sd_a, double sd_b, double mean_b, double target) {
  const double var = sd_a * sd_a + sd_b * sd_b;
  const double fourth = std::pow(sd_a, 4) + std::pow(sd_b, 4);
  return smallest_sufficient_count(
      [&](int k) {
        const double dof = fourth > 0 ? var * var / fourth * double(k - 1) : kInf;
        return relative(power(dof) * std::sqrt(var / double(k)), mean_b) <= target;
      },
      kMaxAdvisedRenders);
}

void require_side(const CompareSide& side, const char* name) {
  if (side.images.empty()) throw Error(fmt::format("side {} has no images; give at least one --{}.", name, name));
  const ForeignImage& img = side.images[0];
  if (side.images.size() == 1 && !img.has_variance())
    throw Error(
        fmt::format("side {} has only image '{}', which has no variance and N channels; a side needs at least "
                    "two independent renders (different seeds) or one furnace EXR.",
                    name, img.path));
  if (side.images.size() == 1)
    for (size_t i = 0; i < img.count.size(); ++i)
      if (img.count[i] < 2)
        throw Error(
            fmt::format("image '{}' has N = {} samples at pixel {}; one image alone needs at least 2 per pixel "
                        "to estimate its variance.",
                        img.path, img.count[i], pixel_name(i, img.width)));
}

bool same_file(const std::string& a, const std::string& b) {
  std::error_code error;
  const bool same = std::filesystem::equivalent(a, b, error);
  return !error && same;
}

}  // namespace

std::string verdict_name(CompareVerdict v) {
  switch (v) {
    case CompareVerdict::kSame:
      return "SAME";
    case CompareVerdict::kDifferent:
      return "DIFFERENT";
    case CompareVerdict::kInconclusive:
      return "INCONCLUSIVE";
  }
  return "?";
}

int exit_code(CompareVerdict v) {
  switch (v) {
    case CompareVerdict::kSame:
      return 0;
    case CompareVerdict::kDifferent:
      return 1;
    case CompareVerdict::kInconclusive:
      return 3;
  }
  return 1;
}

void validate_compare_input(const CompareSide& a, const CompareSide& b) {
  require_side(a, "a");
  require_side(b, "b");
  std::vector<const ForeignImage*> all;
  for (const ForeignImage& img : a.images) all.push_back(&img);
  for (const ForeignImage& img : b.images) all.push_back(&img);
  const ForeignImage& first = *all[0];
  for (const ForeignImage* img : all) {
    if (img->width != first.width || img->height != first.height)
      throw Error(fmt::format("image '{}' is {}x{} pixels but '{}' is {}x{}; both sides must have one resolution.",
                              img->path, img->width, img->height, first.path, first.width, first.height));
    if (img->source_channels != first.source_channels)
      throw Error(
          fmt::format("image '{}' is tested from its channels {} but '{}' from {}; both sides must hold the "
                      "same channels.",
                      img->path, img->source_channels, first.path, first.source_channels));
  }
  for (const ForeignImage& x : a.images)
    for (const ForeignImage& y : b.images)
      if (same_file(x.path, y.path))
        throw Error(fmt::format("image '{}' is given on both sides{}; the sides must be independent renders.", x.path,
                                x.path == y.path ? std::string() : fmt::format(" (as '{}')", y.path)));
  for (size_t i = 0; i < all.size(); ++i)
    for (size_t j = i + 1; j < all.size(); ++j)
      if (all[i]->value == all[j]->value)
        throw Error(
            fmt::format("images '{}' and '{}' hold identical pixels; independent renders (different seeds) "
                        "are needed, and one render given twice has no spread.",
                        all[i]->path, all[j]->path));
}

CompareResult compare_renders(const CompareSide& a, const CompareSide& b, double alpha,
                              double max_detectable_difference, int tile_size, bool test_variance) {
  validate_compare_input(a, b);
  FURNACE_CHECK(tile_size >= 1);
  CompareResult r;
  const ForeignImage& first = a.images[0];
  r.images_a = int(a.images.size());
  r.images_b = int(b.images.size());
  r.negative_a = count_negative_values(a.images);
  r.negative_b = count_negative_values(b.images);
  r.half_float_a = any_half_float(a.images);
  r.half_float_b = any_half_float(b.images);
  r.width = first.width;
  r.height = first.height;
  r.tile_size = tile_size;
  r.method_a = a.furnace_variance() ? "furnace variance" : "K renders";
  r.method_b = b.furnace_variance() ? "furnace variance" : "K renders";
  r.alpha = alpha;
  r.max_detectable_difference = max_detectable_difference;
  const size_t channels = first.channels.size();
  const size_t n = size_t(r.width) * size_t(r.height);
  const size_t tiles = size_t((r.width + tile_size - 1) / tile_size) * size_t((r.height + tile_size - 1) / tile_size);
  r.families = test_variance ? kCompareFamilies : kCompareFamilies - 1;
  guard_spp(a, b, r);
  const double alpha_family = stats::sidak_alpha(alpha, size_t(r.families));
  const double alpha_mean = stats::sidak_alpha(alpha_family, channels);
  const double alpha_tile = stats::sidak_alpha(alpha_family, channels * tiles);
  const double alpha_pixel = stats::sidak_alpha(alpha_family, channels * n);
  const double alpha_variance = stats::sidak_alpha(alpha_family, channels);

  PowerFactor mean_power(alpha_mean);
  double advice_renders = 0, advice_factor = 0;
  bool advice_beyond = false;
  r.pixel_t.resize(channels);
  r.mean_a.assign(channels, std::vector<double>(n));
  r.mean_b.assign(channels, std::vector<double>(n));
  r.tile_t.resize(channels);
  r.tiles_x = (r.width + tile_size - 1) / tile_size;
  r.tiles_y = (r.height + tile_size - 1) / tile_size;
  r.pixel_threshold.resize(channels);
  bool mean_rejects = false, tile_rejects = false, pixel_rejects = false, variance_rejects = false;
  bool mean_held = false, tile_held = false, pixel_held = false;
  for (size_t c = 0; c < channels; ++c) {
    const SideChannel sa(a, c, r.guard_spp_a), sb(b, c, r.guard_spp_b);
    ChannelComparison cc;
    cc.channel = first.channels[c];
    test_image_mean(sa, sb, r.width, r.height, alpha_mean, cc);
    test_tiles(sa, sb, r.width, r.height, tile_size, alpha_tile, cc, r.tile_t[c]);
    for (size_t i = 0; i < n; ++i) {
      r.mean_a[c][i] = sa.pixel(i).mean;
      r.mean_b[c][i] = sb.pixel(i).mean;
    }
    test_pixels(sa, sb, n, alpha_pixel, cc, r.pixel_t[c], r.pixel_threshold[c]);
    if (test_variance)
      test_variance_ratio(sa, sb, n, alpha_variance, cc);
    else
      cc.variance_tested = false;
    mean_rejects = mean_rejects || !cc.image_mean_pass;
    tile_rejects = tile_rejects || cc.tile_failures > 0;
    pixel_rejects = pixel_rejects || cc.pixel_failures > 0;
    variance_rejects = variance_rejects || !cc.variance_pass;
    mean_held = mean_held || cc.image_mean_held;
    tile_held = tile_held || cc.tiles_held > 0;
    pixel_held = pixel_held || cc.pixels_held > 0;
    if (!(cc.detectable_relative_difference <= max_detectable_difference)) {
      const double sd_a = render_spread(cc.mean_a, a.images.size()), sd_b = render_spread(cc.mean_b, b.images.size());
      const int needed = renders_needed(mean_power, sd_a, sd_b, cc.mean_b.mean, max_detectable_difference);
      advice_beyond = advice_beyond || needed == 0;
      advice_renders = std::max(advice_renders, double(needed));
      const double factor = cc.detectable_relative_difference / max_detectable_difference;
      advice_factor = std::max(advice_factor, factor * factor);
    }
    r.detectable_relative_difference = std::max(r.detectable_relative_difference, cc.detectable_relative_difference);
    r.channels.push_back(cc);
  }
  if (mean_rejects) r.rejected.push_back("mean");
  if (tile_rejects) r.rejected.push_back("tiles");
  if (pixel_rejects) r.rejected.push_back("pixels");
  if (variance_rejects) r.rejected.push_back("variance");
  if (mean_held) r.held.push_back("mean");
  if (tile_held) r.held.push_back("tiles");
  if (pixel_held) r.held.push_back("pixels");
  r.image_mean_has_power = r.detectable_relative_difference <= max_detectable_difference;
  if (!r.image_mean_has_power) {
    r.advice.needed = true;
    r.advice.renders_per_side = advice_beyond ? 0 : int(advice_renders);
    r.advice.spp_factor = advice_factor;
    r.advice.current_spp_a = images_spp(a.images);
    r.advice.current_spp_b = images_spp(b.images);
  }
  r.verdict = !r.rejected.empty() ? CompareVerdict::kDifferent
              : (r.held.empty() && r.image_mean_has_power) ? CompareVerdict::kSame
                                                           : CompareVerdict::kInconclusive;
  return r;
}

}  // namespace furnace::verify
