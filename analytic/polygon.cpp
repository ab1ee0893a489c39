#include "analytic/polygon.h"

#include <cmath>

#include "analytic/small_emitter.h"

namespace furnace::analytic {

std::vector<Vec3> clip_to_hemisphere(const std::vector<Vec3>& vertices, const Vec3& n) {
  std::vector<Vec3> out;
  const size_t count = vertices.size();
  for (size_t i = 0; i < count; ++i) {
    const Vec3& a = vertices[i];
    const Vec3& b = vertices[(i + 1) % count];
    const double da = dot(a, n), db = dot(b, n);
    if (da >= 0) out.push_back(a);
    // Strict sign change: the crossing lies strictly inside the edge.
    if ((da > 0 && db < 0) || (da < 0 && db > 0)) out.push_back(a + (b - a) * (da / (da - db)));
  }
  return out;
}

double polygon_irradiance(const std::vector<Vec3>& vertices, const Vec3& n) {
  const std::vector<Vec3> clipped = clip_to_hemisphere(vertices, n);
  const size_t count = clipped.size();
  if (count < 3) return 0.0;
  // Small polygons: Lambert's edge terms would cancel (small_emitter.h).
  if (polygon_angular_size(clipped) <= kSmallAngle) return small_polygon_irradiance(clipped, n);
  double sum = 0;
  for (size_t i = 0; i < count; ++i) {
    const Vec3& a = clipped[i];
    const Vec3& b = clipped[(i + 1) % count];
    // a × b as ½(a × (b − a) + (a − b) × b): the edge vector keeps |a × b|
    // accurate when a ∥ b, and the symmetric form makes the reversed edge's
    // value its exact negative (the result does not depend on the winding).
    const Vec3 c = (cross(a, b - a) + cross(a - b, b)) * 0.5;
    const double c_len = length(c);
    if (!(c_len > 0)) continue;  // zero-length edge or an edge whose line passes through p
    sum += std::atan2(c_len, dot(a, b)) * (dot(n, c) / c_len);
  }
  return 0.5 * std::fabs(sum);
}

}  // namespace furnace::analytic
