// Renderer throughput (samples/s) per strategy on the disk-occluder scene,
// against the ceiling of this design: Embree alone tracing the very rays the
// render traced. Run as
//   build/bench/furnace_bench
// and read the summary table printed after Google Benchmark's rows.
//
// Every BM_Render iteration renders, then (timing paused) replays the
// render's rays three times: through rtcIntersect1/rtcOccluded1 alone on a
// scene without filter functions ("raw", the ceiling), through Embree alone
// with the render's own packets (the renderer traces each batch of light
// samples' shadow rays as one rtcOccluded8: "packets"), and through
// EmbreeScene::intersect/occluded one ray at a time ("+filter": the exact
// endpoint filters and the double-precision hit refinement). Ratios are medians over
// iterations of per-iteration ratios, so a load change on a shared machine
// hits numerator and denominator alike.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <tbb/blocked_range.h>
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

// 32×32 pixels × 256 spp = 262144 samples per render: long enough (~0.1–0.5 s
// on one thread) that render()'s fixed cost (device, BVH, thread arena) is a
// few percent at most.
constexpr int kSpp = 256;
constexpr uint64_t kSeed = 7;
// Raw replays start rays this far (scene units) along the ray and end shadow
// rays this far before their end point, the usual fixed-epsilon convention of
// a renderer without exact endpoint filters; disk_occluder's closest distinct
// surfaces are 1 unit apart.
constexpr float kRawRayEpsilon = 1e-4f;
// Rays per TBB task in the replays.
constexpr size_t kReplayGrain = 256;

RenderOptions options_for(Strategy strategy, int threads) {
  RenderOptions options;
  options.strategy = strategy;
  options.spp = kSpp;
  options.seed = kSeed;
  options.threads = threads;
  return options;
}

// The rays a render traces, recorded once per strategy (the render is
// deterministic, so the timed renders trace the same rays on any thread count).
const std::vector<TracedRay>& traced_rays(Strategy strategy) {
  static Strategy cached_strategy;
  static std::vector<TracedRay> cached;
  static bool valid = false;
  if (!valid || cached_strategy != strategy) {
    cached.clear();
    RenderOptions options = options_for(strategy, 1);
    options.ray_log = &cached;
    render(disk_occluder(), options);
    cached_strategy = strategy;
    valid = true;
  }
  return cached;
}

// A recorded ray as Embree takes it, converted before timing.
struct RawRay {
  RTCRayHit rayhit;
  bool shadow = false;
};

std::vector<RawRay> to_embree_rays(const std::vector<TracedRay>& rays) {
  std::vector<RawRay> out(rays.size());
  for (size_t i = 0; i < rays.size(); ++i) {
    const TracedRay& r = rays[i];
    out[i].shadow = r.shadow;
    RTCRayHit& rh = out[i].rayhit;
    rh.ray.org_x = float(r.origin.x);
    rh.ray.org_y = float(r.origin.y);
    rh.ray.org_z = float(r.origin.z);
    rh.ray.dir_x = float(r.direction.x);
    rh.ray.dir_y = float(r.direction.y);
    rh.ray.dir_z = float(r.direction.z);
    rh.ray.tnear = kRawRayEpsilon;
    rh.ray.tfar = std::isinf(r.t_max) ? std::numeric_limits<float>::infinity() : float(r.t_max) - kRawRayEpsilon;
    rh.ray.time = 0.0f;
    rh.ray.mask = 0xFFFFFFFFu;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = rh.hit.primID = rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rh.hit.Ng_x = rh.hit.Ng_y = rh.hit.Ng_z = 0.0f;
    rh.hit.u = rh.hit.v = 0.0f;
  }
  return out;
}

