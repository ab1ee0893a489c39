// A rendered image: per pixel, the running moments of the single-sample
// estimator, plus the render's counters.
#pragma once

#include <cstdint>
#include <vector>

#include "core/running_moments.h"

namespace furnace {

// Per-pixel central moments of the single-sample estimator Y, accumulated in
// sample order (so the result is independent of threading): the one
// accumulator of core/running_moments.h. Pixel index = py * width + px.
using PixelMoments = RunningMoments;

struct Image {
  int width = 0, height = 0;
  std::vector<PixelMoments> pixels;
  uint64_t nonfinite_samples = 0;  // NaN/Inf estimator values: dropped and counted (error tier 3)
  uint64_t rays = 0;               // rays traced (primary + secondary + shadow); the camera ray
                                   // is the same for every sample of a pixel and counted once
  double seconds = 0;              // wall time of render()
  const PixelMoments& at(int px, int py) const { return pixels[size_t(py) * width + px]; }
};

}  // namespace furnace
