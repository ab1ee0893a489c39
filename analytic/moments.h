// Exact second moments E[Y²] of the single-sample irradiance estimators at a
// receiving point, so verify/ can predict each strategy's variance
// Var Y = E[Y²] − E² (and test it), not only its mean E.
//
// Units: Y is an irradiance estimate (W·m⁻²); E[Y²] is in W²·m⁻⁴.
// Supported: every emitter irradiance() solves for the cosine estimator
// (E[Y²] = π Σ L·E needs only the irradiances); for the uniform-hemisphere
// and light-area estimators, disk lights on the circle fast path (parallel
// receiver, parallel disk occluders) and unoccluded sphere, rectangle and
// triangle lights (light_moments.h); the environment with non-overlapping
// blockers (spheres, polygons, parallel disks). Elsewhere throws
// furnace::Error, like irradiance() does.
#pragma once

#include <optional>

#include "core/scene.h"

namespace furnace::analytic {

// The single-sample irradiance estimators. The names mirror the renderer's
// direct strategies; the definitions are written here independently.
enum class Estimator {
  // ω uniform on the hemisphere about n, p(ω) = 1/(2π) sr⁻¹:
  //   Y = Li(ω)·cos θ·2π,  E[Y²] = 2π ∫ Li² cos²θ dω.
  kUniformHemisphere,
  // ω cosine-distributed, p(ω) = cos θ/π sr⁻¹:
  //   Y = Li(ω)·π,  E[Y²] = π ∫ Li² cos θ dω = π Σ_lights L·E_light.
  kCosineHemisphere,
  // One light chosen uniformly among the K emitters (plus the environment
  // when its radiance is positive, sampled cosine-weighted), then a point x
  // uniform on the chosen emitter's area A, p_A = 1/A:
  //   Y = K·L·V·cos θ·cos θ'/r²·A,  E[Y²] = Σ_lights K·A·L² ∫_visible (cos θ cos θ'/r²)² dA
  //   (+ K·π·L_env·E_env for the environment; an environment map is
  //   importance-sampled instead, see environment_map.h).
  kLightArea,
};

// E[Y²] at p with unit normal n; `receiver` as in irradiance().
// Method: for a parallel disk light at height h the integrands are radial
// about p's foot point, cos θ = cos θ' = h/r, r² = h² + s²:
//   uniform hemisphere: ∫_visible cos²θ·cos θ'/r² dA = ∫_visible h³/(h²+s²)^(5/2) dA,
//   light area:         ∫_visible (cos θ cos θ'/r²)² dA = ∫_visible h⁴/(h²+s²)⁴ dA,
// each reduced to a contour integral over the visible region's boundary
// arcs (contour_quadrature, Green's theorem as in disk.h) with
//   G(s)/s² = (1 + c + c²)/(3r(r + h)), c = h/r    (uniform hemisphere),
//   G(s)/s² = (3h⁴ + 3h²s² + s⁴)/(6h²(h²+s²)³)    (light area),
// (r = √(h² + s²)), both written without the cancelling 1 − (h/r)^k form.
// Unoccluded environment: ∫ cos²θ dω = 2π/3 over the hemisphere.
// Finiteness: every supported case has h > 0 and is finite. The light-area
// moment grows like A·L²/(h²) as p approaches the emitter plane (h → 0) and is
// infinite for a light that touches the receiver (r → 0 on the visible
// region); the hemisphere moments are bounded by 2π²L²/3 and π²L².
double second_moment(Estimator estimator, const Scene& scene, const Vec3& p, const Vec3& n,
                     std::optional<size_t> receiver);

// Second moment of the pixel estimator the renderer averages at the centre of
// pixel (px, py): Y_px = Le + (ρ/π)·Y at a Lambertian hit, so
//   E[Y_px²] = Le² + 2·Le·(ρ/π)·E + (ρ/π)²·E[Y²];
// a miss sees the environment: E[Y_px²] = L_env² (zero variance).
double pixel_center_second_moment(Estimator estimator, const Scene& scene, int px, int py);

}  // namespace furnace::analytic
