#include "analytic/polygon_normal.h"

namespace furnace::analytic {

Vec3 polygon_normal(const std::vector<Vec3>& v) {
  Vec3 area{0, 0, 0};
  for (size_t i = 1; i + 1 < v.size(); ++i) area = area + cross(v[i] - v[0], v[i + 1] - v[0]);
  return normalize(area);
}

}  // namespace furnace::analytic
