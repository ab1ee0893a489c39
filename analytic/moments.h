// Exact second moments E[Y²] of the single-sample irradiance estimators at a
// receiving point, so verify/ can predict each strategy's variance
// Var Y = E[Y²] − E² (and test it), not only its mean E.
//
// Units: Y is an irradiance estimate (W·m⁻²); E[Y²] is in W²·m⁻⁴.
// Supported: every emitter irradiance() solves for the cosine estimator
// (E[Y²] = π Σ L·E needs only the irradiances); for the uniform-hemisphere
// and light-area estimators, disk lights (any receiver orientation; parallel
// disk and planar polygon occluders, planar_light.h) and unoccluded sphere,
// rectangle and triangle lights (light_moments.h); the environment with non-overlapping
// blockers (spheres, polygons, parallel disks). For light solid-angle
// sampling, the cone / spherical polygon cases of unoccluded spheres and of
// polygons (occluders allowed) plus the light-area cases where the renderer
// falls back to area sampling; for MIS, unoccluded emitters and the
// environment. Elsewhere throws furnace::Error, like irradiance() does.
#pragma once

#include <array>
#include <optional>

#include "analytic/point_light.h"
#include "core/scene.h"
#include "core/strategy.h"

namespace furnace::analytic {

// The single-sample irradiance estimators, modelled for the strategies of
// core/strategy.h that have a variance model (the table's variance_model:
// bsdf sampling of a Lambertian receiver is modelled as cosine_hemisphere).
// Only the names are shared with the renderer; the definitions below are
// written here independently.
//  - uniform_hemisphere: ω uniform on the hemisphere about n, p(ω) = 1/(2π) sr⁻¹:
//      Y = Li(ω)·cos θ·2π,  E[Y²] = 2π ∫ Li² cos²θ dω.
//  - cosine_hemisphere: ω cosine-distributed, p(ω) = cos θ/π sr⁻¹:
//      Y = Li(ω)·π,  E[Y²] = π ∫ Li² cos θ dω = π Σ_lights L·E_light.
//  - light_area: one light chosen uniformly among the K emitters (plus the
//    environment when its radiance is positive, sampled cosine-weighted), then
//    a point x uniform on the chosen emitter's area A, p_A = 1/A:
//      Y = K·L·V·cos θ·cos θ'/r²·A,  E[Y²] = Σ_lights K·A·L² ∫_visible (cos θ cos θ'/r²)² dA
//      (+ K·π·L_env·E_env for the environment; an environment map is
//      importance-sampled instead, see environment_map.h).
//  - light_solid_angle: one light chosen uniformly (K as for light_area), then
//    a direction uniform in the solid angle Ω the emitter subtends where the
//    renderer has an exact map: the cone of a sphere seen from outside, the
//    whole spherical triangle, or the whole spherical rectangle (edges
//    perpendicular within kPerpendicularTolerance) of a polygon seen from its
//    emitting side with Ω ≥ kMinSampledSolidAngle, p = 1/Ω (directions below
//    p's horizon or into an occluder give Y = 0). Disks, sheared
//    parallelograms and tinier polygons are sampled by area as in light_area;
//    the environment cosine-weighted:
//      Y = K·L·V·max(cos θ, 0)·Ω,  E[Y²] = Σ_lights K·Ω·L² ∫_visible max(cos θ, 0)² dω
//      (+ the light_area terms of area-sampled emitters and the environment).
//  - mis_balance, mis_power (multi-sample MIS on a Lambertian receiver): one
//    cosine (BSDF) sample and one light_solid_angle sample, each weighted by
//    the heuristic w_s = p_s^β/(p_b^β + p_l^β), β the table's mis_beta, with
//    p_b = cos θ/π and p_l the light strategy's density in solid angle
//    (selection pmf included; 1/Ω, the area density p_A·r²/cos θ', or the
//    environment's cos θ/π):
//      Y = Y_b + Y_l (independent),  E[Y²] = E[Y_b²] + E[Y_l²] + 2·E[Y_b]·E[Y_l],
//      E[Y_s²] = ∫ w_s² (L cos θ)²/p_s dω,  E[Y_s] = ∫ w_s L cos θ dω.
//    Supported: unoccluded emitters (every one by quadrature over its solid
//    angle), the constant environment (w constant on the open sky, so its
//    terms follow from E_env) and point lights (found only by the light
//    sample, weight 1: E_l²/P_l and E_l), under uniform or power selection
//    (each light's own pmf P_l); elsewhere throws furnace::Error.
//  - mis_one_sample: with probability c = kOneSampleBsdfProbability one BSDF
//    sample, else one light_solid_angle sample, weighted by Veach's one-sample
//    balance heuristic, so the direction has the mixture density
//    q = c·p_b + (1 − c)·p_l and Y = L cos θ/q:
//      E[Y²] = ∫ (L cos θ)²/q dω   (same support and quadrature as above).

// E[Y²] at p with unit normal n of the strategy's single-sample estimator;
// `receiver` as in irradiance(). Throws furnace::Error for a strategy without
// a variance model.
// Method: for a parallel disk light at height h the integrands are radial
// about p's foot point, cos θ = cos θ' = h/r, r² = h² + s²:
//   uniform hemisphere: ∫_visible cos²θ·cos θ'/r² dA = ∫_visible h³/(h²+s²)^(5/2) dA,
//   light area:         ∫_visible (cos θ cos θ'/r²)² dA = ∫_visible h⁴/(h²+s²)⁴ dA,
// each reduced to a contour integral over the visible region's boundary
// arcs (contour_quadrature, Green's theorem as in disk.h) with
//   G(s)/s² = (1 + c + c²)/(3r(r + h)), c = h/r    (uniform hemisphere),
//   G(s)/s² = (3h⁴ + 3h²s² + s⁴)/(6h²(h²+s²)³)    (light area),
// (r = √(h² + s²)), both written without the cancelling 1 − (h/r)^k form.
// A disk light under a tilted receiver (or past polygon occluders): the
// general planar path, planar_light_cos2_solid_angle and
// planar_light_area_kernel (contour_area_kernel.h).
// Light solid angle: Ω in closed form (light_moments.h), the cos² integral
// as for the uniform hemisphere (spheres unoccluded; polygons by the exact
// planar path, occluders allowed).
// Unoccluded environment: ∫ cos²θ dω = 2π/3 over the hemisphere.
// Finiteness: every supported case has h > 0 and is finite. The light-area
// moment grows like A·L²/(h²) as p approaches the emitter plane (h → 0) and is
// infinite for a light that touches the receiver (r → 0 on the visible
// region); the hemisphere moments are bounded by 2π²L²/3 and π²L².
// Light selection (light-sampling estimators only): with light l chosen with
// pmf P_l (light_selection_pmf, point_light.h) and M_l the second moment of
// light l's own estimator at pmf 1, E[Y²] = Σ_l M_l/P_l (uniform: P_l = 1/K).
// A point light's estimator at pmf 1 is exact, Y_l = E_l, so M_l = E_l².
// Point lights are invisible to the hemisphere estimators: refused for them.
double second_moment(Strategy strategy, const Scene& scene, const Vec3& p, const Vec3& n,
                     std::optional<size_t> receiver, LightSelection selection = LightSelection::kUniform);

// Second moment of the pixel estimator the renderer averages at the centre of
// pixel (px, py): Y_px = Le + (ρ/π)·Y at a Lambertian hit, so
//   E[Y_px²] = Le² + 2·Le·(ρ/π)·E + (ρ/π)²·E[Y²];
// at a glossy (Phong, GGX) hit Y_px = Le + Y with Y the glossy estimator,
// whose second moment takes the strategy itself (bsdf sampling is the lobe
// there, not cosine sampling);
// a miss sees the environment: E[Y_px²] = L_env² (zero variance).
// (glossy.h's glossy_reflected_radiance and glossy_second_moment).
double pixel_center_second_moment(Strategy strategy, const Scene& scene, int px, int py,
                                  LightSelection selection = LightSelection::kUniform);

// E[Y²] of mis_balance and mis_power ({balance, power}) from one quadrature:
// the two heuristics share every direction's densities, so their terms are
// integrated together (each to its own tolerance). second_moment of either
// strategy computes this pair and returns its entry, so the values are the
// same, bit for bit, whichever function asks; the error reported to the open
// ErrorLedger covers both.
std::array<double, 2> multi_sample_mis_second_moments(const Scene& scene, const Vec3& p, const Vec3& n,
                                                      std::optional<size_t> receiver,
                                                      LightSelection selection = LightSelection::kUniform);
// pixel_center_second_moment of mis_balance and of mis_power ({balance,
// power}), equal to the bit to the two calls, at the cost of about one.
std::array<double, 2> pixel_center_multi_sample_mis_second_moments(const Scene& scene, int px, int py,
                                                                   LightSelection selection = LightSelection::kUniform);

}  // namespace furnace::analytic
