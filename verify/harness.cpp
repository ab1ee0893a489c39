#include "verify/harness.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <fmt/format.h>

#include "analytic/reference.h"
#include "core/error.h"
#include "verify/statistics.h"

namespace furnace::verify {

std::vector<std::string> default_scene_paths() {
  const std::string dir = FURNACE_SCENE_DIR;
  return {dir + "/disk_occluder.json"};
}

Verdict run_case(const Case& c, double per_case_alpha) {
  const Scene scene = load_scene(c.scene_path);
  const std::vector<double> reference = analytic::reference_image(scene);
  const Image image = render(scene, c.options);
  FURNACE_CHECK(image.pixels.size() == reference.size());

  Verdict v;
  v.scene = scene.name;
  v.strategy = strategy_name(c.options.strategy);
  v.defect = defect_name(c.options.defect);
  v.spp = c.options.spp;
  v.pixels = int(reference.size());
  v.seconds = image.seconds;
  v.samples_per_second = double(v.pixels) * v.spp / image.seconds;
  v.nonfinite_samples = image.nonfinite_samples;

  // P pixel tests + 1 image-mean test share this case's α (Šidák).
  const size_t n_tests = reference.size() + 1;
  const double alpha_each = stats::sidak_alpha(per_case_alpha, n_tests);

  double sum_estimate = 0, sum_reference = 0, sum_variance_of_mean = 0, sum_sq_error = 0;
  std::vector<double> pixel_detectable;
  for (size_t i = 0; i < reference.size(); ++i) {
    const PixelMoments& m = image.pixels[i];
    const double variance = m.sample_variance();
    sum_estimate += m.mean;
    sum_reference += reference[i];
    sum_variance_of_mean += variance / double(m.count);
    sum_sq_error += (m.mean - reference[i]) * (m.mean - reference[i]);
    // Sample skewness G1 = (m3/n)/(m2/n)^1.5; undefined (and irrelevant) when s = 0.
    if (m.m2 > 0) {
      const double n = double(m.count);
      const double skewness = (m.m3 / n) / std::pow(m.m2 / n, 1.5);
      if (n < kCochranSkewnessFactor * skewness * skewness) {
        ++v.pixels_untested;
        continue;
      }
    }
    const stats::MeanTestResult t = stats::mean_test(m.count, m.mean, variance, reference[i], alpha_each);
    if (!t.pass) ++v.pixel_failures;
    const double badness = (!t.pass && t.zero_variance) ? HUGE_VAL : std::fabs(t.statistic);
    if (badness > v.worst_pixel_t || i == 0) {
      v.worst_pixel_t = badness;
      v.worst_px = int(i % size_t(image.width));
      v.worst_py = int(i / size_t(image.width));
      v.worst_pixel_mean = m.mean;
      v.worst_pixel_reference = reference[i];
      v.worst_pixel_sample_variance = variance;
    }
    if (reference[i] > 0 && std::isfinite(t.detectable_relative_bias))
      pixel_detectable.push_back(t.detectable_relative_bias);
  }
  const double p = double(reference.size());
  v.image_mean = sum_estimate / p;
  v.reference_mean = sum_reference / p;
  v.rmse = std::sqrt(sum_sq_error / p);
  const double image_se = std::sqrt(sum_variance_of_mean) / p;
  const stats::ZTestResult zt = stats::z_test(v.image_mean, v.reference_mean, image_se, alpha_each);
  v.z = zt.statistic;
  v.threshold = zt.threshold;
  v.detectable_rel_bias = zt.detectable_relative_bias;
  if (!pixel_detectable.empty()) {
    auto mid = pixel_detectable.begin() + pixel_detectable.size() / 2;
    std::nth_element(pixel_detectable.begin(), mid, pixel_detectable.end());
    v.median_pixel_detectable_rel_bias = *mid;
  }
  v.pass = zt.pass && v.pixel_failures == 0 && v.nonfinite_samples == 0;
  return v;
}

std::string format_table(const std::vector<Verdict>& verdicts, double family_alpha) {
  std::string out;
  out += fmt::format("family-wise alpha {} (Sidak over {} cases, each over its pixels + image mean); "
                     "detectable bias at power {}\n",
                     family_alpha, verdicts.size(), kReportedPower);
  out += fmt::format("{:<16} {:<20} {:>6} {:>12} {:>12} {:>8} {:>7} {:>10} {:>7} {:>10} {:>9} {:>8} {:>11}  {}\n", "scene",
                     "strategy", "spp", "mean", "reference", "z", "z crit", "px fail", "px skip", "detect", "px detect",
                     "time s", "Msamples/s", "verdict");
  for (const Verdict& v : verdicts) {
    std::string strategy = v.strategy;
    if (v.defect != "none") strategy += "+" + v.defect;
    out += fmt::format("{:<16} {:<20} {:>6} {:>12.6g} {:>12.6g} {:>8.3f} {:>7.2f} {:>5}/{:<4} {:>7} {:>9.3g}% {:>8.3g}% {:>8.3f} {:>11.3g}  {}\n",
                       v.scene, strategy, v.spp, v.image_mean, v.reference_mean, v.z, v.threshold,
                       v.pixel_failures, v.pixels, v.pixels_untested, 100 * v.detectable_rel_bias,
                       100 * v.median_pixel_detectable_rel_bias, v.seconds, v.samples_per_second / 1e6,
                       v.pass ? "pass" : "FAIL");
    if (!v.pass)
      out += fmt::format("    worst pixel ({}, {}): mean {:.6g}, reference {:.6g}, sample variance {:.3g}, |t| {:.3g}\n",
                         v.worst_px, v.worst_py, v.worst_pixel_mean, v.worst_pixel_reference,
                         v.worst_pixel_sample_variance, v.worst_pixel_t);
  }
  return out;
}

}  // namespace furnace::verify
