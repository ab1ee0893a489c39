// A rendered image: per pixel, the running moments of the single-sample
// estimator, plus the render's counters.
#pragma once

#include <cstdint>
#include <vector>

namespace furnace {

// Per-pixel central moments of the single-sample estimator Y, accumulated in
// sample order (Welford / Terriberry updates, so the result is independent of
// threading). Pixel index = py * width + px.
struct PixelMoments {
  uint64_t count = 0;
  double mean = 0;
  double m2 = 0;  // Σ (y - mean)²
  double m3 = 0;  // Σ (y - mean)³
  double m4 = 0;  // Σ (y - mean)⁴
  void add(double y);
  // Unbiased sample variance s² = m2 / (n - 1); 0 when n < 2.
  double sample_variance() const { return count > 1 ? m2 / double(count - 1) : 0.0; }
};

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
