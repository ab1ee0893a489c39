// DirectLighting's batch form: estimating kRayPacket samples at once (their
// shadow rays traced as one Embree packet) gives every sample the value the
// single-sample estimate gives it, to the bit, for every direct strategy on
// every built-in scene (point lights, environments and touching objects
// included), at the camera rays' first hits, with batches of every size
// 1 … kRayPacket. render() relies on it: an image does not depend on the
// batching. Negative control: the comparison tells streams apart (the batch
// given the next sample's streams differs).
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "renderer/direct_strategies.h"
#include "renderer/embree_scene.h"
#include "renderer/lights.h"

namespace furnace {
namespace {

constexpr uint64_t kSeed = 0xba7c4;
constexpr int kPixelStride = 3;
constexpr int kBatchesPerPoint = 6;

struct Comparison {
  int samples = 0, differ = 0, nonzero = 0;
};

// Batches of size 1 … kRayPacket at every kPixelStride-th pixel's first hit;
// `stream_offset` shifts the batch's streams (0: the same streams as the single estimates).
Comparison compare(const Scene& scene, Strategy strategy, uint64_t stream_offset) {
  const EmbreeDevice device;
  const EmbreeScene rtc(device, scene);
  const LightSet lights(scene);
  Comparison c;
  if (samples_lights(strategy) && lights.count() == 0) return c;
  if (!scene.point_lights.empty() && !strategy_sees_delta_lights(strategy)) return c;
  const DirectLighting direct(rtc, lights, strategy, Defect::kNone);
  for (int py = 0; py < scene.camera.height_px; py += kPixelStride)
    for (int px = 0; px < scene.camera.width_px; px += kPixelStride) {
      const Camera::Ray ray = scene.camera.pixel_center_ray(px, py);
      const auto hit = rtc.intersect(ray.origin, ray.direction);
      if (!hit) continue;
      const ShadingContext ctx = ShadingContext::at(*hit, -ray.direction, scene.objects[hit->object].material);
      const uint64_t pixel_key = Rng::pixel_key(kSeed, uint64_t(py * scene.camera.width_px + px));
      EmitterSetups batch_setups, single_setups;
      batch_setups.bind(ctx, scene.objects.size());
      single_setups.bind(ctx, scene.objects.size());
      for (int b = 0; b < kBatchesPerPoint; ++b) {
        const size_t n = 1 + size_t(b + px + py) % kRayPacket;
        const uint64_t first = uint64_t(b) * kRayPacket;
        std::vector<Rng> rngs;
        for (size_t i = 0; i < n; ++i) rngs.push_back(Rng::for_sample(pixel_key, first + i + stream_offset));
        std::array<double, kRayPacket> batch{};
        TraceCounters batch_rays, single_rays;
        direct.estimate(ctx, rngs.data(), n, batch_rays, &batch_setups, batch.data());
        for (size_t i = 0; i < n; ++i) {
          Rng rng = Rng::for_sample(pixel_key, first + i);
          const double single = direct.estimate(ctx, rng, single_rays, &single_setups);
          ++c.samples;
          c.nonzero += single != 0;
          c.differ += !(batch[i] == single || (batch[i] != batch[i] && single != single));
        }
        if (stream_offset == 0) {
          EXPECT_EQ(batch_rays.rays, single_rays.rays) << scene.name;
        }
      }
    }
  return c;
}

std::vector<Scene> built_in_scenes() {
  std::vector<Scene> scenes;
  for (const auto& entry : std::filesystem::directory_iterator(FURNACE_SCENE_DIR))
    if (entry.path().extension() == ".json") scenes.push_back(load_scene(entry.path().string()));
  return scenes;
}

const std::vector<Strategy> kDirect{Strategy::kUniformHemisphere, Strategy::kCosineHemisphere, Strategy::kLightArea,
                                    Strategy::kLightSolidAngle,   Strategy::kBsdf,             Strategy::kMisBalance,
                                    Strategy::kMisPower,          Strategy::kMisOneSample};

TEST(DirectLightingBatch, EverySampleEqualsItsSingleEstimateToTheBit) {
  Comparison total;
  for (const Scene& scene : built_in_scenes())
    for (Strategy s : kDirect) {
      const Comparison c = compare(scene, s, 0);
      EXPECT_EQ(c.differ, 0) << scene.name << " " << strategy_name(s);
      total.samples += c.samples, total.differ += c.differ, total.nonzero += c.nonzero;
    }
  std::printf("batch vs single estimates: %d samples (%d non-zero), %d differ\n", total.samples, total.nonzero,
              total.differ);
  EXPECT_GT(total.nonzero, 20000);
}

TEST(DirectLightingBatch, ComparisonTellsStreamsApart) {
  // Negative control: the batch fed the streams of the following samples.
  Comparison total;
  for (const Scene& scene : built_in_scenes()) {
    const Comparison c = compare(scene, Strategy::kMisPower, 1);
    total.samples += c.samples, total.differ += c.differ;
  }
  std::printf("shifted streams: %d of %d samples differ\n", total.differ, total.samples);
  EXPECT_GT(total.differ, total.samples / 2);
}

}  // namespace
}  // namespace furnace
