// One emitter's contribution at a receiving point, and the check that
// nothing hides any of it (the unoccluded closed forms and moment kernels
// need that).
#pragma once

#include <optional>

#include "core/scene.h"

namespace furnace::analytic {

// E/L at p (unit normal n) from emitter `emitter` alone, past every other
// object (`receiver` excluded). Disks: the circle fast path (disk_light.h),
// else the exact planar path (planar_light.h); rectangles and triangles: the
// exact planar path; spheres: Snyder's form (sphere.h) when nothing can
// block them, else azimuthal quadrature over exactly computed visible
// intervals (sphere_occluded.h) when every possible blocker is planar.
// Throws furnace::Error outside those configurations.
double emitter_irradiance(const Scene& scene, size_t emitter, const Vec3& p, const Vec3& n,
                          std::optional<size_t> receiver);

// Throws furnace::Error unless no object other than `emitter` and
// `receiver` can meet the hull of p and the emitter's bounding ball above p's
// horizon (objects wholly below the horizon block only directions with
// cos θ ≤ 0, which carry no irradiance). Of a planar emitter, objects wholly
// on the far side of its plane from p are admitted too, and those reaching
// the plane only from there (coplanar ones) when their bounding balls are
// apart: neither can meet a segment from p to the light.
void require_unoccluded(const Scene& scene, size_t emitter, const Vec3& p, const Vec3& n,
                        std::optional<size_t> receiver);
// The first object require_unoccluded would name, if any.
std::optional<size_t> possible_blocker(const Scene& scene, size_t emitter, const Vec3& p, const Vec3& n,
                                       std::optional<size_t> receiver);

}  // namespace furnace::analytic
