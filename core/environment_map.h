// An image-based environment: a gray latitude-longitude map of relative
// radiance (dimensionless; the scene's Environment scales it to W·m⁻²·sr⁻¹).
//
// Direction convention (z up, the scenes' receivers face +z):
//   θ = acos(z) ∈ [0, π] (polar angle from +z), φ = atan2(y, x) wrapped into [0, 2π);
//   row i = floor(θ/π·H), column j = floor(φ/(2π)·W), clamped to the last row/column.
// Texel (i, j) covers θ ∈ [iπ/H, (i+1)π/H], φ ∈ [2πj/W, 2π(j+1)/W]. The map is
// piecewise constant (nearest texel, no filtering), so integrals over it are
// exact sums over texels, which is what makes exact references possible.
#pragma once

#include <cstddef>
#include <filesystem>
#include <vector>

#include "core/vec3.h"

namespace furnace {

struct LatLongMap {
  int width = 0, height = 0;
  std::vector<double> texels;  // row-major: index = i * width + j, row i from θ = 0 (+z)

  double texel(int i, int j) const { return texels[size_t(i) * size_t(width) + size_t(j)]; }
  // Row and column of a unit direction (the convention above).
  int row_of(const Vec3& dir) const;
  int column_of(const Vec3& dir) const;
  // The texel value along a unit direction.
  double lookup(const Vec3& dir) const { return texel(row_of(dir), column_of(dir)); }
};

// Reads a gray lat-long OpenEXR file: either one Y channel, or R, G, B equal at
// every texel. Throws furnace::Error (one sentence naming the file, and the
// texel, channel and value where one is at fault) for a missing or unreadable
// file, any other channel layout, unequal R, G, B, or a negative or
// non-finite texel.
LatLongMap load_latlong_exr(const std::filesystem::path& path);

// Writes a map as a one-channel (Y, FLOAT, ZIP: lossless for float values)
// OpenEXR file, atomically (temporary file, then rename). Throws furnace::Error
// naming the file on failure.
void write_latlong_exr(const std::filesystem::path& path, const LatLongMap& map);

}  // namespace furnace
