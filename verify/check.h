// Reference checking of other renderers' images: `furnace check` compares
// OpenEXR renders of one of our scenes, made by any renderer, against the
// scene's exact reference.
//
// A single image carries no error bar, so a statistical verdict needs either
//  - K ≥ 2 independent renders (different seeds): per pixel the mean over the
//    K images is t-tested with the spread across them (Student t, K − 1 d.o.f.),
//    and so is the image mean (the K image means are independent), or
//  - one furnace EXR (with variance.R and N channels): the z-tests of
//    `furnace verify`.
// All tests share the family-wise α by the Šidák correction.
#pragma once

#include <string>
#include <vector>

#include "core/scene.h"

namespace furnace::verify {

// One gray value per pixel, row-major from the top-left (EXR's data window
// order), read as 32-bit floats from channel Y, or the mean of R, G and B.
struct ForeignImage {
  std::string path;
  int width = 0, height = 0;
  std::vector<double> value;
  std::vector<double> variance;  // furnace EXRs only: per-sample s² (empty otherwise)
  std::vector<double> count;     // furnace EXRs only: samples per pixel
};

// Throws furnace::Error naming the file and what is wrong (unreadable, no
// R/G/B or Y channel, resolution differing from the scene's camera).
ForeignImage read_foreign_image(const std::string& path, const Scene& scene);

struct CheckResult {
  int images = 0;
  int pixels = 0;
  std::string method;         // "across-images t" or "furnace variance z"
  double image_mean = 0, reference_mean = 0;
  double statistic = 0, threshold = 0;
  double detectable_relative_bias = 0;
  int pixel_failures = 0;
  double median_pixel_detectable_relative_bias = 0;
  double relative_rmse = 0;   // of the (averaged) image against the reference
  bool pass = false;
};

// `max_segments`: for a global-illumination reference (0: direct lighting).
CheckResult check_images(const Scene& scene, const std::vector<ForeignImage>& images, double alpha,
                         int max_segments);

std::string format_check(const Scene& scene, const CheckResult& r, double alpha);

}  // namespace furnace::verify
