#include "verify/harness.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include "core/error.h"
#include "stats/pixel_tests.h"
#include "stats/statistics.h"

namespace furnace::verify {

namespace {

// The verdict of case c on its rendered `image` (c's render, or a shared
// render's image for c's strategy), against `reference`.
Verdict evaluate_case(const Case& c, const Scene& scene, const Image& image, const std::vector<double>& reference,
                      double per_case_alpha, AnalyticCache& analytic_values) {
  FURNACE_CHECK(image.pixels.size() == reference.size());

  Verdict v;
  v.scene = scene.name;
  v.strategy = case_label(c.options);
  v.defect = defect_name(c.options.defect);
  v.spp = c.options.spp;
  v.pixels = int(reference.size());
  v.seconds = image.seconds;
  v.samples_per_second = double(v.pixels) * v.spp / image.seconds;
  v.nonfinite_samples = image.nonfinite_samples;

  // Tested under an injected defect too: a defect that keeps the mean must be
  // caught here (DEFECT(mis_power_exponent_3)).
  // The exact variance per sample of every pixel, where modelled (empty
  // elsewhere): the mean tests use it at any spp (Bernstein's bound below the
  // reference, stats/pixel_tests.h), so a rare contribution a run missed
  // cannot fail them; the variance test needs kMinVarianceTestSamples.
  const std::vector<double> exact_variance = analytic_values.predicted_variance(c, scene, reference);
  v.exact_variance = !exact_variance.empty();
  // A test that cannot run at this spp is skipped and named, never failed.
  if (v.exact_variance && uint64_t(c.options.spp) < stats::kMinVarianceTestSamples)
    v.variance_skipped = fmt::format("{} samples per pixel, the variance test needs at least {}", c.options.spp,
                                     stats::kMinVarianceTestSamples);
  v.variance_tested = v.exact_variance && v.variance_skipped.empty();
  // P pixel tests + 1 image-mean test (+ 1 aggregate variance test when the
  // variance is modelled) share this case's α (Šidák).
  const size_t n_tests = reference.size() + 1 + (v.variance_tested ? 1 : 0);
  const double alpha_each = stats::sidak_alpha(per_case_alpha, n_tests);
  const bool zero_variance_case = stats::zero_variance_image(image.pixels);

  // Every pixel's variance test, for the aggregate and the outlier count.
  std::vector<stats::VarianceTestResult> pixel_variance_tests;
  if (v.variance_tested)
    for (size_t i = 0; i < reference.size(); ++i)
      pixel_variance_tests.push_back(stats::variance_test(image.pixels[i], exact_variance[i], alpha_each));

  std::vector<double> pixel_means, variances_of_mean, pixel_detectable;
  double sum_sq_error = 0;
  for (size_t i = 0; i < reference.size(); ++i) {
    const PixelMoments& m = image.pixels[i];
    pixel_means.push_back(m.mean);
    variances_of_mean.push_back(m.sample_variance() / double(m.count));
    sum_sq_error += (m.mean - reference[i]) * (m.mean - reference[i]);
    const stats::PixelTestResult pixel =
        stats::pixel_mean_test(m, reference[i], alpha_each, zero_variance_case, stats::kDefaultPower,
                               exact_variance.empty() ? -1.0 : exact_variance[i]);
    if (!pixel.tested()) {
      ++v.pixels_untested;
      continue;
    }
    const stats::MeanTestResult& t = pixel.test;
    // Per-pixel variance outliers are reported, not part of the verdict
    // (stats::aggregate_variance_test says why).
    if (v.variance_tested && !pixel_variance_tests[i].pass) ++v.variance_pixel_failures;
    if (!t.pass) ++v.pixel_failures;
    const double badness = (!t.pass && t.zero_variance) ? HUGE_VAL : std::fabs(t.statistic);
    if (badness > v.worst_pixel_t || i == 0) {
      v.worst_pixel_t = badness;
      v.worst_px = int(i % size_t(image.width));
      v.worst_py = int(i / size_t(image.width));
      v.worst_pixel_mean = m.mean;
      v.worst_pixel_reference = reference[i];
      v.worst_pixel_sample_variance = m.sample_variance();
    }
    if (reference[i] > 0 && std::isfinite(t.detectable_relative_bias))
      pixel_detectable.push_back(t.detectable_relative_bias);
  }
  const stats::ImageMeanTestResult image_test =
      stats::image_mean_test(pixel_means, variances_of_mean, reference, alpha_each, zero_variance_case,
                             stats::kDefaultPower, exact_variance, uint64_t(c.options.spp));
  v.image_mean = image_test.image_mean;
  v.reference_mean = image_test.reference_mean;
  v.rmse = std::sqrt(sum_sq_error / double(reference.size()));
  v.z = image_test.test.statistic;
  v.threshold = image_test.test.threshold;
  v.detectable_rel_bias = image_test.test.detectable_relative_bias;
  v.median_pixel_detectable_rel_bias = stats::median(std::move(pixel_detectable));
  bool variance_pass = true;
  if (v.variance_tested) {
    const stats::AggregateVarianceTestResult aggregate =
        stats::aggregate_variance_test(pixel_variance_tests, reference, alpha_each, zero_variance_case);
    v.measured_variance = aggregate.sum_sample_variance / double(reference.size());
    v.predicted_variance = aggregate.sum_predicted_variance / double(reference.size());
    v.variance_z = aggregate.statistic;
    v.variance_detectable_rel_error = aggregate.detectable_relative_error;
    variance_pass = aggregate.pass;
  }
  v.variance_pass = variance_pass;
  v.mean_pass = image_test.test.pass && v.pixel_failures == 0 && v.nonfinite_samples == 0;
  v.pass = v.mean_pass && variance_pass;
  if (!v.exact_variance && c.options.spp < min_calibrated_spp(c.options.strategy))
    v.calibrated_from_spp = min_calibrated_spp(c.options.strategy);
  return v;
}


// Whether cases a and b can take their images from one render: the same
// scene file and options but for strategies that share their samples
// (render_options.h's shares_samples), no ray log.
bool share_render(const Case& a, const Case& b) {
  const RenderOptions &x = a.options, &y = b.options;
  return a.scene_path == b.scene_path && shares_samples(x.strategy, y.strategy) && x.defect == y.defect &&
         x.light_selection == y.light_selection && x.spp == y.spp && x.seed == y.seed && x.threads == y.threads &&
         x.max_depth == y.max_depth && x.roulette_depth == y.roulette_depth && !x.ray_log && !y.ray_log;
}

}  // namespace

std::vector<Verdict> run_cases(const std::vector<Case>& cases, double per_case_alpha, int threads,
                               const std::function<void()>& case_done) {
  std::optional<tbb::global_control> limit;
  if (threads > 0) limit.emplace(tbb::global_control::max_allowed_parallelism, size_t(threads));
  AnalyticCache analytic_values;
  // Cases that can share one render (share_render), up to kMaxSharedStrategies
  // each, in case order: each group renders once (render_sharing_samples,
  // every image the one its case's own render gives, to the bit).
  std::vector<std::vector<size_t>> groups;
  for (size_t i = 0; i < cases.size(); ++i) {
    auto joins = [&](const std::vector<size_t>& g) {
      return g.size() < kMaxSharedStrategies && cases[g.front()].options.strategy != cases[i].options.strategy &&
             share_render(cases[g.front()], cases[i]);
    };
    auto it = std::find_if(groups.begin(), groups.end(), joins);
    if (it != groups.end()) it->push_back(i);
    else groups.push_back({i});
  }
  std::vector<Verdict> verdicts(cases.size());
  std::mutex done_mutex;
  // One group per task: TBB runs as many at once as it has workers and
  // splits each render's pixel loops among idle ones, so no core waits for a
  // case's serial steps (scene set-up, the statistics) or for the last pixels.
  tbb::parallel_for(tbb::blocked_range<size_t>(0, groups.size(), 1), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t g = r.begin(); g != r.end(); ++g) {
      const std::vector<size_t>& group = groups[g];
      const Case& first = cases[group.front()];
      const Scene scene = load_scene(first.scene_path);
      std::vector<Strategy> strategies;
      for (size_t i : group) strategies.push_back(cases[i].options.strategy);
      const std::vector<double>& reference = analytic_values.reference(first, scene);
      const std::vector<Image> images = render_sharing_samples(scene, first.options, strategies);
      for (size_t k = 0; k < group.size(); ++k) {
        verdicts[group[k]] = evaluate_case(cases[group[k]], scene, images[k], reference, per_case_alpha,
                                           analytic_values);
        if (case_done) {
          std::lock_guard<std::mutex> lock(done_mutex);
          case_done();
        }
      }
    }
  });
  return verdicts;
}

