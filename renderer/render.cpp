// render(): the per-pixel driver. Every pixel accumulates its samples in
// sample order from its own random streams, so the image does not depend on
// the thread count or the schedule.
#include "renderer/render.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>
#include <variant>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include "core/error.h"
#include "core/path_length.h"
#include "renderer/direct_strategies.h"
#include "renderer/embree_scene.h"
#include "renderer/lights.h"
#include "renderer/path_tracer.h"
#include "renderer/rng.h"

namespace furnace {

namespace {

// Smallest TBB task, in pixels: one pixel already holds spp samples of work, so
// the auto partitioner may split down to single pixels (tiny test images too).
constexpr size_t kPixelGrain = 1;

// The streams of samples first … first + kRayPacket − 1 of a pixel.
template <size_t... I>
std::array<Rng, sizeof...(I)> streams(uint64_t pixel_key, uint64_t first, std::index_sequence<I...>) {
  return {Rng::for_sample(pixel_key, first + I)...};
}
std::array<Rng, kRayPacket> streams(uint64_t pixel_key, uint64_t first) {
  return streams(pixel_key, first, std::make_index_sequence<kRayPacket>{});
}

}  // namespace

Image render(const Scene& scene, const RenderOptions& options) {
  return std::move(render_sharing_samples(scene, options, {options.strategy}).front());
}

std::vector<Image> render_sharing_samples(const Scene& scene, const RenderOptions& options_in,
                                          const std::vector<Strategy>& strategies) {
  if (strategies.empty()) throw Error("render_sharing_samples needs at least one strategy.");
  RenderOptions options = options_in;
  options.strategy = strategies.front();
  // DEFECT(back_face_emits): every planar emitter taken as two-sided, so a
  // one-sided light also emits from its back. (A sphere's back is its inside,
  // which no point outside it sees: spheres are left as they are.)
  if (options.defect == Defect::kBackFaceEmits) {
    Scene both_sides = scene;
    for (Object& o : both_sides.objects)
      if (o.is_emitter() && is_planar(o.shape)) o.two_sided = true;
    RenderOptions rest = options;
    rest.defect = Defect::kNone;
    return render_sharing_samples(both_sides, rest, strategies);
  }
  const auto start = std::chrono::steady_clock::now();
  if (options.spp < 1) throw Error(fmt::format("render option spp must be at least 1, got {}.", options.spp));
  if (options.threads < 0)
    throw Error(fmt::format("render option threads must be 0 (all) or positive, got {}.", options.threads));
  if (options.max_depth < 1)
    throw Error(fmt::format("render option max_depth must be at least 1, got {}.", options.max_depth));

  // load_scene() bounds the pixel count (scene_limits::kMaxPixels); a scene
  // built in code is held to the same memory budget before allocating.
  if (scene.camera.width_px < 1 || scene.camera.height_px < 1 ||
      uint64_t(scene.camera.width_px) * uint64_t(scene.camera.height_px) > scene_limits::kMaxPixels)
    throw Error(fmt::format("scene '{}': camera resolution {}x{} is outside [1, {}] pixels (the {} GiB budget at {} "
                            "bytes per pixel).", scene.source.empty() ? scene.name : scene.source, scene.camera.width_px,
                            scene.camera.height_px, scene_limits::kMaxPixels, scene_limits::kPixelMemoryBudget >> 30,
                            scene_limits::kBytesPerPixel));

  // Thread count via TBB, never via the Embree device config (a device
  // created with threads=1 would limit TBB for the whole process).
  std::optional<tbb::global_control> thread_limit;
  if (options.threads > 0) thread_limit.emplace(tbb::global_control::max_allowed_parallelism, size_t(options.threads));

  if (options.ray_log && options.threads != 1)
    throw Error(fmt::format("render option ray_log needs threads = 1 (one ordered log), got threads = {}.",
                            options.threads));

  const EmbreeDevice device;
  EmbreeScene rtc_scene(device, scene);
  rtc_scene.record_rays(options.ray_log);
  const LightSet lights(scene, options.light_selection);
  for (Strategy strategy : strategies) {
    if (samples_lights(strategy) && lights.count() == 0)
      throw Error(fmt::format("scene '{}' has no emitter and no environment, so strategy '{}' has no light to sample.",
                              scene.source.empty() ? scene.name : scene.source, strategy_name(strategy)));
    for (const Object& o : scene.objects) {
      const Dielectric* d = o.material.as<Dielectric>();
      if (!d || !o.material.reflects()) continue;
      if (strategy_info(strategy).viewer_side_only)
        throw Error(fmt::format("scene '{}': strategy '{}' samples directions on the viewer's side of a surface "
                                "only, so it cannot see what the dielectric object '{}' transmits (use bsdf, a "
                                "light strategy, MIS or a path tracer).",
                                scene.source.empty() ? scene.name : scene.source, strategy_name(strategy), o.name));
      if (d->smooth() && !strategy_info(strategy).samples_bsdf)
        throw Error(fmt::format("scene '{}': strategy '{}' does not sample the BSDF, so it cannot follow the delta "
                                "lobes of the smooth dielectric object '{}' (use bsdf, MIS or a path tracer).",
                                scene.source.empty() ? scene.name : scene.source, strategy_name(strategy), o.name));
    }
    if (!scene.point_lights.empty() && !strategy_sees_delta_lights(strategy))
      throw Error(fmt::format("scene '{}' has point lights, which strategy '{}' cannot see (no ray hits a delta light).",
                              scene.source.empty() ? scene.name : scene.source, strategy_name(strategy)));
  }

  const bool path = is_path_tracer(options.strategy);
  // A closed scene whose answer is infinite, or whose paths would be about
  // endless, is refused before anything is traced (core/path_length.h).
  if (path) require_bounded_paths(scene, options.max_depth, options.roulette_depth);
  // A path tracer shares its samples with no other strategy (shares_samples):
  // one estimator. DirectLighting checks the direct strategies' list.
  if (path && strategies.size() != 1)
    throw Error(fmt::format("strategy '{}' shares its samples with no other strategy, so one render gives one image.",
                            strategy_name(options.strategy)));
  // Only the integrator the strategy needs is built.
  std::optional<DirectLighting> direct;
  std::optional<PathTracer> path_tracer;
  if (path) path_tracer.emplace(rtc_scene, lights, options);
  else direct.emplace(rtc_scene, lights, strategies, options.defect);
  const size_t n_estimators = strategies.size();

  const size_t n_pixels = size_t(scene.camera.width_px) * size_t(scene.camera.height_px);
  std::vector<Image> images(n_estimators);
  for (Image& image : images) {
    image.width = scene.camera.width_px;
    image.height = scene.camera.height_px;
    image.pixels.assign(n_pixels, PixelMoments{});
  }
  const int width = scene.camera.width_px;

  tbb::combinable<TraceCounters> counters;
  using Nonfinite = std::array<uint64_t, DirectLighting::kMaxSharedEstimators>;
  tbb::combinable<Nonfinite> nonfinite([] { return Nonfinite{}; });
  // The light strategy's per-emitter set-up at a pixel's shading point, one
  // store per thread (its vectors grow once, not per chunk of pixels).
  tbb::combinable<EmitterSetups> emitter_setups;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n_pixels, kPixelGrain), [&](const tbb::blocked_range<size_t>& r) {
    TraceCounters& c = counters.local();
    Nonfinite& bad = nonfinite.local();
    EmitterSetups& setups = emitter_setups.local();  // rebound to each pixel's shading point below
    for (size_t pixel = r.begin(); pixel != r.end(); ++pixel) {
      const int px = int(pixel % size_t(width));
      const int py = int(pixel / size_t(width));
      const Camera::Ray ray = scene.camera.pixel_center_ray(px, py);
      // The camera ray is the same for every sample of the pixel: trace it once.
      ++c.rays;
      const std::optional<SurfaceHit> hit = rtc_scene.intersect(ray.origin, ray.direction);
      const double le = emitted_radiance_towards(scene, hit, ray.direction);
      std::optional<ShadingContext> ctx;
      if (hit) {
        ctx = ShadingContext::at(*hit, -ray.direction, scene.objects[hit->object].material, options.defect,
                                 options.convention);
        setups.bind(*ctx, scene.objects.size());
      }
      // Accumulated in locals, stored once: the image's element, reached
      // through a reference the estimator calls might alias, would be loaded
      // and stored around every sample.
      std::array<PixelMoments, DirectLighting::kMaxSharedEstimators> moments;
      const uint64_t pixel_key = Rng::pixel_key(options.seed, pixel);
      // Samples kRayPacket at a time, each from its own stream, accumulated in
      // sample order: direct lighting traces a batch's rays as Embree packets.
      for (int first = 0; first < options.spp; first += int(kRayPacket)) {
        const size_t n = std::min(kRayPacket, size_t(options.spp - first));
        std::array<Rng, kRayPacket> rngs = streams(pixel_key, uint64_t(first));
        std::array<std::array<double, kRayPacket>, DirectLighting::kMaxSharedEstimators> y;
        if (path) {
          for (size_t i = 0; i < n; ++i) y[0][i] = path_tracer->radiance(ray.direction, hit, rngs[i], c, &setups);
        } else if (ctx) {
          std::array<double*, DirectLighting::kMaxSharedEstimators> outs;
          for (size_t e = 0; e < n_estimators; ++e) outs[e] = y[e].data();
          direct->estimate_shared(*ctx, rngs.data(), n, c, &setups, outs.data());
          for (size_t e = 0; e < n_estimators; ++e)
            for (size_t i = 0; i < n; ++i) y[e][i] = le + y[e][i];
        } else {
          for (size_t e = 0; e < n_estimators; ++e) y[e].fill(le);
        }
        for (size_t e = 0; e < n_estimators; ++e)
          for (size_t i = 0; i < n; ++i) {
            // DEFECT(nan_sample): a fixed 1/1024 of the (pixel, sample) pairs runs away.
            if (options.defect == Defect::kNanSample && (pixel + size_t(first) + i) % 1024 == 0)
              y[e][i] = std::numeric_limits<double>::quiet_NaN();
            if (std::isfinite(y[e][i])) moments[e].add(y[e][i]);
            else ++bad[e];  // error tier 3: dropped and counted
          }
      }
      for (size_t e = 0; e < n_estimators; ++e) images[e].pixels[pixel] = moments[e];
    }
  });
  device.check(fmt::format("rendering the scene '{}'", scene.name));

  uint64_t rays = 0;
  counters.combine_each([&](const TraceCounters& c) { rays += c.rays; });
  Nonfinite nonfinite_total{};
  nonfinite.combine_each([&](const Nonfinite& n) {
    for (size_t e = 0; e < n_estimators; ++e) nonfinite_total[e] += n[e];
  });
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  for (size_t e = 0; e < n_estimators; ++e) {
    images[e].rays = rays;
    images[e].nonfinite_samples = nonfinite_total[e];
    images[e].seconds = seconds;
  }
  return images;
}

}  // namespace furnace
