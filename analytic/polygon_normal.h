// The unit normal of a planar polygon, shared by Lambert's edge sum
// (polygon.h) and the small emitters' area rules (small_emitter.h).
#pragma once

#include <vector>

#include "core/vec3.h"

namespace furnace::analytic {

// Unit normal of a planar polygon (≥ 3 vertices, winding as given) from
// Σ (v_i − v_0) × (v_{i+1} − v_0) (twice its vector area), so that repeated
// or collinear vertices, as clipping leaves them, do not matter.
Vec3 polygon_normal(const std::vector<Vec3>& vertices);

}  // namespace furnace::analytic