// Embree alone: rtcIntersect1 or rtcOccluded1 on a scene without filter functions.
uint64_t replay_raw(RTCScene scene, const std::vector<RawRay>& rays) {
  std::atomic<uint64_t> hits{0};
  tbb::parallel_for(tbb::blocked_range<size_t>(0, rays.size(), kReplayGrain), [&](const tbb::blocked_range<size_t>& r) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    uint64_t local = 0;
    for (size_t i = r.begin(); i != r.end(); ++i) {
      RTCRayHit rh = rays[i].rayhit;  // a copy: Embree writes tfar and the hit
      if (rays[i].shadow) {
        rtcOccluded1(scene, &context, &rh.ray);
        local += rh.ray.tfar < 0;
      } else {
        rtcIntersect1(scene, &context, &rh);
        local += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
      }
    }
    hits += local;
  });
  return hits;
}

// The renderer's packets, as the ray log shows them: runs of up to
// kRayPacket consecutive shadow rays from one origin (a batch of light samples
// at one shading point), each a [begin, end) range of `rays`; every other ray
// is a run of its own.
std::vector<std::pair<size_t, size_t>> packet_runs(const std::vector<RawRay>& rays) {
  std::vector<std::pair<size_t, size_t>> runs;
  for (size_t i = 0; i < rays.size();) {
    size_t end = i + 1;
    const RTCRay& a = rays[i].rayhit.ray;
    while (rays[i].shadow && end < rays.size() && end - i < kRayPacket && rays[end].shadow &&
           rays[end].rayhit.ray.org_x == a.org_x && rays[end].rayhit.ray.org_y == a.org_y &&
           rays[end].rayhit.ray.org_z == a.org_z)
      ++end;
    runs.emplace_back(i, end);
    i = end;
  }
  return runs;
}

// Embree alone with the renderer's packets: each run of two or more shadow
// rays in one rtcOccluded8, every other ray in its own rtcIntersect1 or
// rtcOccluded1, on a scene without filter functions.
uint64_t replay_raw_packets(RTCScene scene, const std::vector<RawRay>& rays,
                            const std::vector<std::pair<size_t, size_t>>& runs) {
  std::atomic<uint64_t> hits{0};
  tbb::parallel_for(tbb::blocked_range<size_t>(0, runs.size(), kReplayGrain / 4),
                    [&](const tbb::blocked_range<size_t>& r) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    uint64_t local = 0;
    for (size_t g = r.begin(); g != r.end(); ++g) {
      const auto [begin, end] = runs[g];
      if (end - begin == 1) {  // a lone ray: one call, as the renderer makes it
        RTCRayHit rh = rays[begin].rayhit;
        if (rays[begin].shadow) {
          rtcOccluded1(scene, &context, &rh.ray);
          local += rh.ray.tfar < 0;
        } else {
          rtcIntersect1(scene, &context, &rh);
          local += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
        }
        continue;
      }
      alignas(32) int valid[kRayPacket] = {};
      RTCRay8 packet;
      for (size_t i = begin; i < end; ++i) {
        const RTCRay& ray = rays[i].rayhit.ray;
        const size_t k = i - begin;
        packet.org_x[k] = ray.org_x, packet.org_y[k] = ray.org_y, packet.org_z[k] = ray.org_z;
        packet.dir_x[k] = ray.dir_x, packet.dir_y[k] = ray.dir_y, packet.dir_z[k] = ray.dir_z;
        packet.tnear[k] = ray.tnear, packet.tfar[k] = ray.tfar, packet.time[k] = ray.time;
        packet.mask[k] = ray.mask, packet.id[k] = ray.id, packet.flags[k] = ray.flags;
        valid[k] = -1;
      }
      rtcOccluded8(valid, scene, &context, &packet);
      for (size_t k = 0; k < end - begin; ++k) local += packet.tfar[k] < 0;
    }
    hits += local;
  });
  return hits;
}

// The same rays through furnace's queries: exact endpoint filters, hit refinement.
uint64_t replay_exact(const EmbreeScene& scene, const std::vector<TracedRay>& rays) {
  std::atomic<uint64_t> hits{0};
  tbb::parallel_for(tbb::blocked_range<size_t>(0, rays.size(), kReplayGrain), [&](const tbb::blocked_range<size_t>& r) {
    uint64_t local = 0;
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const TracedRay& ray = rays[i];
      if (ray.shadow) local += scene.occluded(ray.origin, ray.direction, ray.t_max, ray.ends);
      else local += scene.intersect(ray.origin, ray.direction, ray.t_max, ray.ends).has_value();
    }
    hits += local;
  });
  return hits;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