Verdict run_case(const Case& c, double per_case_alpha, AnalyticCache* cache) {
  AnalyticCache own;  // a cache for this case alone when the caller keeps none
  AnalyticCache& analytic_values = cache ? *cache : own;
  const Scene scene = load_scene(c.scene_path);
  const std::vector<double>& reference = analytic_values.reference(c, scene);
  return evaluate_case(c, scene, render(scene, c.options), reference, per_case_alpha, analytic_values);
}

VerdictKind verdict_kind(const Verdict& v) {
  if (!v.mean_pass)
    return v.nonfinite_samples == 0 && v.calibrated_from_spp > 0 ? VerdictKind::kInconclusive : VerdictKind::kBiased;
  if (!v.variance_pass) return VerdictKind::kVarianceMismatch;
  return VerdictKind::kPass;
}

RunOutcome run_outcome(const std::vector<Verdict>& verdicts) {
  bool inconclusive = false;
  for (const Verdict& v : verdicts) {
    const VerdictKind kind = verdict_kind(v);
    if (kind == VerdictKind::kBiased || kind == VerdictKind::kVarianceMismatch) return RunOutcome::kFail;
    inconclusive = inconclusive || kind == VerdictKind::kInconclusive;
  }
  return inconclusive ? RunOutcome::kInconclusive : RunOutcome::kPass;
}

const char* run_outcome_word(RunOutcome outcome) {
  switch (outcome) {
    case RunOutcome::kPass: return "PASS";
    case RunOutcome::kFail: return "FAIL";
    case RunOutcome::kInconclusive: return "INCONCLUSIVE";
  }
  return "FAIL";
}

std::string verdict_explanation(const Verdict& v) {
  const VerdictKind kind = verdict_kind(v);
  if (kind != VerdictKind::kInconclusive) return verdict_explanation(kind);
  return fmt::format("{} (rerun at {} spp or more)", verdict_explanation(kind), v.calibrated_from_spp);
}

std::string verdict_explanation(VerdictKind kind) {
  switch (kind) {
    case VerdictKind::kPass: return "pass";
    case VerdictKind::kBiased: return "biased: a mean test rejects the exact reference (or a sample was not finite)";
    case VerdictKind::kVarianceMismatch:
      return "unbiased, but variance differs from its model (not the estimator it claims to be)";
    case VerdictKind::kInconclusive:
      return "inconclusive: a mean test rejects, but this strategy's variance is not modelled here and its "
             "sample-variance tests are not calibrated at this spp (a rare contribution the run missed shrinks the "
             "sample variance)";
  }
  return "";
}

}  // namespace furnace::verify
