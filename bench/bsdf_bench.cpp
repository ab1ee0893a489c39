// BSDF sampling throughput (samples/s) through the renderer's Bsdf interface
// (renderer/bsdf.h: the material dispatch, sample() with its pdf() and
// eval()): GGX beside Lambertian (cosine sampling) and normalised Phong. Run as
//   build/bench/furnace_bsdf_bench --benchmark_repetitions=9 --benchmark_report_aggregates_only=true
// and read the medians' items_per_second; GGX's cost over Lambertian's is
// the ratio of the two.
//
// Each iteration samples one batch of kBatch pre-drawn (u1, u2) pairs at a
// fixed view (45°, in the plane φ = 0), so the random-number generator is not
// timed; the weights are summed so that nothing is optimised away.
#include <benchmark/benchmark.h>

#include <array>
#include <cmath>
#include <vector>

#include "core/scene.h"
#include "renderer/bsdf.h"
#include "renderer/rng.h"

namespace furnace {
namespace {

// 4096 pairs (64 KiB) stay in L1/L2: the benchmark measures arithmetic, not memory.
constexpr size_t kBatch = 4096;
constexpr uint64_t kSeed = 0xbe7c;
constexpr double kViewDeg = 45;

// (u1, u2, u_lobe): the warp's pair and the dielectric's lobe choice.
const std::vector<std::array<double, 3>>& uniforms() {
  static const std::vector<std::array<double, 3>> u = [] {
    std::vector<std::array<double, 3>> v(kBatch);
    Rng rng(kSeed, 0, 0);
    for (auto& p : v) {
      const double u1 = rng.next_double();
      const double u2 = rng.next_double();
      p = {u1, u2, rng.next_double()};
    }
    return v;
  }();
  return u;
}

// `viewer_in_front`: false views a dielectric from inside (η inverted).
void BM_BsdfSample(benchmark::State& state, Material material, bool viewer_in_front = true) {
  const Bsdf bsdf(material, BsdfSetting(Defect::kNone, TransportConvention::kRadiance, viewer_in_front));
  const double t = kViewDeg * kPi / 180;
  const Vec3 wo{std::sin(t), 0, std::cos(t)};
  const auto& u = uniforms();
  double sum = 0;
  size_t failed = 0;
  for (auto _ : state) {
    for (const auto& p : u) {
      const auto s = bsdf.sample(wo, p[0], p[1], p[2]);
      if (s) sum += s->weight;
      else ++failed;
    }
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(kBatch));
  state.counters["failed_fraction"] = double(failed) / (double(state.iterations()) * double(kBatch));
}

Material lambertian() { return Material{0.8, Lambertian{}}; }
Material phong(double n) { return Material{0.8, Phong{n}}; }
Material ggx(double alpha, MicrofacetShadowing shadowing) { return Material{0.8, Ggx{alpha, shadowing, std::nullopt}}; }
Material conductor(double alpha) {
  return Material{1, Ggx{alpha, MicrofacetShadowing::kHeightCorrelated, ConductorIndex{0.2, 3.4}}};
}
// Glass of η 1.5 (viewed at 45°: from inside, past the critical angle 41.8° for the smooth one).
Material dielectric(double alpha) { return Material{1, Dielectric{1.5, alpha, MicrofacetShadowing::kHeightCorrelated}}; }

BENCHMARK_CAPTURE(BM_BsdfSample, lambertian, lambertian());
BENCHMARK_CAPTURE(BM_BsdfSample, phong_n100, phong(100));
BENCHMARK_CAPTURE(BM_BsdfSample, ggx_alpha0p2_height_correlated, ggx(0.2, MicrofacetShadowing::kHeightCorrelated));
BENCHMARK_CAPTURE(BM_BsdfSample, ggx_alpha0p2_separable, ggx(0.2, MicrofacetShadowing::kSeparable));
BENCHMARK_CAPTURE(BM_BsdfSample, ggx_alpha0p001_height_correlated, ggx(1e-3, MicrofacetShadowing::kHeightCorrelated));
BENCHMARK_CAPTURE(BM_BsdfSample, ggx_alpha0p2_fresnel_gold, conductor(0.2));
BENCHMARK_CAPTURE(BM_BsdfSample, dielectric_smooth_outside, dielectric(0), true);
BENCHMARK_CAPTURE(BM_BsdfSample, dielectric_smooth_inside, dielectric(0), false);
BENCHMARK_CAPTURE(BM_BsdfSample, dielectric_alpha0p2_outside, dielectric(0.2), true);
BENCHMARK_CAPTURE(BM_BsdfSample, dielectric_alpha0p2_inside, dielectric(0.2), false);

}  // namespace
}  // namespace furnace

BENCHMARK_MAIN();
