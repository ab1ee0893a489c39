// Closed forms for uniform Lambertian disk emitters seen from a receiver
// plane parallel to the disk, and the contour (Stokes) integral along circle
// arcs that the occluded configurations are built from.
//
// Geometry and units: the emitter plane lies at height h > 0 above the
// receiving point p, measured along the receiver normal; lengths in scene
// units, radiance L in W·m⁻²·sr⁻¹, irradiance in W·m⁻². All functions
// return E/L (dimensionless, "πF" with F the configuration factor), so a
// caller multiplies by L.
#pragma once

namespace furnace::analytic {

// Unoccluded disk of radius R in a plane at height h, its centre at in-plane
// distance d from the foot point of p; receiver normal perpendicular to both
// planes. Returns E/L = π·F with
//   F = ½·(1 − (h² + d² − R²) / √((h² + d² + R²)² − 4R²d²))
// (Howell, "A Catalog of Radiation Heat Transfer Configuration Factors",
// factor B-13, differential planar element to parallel disk; Sparrow & Cess,
// "Radiation Heat Transfer", 1978).
// Stable form: the root factors as S = √(h²+(d−R)²)·√(h²+(d+R)²) (no overflow,
// no cancellation), and when a = h² + d² − R² ≥ 0 the difference 1 − a/S is
// rewritten as (S² − a²)/(S(S + a)) = 4R²h²/(S(S + a)), which keeps full
// relative precision for tiny (R ≪ h) and far lights. When a < 0 the two
// terms of 1 − a/S add and nothing cancels.
// Domain: h > 0, R ≥ 0, d ≥ 0 (finite). Throws furnace::Error otherwise.
// Limits: R → 0 gives πR²·h²/(h²+d²)² (point light of intensity L·πR²·cosθ');
// h → 0 with d < R gives π; d = 0 gives π·R²/(h² + R²).
double disk_irradiance_parallel(double R, double h, double d);

// π − disk_irradiance_parallel(R, h, d): the projected solid angle of the
// hemisphere the disk leaves open, computed directly,
//   π − E/L = (π/2)·(1 + a/S),
// with 1 + a/S = 4R²h²/(S(S − a)) when a < 0 (a disk much wider than its
// height, the near-total blocking case, where π − E would cancel), the plain
// sum otherwise. Same domain.
double disk_irradiance_parallel_complement(double R, double h, double d);

// A circle in the emitter plane, in 2-D coordinates whose origin is the foot
// point of p (the orthogonal projection of p onto the plane).
struct Circle2 {
  double cx = 0, cy = 0, radius = 0;
};

// Contour integral ½·∫ s²/(h² + s²) dφ along the arc of `circle` from
// parameter angle t0 to t0 + sweep (sweep > 0 is counter-clockwise; points
// are (cx + r·cos t, cy + r·sin t)); s is the distance from the origin and φ
// the polar angle about it.
// Why: for a region A in the plane, by Green's theorem in polar coordinates,
//   ∫_A h²/(h²+s²)² dA = ∫ dφ ∫₀^s h² s'/(h²+s'²)² ds' = ½ ∮_∂A s²/(h²+s²) dφ,
// and h²/(h²+s²)² = cosθ·cosθ'/r² is the irradiance kernel for parallel planes.
// The inner antiderivative vanishes at s = 0, so the form also holds when A
// contains the origin. Boundary counter-clockwise; holes clockwise.
// Closed form (derived here): with u = t − atan2(cy, cx), D = √(cx²+cy²),
// α = √(h² + (D−r)²), β = √(h² + (D+r)²), S = αβ, a = h² + D² − r²,
//   arc = ½·[(1 − a/S)·sweep/2 + (a/S)·(δ(u₁) − δ(u₀))],
//   δ(u) = atan2((β−α)·sin u, (β+α) + (β−α)·cos u),
// from ∫ du/(P + Q cos u) = (2/S)·atan((α/β)·tan(u/2)) with P = h²+D²+r²,
// Q = 2rD, and the identity u/2 − atan((α/β)·tan(u/2)) = δ(u), which removes the
// branch of tan(u/2). β − α is evaluated as 4rD/(β+α) and 1 − a/S as in
// disk_irradiance_parallel, so a full circle reproduces it exactly in form.
// Domain: h > 0, r ≥ 0.
double arc_contour(double h, const Circle2& circle, double t0, double sweep);

}  // namespace furnace::analytic
