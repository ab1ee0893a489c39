#include "core/environment_map.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <system_error>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/error.h"

namespace furnace {

namespace {

// Largest width or height accepted: the scene loader's resolution limit.
constexpr long kMaxDimension = 16384;

// OpenEXR's messages sometimes end with a period and sometimes not, and some
// hold two sentences; the error must be one sentence ending with one period.
std::string as_sentence_end(std::string text) {
  while (!text.empty() && (text.back() == '.' || text.back() == ' ')) text.pop_back();
  for (size_t at = text.find(". "); at != std::string::npos; at = text.find(". ", at)) text.replace(at, 2, "; ");
  return text + ".";
}

// A name in the destination directory no other writer in this or another process uses.
std::filesystem::path temporary_path_for(const std::filesystem::path& path) {
  static std::atomic<unsigned> counter{0};
  const std::string name = fmt::format(".{}.tmp-{}-{}", path.filename().string(), ::getpid(), counter++);
  return path.parent_path() / name;
}

int clamp_index(double x, int n) { return std::clamp(int(std::floor(x)), 0, n - 1); }

}  // namespace

int LatLongMap::row_of(const Vec3& dir) const {
  // atan2 form: accurate near the poles, where acos(z) loses half the digits.
  const double theta = std::atan2(std::hypot(dir.x, dir.y), dir.z);
  return clamp_index(theta / kPi * height, height);
}

int LatLongMap::column_of(const Vec3& dir) const {
  double phi = std::atan2(dir.y, dir.x);
  if (phi < 0) phi += 2 * kPi;  // may round to exactly 2π: clamped to the last column
  return clamp_index(phi / (2 * kPi) * width, width);
}

LatLongMap load_latlong_exr(const std::filesystem::path& path) {
  const std::string file_name = path.string();
  if (!std::filesystem::is_regular_file(path))
    throw Error(fmt::format("environment map '{}' does not exist or is not a regular file.", file_name));
  LatLongMap map;
  std::vector<std::vector<float>> channels;
  std::vector<std::string> names;
  try {
    Imf::InputFile file(file_name.c_str());
    const Imf::Header& header = file.header();
    const Imath::Box2i dw = header.dataWindow();
    const long width = long(dw.max.x) - long(dw.min.x) + 1;
    const long height = long(dw.max.y) - long(dw.min.y) + 1;
    if (width < 1 || height < 1 || width > kMaxDimension || height > kMaxDimension)
      throw Error(fmt::format("environment map '{}' has a data window of {}x{} texels; expected 1 to {} per side.",
                              file_name, width, height, kMaxDimension));
    std::vector<std::string> present;
    for (auto c = header.channels().begin(); c != header.channels().end(); ++c) present.emplace_back(c.name());
    std::sort(present.begin(), present.end());
    if (present == std::vector<std::string>{"Y"}) names = {"Y"};
    else if (present == std::vector<std::string>{"B", "G", "R"}) names = {"R", "G", "B"};
    else
      throw Error(fmt::format("environment map '{}' has the channels [{}]; a gray map needs exactly Y, or R, G and B.",
                              file_name, fmt::join(present, ", ")));
    for (const std::string& name : names) {
      const Imf::Channel* c = header.channels().findChannel(name.c_str());
      if (c->xSampling != 1 || c->ySampling != 1)
        throw Error(fmt::format("environment map '{}': channel '{}' is subsampled.", file_name, name));
    }
    map.width = int(width);
    map.height = int(height);
    const size_t n = size_t(width) * size_t(height);
    // Slices are addressed from the data window's origin; HALF and UINT channels convert to FLOAT.
    const ptrdiff_t origin = -ptrdiff_t(dw.min.x) - ptrdiff_t(dw.min.y) * ptrdiff_t(width);
    channels.assign(names.size(), std::vector<float>(n));
    Imf::FrameBuffer frame;
    const size_t stride = sizeof(float);
    for (size_t k = 0; k < names.size(); ++k)
      frame.insert(names[k], Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(channels[k].data() + origin), stride,
                                        stride * width));
    file.setFrameBuffer(frame);
    file.readPixels(dw.min.y, dw.max.y);
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw Error(fmt::format("cannot read environment map '{}': {}", file_name, as_sentence_end(e.what())));
  }
  map.texels.resize(channels[0].size());
  for (size_t t = 0; t < map.texels.size(); ++t) {
    const long row = long(t) / map.width, column = long(t) % map.width;
    for (size_t k = 0; k < names.size(); ++k) {
      const float v = channels[k][t];
      if (!std::isfinite(v) || v < 0)
        throw Error(fmt::format("environment map '{}': texel (row {}, column {}) of channel '{}' is {}; radiance "
                                "must be finite and non-negative.",
                                file_name, row, column, names[k], v));
      if (k > 0 && v != channels[0][t])
        throw Error(fmt::format("environment map '{}': texel (row {}, column {}) has R = {} but {} = {}; only gray "
                                "maps (R = G = B) are supported.",
                                file_name, row, column, channels[0][t], names[k], v));
    }
    map.texels[t] = double(channels[0][t]);
  }
  return map;
}

void write_latlong_exr(const std::filesystem::path& path, const LatLongMap& map) {
  const size_t n = size_t(map.width) * size_t(map.height);
  if (map.width < 1 || map.height < 1 || map.texels.size() != n)
    throw Error(fmt::format("cannot write environment map '{}': the map is {}x{} with {} texels.", path.string(),
                            map.width, map.height, map.texels.size()));
  std::vector<float> values(map.texels.begin(), map.texels.end());
  Imf::Header header(map.width, map.height);
  header.compression() = Imf::ZIP_COMPRESSION;
  header.channels().insert("Y", Imf::Channel(Imf::FLOAT));
  Imf::FrameBuffer frame;
  const size_t stride = sizeof(float);
  frame.insert("Y", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(values.data()), stride, stride * map.width));
  const std::filesystem::path tmp = temporary_path_for(path);
  try {
    {
      Imf::OutputFile file(tmp.string().c_str(), header);
      file.setFrameBuffer(frame);
      file.writePixels(map.height);
    }  // closed (and flushed) before the rename
    std::filesystem::rename(tmp, path);
  } catch (const std::exception& e) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    throw Error(fmt::format("cannot write environment map '{}': {}", path.string(), as_sentence_end(e.what())));
  }
}

}  // namespace furnace
