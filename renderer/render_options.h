// What one render is asked to do: the strategy, the negative-control defect,
// the light selection, the sample budget, the seed and the path depth.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/strategy.h"

namespace furnace {

struct TracedRay;  // renderer/embree_scene.h

// The most strategies one render renders together from shared samples
// (render_sharing_samples in render.h, DirectLighting's shared estimators).
inline constexpr size_t kMaxSharedStrategies = 2;

// Whether strategies a and b, from one seed, draw the same numbers, trace the
// same rays and compute the same densities, and differ only in how they
// weigh the samples: true for a == b and for mis_balance with mis_power (the
// MIS heuristic). One render then gives both images (render_sharing_samples
// in render.h).
inline bool shares_samples(Strategy a, Strategy b) {
  return a == b || (is_multi_sample_mis(a) && is_multi_sample_mis(b));
}

struct RenderOptions {
  Strategy strategy = Strategy::kLightArea;
  Defect defect = Defect::kNone;
  LightSelection light_selection = LightSelection::kUniform;
  int spp = 64;
  uint64_t seed = 1;
  int threads = 0;  // 0: all hardware threads (tbb::global_control otherwise)
  // Path tracers only: the longest path in segments from the camera (the
  // camera segment counts as 1; kUnlimitedDepth: no cap), and the depth from
  // which Russian roulette starts (survival probability min(1, throughput),
  // reweighted by 1/p).
  int max_depth = kUnlimitedDepth;
  int roulette_depth = 3;
  // How a dielectric transports the radiance it transmits (core/strategy.h).
  TransportConvention convention = TransportConvention::kRadiance;
  // Benchmarks only: every ray the render traces is appended here, in the
  // order traced (render() then requires threads == 1).
  std::vector<TracedRay>* ray_log = nullptr;
};

}  // namespace furnace
