// Irradiance from planar emitters that subtend a small angle, by product
// Gauss rules over the emitter itself instead of a contour integral.
//
// Why: the contour forms (Lambert's edge sum, the arc integral of a circle)
// add boundary terms of size ~ (size/distance) that cancel down to an
// irradiance of size ~ (size/distance)², so a double evaluation loses about
// ε·(distance/size)² relative (1e-9 for a light 1e-4 of its distance).
// The area integral E/L = ∫ cos θ·cos θ'/r² dA has a positive integrand with
// no cancellation, and over an emitter of angular size q = size/distance it
// is analytic with its nearest complex singularity (r = 0) at a distance
// ~ 1/q in units of the emitter: an N-point Gauss–Legendre rule errs by
// ~ (q/4)^(2N), far below ε for q ≤ kSmallAngle with the N used here.
#pragma once

#include <vector>

#include "core/vec3.h"

namespace furnace::analytic {

// Largest size/distance ratio (emitter diameter over the distance from p to
// its nearest point) for which the product rules below are used. In the
// rule's own parameter (the emitter mapped to [−1, 1]) the kernel's nearest
// singularity lies ≥ 2/q away, so an N-point Gauss–Legendre rule errs by
// ~ (q/4)^(2N): at q = 0.25 and N = 16, ~ 1e-38. Lambert's edge sum, used
// above it, loses ~ ε·(1/q)² ≈ 16 ε there (more toward grazing).
inline constexpr double kSmallAngle = 0.25;

// size/distance of a polygon (vertices relative to p): its diameter over a
// lower bound of its distance from p (nearest vertex minus the diameter);
// infinity when that bound is not positive.
double polygon_angular_size(const std::vector<Vec3>& vertices);

// E/L = ∫_P max(n·x, 0)·|m·x|/|x|⁴ dA over a convex planar polygon P
// (vertices relative to p, either winding, m its unit normal) wholly on the
// upper side of p's horizon (n·x ≥ 0 at every vertex): a fan of triangles
// from vertex 0, each by a 16×16 Gauss–Legendre rule on the collapsed square
// (Duffy) x = v0 + s·(vi − v0) + s·t·(vi+1 − vi), dA = s·|e1 × e2| ds dt.
// Every term is ≥ 0, so the sum keeps full relative precision.
// Domain: polygon_angular_size ≤ kSmallAngle.
double small_polygon_irradiance(const std::vector<Vec3>& vertices, const Vec3& n);

// ∫_P (max(n·x, 0)·|m·x|/|x|⁴)² dA, m⁻² (the light-area second-moment kernel),
// by the same fan of product rules; same domain and preconditions. The
// squared kernel has the same singularity (a pole of twice the order), so
// the rule converges at the same rate with a larger constant.
double small_polygon_area_kernel(const std::vector<Vec3>& vertices, const Vec3& n);

// E/L = ∫ max(n·x, 0)·|m·x|/|x|⁴ dA over a disk (centre relative to p, unit
// normal m, radius R), the part below p's horizon cut off exactly: with e2
// along the in-plane gradient of n·x (any unit vector of the plane when
// n ∥ m) and e1 = e2 × m, the lit part is the segment β ≥ β0 of
// x = c + α·e1 + β·e2, mapped to β = R sin ψ (ψ ∈ [ψ0, π/2]),
// α = τ·R cos ψ (τ ∈ [−1, 1]), dA = R² cos²ψ dτ dψ, which removes the
// square-root end points of the chord; 16 × 16 Gauss–Legendre nodes.
// Domain: R/(|centre| − R) ≤ kSmallAngle.
double small_disk_irradiance(const Vec3& center, const Vec3& m, double R, const Vec3& n);

// ∫ (max(n·x, 0)·|m·x|/|x|⁴)² dA = ∫_lit (cos θ cos θ'/r²)² dA over the same
// disk (the light-area second-moment kernel, m⁻²), by the same segment map
// and rule. The squared kernel has the same singularity (r = 0, now a pole of
// twice the order), so the rule converges at the same rate, ~ (q/4)^(2N),
// with a larger constant. Domain: R/(|centre| − R) ≤ kSmallAngle.
double small_disk_area_kernel(const Vec3& center, const Vec3& m, double R, const Vec3& n);

}  // namespace furnace::analytic
