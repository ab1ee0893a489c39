// The images `furnace check` tests: OpenEXR renders of one of our scenes,
// made by any renderer, read through core/exr.h and validated before any
// statistics (a bad image is bad input, exit 2, never a verdict).
#pragma once

#include <string>
#include <vector>

#include "core/provenance.h"
#include "core/scene.h"

namespace furnace::verify {

// What is tested per pixel.
enum class ChannelMode {
  kGray,  // "gray": one value per pixel, the mean of R, G and B, or Y when the image has no R, G, B
  kRgb,   // "rgb": R, G and B separately (a colour error that keeps the gray mean, R +3 % with B −3 %, fails)
};
std::string channel_mode_name(ChannelMode mode);

// One image, validated: row-major from the top-left, as 64-bit values of the
// stored 32-bit floats (or halves).
struct ForeignImage {
  std::string path;
  int width = 0, height = 0;
  std::vector<std::string> channels;         // tested channels: {"gray"} or {"R", "G", "B"}
  std::string source_channels;               // the file's channels they come from: "R, G, B" or "Y"
  std::vector<std::vector<double>> value;    // [channel][pixel]
  // Furnace EXRs (variance.R, variance.G, variance.B and N present): the
  // per-sample s² of each tested channel, [channel][pixel], and the sample
  // count per pixel. Empty otherwise. For the gray mean of R, G and B the
  // variance is ((s_R + s_G + s_B)/3)²: exact when R = G = B (furnace is gray)
  // and an upper bound otherwise (perfectly correlated channels).
  std::vector<std::vector<double>> variance;
  std::vector<double> count;
  ImageProvenance provenance;  // empty for other renderers' images
  bool has_variance() const { return !variance.empty(); }
};

// Reads and validates one image. Throws furnace::Error, one sentence naming
// the file (and the pixel, channel and value where one is at fault), for:
// an unreadable file or non-OpenEXR file; a resolution differing from the
// scene's camera; no R, G and B channels (nor Y, for kGray); a negative, NaN
// or infinite radiance in R, G, B or Y; a NaN, infinite or negative
// variance.* channel; a sample count N that is not a positive integer.
ForeignImage read_foreign_image(const std::string& path, const Scene& scene, ChannelMode mode);
// The same without a scene (furnace compare): any resolution is accepted.
ForeignImage read_foreign_image(const std::string& path, ChannelMode mode);

// Throws furnace::Error naming both files when two images hold the same
// values in every tested channel: K copies of one render have no spread, so
// the across-images test would divide by zero and fail every pixel. Copies
// that reproduce `reference` exactly (a zero-variance estimator, identical
// whatever the seed) are accepted.
void reject_identical_images(const std::vector<ForeignImage>& images, const std::vector<double>& reference);

}  // namespace furnace::verify
