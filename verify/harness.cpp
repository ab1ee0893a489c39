#include "verify/harness.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include "analytic/global.h"
#include "analytic/moments.h"
#include "analytic/reference.h"
#include "core/error.h"
#include "stats/pixel_tests.h"
#include "stats/statistics.h"
#include "verify/resources.h"

namespace furnace::verify {

int min_calibrated_spp(Strategy strategy) {
  // `furnace sweep --strategy NAME --seeds 10 --spp N`, per-case α 0.05; a
  // case is in excess when it rejects significantly more often than α
  // (binomial p < 0.01: 4 or more of 10). A strategy's threshold is the
  // smallest spp measured (128, 256, 512) whose sweep, and every larger one,
  // had no case in excess; a strategy measured at 512 only keeps 512, the
  // level α was shown to hold at. Rejected runs per level are in the README.
  switch (strategy) {
    case Strategy::kUniformHemisphere: return 512;  // 256: three_lights 10/10
    case Strategy::kCosineHemisphere: return 128;   // 0/90 at 128, 256 and 512
    case Strategy::kLightArea: return 512;          // 256: point_and_area (power selection) 6/10
    case Strategy::kLightSolidAngle: return 256;    // 128: sphere_occluder 4/10, polygon_occluder 5/10
    case Strategy::kBsdf: return 128;               // at most 1/110 at 128, 256 and 512
    case Strategy::kMisBalance: return 512;         // 256: rectangle_light 8/10
    case Strategy::kMisPower: return 512;           // measured at 512 only (3/200), as mis_balance
    case Strategy::kMisOneSample: return 512;       // measured at 512 only (3/200), as mis_balance
    case Strategy::kPathNaive: return 128;          // at most 2/130 at 128, 256 and 512
    case Strategy::kPathMis: return 256;            // 128: polygon_occluder 5/10
  }
  return 512;  // unreachable: the switch names every strategy
}

int lowest_min_calibrated_spp() {
  int lowest = std::numeric_limits<int>::max();
  for (const StrategyInfo& info : kStrategyTable) lowest = std::min(lowest, min_calibrated_spp(info.strategy));
  return lowest;
}

int highest_min_calibrated_spp() {
  int highest = 0;
  for (const StrategyInfo& info : kStrategyTable) highest = std::max(highest, min_calibrated_spp(info.strategy));
  return highest;
}

std::string low_spp_warning(const std::vector<Case>& cases) {
  // Each strategy once, in table order, at its smallest case spp.
  std::vector<std::string> below;
  int smallest_spp = std::numeric_limits<int>::max();
  for (const StrategyInfo& info : kStrategyTable) {
    int spp = std::numeric_limits<int>::max();
    for (const Case& c : cases)
      if (c.options.strategy == info.strategy) spp = std::min(spp, c.options.spp);
    if (spp >= min_calibrated_spp(info.strategy)) continue;
    below.push_back(fmt::format("{} ({})", info.name, min_calibrated_spp(info.strategy)));
    smallest_spp = std::min(smallest_spp, spp);
  }
  if (below.empty()) return "";
  return fmt::format("{} spp is below the smallest spp at which the suite's false-alarm rate was measured to stay "
                     "within alpha for {}; correct cases may fail more often than alpha says.",
                     smallest_spp, fmt::join(below, ", "));
}

// Relative round-off of E[Y²] − E² (each a short sum of double products):
// a predicted variance below this fraction of E² is taken as exactly 0.
constexpr double kPredictedVarianceRoundOff = 64 * std::numeric_limits<double>::epsilon();


namespace {

// Calls per_pixel(i) for every pixel index i < n on `threads` workers (0: all).
// The analytic per-pixel values are pure functions of the pixel, each written
// to its own slot, so the result does not depend on the thread count; an
// exception from any pixel propagates (TBB rethrows it).
template <class PerPixel>
void for_each_pixel(size_t n, int threads, PerPixel per_pixel) {
  std::optional<tbb::global_control> limit;
  if (threads > 0) limit.emplace(tbb::global_control::max_allowed_parallelism, size_t(threads));
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) per_pixel(i);
  });
}

}  // namespace

