// THE OpenEXR reader and writer of furnace: environment maps (core/), render
// output (renderer/exr_io), other renderers' images and per-pixel t maps
// (verify/check) all go through these two functions.
//
// Facts of the format relied on (OpenEXR 3.1):
//  - Pixels live in the data window [min, max] (inclusive); a file's pixel
//    (x, y) is stored here at index (y − min.y)·width + (x − min.x), row-major
//    from the top-left, whatever the data window's origin.
//  - Channels are listed alphabetically ("B" < "G" < "R" < "variance.R").
//  - The library converts between HALF, FLOAT and UINT while reading; HALF
//    and FLOAT widen exactly to float, so both are read as float here, while
//    UINT channels (exact counts up to 2³² − 1) are read as uint32_t.
//  - ZIP compression is lossless for every pixel type (PXR24 is lossy for
//    FLOAT), so write() uses ZIP.
//  - Subsampled channels (x or y sampling ≠ 1, e.g. luminance–chroma RY/BY)
//    hold fewer pixels; they are listed but not read.
//
// Every failure is a furnace::Error whose message is one sentence naming the
// file and what is wrong (missing, not an OpenEXR file, deep, wrong size, no
// such channel, wrong pixel type).
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace furnace::exr {

// Largest width or height read or written: the scene loader's resolution limit.
inline constexpr int kMaxDimension = 16384;

enum class PixelType { kUint, kHalf, kFloat };
const char* pixel_type_name(PixelType type);  // "UINT", "HALF", "FLOAT"

struct ChannelInfo {
  std::string name;
  PixelType type = PixelType::kFloat;
  bool subsampled = false;  // listed, but its pixels are not read
};

// An image with named channels, as read from a file or to be written.
struct Image {
  std::string path;  // the file read (messages only; ignored by write())
  int width = 0, height = 0;
  // Pixel values per channel, row-major from the top-left (index y·width + x).
  std::map<std::string, std::vector<float>> floats;     // read: HALF and FLOAT channels; written as FLOAT
  std::map<std::string, std::vector<uint32_t>> uints;   // read: UINT channels; written as UINT
  std::map<std::string, std::string> attributes;        // string header attributes
  // read: int, float and double header attributes (pbrt-v4 writes its
  // samplesPerPixel as an int); ignored by write(). Other types are skipped.
  std::map<std::string, double> numbers;
  std::vector<ChannelInfo> channels;  // read: every channel in the file, alphabetical; ignored by write()

  bool has_channel(const std::string& name) const;
  // The channel's pixels as double (exact for every pixel type). Throws
  // furnace::Error naming the file, the channel and the channels present
  // when there is no such (full-resolution) channel.
  std::vector<double> values(const std::string& name) const;
  // A string attribute, or empty when absent.
  std::optional<std::string> attribute(const std::string& name) const;
  // Names of every channel in the file, for messages ("R, G, B").
  std::string channel_list() const;
};

// Reads every full-resolution channel and every string attribute of the file.
// `what` names the kind of file in messages ("environment map", "image").
Image read(const std::filesystem::path& path, std::string_view what = "OpenEXR file");

// Writes image.floats (FLOAT) and image.uints (UINT) channels, each of
// width·height values, and image.attributes as string attributes, ZIP
// compressed, atomically (core/atomic_file.h: a temporary file in the
// target's directory, then rename; nothing is left behind on failure).
// Throws furnace::Error naming the file on a malformed image or I/O failure.
void write(const std::filesystem::path& path, const Image& image, std::string_view what = "OpenEXR file");

}  // namespace furnace::exr
