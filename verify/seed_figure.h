// The comparison the lecture notes make with pictures, with numbers: a
// Lambertian receiver under a disk light with a blocker (scenes/disk_occluder),
// rendered with uniform hemisphere sampling at 100 spp beside light-area
// sampling at 16 spp, each with its RMSE and time, and the ratio of the two
// images' pixel variances that the analytic second moments predict
// (analytic::pixel_center_second_moment) next to the measured ones.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace furnace::verify {

inline constexpr const char* kSeedFigureScene = "disk_occluder.json";
inline constexpr int kSeedHemisphereSpp = 100;
inline constexpr int kSeedLightSpp = 16;
// The figure renders the scene at this resolution (its file says 32×32) so
// that the noise reads as a picture; the camera's extent stays the same.
inline constexpr int kSeedFigureResolution = 128;

struct SeedFigureRender {
  std::string strategy;
  int spp = 0;
  double seconds = 0;
  double rmse = 0, relative_rmse = 0;      // against the exact reference, over pixels
  double mean_sample_variance = 0;         // mean over pixels of the per-sample s²
  double mean_predicted_variance = 0;      // mean over pixels of E[Y²] − E[Y]² (analytic)
  std::vector<double> mean;                // per-pixel estimate, row-major
};

struct SeedFigure {
  std::string scene;
  int width = 0, height = 0;
  std::vector<double> reference;
  double reference_mean = 0;
  SeedFigureRender hemisphere, light;
  // Ratios of the variance of one pixel's estimate, hemisphere over light:
  // (σ̄²_hemisphere / 100) / (σ̄²_light / 16), with σ̄² the mean over pixels of
  // the per-sample variance, predicted (analytic moments) and measured (s²);
  // and the ratio of the two images' mean squared errors, which estimates the
  // same number for unbiased estimators.
  double predicted_variance_ratio = 0;
  double measured_variance_ratio = 0;
  double measured_mse_ratio = 0;
};

// Renders and measures the figure (about a second on two cores).
SeedFigure measure_seed_figure(uint64_t seed, int threads);

}  // namespace furnace::verify
