// Double-precision ray–shape intersection for the references, written
// independently of the renderer's Embree geometry (a shared intersector would
// hide a shared bug). Rays are o + t·d; d need not be unit length and t is in
// units of d. Each function returns the smallest root t > t_min, or empty.
#pragma once

#include <optional>

#include "core/scene.h"

namespace furnace::analytic {

// Parallelogram corner + s·edge_u + t·edge_v, s, t ∈ [0, 1] (both faces).
std::optional<double> intersect_rectangle(const Rectangle& r, const Vec3& o, const Vec3& d, double t_min);
// Disk: plane hit with |x − centre| ≤ radius (both faces).
std::optional<double> intersect_disk(const Disk& disk, const Vec3& o, const Vec3& d, double t_min);
// Sphere: the quadratic solved in the cancellation-free form of Haines et al.,
// "Precision Improvements for Ray/Sphere Intersection" (Ray Tracing Gems,
// 2019, ch. 7): discriminant r² − |f|² = (r − |f|)(r + |f|) with f the
// perpendicular from the centre to the ray, roots q and c/q.
std::optional<double> intersect_sphere(const Sphere& s, const Vec3& o, const Vec3& d, double t_min);
// Triangle: Möller & Trumbore 1997, edges inclusive (both faces).
std::optional<double> intersect_triangle(const Triangle& tri, const Vec3& o, const Vec3& d, double t_min);

// Dispatch on the shape variant.
std::optional<double> intersect_shape(const Shape& shape, const Vec3& o, const Vec3& d, double t_min);

}  // namespace furnace::analytic