std::vector<double> reference_for(const Scene& scene, const RenderOptions& options) {
  std::vector<double> reference;
  if (is_path_tracer(options.strategy)) {
    reference = analytic::global_reference_image(scene, options.max_depth);
  } else {
    // analytic::reference_image's pixels, computed in parallel.
    const size_t width = size_t(scene.camera.width_px);
    reference.resize(width * size_t(scene.camera.height_px));
    for_each_pixel(reference.size(), options.threads, [&](size_t i) {
      reference[i] = analytic::pixel_center_radiance(scene, int(i % width), int(i / width));
    });
  }
  require_finite_reference(reference, scene);
  return reference;
}

void require_finite_reference(const std::vector<double>& reference, const Scene& scene) {
  const size_t width = size_t(std::max(scene.camera.width_px, 1));
  for (size_t i = 0; i < reference.size(); ++i)
    if (!std::isfinite(reference[i]))
      throw Error(fmt::format("scene file '{}': the exact reference of pixel ({}, {}) is {}, not a finite number (an "
                              "emission, radiance or intensity too large for double precision).",
                              scene.source, i % width, i / width, reference[i]));
}

std::vector<Case> default_suite(int spp, uint64_t seed, int threads) {
  struct Entry {
    const char* scene;
    std::vector<Strategy> strategies;
    int max_depth;
    LightSelection selection = LightSelection::kUniform;
  };
  std::vector<Strategy> direct = direct_strategies();
  std::vector<Strategy> paths = path_tracing_strategies();
  std::vector<Strategy> everything = direct;
  everything.insert(everything.end(), paths.begin(), paths.end());
  // Scenes with point lights: only the strategies that sample lights see them.
  // The same set on the environment maps: their 100× sun makes the hemisphere
  // strategies too skewed for per-pixel tests at 4096 spp (Cochran's rule
  // leaves ~95 % of pixels untested); tests/integration/environment_map_test.cpp
  // runs those at 16384 spp.
  std::vector<Strategy> delta_aware;
  for (Strategy s : everything)
    if (strategy_sees_delta_lights(s)) delta_aware.push_back(s);
  // Glossy receivers (Phong n = 10 and 100): the strategies whose estimate
  // involves the lobe's value (hemisphere sampling adds only power-less rows;
  // under the constant sky light_area samples exactly like light_solid_angle).
  const std::vector<Strategy> glossy_sphere = {Strategy::kLightArea, Strategy::kLightSolidAngle, Strategy::kBsdf,
                                               Strategy::kMisBalance, Strategy::kMisPower, Strategy::kMisOneSample};
  const std::vector<Strategy> glossy_sky = {Strategy::kLightSolidAngle, Strategy::kBsdf, Strategy::kMisBalance,
                                            Strategy::kMisPower, Strategy::kMisOneSample};
  const std::vector<Entry> entries = {
      {"disk_occluder.json", everything, kUnlimitedDepth},
      {"sphere_light.json", direct, kUnlimitedDepth},
      {"sphere_occluder.json", direct, kUnlimitedDepth},
      {"rectangle_light.json", direct, kUnlimitedDepth},
      {"environment_blocker.json", direct, kUnlimitedDepth},
      {"three_lights.json", everything, kUnlimitedDepth},
      {"three_lights.json", delta_aware, kUnlimitedDepth, LightSelection::kPower},
      {"polygon_occluder.json", everything, kUnlimitedDepth},
      {"environment_map.json", delta_aware, kUnlimitedDepth},
      {"environment_map_tilted.json", delta_aware, kUnlimitedDepth},
      {"point_light.json", delta_aware, kUnlimitedDepth},
      {"point_light_unoccluded.json", delta_aware, kUnlimitedDepth},
      {"point_and_area.json", delta_aware, kUnlimitedDepth},
      {"point_and_area.json", delta_aware, kUnlimitedDepth, LightSelection::kPower},
      {"white_furnace.json", paths, kUnlimitedDepth},
      {"convex_furnace.json", paths, kUnlimitedDepth},
      {"enclosure_box.json", paths, kUnlimitedDepth},
      {"enclosure_box.json", paths, 4},
      {"enclosure_box_rho5.json", paths, kUnlimitedDepth},
      {"enclosure_sphere.json", paths, kUnlimitedDepth},
      {"enclosure_blockers.json", paths, kUnlimitedDepth},
      {"mirror_disk.json", paths, kUnlimitedDepth},
      {"glossy_sphere_light.json", glossy_sphere, kUnlimitedDepth},
      {"glossy_environment.json", glossy_sky, kUnlimitedDepth},
      // Hard cases, each there for one bug class (README, "The built-in suite").
      // Receivers and camera rays that see the backs of one-sided lights.
      {"back_facing_emitters.json", everything, kUnlimitedDepth},
      // Occluders and lights 1e-5 … 1e-3 above the receiver (camera below them).
      {"near_contact.json", everything, kUnlimitedDepth},
      // Receivers within ~3° of the planes of a disk and a rectangle light:
      // those lights subtend too little for hemisphere sampling to find them.
      {"grazing_emitters.json", delta_aware, kUnlimitedDepth},
      // Lights of 1e-8 … 1e-6 sr: only light sampling ever finds them.
      {"tiny_lights.json", delta_aware, kUnlimitedDepth},
  };
  std::vector<Case> cases;
  for (const Entry& e : entries) {
    for (Strategy s : e.strategies) {
      Case c;
      c.scene_path = scene_dir() + "/" + e.scene;
      c.options.strategy = s;
      c.options.spp = spp;
      c.options.seed = seed;
      c.options.threads = threads;
      c.options.max_depth = e.max_depth;
      c.options.light_selection = e.selection;
      cases.push_back(c);
    }
  }
  return cases;
}

