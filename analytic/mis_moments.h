// The MIS estimators' second moments at a Lambertian receiver, for
// second_moment (moments.h), which states the estimators and what is
// supported: one-sample MIS and multi-sample MIS under the balance and power
// heuristics, over unoccluded emitters (sphere cones, disks by area,
// rectangles and triangles by the renderer's choice of map), point lights
// and the constant sky. Per direction the integrands see cos θ and the light
// density p_l (selection included); the cosine density p_b = cos θ/π.
// Method: spheres and disks in ring coordinates (outer polar variable, inner
// azimuth over the exact arcs above the horizon, by the half-angle variable),
// polygons in their plane's spherical coordinates (polygon_patch.h); nested
// adaptive Gauss–Kronrod, the error reached reported to the ErrorLedger.
#pragma once

#include <array>
#include <optional>
#include <vector>

#include "core/scene.h"

namespace furnace::analytic {

// E[Y²] of MIS at p (normal n): multi_sample false gives one-sample MIS at
// index 0; multi_sample true gives the balance heuristic's multi-sample MIS
// at index 0 and the power heuristic's at index 1, integrated together.
// `pmf`: the selection pmf of every light (light_selection_pmf: emitters in
// object order, then point lights, then the environment). Throws
// furnace::Error for an occluded emitter or p on or inside a sphere light.
std::array<double, 2> mis_second_moments(const Scene& scene, const Vec3& p, const Vec3& n,
                                         std::optional<size_t> receiver, bool multi_sample,
                                         const std::vector<double>& pmf);

}  // namespace furnace::analytic
