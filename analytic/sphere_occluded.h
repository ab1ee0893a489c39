// A uniform Lambertian sphere light partly hidden by planar occluders
// (rectangles, triangles, disks): E/L by quadrature over exactly computed
// limits in the cone of directions that the sphere subtends.
#pragma once

#include <optional>
#include <vector>

#include "core/scene.h"

namespace furnace::analytic {

// E/L at p (unit normal n) = ∫ V(ω)·max(cos θ, 0) dω over the cone of the
// sphere `light` (p outside it), V = 0 where one of `occluders` (Rectangle,
// Triangle or Disk; throws furnace::Error on a Sphere) lies between p and the
// sphere's near surface.
// Method: with a = (c − p)/|c − p|, sin θmax = R/|c − p| and (u, v) ⟂ a,
// directions are ω(α, φ) = cos α·a + sin α·(cos φ·u + sin φ·v), dω = sin α dα dφ.
// For fixed φ the half-plane {p + r·ω(α, φ)} meets each occluder in a segment
// (plane–polygon or plane–disk intersection, exact), which blocks the
// α-interval it spans where it lies in front of the sphere's entry distance
// D·cos α − √(R² − D²sin²α) (the segment is cut where it crosses the sphere's
// great circle in that plane; pieces inside or behind the sphere block
// nothing). The blocked intervals are merged, clipped to [0, θmax] and to the
// horizon cos θ = A·cos α + B·sin α ≥ 0 (A = n·a, B = n·w_φ, i.e.
// |α − atan2(B, A)| ≤ π/2), and on each visible [α₀, α₁]
//   ∫ cos θ sin α dα = A·(sin²α₁ − sin²α₀)/2 + B·[α/2 − sin 2α/4]_{α₀}^{α₁}.
// The φ-integral is adaptive 15-point Gauss–Kronrod (Boost), split at the
// kinks known in closed form (the planes through a and an occluder vertex,
// a polygon edge's crossings of the cone, the planes tangent to a disk), with
// bisection capped in depth and in total count for the kinks left over (where
// an occluder's trace crosses the horizon or the sphere), so that the cost is
// bounded; the error estimate reached is reported to the open ErrorLedger
// (error_ledger.h). Target: 1e-13 of the unoccluded value, absolute. Units: dimensionless (E/L). Domain: |c − p| > R; occluders
// through p (seen edge-on) block nothing and are skipped.
double occluded_sphere_irradiance(const Sphere& light, const std::vector<Shape>& occluders, const Vec3& p,
                                  const Vec3& n);

// Scene-level: E/L at p from the sphere emitter `emitter`, past every object
// other than the emitter and `receiver`. Snyder's closed form
// (sphere_irradiance) when no object can block the cone (occlusion.h);
// occluded_sphere_irradiance when every possible blocker is planar; throws
// furnace::Error (naming the object) when a sphere may block.
double sphere_light_irradiance(const Scene& scene, size_t emitter, const Vec3& p, const Vec3& n,
                               std::optional<size_t> receiver);

}  // namespace furnace::analytic