namespace {

// The keys under which AnalyticCache keeps a scene file's values.
std::string reference_key(const Case& c) {
  return is_path_tracer(c.options.strategy) ? fmt::format("{}|path|{}", c.scene_path, c.options.max_depth)
                                            : c.scene_path + "|direct";
}
std::string variance_key(const Case& c) {
  return fmt::format("{}|{}|{}", c.scene_path, strategy_name(c.options.strategy),
                     c.options.light_selection == LightSelection::kPower ? "power" : "uniform");
}

// Predicted per-pixel variances E[Y²] − E² of N estimators, `second_moments(px,
// py)` giving their N second moments at a pixel centre; all N empty when
// analytic/ does not solve this scene's second moments.
template <size_t N, class SecondMoments>
std::array<std::vector<double>, N> compute_variances(const Case& c, const Scene& scene,
                                                     const std::vector<double>& reference,
                                                     SecondMoments second_moments) {
  std::array<std::vector<double>, N> variances;
  try {
    for (auto& v : variances) v.resize(reference.size());
    const size_t width = size_t(scene.camera.width_px);
    for_each_pixel(reference.size(), c.options.threads, [&](size_t i) {
      const std::array<double, N> m2 = second_moments(int(i % width), int(i / width));
      const double e2 = reference[i] * reference[i];
      // An exact estimator (a lone point light) has E[Y²] = E², computed
      // along two double paths: a difference within round-off is zero.
      for (size_t k = 0; k < N; ++k) variances[k][i] = m2[k] - e2 <= kPredictedVarianceRoundOff * e2 ? 0.0 : m2[k] - e2;
    });
  } catch (const Error&) {
    for (auto& v : variances) v.clear();  // not modelled for this scene: mean tests only
  }
  return variances;
}

// Predicted per-pixel variances, when the strategy has an analytic model and
// analytic/ solves this scene's second moments; empty otherwise.
std::vector<double> compute_predicted_variance(const Case& c, const Scene& scene,
                                               const std::vector<double>& reference) {
  if (!has_variance_model(c.options.strategy)) return {};
  return std::move(compute_variances<1>(c, scene, reference, [&](int px, int py) {
    return std::array<double, 1>{
        analytic::pixel_center_second_moment(c.options.strategy, scene, px, py, c.options.light_selection)};
  })[0]);
}

// Whether c's strategy is one of the multi-sample MIS pair whose variances
// analytic/ computes together (pixel_center_multi_sample_mis_second_moments).
bool multi_sample_mis(const Case& c) {
  return c.options.strategy == Strategy::kMisBalance || c.options.strategy == Strategy::kMisPower;
}

// compute_predicted_variance of mis_balance and of mis_power for c's scene and
// light selection ({balance, power}), from one quadrature per pixel; each
// equal to the bit to compute_predicted_variance of that strategy.
std::array<std::vector<double>, 2> compute_multi_sample_mis_variances(const Case& c, const Scene& scene,
                                                                     const std::vector<double>& reference) {
  return compute_variances<2>(c, scene, reference, [&](int px, int py) {
    return analytic::pixel_center_multi_sample_mis_second_moments(scene, px, py, c.options.light_selection);
  });
}

}  // namespace

