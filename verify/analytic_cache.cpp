#include "verify/analytic_cache.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include "analytic/glass.h"
#include "analytic/global.h"
#include "analytic/moments.h"
#include "analytic/reference.h"
#include "core/error.h"

namespace furnace::verify {

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
    reference = analytic::global_reference_image(scene, options.max_depth, options.convention);
  } else if (analytic::has_dielectric(scene)) {
    // Glass: the direct-lighting reference of glass.h, in the run's convention.
    reference = analytic::glass_reference_image(scene, 2, options.convention, true);
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

namespace {

// The keys under which AnalyticCache keeps a scene file's values.
std::string reference_key(const Case& c) {
  const std::string convention = transport_convention_name(c.options.convention);
  return is_path_tracer(c.options.strategy)
             ? fmt::format("{}|path|{}|{}", c.scene_path, c.options.max_depth, convention)
             : fmt::format("{}|direct|{}", c.scene_path, convention);
}
std::string variance_key(const Case& c) {
  return fmt::format("{}|{}|{}|{}", c.scene_path, strategy_name(c.options.strategy),
                     c.options.light_selection == LightSelection::kPower ? "power" : "uniform",
                     transport_convention_name(c.options.convention));
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
  if (analytic::has_dielectric(scene)) {
    // Glass (glass.h): the whole image at once, or mean tests only where it is not modelled.
    try {
      std::vector<double> v = analytic::glass_second_moment_image(scene, c.options.strategy, c.options.convention,
                                                                  c.options.light_selection);
      for (size_t i = 0; i < v.size(); ++i) {
        const double e2 = reference[i] * reference[i];
        v[i] = v[i] - e2 <= kPredictedVarianceRoundOff * e2 ? 0.0 : v[i] - e2;
      }
      return v;
    } catch (const Error&) {
      return {};
    }
  }
  return std::move(compute_variances<1>(c, scene, reference, [&](int px, int py) {
    return std::array<double, 1>{
        analytic::pixel_center_second_moment(c.options.strategy, scene, px, py, c.options.light_selection)};
  })[0]);
}

// The multi-sample MIS strategies (core/strategy.h), whose variances
// analytic/ computes together (pixel_center_multi_sample_mis_second_moments
// returns one second moment per strategy, in table order).
constexpr size_t kMultiSampleMis = multi_sample_mis_count();
static_assert(kMultiSampleMis == 2,
              "analytic::pixel_center_multi_sample_mis_second_moments gives one moment per multi-sample MIS strategy");

// compute_predicted_variance of every multi-sample MIS strategy for c's scene
// and light selection (in table order), from one quadrature per pixel; each
// equal to the bit to compute_predicted_variance of that strategy.
std::array<std::vector<double>, kMultiSampleMis> compute_multi_sample_mis_variances(
    const Case& c, const Scene& scene, const std::vector<double>& reference) {
  if (analytic::has_dielectric(scene)) {
    // Glass: each strategy's whole image (glass.h), the same values compute_predicted_variance gives.
    std::array<std::vector<double>, kMultiSampleMis> all;
    const std::vector<Strategy> strategies = multi_sample_mis_strategies();
    for (size_t k = 0; k < kMultiSampleMis; ++k) {
      Case one = c;
      one.options.strategy = strategies[k];
      all[k] = compute_predicted_variance(one, scene, reference);
    }
    return all;
  }
  return compute_variances<kMultiSampleMis>(c, scene, reference, [&](int px, int py) {
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
  if (!is_multi_sample_mis(c.options.strategy))
    return find_or_compute(mutex_, variances_, variance_key(c),
                           [&] { return compute_predicted_variance(c, scene, reference); });
  // The multi-sample MIS strategies: all computed together, the others stored too.
  return find_or_compute(mutex_, variances_, variance_key(c), [&] {
    std::array<std::vector<double>, kMultiSampleMis> all = compute_multi_sample_mis_variances(c, scene, reference);
    const std::vector<Strategy> strategies = multi_sample_mis_strategies();
    const size_t own = size_t(std::find(strategies.begin(), strategies.end(), c.options.strategy) - strategies.begin());
    for (size_t k = 0; k < kMultiSampleMis; ++k) {
      if (k == own) continue;
      Case twin = c;
      twin.options.strategy = strategies[k];
      std::lock_guard<std::mutex> lock(mutex_);
      variances_.emplace(variance_key(twin), std::move(all[k]));  // keeps an equal value stored meanwhile
    }
    return std::move(all[own]);
  });
}

}  // namespace furnace::verify