struct SummaryRow {
  double samples_per_second = 0, rays_per_sample = 0, shadow_rays_per_sample = 0;
  double ceiling_samples_per_second = 0, ratio_to_raw = 0, ratio_to_filtered = 0, ratio_to_packets = 0;
};
// strategy name → threads → the last run's row (repetitions overwrite).
std::map<std::string, std::map<int, SummaryRow>>& summary() {
  static std::map<std::string, std::map<int, SummaryRow>> rows;
  return rows;
}

void BM_Render(benchmark::State& state, Strategy strategy) {
  const int threads = int(state.range(0));
  const Scene& scene = disk_occluder();
  const std::vector<TracedRay>& rays = traced_rays(strategy);
  const std::vector<RawRay> embree_rays = to_embree_rays(rays);
  const std::vector<std::pair<size_t, size_t>> runs = packet_runs(embree_rays);
  uint64_t shadow_rays = 0;
  for (const TracedRay& r : rays) shadow_rays += r.shadow;

  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
  const EmbreeDevice device;
  const EmbreeScene raw_scene(device, scene, EndpointFilter::kNone);
  const EmbreeScene exact_scene(device, scene);
  const RenderOptions options = options_for(strategy, threads);
  const double samples = double(scene.camera.width_px) * scene.camera.height_px * kSpp;

  std::vector<double> render_s, raw_s, exact_s, to_raw, to_exact, to_packets;
  uint64_t rendered_rays = 0;
  for (auto _ : state) {
    auto start = std::chrono::steady_clock::now();
    const Image image = render(scene, options);
    render_s.push_back(seconds_since(start));
    rendered_rays = image.rays;
    benchmark::DoNotOptimize(image.pixels.data());

    state.PauseTiming();
    start = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(replay_raw(raw_scene.rtc_scene(), embree_rays));
    raw_s.push_back(seconds_since(start));
    start = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(replay_exact(exact_scene, rays));
    exact_s.push_back(seconds_since(start));
    start = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(replay_raw_packets(raw_scene.rtc_scene(), embree_rays, runs));
    to_packets.push_back(seconds_since(start) / render_s.back());
    to_raw.push_back(raw_s.back() / render_s.back());
    to_exact.push_back(exact_s.back() / render_s.back());
    state.ResumeTiming();
  }
  if (rendered_rays != rays.size()) state.SkipWithError("the timed render traced other rays than the recorded one");

  SummaryRow row;
  row.samples_per_second = samples / median(render_s);
  row.rays_per_sample = double(rays.size()) / samples;
  row.shadow_rays_per_sample = double(shadow_rays) / samples;
  row.ceiling_samples_per_second = samples / median(raw_s);
  row.ratio_to_raw = median(to_raw);
  row.ratio_to_filtered = median(to_exact);
  row.ratio_to_packets = median(to_packets);
  summary()[strategy_name(strategy)][threads] = row;

  state.SetItemsProcessed(int64_t(samples * double(state.iterations())));
  state.counters["rays_per_sample"] = row.rays_per_sample;
  state.counters["ceiling_samples_per_s"] = row.ceiling_samples_per_second;
  state.counters["ratio_to_raw_embree"] = row.ratio_to_raw;
  state.counters["ratio_to_embree_filters"] = row.ratio_to_filtered;
  state.counters["ratio_to_embree_packets"] = row.ratio_to_packets;
}

// Embree alone on synthetic rays of one kind: from receiver points just above
// the plane, towards points on the light disk (shadow segments ending just
// before it, or unbounded rays for rtcIntersect1), on the scene without
// filter functions.
const std::vector<RawRay>& synthetic_rays() {
  static const std::vector<RawRay> rays = [] {
    std::vector<TracedRay> traced;
    const int n = 1 << 16;
    for (int i = 0; i < n; ++i) {
      Rng rng(kSeed, uint64_t(i), 0);
      const Vec3 origin{4 * rng.next_double() - 2, 4 * rng.next_double() - 2, 1e-6};
      const auto d = sample_uniform_disk_concentric(rng.next_double(), rng.next_double());
      const Vec3 to = Vec3{0.75 * d[0], 0.75 * d[1], 2.0} - origin;
      traced.push_back({origin, normalize(to), length(to), true, {}});
    }
    return to_embree_rays(traced);
  }();
  return rays;
}