// The value of `key` in `map`, computed by `compute` (outside the lock) when absent.
template <class Compute>
const std::vector<double>& find_or_compute(std::mutex& mutex, std::map<std::string, std::vector<double>>& map,
                                           const std::string& key, Compute compute) {
  {
    std::lock_guard<std::mutex> lock(mutex);
    if (auto it = map.find(key); it != map.end()) return it->second;
  }
  std::vector<double> value = compute();
  std::lock_guard<std::mutex> lock(mutex);
  return map.emplace(key, std::move(value)).first->second;  // keeps an equal value stored meanwhile
}

const std::vector<double>& AnalyticCache::reference(const Case& c, const Scene& scene) {
  return find_or_compute(mutex_, references_, reference_key(c), [&] { return reference_for(scene, c.options); });
}

const std::vector<double>& AnalyticCache::predicted_variance(const Case& c, const Scene& scene,
                                                             const std::vector<double>& reference) {
  if (!multi_sample_mis(c))
    return find_or_compute(mutex_, variances_, variance_key(c),
                           [&] { return compute_predicted_variance(c, scene, reference); });
  // mis_balance and mis_power: both computed together, the twin stored too.
  return find_or_compute(mutex_, variances_, variance_key(c), [&] {
    std::array<std::vector<double>, 2> pair = compute_multi_sample_mis_variances(c, scene, reference);
    const size_t own = c.options.strategy == Strategy::kMisPower ? 1 : 0;
    Case twin = c;
    twin.options.strategy = own == 1 ? Strategy::kMisBalance : Strategy::kMisPower;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      variances_.emplace(variance_key(twin), std::move(pair[1 - own]));  // keeps an equal value stored meanwhile
    }
    return std::move(pair[own]);
  });
}

