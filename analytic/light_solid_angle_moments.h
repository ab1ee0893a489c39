// Light solid-angle sampling (Strategy::kLightSolidAngle) of one emitter,
// for second_moment (moments.h). The renderer's choice of method per emitter
// is its contract in core/strategy.h: spherical maps from
// kMinSampledSolidAngle up, rectangles within kPerpendicularTolerance of
// perpendicular, area sampling otherwise (disks, sheared parallelograms,
// tinier polygons, a point on or inside a sphere).
#pragma once

#include <optional>

#include "core/scene.h"

namespace furnace::analytic {

// E[Y²]/(K·L²) of emitter i under light_solid_angle sampling (K the inverse
// selection pmf, applied by the caller):
//   cone or whole spherical polygon: Ω·∫_visible max(cos θ, 0)² dω,
//   area fallback:                  A·∫_visible (cos θ cos θ'/r²)² dA (as light_area).
// 0 when nothing of the emitter reaches p. Spheres must be unoccluded
// (throws furnace::Error otherwise); polygons by the exact planar path,
// occluders allowed.
double solid_angle_emitter_kernel(const Scene& scene, size_t i, const Vec3& p, const Vec3& n,
                                  std::optional<size_t> receiver);

}  // namespace furnace::analytic
