// Moment kernels of emitters, used by second_moment (moments.h): first the
// closed forms of unoccluded sphere and polygon emitters, then the
// scene-level kernels of one object, which pick the closed form or the exact
// planar / circle-region path its geometry and occluders need. Every function
// integrates over the part of the emitter above p's horizon (cos θ > 0) that
// faces p; vertices and centres are relative to p; n is p's unit normal.
// Dimensionless unless stated.
#pragma once

#include <optional>
#include <vector>

#include "core/scene.h"
#include "core/vec3.h"

namespace furnace::analytic {

// ∫_cone max(cos θ, 0)² dω over the directions to a sphere of radius R
// (|center| > R). Cone coordinates (γ, ψ) about the centre direction, angle β
// to n: cos θ = a + b cos ψ with a = cos γ cos β, b = sin γ sin β; the ψ
// integral of max(a + b cos ψ, 0)² is closed form,
//   2[(a² + b²/2)ψ_m + 2ab sin ψ_m + (b²/4) sin 2ψ_m],  ψ_m = acos(clamp(−a/b)),
// and γ ∈ [0, α] (sin α = R/|center|) by tanh–sinh, split where the horizon
// starts to cut the rings (γ = |π/2 − β|). Relative tolerance 1e-13. The
// ledger also gets the rings' round-off, kRoundoffUlps·ε times the whole
// cone's ∫ cos²θ dω: large relative to a sliver above the horizon.
double sphere_cos2_solid_angle(const Vec3& center, double R, const Vec3& n);

// ∫_{visible surface} (cos θ cos θ'/r²)² dA of a sphere = ∫_cone max(cos θ, 0)²·cos θ'/r² dω
// (dA = r² dω/cos θ'), with the near-side distance and cosine along a ray at
// angle γ from the axis, D = |center|:
//   r = (D² − R²)/(D cos γ + q),  cos θ' = q/R,  q = √((R − D sin γ)(R + D sin γ)),
// both cancellation-free. Units: m⁻². Same quadrature as above.
double sphere_area_kernel(const Vec3& center, double R, const Vec3& n);

// ∫_P max(cos θ, 0)² dω over a planar polygon (clipped to the horizon first):
// Arvo's recurrence for axial moments (Arvo, "Applications of Irradiance
// Tensors to the Simulation of Non-Lambertian Phenomena", SIGGRAPH 1995):
//   τ² = (σ + s·Σ_i (n_i·n)·∫_{edge i} (n·u) dθ)/3,
// σ the polygon's solid angle (fans of Van Oosterom–Strackee triangles,
// Ω = 2·atan2(a·(b × c), 1 + a·b + b·c + c·a)), n_i = unit(u_i × u_{i+1}),
// the edge integral (n·a) sin Θ + (n·b)(1 − cos Θ) with b ⟂ a in the edge's
// plane and 1 − cos Θ = 2 sin²(Θ/2), and s = ±1 the winding sign that makes
// Lambert's first moment ½ s Σ Θ_i (n_i·n) positive.
double polygon_cos2_solid_angle(const std::vector<Vec3>& vertices, const Vec3& n);

// ∫_P (max(cos θ, 0)·cos θ'/r²)² dA over a convex planar polygon (vertices
// relative to p, any winding), clipped to the horizon, = ∫ (n·x)²h²/(h²+ρ²)⁴ dA
// with h the plane's distance and ρ the distance from p's foot point F:
// Green's theorem in polar coordinates about F, the radial integral in
// closed form, its limit G∞ (~ 1/h⁴) integrated in closed form (skipped when
// F is outside, where it integrates to 0) and the remaining tail by adaptive
// Gauss–Kronrod along each edge in the edge's own polar angle (bounded
// cost; the error reached goes to the ErrorLedger). Keeps full precision and
// a cost of milliseconds as h → 0 (the kernel's peak of width h at F).
// Units: m⁻². Relative tolerance 1e-14. A small polygon (angular size ≤
// kSmallAngle, small_emitter.h) goes to small_polygon_area_kernel instead:
// with F far outside, the tails cancel to ~ (size/distance)² of their terms.
double polygon_area_kernel(const std::vector<Vec3>& vertices, const Vec3& n);

// Full (unclipped) solid angles, sr, for the solid-angle sampling densities
// p = 1/Ω: a sphere of radius R at distance D > R,
//   Ω = 2π(1 − cos α) = 2π·(R/D)²/(1 + √(1 − (R/D)²))   (no cancellation for small R/D),
// and a planar convex polygon (vertices relative to p, any winding) as the
// absolute sum of its fan of Van Oosterom–Strackee triangles,
//   Ω_abc = 2·atan2(a·(b × c), 1 + a·b + b·c + c·a)   (a, b, c unit).
double sphere_solid_angle(double D, double R);
double polygon_solid_angle(const std::vector<Vec3>& vertices);

// ---------------------------------------------------------------------------
// Scene-level kernels of object i of `scene` at p (receiver: the object p
// lies on, ignored as an occluder), over the part of it visible from p.

// A rectangle's or triangle's vertices relative to p.
std::vector<Vec3> polygon_vertices_relative(const Rectangle& r, const Vec3& p);
std::vector<Vec3> polygon_vertices_relative(const Triangle& t, const Vec3& p);

// K_cos2 = ∫_visible max(cos θ, 0)² dω of emitter i (the uniform-hemisphere
// and solid-angle estimators' kernel). A parallel disk light at height h:
// ∫_visible h³/(h²+s²)^(5/2) dA by contour quadrature (moments.h); a tilted
// one or a polygon: the exact planar path (planar_light.h); a sphere: the
// closed form above, unoccluded.
double emitter_cos2_kernel(const Scene& scene, size_t i, const Vec3& p, const Vec3& n, std::optional<size_t> receiver);

// K_area = ∫_visible (max(cos θ, 0)·cos θ'/r²)² dA of emitter i (the
// light-area estimator's kernel), m⁻²: as emitter_cos2_kernel, the
// unoccluded disk and polygon by the planar path's closed forms.
double emitter_area_kernel(const Scene& scene, size_t i, const Vec3& p, const Vec3& n, std::optional<size_t> receiver);

// ∫_object max(cos θ, 0)² dω of object j (any shape, unoccluded): the
// cos²-weighted solid angle an environment blocker hides from the
// uniform-hemisphere estimator.
double blocker_cos2_solid_angle(const Scene& scene, size_t j, const Vec3& p, const Vec3& n);

}  // namespace furnace::analytic
