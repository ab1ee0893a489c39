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
  // The samples per pixel the file's header states, as written there, and the
  // attribute it came from: furnace's furnace.spp, pbrt-v4's samplesPerPixel
  // (an int attribute), or Blender's cycles.<view layer>.samples. Empty when
  // the header states none or something other than a positive whole number.
  std::string stated_spp, spp_attribute;
  // A tested radiance channel (R, G, B or Y) is stored as a 16-bit HALF
  // (pbrt-v4's default output): its values are rounded to 11 significant
  // bits (a relative step of 2⁻¹⁰ to 2⁻¹¹), so K renders of a pixel whose
  // noise is smaller than that step repeat the same few values.
  bool half_float = false;
  // Finite negative values in the radiance channels (R, G, B or Y), counted
  // over every channel and pixel: data, used as is. A spectral renderer's
  // RGB film holds small ones where a sampled spectrum maps outside the RGB
  // gamut (pbrt-v4: −1.5e-4 to −2e-6 in 8 of 58 renders of one scene). The
  // most negative value and where it is, for the report.
  size_t negative_values = 0;
  double most_negative = 0;
  std::string most_negative_channel;
  int most_negative_x = 0, most_negative_y = 0;
  bool has_variance() const { return !variance.empty(); }
};

// Reads and validates one image. Throws furnace::Error, one sentence naming
// the file (and the pixel, channel and value where one is at fault), for:
// an unreadable file or non-OpenEXR file; a resolution differing from the
// scene's camera; no R, G and B channels (nor Y, for kGray); a NaN or
// infinite radiance in R, G, B or Y; a NaN, infinite or negative variance.*
// channel; a sample count N that is not a positive integer. Finite negative
// radiance is accepted and counted (ForeignImage::negative_values).
ForeignImage read_foreign_image(const std::string& path, const Scene& scene, ChannelMode mode);
// The same without a scene (furnace compare): any resolution is accepted.
ForeignImage read_foreign_image(const std::string& path, ChannelMode mode);

// Throws furnace::Error naming both files when two images hold the same
// values in every tested channel: K copies of one render have no spread, so
// the across-images test would divide by zero and fail every pixel. Copies
// that reproduce `reference` exactly (a zero-variance estimator, identical
// whatever the seed) are accepted.
void reject_identical_images(const std::vector<ForeignImage>& images, const std::vector<double>& reference);

// Negative values over a set of images (one side of a comparison, or the
// images of a check), for the reports.
struct NegativeValues {
  size_t values = 0;  // summed over the images' radiance channels and pixels
  int images = 0;     // images holding any
  double most_negative = 0;
  std::string path, channel;  // where the most negative value is
  int x = 0, y = 0;
};
NegativeValues count_negative_values(const std::vector<ForeignImage>& images);

// True when any image stores a tested radiance channel as HALF.
bool any_half_float(const std::vector<ForeignImage>& images);

// The samples per pixel of a set of renders: the spp their headers state
// (furnace's, pbrt-v4's or Blender's attribute) when every image states the
// same, else a furnace EXR's median N, else 0 (unknown).
double images_spp(const std::vector<ForeignImage>& images);

// The spp per render the rare-event guards (check's --guard, compare's) take
// for two sets `a` and `b` (0 for a set that is one furnace EXR: its N
// channel counts the samples), and what they assumed for a set whose files
// state none: the other set's spp (or median N), or, with neither stated,
// equal spp. `a_owner`, `b_owner` name each set's files in the possessive
// ("side A's", "the images'"); `neither` names both ("neither side's").
struct GuardSpp {
  double a = 0, b = 0;
  std::string assumption;  // empty: nothing assumed
};
GuardSpp guard_spp(const std::vector<ForeignImage>& a, const std::vector<ForeignImage>& b, const std::string& a_owner,
                   const std::string& b_owner, const std::string& neither);

}  // namespace furnace::verify
