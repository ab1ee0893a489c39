// OpenEXR output of a render and its read-back (through core/exr.h).
//
// File layout (all channels full resolution, ZIP compression, so lossless):
//   R, G, B                        FLOAT  pixel mean (the renderer is gray: R = G = B)
//   variance.R, variance.G, variance.B
//                                  FLOAT  unbiased per-sample variance s² = M2/(N−1),
//                                         0 when N < 2 (not the variance of the mean:
//                                         divide by N for that)
//   N                              UINT   samples accumulated in the pixel (exact up to 2³²−1)
// Header attributes (strings): furnace.nonfinite_samples, furnace.rays (decimal),
// and the provenance of core/provenance.h (scene, scene-file hash, strategy,
// spp, seed, max depth, light selection, defect, version) when given.
// Means and variances are rounded to 32-bit floats on writing.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "core/provenance.h"
#include "core/scene.h"
#include "renderer/image.h"
#include "renderer/render_options.h"

namespace furnace {

// Writes atomically: a temporary file in the destination's directory, renamed
// over `path` once complete, so a failure leaves no partial file behind.
// Throws furnace::Error naming the file on any failure.
void write_exr(const std::filesystem::path& path, const Image& image,
               const ImageProvenance& provenance = ImageProvenance{});

// The provenance of a render of the scene file `scene_path` (already loaded
// as `scene`) with `options`. Throws furnace::Error when the file cannot be read.
ImageProvenance render_provenance(const std::filesystem::path& scene_path, const Scene& scene,
                                  const RenderOptions& options);

struct ExrImage {
  int width = 0, height = 0;
  std::vector<float> mean;      // row-major, index = y * width + x
  std::vector<float> variance;  // per-sample unbiased variance
  std::vector<uint32_t> count;  // samples per pixel
  std::map<std::string, std::string> attributes;  // every string attribute of the header
};

// Reads a file written by write_exr. Throws furnace::Error naming the file and
// the problem (unreadable, missing channel, wrong channel type, bad size).
ExrImage read_exr(const std::filesystem::path& path);

}  // namespace furnace
