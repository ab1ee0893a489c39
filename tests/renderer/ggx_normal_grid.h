// The (θ, φ) grid of GGX microfacet normals the χ² tests bin in
// (ggx_chi2_test.cpp, dielectric_chi2_test.cpp): kGgxGridRows rows of equal
// mass of D(m)·cos θm (tan²θ = α² v/(1 − v) at row edge v), so the peak of
// width α is resolved at every α, and kGgxGridColumns equal steps of φ,
// odd so that no cell edge lies on the plane of wo (φ = 0, π).
#pragma once

#include <algorithm>
#include <cmath>

#include "core/vec3.h"
#include "renderer/sampling.h"

namespace furnace {

inline constexpr int kGgxGridRows = 20;
inline constexpr int kGgxGridColumns = 21;

struct GgxNormalGrid {
  double alpha;
  double theta_edge(int row) const {
    if (row == kGgxGridRows) return kPi / 2;
    const double v = double(row) / kGgxGridRows;
    return std::atan(alpha * std::sqrt(v / (1 - v)));  // tan²θ = α² v/(1 − v)
  }
  // -1 for a normal that is not finite or not above the horizon.
  long cell_of(const Vec3& m) const {
    if (!(is_finite(m) && m.z > 0)) return -1;
    const double t2 = m.x * m.x + m.y * m.y;
    const double v = t2 / (alpha * alpha * m.z * m.z + t2);
    double phi = std::atan2(m.y, m.x);
    if (phi < 0) phi += 2 * kPi;
    const int row = std::min(kGgxGridRows - 1, int(v * kGgxGridRows));
    const int col = std::min(kGgxGridColumns - 1, int(phi / (2 * kPi) * kGgxGridColumns));
    return long(row) * kGgxGridColumns + col;
  }
};

}  // namespace furnace
