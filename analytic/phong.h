// Exact direct lighting of a glossy (normalised Phong) receiver: the radiance
// it reflects toward a viewer and the second moments of the single-sample
// estimators of it, by quadrature.
//
// The lobe, written here from its definition (Lafortune & Willems 1994,
// "Using the modified Phong reflectance model for physically based
// rendering"; the same convention core/scene.h's Material names): with n the
// receiver's unit normal facing the viewer, ωo the unit direction toward the
// viewer, r = 2(n·ωo)n − ωo the mirror direction and cos α = max(r·ωi, 0),
//     f(ωo, ωi) = ρ·(e+2)/(2π)·cos^e α        for n·ωi > 0, n·ωo > 0,
// e the exponent, ρ the material's albedo. The constant (e+2)/(2π) is the one
// that makes the albedo at normal incidence (r = n, no horizon cut) exactly ρ:
//     ∫ (e+2)/(2π) cos^e α cos α dω = (e+2)·∫₀^{π/2} cos^{e+1} α sin α dα = 1.
// Away from normal incidence the horizon cuts the lobe and the albedo is
// ρ·∫_{n·ω>0} (e+2)/(2π) cos^e α (n·ω) dω < ρ (the quadrature below; the
// closed form ρ·(n·r) holds only where no lobe direction with cos α > 0 is
// below the horizon, i.e. r = n).
//
// The estimators (only the names are shared with the renderer), each of
// h(ω) = f(ωo, ω)·(n·ω)·Li(ω) with Li the light's radiance along ω:
//  - bsdf: ω from the lobe density p_b(ω) = (e+1)/(2π)·cos^e α about r,
//    directions below the horizon a failed sample (Y = 0): Y = h/p_b;
//  - uniform_hemisphere (p = 1/(2π)), cosine_hemisphere (p = (n·ω)/π): Y = h/p;
//  - light_solid_angle: a light chosen with pmf P, a sphere's cone uniformly
//    (p_l = P/Ω), the constant environment cosine-weighted (p_l = P·(n·ω)/π);
//  - light_area: a sphere's surface uniformly, p_l = P·d²/(A cos θ') with d
//    the distance to the near intersection, θ' the emission angle, A = 4πR²;
//    the environment as for light_solid_angle;
//  - mis_balance, mis_power: one bsdf and one light_solid_angle sample, Veach's
//    heuristic w_s = p_s^β/(p_b^β + p_l^β) (β = 1, 2):
//      E[Y²] = E[Y_b²] + E[Y_l²] + 2 E[Y_b] E[Y_l],
//      E[Y_s²] = ∫ w_s² h²/p_s dω, E[Y_s] = ∫ w_s h dω;
//  - mis_one_sample: bsdf with probability c = kOneSampleBsdfProbability, else
//    light_solid_angle, q = c·p_b + (1 − c)·p_l, E[Y²] = ∫ h²/q dω.
// Every other single-sample estimator has E[Y²] = ∫ h²/p dω over the support
// of h, summed over the lights (whose solid angles do not overlap).
//
// Method: each light's directions are a spherical cap (a sphere's cone, or
// for the environment the lobe's own cap cos α ≥ 0 about r, outside which f
// is 0), integrated in coordinates centred on the cap's axis: outer polar
// angle, inner azimuth over the exact arcs where n·ω > 0 (n·ω = A + B cos ψ +
// C sin ψ on a ring). Adaptive Gauss–Kronrod (core/adaptive_quadrature.h),
// relative tolerance kPhongQuadratureTolerance, with the outer interval cut
// where the horizon starts to cut the rings and at the ring through the mirror
// direction, and the inner arcs cut at the mirror direction's azimuth (the
// lobe's peak). For a sphere the outer variable is v with
// sin γ = (R/D)·sin v, so √(R² − D² sin²γ) = R cos v is smooth at the rim
// (the light-area density's emission cosine).
//
// Domain: receiver points outside every sphere light, viewer above the
// receiver (n·ωo > 0), exponent ≥ 0. Units: radiance W·m⁻²·sr⁻¹, second
// moments its square.
#pragma once

#include <optional>

#include "core/scene.h"
#include "core/strategy.h"

namespace furnace::analytic {

// Relative tolerance of the nested quadratures (far below any test's power:
// the suite detects relative biases of 1e-4 at best).
inline constexpr double kPhongQuadratureTolerance = 1e-9;

// f(ωo, ωi) of the normalised Phong lobe above; `cos_alpha` = r·ωi. 0 for
// cos α ≤ 0 (the caller excludes directions below the horizon).
double phong_brdf(double albedo, double exponent, double cos_alpha);

// The glossy receiver at one point: its frame and lobe.
struct PhongReceiver {
  Vec3 n;   // unit normal on the viewer's side
  Vec3 wo;  // unit direction toward the viewer, n·wo > 0
  double albedo = 0;
  double exponent = 0;
  Vec3 mirror() const;  // r = 2(n·ωo)n − ωo
};

// ∫_{cone ∩ n·ω>0} f·(n·ω) dω over the cone of a sphere of radius R whose
// centre is at `center` relative to the receiving point (|center| > R): the
// reflected radiance per unit emitted radiance, unoccluded.
double phong_sphere_reflectance(const PhongReceiver& receiver, const Vec3& center, double radius);

// ∫_{n·ω>0} f·(n·ω) dω: the directional albedo, the reflected radiance per
// unit radiance of an unblocked constant environment.
double phong_directional_albedo(const PhongReceiver& receiver);

// Radiance reflected toward `wo` at point p of the Phong object `receiver`
// (normal n facing wo), direct lighting only: sphere emitters (unoccluded)
// and the constant environment (unblocked). Throws furnace::Error naming the
// scene and the configuration for anything else (point lights, an
// environment map, other emitter shapes, occluders).
double phong_reflected_radiance(const Scene& scene, const Vec3& p, const Vec3& n, const Vec3& wo, size_t receiver);

// E[Y²] of the strategy's single-sample estimator of that radiance (Y the
// reflected part only, emission excluded), for the lights
// phong_reflected_radiance solves, under the given light selection. Throws
// furnace::Error for a path tracer or an unsupported configuration.
double phong_second_moment(Strategy strategy, const Scene& scene, const Vec3& p, const Vec3& n, const Vec3& wo,
                           size_t receiver, LightSelection selection = LightSelection::kUniform);

}  // namespace furnace::analytic