template <bool kOccluded>
void BM_RawEmbree(benchmark::State& state) {
  const int threads = int(state.range(0));
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
  const EmbreeDevice device;
  const EmbreeScene scene(device, disk_occluder(), EndpointFilter::kNone);
  std::vector<RawRay> rays = synthetic_rays();
  for (RawRay& r : rays) {
    r.shadow = kOccluded;
    if (!kOccluded) r.rayhit.ray.tfar = std::numeric_limits<float>::infinity();
  }
  uint64_t hits = 0;
  for (auto _ : state) hits += replay_raw(scene.rtc_scene(), rays);
  state.SetItemsProcessed(int64_t(rays.size()) * state.iterations());
  state.counters["hit_fraction"] = double(hits) / (double(rays.size()) * double(state.iterations()));
}

void thread_args(benchmark::internal::Benchmark* b) {
  b->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
}

void register_benchmarks() {
  for (const StrategyInfo& info : kStrategyTable)
    benchmark::RegisterBenchmark((std::string("BM_Render/") + info.name).c_str(), BM_Render, info.strategy)
        ->Apply(thread_args);
  benchmark::RegisterBenchmark("BM_RawIntersect1", BM_RawEmbree<false>)->Apply(thread_args);
  benchmark::RegisterBenchmark("BM_RawOccluded1", BM_RawEmbree<true>)->Apply(thread_args);
}

void print_summary() {
  if (summary().empty()) return;
  std::printf("\nCeiling: Embree alone on the rays each render traced (disk_occluder, %d spp, seed %llu).\n", kSpp,
              static_cast<unsigned long long>(kSeed));
  std::printf("%-20s %7s %7s | %11s %11s %8s %8s %8s | %11s %8s %8s %8s | %7s\n", "strategy", "rays", "shadow",
              "1T Ms/s", "ceil Ms/s", "ratio", "packets", "+filter", "2T Ms/s", "ratio", "packets", "+filter",
              "scaling");
  for (const StrategyInfo& info : kStrategyTable) {
    const auto it = summary().find(info.name);
    if (it == summary().end()) continue;
    const auto& by_threads = it->second;
    const SummaryRow one = by_threads.count(1) ? by_threads.at(1) : SummaryRow{};
    const SummaryRow two = by_threads.count(2) ? by_threads.at(2) : SummaryRow{};
    std::printf("%-20s %7.3f %7.3f | %11.3f %11.3f %8.3f %8.3f %8.3f | %11.3f %8.3f %8.3f %8.3f | %7.2f\n",
                info.name, one.rays_per_sample, one.shadow_rays_per_sample, one.samples_per_second / 1e6,
                one.ceiling_samples_per_second / 1e6, one.ratio_to_raw, one.ratio_to_packets, one.ratio_to_filtered,
                two.samples_per_second / 1e6, two.ratio_to_raw, two.ratio_to_packets, two.ratio_to_filtered,
                one.samples_per_second > 0 ? two.samples_per_second / one.samples_per_second : 0.0);
  }
  std::printf("rays: rays per sample (camera ray counted once per pixel); shadow: of which occlusion queries.\n"
              "ratio: render samples/s over Embree-alone samples/s, one ray per call (1 = the ceiling); packets:\n"
              "over Embree alone with the render's packets (runs of up to 8 shadow rays from one point in one\n"
              "rtcOccluded8, the rest one per call); +filter: over furnace's own queries, one per call (exact\n"
              "endpoint filters, hit refinement). scaling: 2-thread over 1-thread samples/s.\n");
}

}  // namespace
}  // namespace furnace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  furnace::register_benchmarks();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  furnace::print_summary();
  return 0;
}
