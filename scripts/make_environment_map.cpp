// Writes scenes/environment_map.exr, the map of the environment_map scenes:
// a 64×32 gray lat-long map (core/environment_map.h convention) holding a
// smooth sky gradient, bright at the zenith and dimming towards the horizon,
// a dim ground below the horizon, and a small "sun" of 2×2 texels about 100×
// brighter than the sky, 40° from the zenith. Piecewise constant by design
// (the references integrate it texel by texel).
//
// With --sky-above it writes scenes/sky_above.exr instead, the map of the
// glass_sky_* scenes: a sky on one side, 1 on the upper hemisphere (z > 0)
// and 0 on the lower, 4×2 texels (the equator a row edge), so a glass plane
// z = const sees it by reflection from above and by transmission from below
// (analytic/glass.h).
//
// Usage: make_environment_map [--sky-above] <output.exr>. Deterministic: no
// randomness, values are computed in double and written as 32-bit floats, so
// rerunning it reproduces the committed file texel for texel (tests/core
// checks that).
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>

#include "core/environment_map.h"

namespace {

constexpr int kWidth = 64;
constexpr int kHeight = 32;
constexpr double kZenith = 1.0;    // sky at the zenith (relative radiance)
constexpr double kHorizon = 0.35;  // sky at the horizon
constexpr double kGround = 0.1;    // below the horizon (lights only tilted receivers)
constexpr double kSun = 100.0;     // ~100× the sky, so importance sampling matters
// The sun's texels: rows 7–8 (θ ∈ [39.4°, 50.6°]), columns 10–11 (φ ∈ [56°, 67.5°]).
constexpr int kSunRow = 7, kSunColumn = 10, kSunSize = 2;
// The sky-above map's columns.
constexpr int kSkyWidth = 4;

// Writes the map; the process's exit code (1 with the error on stderr).
int write(const char* path, const furnace::LatLongMap& map) {
  try {
    furnace::write_latlong_exr(path, map);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const bool sky_above = argc == 3 && std::strcmp(argv[1], "--sky-above") == 0;
  if (argc != 2 && !sky_above) {
    std::fprintf(stderr, "usage: %s [--sky-above] <output.exr>\n", argv[0]);
    return 2;
  }
  if (sky_above) {
    furnace::LatLongMap sky;
    sky.width = kSkyWidth;
    sky.height = 2;
    sky.texels.assign(size_t(kSkyWidth), 1.0);
    sky.texels.resize(size_t(2 * kSkyWidth), 0.0);
    return write(argv[2], sky);
  }
  furnace::LatLongMap map;
  map.width = kWidth;
  map.height = kHeight;
  map.texels.resize(size_t(kWidth) * kHeight);
  for (int i = 0; i < kHeight; ++i) {
    const double cos_theta = std::cos((i + 0.5) * furnace::kPi / kHeight);  // at the row's centre
    for (int j = 0; j < kWidth; ++j) {
      const double phi = (j + 0.5) * 2 * furnace::kPi / kWidth;
      // A gentle azimuthal variation so the map is not rotationally symmetric.
      const double sky = (kHorizon + (kZenith - kHorizon) * cos_theta) * (1 + 0.2 * std::cos(phi));
      double value = cos_theta > 0 ? sky : kGround;
      if (i >= kSunRow && i < kSunRow + kSunSize && j >= kSunColumn && j < kSunColumn + kSunSize) value = kSun;
      map.texels[size_t(i) * kWidth + j] = value;
    }
  }
  return write(argv[1], map);
}
