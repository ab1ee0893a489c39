// Renderer throughput (samples/s) per strategy on the disk-occluder scene,
// against the raw Embree throughput (rtcIntersect1 / rtcOccluded1 alone) on
// the same scene, single-threaded and on all threads. The ratio says how much
// of the ceiling the estimator code costs.
#include <benchmark/benchmark.h>

#include <atomic>
#include <string>
#include <vector>

#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include "core/scene.h"
#include "renderer/embree_scene.h"
#include "renderer/render.h"
#include "renderer/rng.h"
#include "renderer/sampling.h"

namespace furnace {
namespace {

const Scene& disk_occluder() {
  static const Scene scene = load_scene(std::string(FURNACE_SCENE_DIR) + "/disk_occluder.json");
  return scene;
}

constexpr int kSpp = 64;
constexpr uint64_t kSeed = 7;

void BM_Render(benchmark::State& state, Strategy strategy) {
  RenderOptions options;
  options.strategy = strategy;
  options.spp = kSpp;
  options.seed = kSeed;
  options.threads = int(state.range(0));
  const Scene& scene = disk_occluder();
  uint64_t rays = 0;
  for (auto _ : state) {
    const Image image = render(scene, options);
    rays += image.rays;
    benchmark::DoNotOptimize(image.pixels.data());
  }
  const double samples = double(scene.camera.width_px) * scene.camera.height_px * kSpp;
  state.SetItemsProcessed(int64_t(samples * state.iterations()));
  state.counters["rays_per_sample"] = double(rays) / (samples * state.iterations());
}

// The rays a light-area sample traces, without any estimator code: from
// receiver points on the plane, one shadow ray to a point on the light disk
// (rtcOccluded1), and one hemisphere ray (rtcIntersect1).
struct RayBatch {
  std::vector<Vec3> origins, directions;
  std::vector<double> lengths;
};

const RayBatch& ray_batch() {
  static const RayBatch batch = [] {
    RayBatch b;
    const Scene& scene = disk_occluder();
    const int n = 1 << 16;
    for (int i = 0; i < n; ++i) {
      Rng rng(kSeed, uint64_t(i), 0);
      const Vec3 origin{4 * rng.next_double() - 2, 4 * rng.next_double() - 2, 1e-6};
      const auto d = sample_uniform_disk_concentric(rng.next_double(), rng.next_double());
      const Vec3 target{0.75 * d[0], 0.75 * d[1], 2.0};
      const Vec3 to = target - origin;
      b.origins.push_back(origin);
      b.directions.push_back(normalize(to));
      b.lengths.push_back(length(to) * (1 - 1e-6));
    }
    (void)scene;
    return b;
  }();
  return batch;
}

template <bool kOccluded>
void trace_one(RTCScene rtc, const RayBatch& b, size_t i, RTCIntersectContext& ctx, uint64_t& hits) {
  RTCRayHit rh;
  rh.ray.org_x = float(b.origins[i].x); rh.ray.org_y = float(b.origins[i].y); rh.ray.org_z = float(b.origins[i].z);
  rh.ray.dir_x = float(b.directions[i].x); rh.ray.dir_y = float(b.directions[i].y); rh.ray.dir_z = float(b.directions[i].z);
  rh.ray.tnear = 0.0f;
  rh.ray.tfar = kOccluded ? float(b.lengths[i]) : std::numeric_limits<float>::infinity();
  rh.ray.time = 0.0f;
  rh.ray.mask = 0xFFFFFFFFu;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rh.hit.Ng_x = rh.hit.Ng_y = rh.hit.Ng_z = 0.0f;
  rh.hit.u = rh.hit.v = 0.0f;
  if constexpr (kOccluded) {
    rtcOccluded1(rtc, &ctx, &rh.ray);
    hits += rh.ray.tfar < 0;
  } else {
    rtcIntersect1(rtc, &ctx, &rh);
    hits += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
  }
}

template <bool kOccluded>
void BM_RawEmbree(benchmark::State& state) {
  const int threads = int(state.range(0));
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
  EmbreeDevice device;
  EmbreeScene scene(device, disk_occluder());
  const RayBatch& b = ray_batch();
  std::atomic<uint64_t> total_hits{0};
  for (auto _ : state) {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, b.origins.size(), 1024), [&](const tbb::blocked_range<size_t>& r) {
      RTCIntersectContext ctx;
      rtcInitIntersectContext(&ctx);
      uint64_t hits = 0;
      for (size_t i = r.begin(); i != r.end(); ++i) trace_one<kOccluded>(scene.rtc_scene(), b, i, ctx, hits);
      total_hits += hits;
    });
  }
  state.SetItemsProcessed(int64_t(b.origins.size()) * state.iterations());
  state.counters["hit_fraction"] = double(total_hits) / (double(b.origins.size()) * state.iterations());
}

void render_args(benchmark::internal::Benchmark* b) { b->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime(); }

BENCHMARK_CAPTURE(BM_Render, uniform_hemisphere, Strategy::kUniformHemisphere)->Apply(render_args);
BENCHMARK_CAPTURE(BM_Render, cosine_hemisphere, Strategy::kCosineHemisphere)->Apply(render_args);
BENCHMARK_CAPTURE(BM_Render, light_area, Strategy::kLightArea)->Apply(render_args);
BENCHMARK_CAPTURE(BM_Render, light_solid_angle, Strategy::kLightSolidAngle)->Apply(render_args);
BENCHMARK_CAPTURE(BM_Render, mis_power, Strategy::kMisPower)->Apply(render_args);
BENCHMARK_TEMPLATE(BM_RawEmbree, false)->Name("BM_RawIntersect1")->Apply(render_args);
BENCHMARK_TEMPLATE(BM_RawEmbree, true)->Name("BM_RawOccluded1")->Apply(render_args);

}  // namespace
}  // namespace furnace

BENCHMARK_MAIN();
