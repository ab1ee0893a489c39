// Synthetic renders of a light seen rarely, for the rare-event guards of
// `furnace compare` (verify/compare.h) and `furnace check` (verify/check.h).
// A 16 × 16 crop: every pixel a background b = 1 + 0.2·x/16 of per-sample
// relative noise kRareBackgroundNoise, and pixel (8, 8) also a light hit with
// probability kRareHitProbability per sample, each hit worth kRareHitValue
// (mean contribution p·c = 1, so the exact answer there is b + 1). A render
// of S spp holds the exact mean of its S samples' background (normal at that
// size) plus Binomial(S, p)·c/S, stored as a 32-bit float, and states S in
// its header, as pbrt-v4's do. At 8 × 16 spp the light pixel has 128
// samples, expected hits 1: all miss with probability e^-1 ≈ 0.37, and its
// mean and spread are then the background's alone; at 8 × 4096 spp it has
// 256 hits on average.
#pragma once

#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "verify/check_image.h"

namespace furnace::verify {

inline constexpr int kRareSize = 16;
inline constexpr size_t kRarePixel = size_t(8) * kRareSize + 8;
inline constexpr double kRareBackgroundNoise = 0.3;
inline constexpr double kRareHitProbability = 1.0 / 128;
inline constexpr double kRareHitValue = 1 / kRareHitProbability;
inline constexpr int kRareK = 8;

inline double rare_background(size_t i) { return 1 + 0.2 * double(i % kRareSize) / kRareSize; }

// The exact answer per pixel: the background, plus 1 at the light pixel.
inline std::vector<double> rare_reference() {
  std::vector<double> reference(size_t(kRareSize) * kRareSize);
  for (size_t i = 0; i < reference.size(); ++i) reference[i] = rare_background(i) + (i == kRarePixel ? 1.0 : 0.0);
  return reference;
}

// kRareK renders of `spp` samples from `seed`, named name0.exr, name1.exr, …;
// `light_present` false: a renderer that drops the light.
inline std::vector<ForeignImage> rare_renders(int spp, uint64_t seed, bool light_present, const std::string& name) {
  std::vector<ForeignImage> images;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise;
  std::binomial_distribution<int> hits(spp, kRareHitProbability);
  const size_t n = size_t(kRareSize) * kRareSize;
  for (int j = 0; j < kRareK; ++j) {
    ForeignImage img;
    img.path = name + std::to_string(j) + ".exr";
    img.width = img.height = kRareSize;
    img.source_channels = "R, G, B";
    img.channels = {"gray"};
    img.stated_spp = std::to_string(spp);
    img.spp_attribute = "samplesPerPixel";
    img.value.assign(1, std::vector<double>(n));
    for (size_t i = 0; i < n; ++i) {
      double v = rare_background(i) * (1 + kRareBackgroundNoise * noise(rng) / std::sqrt(double(spp)));
      if (i == kRarePixel && light_present) v += hits(rng) * kRareHitValue / spp;
      img.value[0][i] = float(v);
    }
    images.push_back(std::move(img));
  }
  return images;
}

}  // namespace furnace::verify