namespace {

// The verdict of case c on its rendered `image` (c's render, or a shared
// render's image for c's strategy), against `reference`.
Verdict evaluate_case(const Case& c, const Scene& scene, const Image& image, const std::vector<double>& reference,
                      double per_case_alpha, AnalyticCache& analytic_values) {
  FURNACE_CHECK(image.pixels.size() == reference.size());

  Verdict v;
  v.scene = scene.name;
  v.strategy = strategy_name(c.options.strategy);
  if (is_path_tracer(c.options.strategy))
    v.strategy += c.options.max_depth == kUnlimitedDepth ? "/inf" : "/d" + std::to_string(c.options.max_depth);
  if (c.options.light_selection == LightSelection::kPower) v.strategy += "@power";
  v.defect = defect_name(c.options.defect);
  v.spp = c.options.spp;
  v.pixels = int(reference.size());
  v.seconds = image.seconds;
  v.samples_per_second = double(v.pixels) * v.spp / image.seconds;
  v.nonfinite_samples = image.nonfinite_samples;

  // Tested under an injected defect too: a defect that keeps the mean must be
  // caught here (DEFECT(mis_power_exponent_3)).
  std::vector<double> predicted_variance = analytic_values.predicted_variance(c, scene, reference);
  // A test that cannot run at this spp is skipped and named, never failed.
  if (!predicted_variance.empty() && uint64_t(c.options.spp) < stats::kMinVarianceTestSamples) {
    v.variance_skipped = fmt::format("{} samples per pixel, the variance test needs at least {}", c.options.spp,
                                     stats::kMinVarianceTestSamples);
    predicted_variance.clear();
  }
  v.variance_tested = !predicted_variance.empty();
  // P pixel tests + 1 image-mean test (+ 1 aggregate variance test when the
  // variance is modelled) share this case's α (Šidák).
  const size_t n_tests = reference.size() + 1 + (v.variance_tested ? 1 : 0);
  const double alpha_each = stats::sidak_alpha(per_case_alpha, n_tests);
  const bool zero_variance_case = stats::zero_variance_image(image.pixels);

  // Every pixel's variance test, for the aggregate and the outlier count.
  std::vector<stats::VarianceTestResult> pixel_variance_tests;
  if (v.variance_tested)
    for (size_t i = 0; i < reference.size(); ++i)
      pixel_variance_tests.push_back(stats::variance_test(image.pixels[i], predicted_variance[i], alpha_each));

  std::vector<double> pixel_means, variances_of_mean, pixel_detectable;
  double sum_sq_error = 0;
  for (size_t i = 0; i < reference.size(); ++i) {
    const PixelMoments& m = image.pixels[i];
    pixel_means.push_back(m.mean);
    variances_of_mean.push_back(m.sample_variance() / double(m.count));
    sum_sq_error += (m.mean - reference[i]) * (m.mean - reference[i]);
    const stats::PixelTestResult pixel = stats::pixel_mean_test(m, reference[i], alpha_each, zero_variance_case);
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
      stats::image_mean_test(pixel_means, variances_of_mean, reference, alpha_each, zero_variance_case);
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
  return v;
}


// Whether cases a and b can take their images from one render: the same
// scene file and options but for strategies that share their samples
// (render.h's shares_samples), no ray log.
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
  if (!v.mean_pass) return VerdictKind::kBiased;
  if (!v.variance_pass) return VerdictKind::kVarianceMismatch;
  return VerdictKind::kPass;
}

std::string verdict_explanation(VerdictKind kind) {
  switch (kind) {
    case VerdictKind::kPass: return "pass";
    case VerdictKind::kBiased: return "biased: a mean test rejects the exact reference (or a sample was not finite)";
    case VerdictKind::kVarianceMismatch:
      return "unbiased, but variance differs from its model (not the estimator it claims to be)";
  }
  return "";
}

const char* verdict_label(VerdictKind kind) {
  switch (kind) {
    case VerdictKind::kPass: return "pass";
    case VerdictKind::kBiased: return "FAIL biased";
    case VerdictKind::kVarianceMismatch: return "FAIL variance";
  }
  return "";
}

std::string strategy_label(const Verdict& v) { return v.defect == "none" ? v.strategy : v.strategy + "+" + v.defect; }

std::string variance_detect_cell(const Verdict& v) {
  if (!v.variance_tested) return "-";
  return std::isfinite(v.variance_detectable_rel_error) ? fmt::format("{:.3g}%", 100 * v.variance_detectable_rel_error)
                                                         : std::string("exact");
}

std::vector<const Verdict*> weakest_cases(const std::vector<Verdict>& verdicts, double Verdict::*detect,
                                          bool (*applies)(const Verdict&), size_t count) {
  std::vector<const Verdict*> cases;
  for (const Verdict& v : verdicts)
    if (applies(v) && std::isfinite(v.*detect)) cases.push_back(&v);
  std::stable_sort(cases.begin(), cases.end(),
                   [&](const Verdict* a, const Verdict* b) { return a->*detect > b->*detect; });
  cases.resize(std::min(count, cases.size()));
  return cases;
}

namespace {

// "a 1.2%, b 0.9%, …", or "none".
std::string weakest(const std::vector<Verdict>& verdicts, double Verdict::*detect, bool (*applies)(const Verdict&),
                    size_t count) {
  std::string out;
  for (const Verdict* v : weakest_cases(verdicts, detect, applies, count))
    out += fmt::format("{}{} {} {:.3g}%", out.empty() ? "" : ", ", v->scene, strategy_label(*v), 100 * (v->*detect));
  return out.empty() ? "none" : out;
}

}  // namespace

std::string format_table(const std::vector<Verdict>& verdicts, double family_alpha) {
  std::string out;
  out += fmt::format("family-wise alpha {} (Sidak over {} cases, each over its pixels + image mean); "
                     "detectable bias and variance error at power {}\n",
                     family_alpha, verdicts.size(), kReportedPower);
  out += fmt::format("{:<22} {:<24} {:>6} {:>10} {:>10} {:>7} {:>6} {:>9} {:>7} {:>9} {:>9} {:>9} {:>10} {:>7} {:>10}  {}\n",
                     "scene", "strategy", "spp", "mean", "reference", "z", "z crit", "px fail", "px skip", "rel RMSE",
                     "detect", "px detect", "var detect", "time s", "Msamples/s", "verdict");
  for (const Verdict& v : verdicts) {
    const std::string strategy = strategy_label(v);
    const VerdictKind kind = verdict_kind(v);
    const std::string variance_detect = variance_detect_cell(v);
    out += fmt::format("{:<22} {:<24} {:>6} {:>10.6g} {:>10.6g} {:>7.3f} {:>6.2f} {:>4}/{:<4} {:>7} {:>9.3g} {:>8.3g}% {:>8.3g}% {:>10} {:>7.3f} {:>10.3g}  {}\n",
                       v.scene, strategy, v.spp, v.image_mean, v.reference_mean, v.z, v.threshold,
                       v.pixel_failures, v.pixels, v.pixels_untested,
                       v.reference_mean > 0 ? v.rmse / v.reference_mean : v.rmse, 100 * v.detectable_rel_bias,
                       100 * v.median_pixel_detectable_rel_bias, variance_detect, v.seconds,
                       v.samples_per_second / 1e6, verdict_label(kind));
    if (v.variance_tested)
      out += fmt::format("    variance: measured {:.6g}, predicted {:.6g} (mean per pixel), z {:.3f}, {} pixel outliers (not in verdict), "
                         "detectable {:.3g}%\n",
                         v.measured_variance, v.predicted_variance, v.variance_z, v.variance_pixel_failures,
                         100 * v.variance_detectable_rel_error);
    if (!v.variance_skipped.empty()) out += fmt::format("    variance: skipped ({})\n", v.variance_skipped);
    if (v.nonfinite_samples > 0)
      out += fmt::format("    non-finite samples: {} (NaN or Inf, dropped from the image): the case fails\n",
                         v.nonfinite_samples);
    if (kind != VerdictKind::kPass) out += fmt::format("    {}\n", verdict_explanation(kind));
    if (kind == VerdictKind::kBiased)
      out += fmt::format("    worst pixel ({}, {}): mean {:.6g}, reference {:.6g}, sample variance {:.3g}, |t| {:.3g}\n",
                         v.worst_px, v.worst_py, v.worst_pixel_mean, v.worst_pixel_reference,
                         v.worst_pixel_sample_variance, v.worst_pixel_t);
  }
  const auto skipped = std::count_if(verdicts.begin(), verdicts.end(),
                                     [](const Verdict& v) { return !v.variance_skipped.empty(); });
  if (skipped > 0)
    out += fmt::format("skipped: the variance test of {} case(s), fewer than {} samples per pixel (the verdicts rest "
                       "on the mean tests)\n",
                       skipped, stats::kMinVarianceTestSamples);
  out += fmt::format("weakest mean tests (detect): {}\n",
                     weakest(verdicts, &Verdict::detectable_rel_bias, [](const Verdict&) { return true; },
                             kWeakestCasesListed));
  out += fmt::format("weakest variance tests (var detect): {}\n",
                     weakest(verdicts, &Verdict::variance_detectable_rel_error,
                             [](const Verdict& v) { return v.variance_tested; }, kWeakestCasesListed));
  return out;
}

}  // namespace furnace::verify
