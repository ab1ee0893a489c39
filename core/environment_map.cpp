#include "core/environment_map.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/error.h"
#include "core/exr.h"

namespace furnace {

namespace {

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
  const exr::Image image = exr::read(path, "environment map");
  const std::string& file_name = image.path;
  std::vector<std::string> present;
  for (const exr::ChannelInfo& c : image.channels) present.push_back(c.name);  // alphabetical
  std::vector<std::string> names;
  if (present == std::vector<std::string>{"Y"}) names = {"Y"};
  else if (present == std::vector<std::string>{"B", "G", "R"}) names = {"R", "G", "B"};
  else
    throw Error(fmt::format("environment map '{}' has the channels [{}]; a gray map needs exactly Y, or R, G and B.",
                            file_name, fmt::join(present, ", ")));
  for (const exr::ChannelInfo& c : image.channels)
    if (c.subsampled) throw Error(fmt::format("environment map '{}': channel '{}' is subsampled.", file_name, c.name));
  // HALF, FLOAT and UINT texels, exactly; messages print them as the 32-bit
  // floats they are stored as.
  std::vector<std::vector<double>> channels;
  for (const std::string& name : names) channels.push_back(image.values(name));

  LatLongMap map;
  map.width = image.width;
  map.height = image.height;
  map.texels.resize(channels[0].size());
  for (size_t t = 0; t < map.texels.size(); ++t) {
    const long row = long(t) / map.width, column = long(t) % map.width;
    for (size_t k = 0; k < names.size(); ++k) {
      const double v = channels[k][t];
      if (!std::isfinite(v) || v < 0)
        throw Error(fmt::format("environment map '{}': texel (row {}, column {}) of channel '{}' is {}; radiance "
                                "must be finite and non-negative.",
                                file_name, row, column, names[k], float(v)));
      if (k > 0 && v != channels[0][t])
        throw Error(fmt::format("environment map '{}': texel (row {}, column {}) has R = {} but {} = {}; only gray "
                                "maps (R = G = B) are supported.",
                                file_name, row, column, float(channels[0][t]), names[k], float(v)));
    }
    map.texels[t] = channels[0][t];
  }
  return map;
}

void write_latlong_exr(const std::filesystem::path& path, const LatLongMap& map) {
  const size_t n = size_t(map.width) * size_t(map.height);
  if (map.width < 1 || map.height < 1 || map.texels.size() != n)
    throw Error(fmt::format("cannot write environment map '{}': the map is {}x{} with {} texels.", path.string(),
                            map.width, map.height, map.texels.size()));
  exr::Image image;
  image.width = map.width;
  image.height = map.height;
  image.floats["Y"].assign(map.texels.begin(), map.texels.end());  // rounded to 32-bit floats
  exr::write(path, image, "environment map");
}

}  // namespace furnace
