// The general exact path for planar emitters (disks, rectangles, triangles):
// any receiver orientation (horizon clipping included), occluders that are
// disks parallel to the light or planar polygons. The visible region in the
// light's plane comes from exact Boolean operations (exact_region.h) and the
// irradiance from the vector form of the contour integral over its boundary.
#pragma once

#include <optional>
#include <vector>

#include "analytic/exact_region.h"
#include "core/scene.h"

namespace furnace::analytic {

// E/L = ∫_A cos θ·cos θ'/r² dA for a planar region A in the plane through
// `origin` spanned by the orthonormal e1, e2, lying wholly on the upper side
// of p's horizon (n·(x − p) ≥ 0 on A), given its positively oriented
// boundary in (e1, e2) coordinates:
//   E/L = |½ n·∮_∂A (x − p) × dx / |x − p|²|.
// Derivation: the vector irradiance of a region bounded by a closed curve,
// Φ = ∫ (x−p)/|x−p|·dω, equals ½∮ (x−p)×dx/|x−p|² (Stokes on the unit sphere;
// for straight edges it is Lambert's Σ Θ_i·unit(v_i × v_{i+1}), Arvo 1995).
// Straight edges use that closed form (atan2 angle); arcs are integrated by
// adaptive Gauss–Kronrod (61 points, relative tolerance 1e-14).
double contour_irradiance(const Vec3& origin, const Vec3& e1, const Vec3& e2, const std::vector<Curve2>& boundary,
                          const Vec3& p, const Vec3& n);

// E/L at p (unit normal n) from emitter `light_index` (Disk, Rectangle or
// Triangle; one-sided unless two_sided), seen past the other objects
// (`receiver` excluded). Objects wholly below p's horizon, wholly behind p
// or beyond the light's plane, or whose bounding ball misses the hull of p
// and the light's bounding ball, are ignored. The rest must be disks
// parallel to the light (projected as circles) or rectangles/triangles
// (clipped to the pyramid from p over the light's bounding square and to the
// light's plane, then projected centrally onto the light plane as polygons;
// an occluder may stand on the receiver plane, but not touch p itself);
// throws furnace::Error otherwise (tilted disks and spheres project to
// ellipses, which the circle–segment Booleans do not represent).
// Returns exactly 0 when nothing is visible. With no occluder, polygons go
// to polygon_irradiance (horizon-clipped Lambert, small ones by the area
// rule of small_emitter.h) and disks to Howell's form (parallel receiver) or,
// when small (R ≤ kSmallAngle·(distance − R)), to small_disk_irradiance,
// horizon-clipped: the contour's boundary terms would cancel there.
double planar_light_irradiance(const Scene& scene, size_t light_index, const Vec3& p, const Vec3& n,
                               std::optional<size_t> receiver);

// ∫_visible max(cos θ, 0)² dω for the same configurations (the uniform-
// hemisphere second-moment kernel), by Arvo's recurrence for a region bounded
// by any closed curve on the sphere (the boundary term of the divergence
// theorem with conormal ν ds = u × du):
//   τ² = (σ + s·∮ (n·u)·n·(u × du))/3,  u × du = (x − p) × dx/|x − p|²,
// σ = ∫ cos θ'/r² dA by Green's theorem about p's foot point (G(s)/s² =
// 1/(r(r + h))), s the sign that makes the first moment ½∮ n·(u × du)
// positive. Every piece by adaptive Gauss–Kronrod (61 points, 1e-14).
double planar_light_cos2_solid_angle(const Scene& scene, size_t light_index, const Vec3& p, const Vec3& n,
                                     std::optional<size_t> receiver);

// ∫_visible (cos θ·cos θ'/r²)² dA, m⁻² (the light-area second-moment kernel),
// for the same configurations, any receiver orientation: a small unoccluded
// disk (R ≤ kSmallAngle·(distance − R)) by small_disk_area_kernel's product
// rule (the contour's ray terms would cancel, as for E); everything else by
// contour_area_kernel over the exact visible boundary.
double planar_light_area_kernel(const Scene& scene, size_t light_index, const Vec3& p, const Vec3& n,
                                std::optional<size_t> receiver);

// The object `object` of `scene` alone, as a two-sided emitter of unit
// radiance: its irradiance and cos² kernel through the functions above are
// the solid-angle measures of a blocker (a tilted disk hiding the sky).
Scene as_lone_unit_emitter(const Scene& scene, size_t object);

}  // namespace furnace::analytic
