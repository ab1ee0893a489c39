// Planar polygon emitters: Lambert's formula for the irradiance from a
// uniform Lambertian polygon, with the polygon clipped to the receiver's
// hemisphere first.
#pragma once

#include <vector>

#include "analytic/polygon_normal.h"  // polygon_normal, which the users of polygons call
#include "core/vec3.h"

namespace furnace::analytic {

// The part of a planar polygon (vertices relative to p) on the upper side of
// the plane dot(x, n) = 0 (Sutherland–Hodgman against one plane). Vertices
// exactly on the plane are kept; the result may be empty.
std::vector<Vec3> clip_to_hemisphere(const std::vector<Vec3>& vertices, const Vec3& n);

// E/L at p = ∫_polygon max(cos θ, 0)·cos θ'/r² dA for a planar polygon
// (vertices relative to p, either winding) whose emitting face sees p:
//   E/L = |½ Σ_i Θ_i · (n · unit(v_i × v_{i+1}))|  over the clipped polygon,
//   Θ_i = atan2(|v_i × v_{i+1}|, v_i · v_{i+1})      (angle subtended by edge i).
// Lambert, "Photometria" (1760); Arvo, "Applications of Irradiance Tensors
// to the Simulation of Non-Lambertian Phenomena", SIGGRAPH 1995, eq. 6 (his
// form is for the whole polygon above the horizon; the clip makes it so).
// The atan2 angle is accurate for short and nearly straight (Θ ≈ π) edges
// where acos(v̂_i·v̂_{i+1}) would lose digits. Units: dimensionless (E/L).
// Accuracy: the sum of edge terms ~ (edge/distance) cancels to
// ~ (area/distance²), losing ~ ε·(distance/size)² relative; polygons with
// size/distance ≤ kSmallAngle are therefore integrated over their area by a
// product Gauss rule instead (small_polygon_irradiance, small_emitter.h), so
// the loss stays ≤ ~ ε·(1/kSmallAngle)² ≈ 2e-14. Domain: p not on the polygon's edges (an edge through p has
// v_i × v_{i+1} = 0 and is skipped, which is correct when p is not in its
// interior).
double polygon_irradiance(const std::vector<Vec3>& vertices, const Vec3& n);

}  // namespace furnace::analytic
