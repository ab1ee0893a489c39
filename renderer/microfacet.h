// The isotropic Trowbridge–Reitz (GGX) microfacet distribution: its normal
// density D, Smith's Λ, G1 and both forms of G2, and the exact sampling of
// its visible normals as a trio (sample, pdf, invert), in the style of
// renderer/sampling.h. Free functions of the local frame: z is the
// macrosurface normal, all directions unit vectors, α the roughness in
// [scene_limits::kMinGgxAlpha, 1].
//
// Formulas (Walter et al. 2007, "Microfacet models for refraction through
// rough surfaces"; Heitz 2014, "Understanding the masking-shadowing function
// in microfacet-based BRDFs", JCGT 3(2)):
//   D(m)  = α² / (π (α² m_z² + m_x² + m_y²)²)   for m_z > 0, else 0
//         = α² / (π cos⁴θm (α² + tan²θm)²);      ∫ D(m) cos θm dωm = 1;
//   Λ(ω)  = (√(1 + α² tan²θ) − 1)/2,  G1(ω) = 1/(1 + Λ(ω));
//   G2    = G1(ωo)·G1(ωi) (separable) or 1/(1 + Λ(ωo) + Λ(ωi)) (height-correlated);
//   D_ωo(m) = G1(ωo)·max(0, ωo·m)·D(m)/cos θo, the density of the normals
//         visible from ωo (sr⁻¹); ∫ D_ωo(m) dωm = 1.
//
// Numeric choices (the scene minimum α = 1e-3 and views down to cos θo ~ 1e-4
// are inside the contract):
//  - D uses m_x² + m_y² for sin²θm (never 1 − m_z², which cancels near the
//    normal, exactly where D peaks at 1/(πα²));
//  - Λ uses tan²θ = (x² + y²)/z² and the cancellation-free form
//    α²tan²θ/(2(√(1 + α²tan²θ) + 1)); at z → 0 the form gives Λ = +∞ and
//    G1 = G2 = 0 (never ∞/∞);
//  - the sampler is Dupuy & Benyoub 2023 ("Sampling Visible GGX Normals with
//    Spherical Caps", Computer Graphics Forum 42(8), HPG), exact like Heitz
//    2018 ("Sampling the GGX Distribution of Visible Normals", JCGT 7(4)) and
//    unlike the approximate inverse CDF of Heitz & d'Eon 2014. In the
//    configuration stretched to α = 1 the visible normals of view v are the
//    directions of c + v, c uniform on the spherical cap {c_z ≥ −v_z} of the
//    unit sphere; the normal is then unstretched. The cap's 1 − c_z and 1 + c_z are formed without
//    subtraction (1 − v_z = (v_x² + v_y²)/(1 + v_z)), and h_z = c_z + v_z
//    directly as (1 − u1)(1 + v_z) > 0, so every normal drawn has m_z > 0;
//  - no α² − 1 forms (which lose all digits as α → 1 and divide by zero at 1).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>

#include "core/vec3.h"
#include "renderer/sampling.h"

namespace furnace {

// GGX normal density D(m), per unit solid angle of m and unit projected area
// of the macrosurface (so ∫ D cos θm dωm = 1); 0 for m_z ≤ 0.
inline double ggx_distribution(const Vec3& m, double alpha) {
  if (!(m.z > 0)) return 0.0;
  const double a2 = alpha * alpha;
  const double s = a2 * m.z * m.z + (m.x * m.x + m.y * m.y);  // |m|²·cos²θm·(α² + tan²θm)
  return a2 / (kPi * s * s);
}

// Smith's Λ(ω) of GGX for ω above the horizon (ω_z > 0); +∞ for ω_z ≤ 0
// (no microsurface point sees a direction at or below the horizon).
inline double ggx_lambda(const Vec3& w, double alpha) {
  if (!(w.z > 0)) return std::numeric_limits<double>::infinity();
  const double a2t2 = alpha * alpha * (w.x * w.x + w.y * w.y) / (w.z * w.z);  // α²tan²θ, +∞ when z² underflows
  if (!(a2t2 < std::numeric_limits<double>::infinity())) return a2t2;
  return a2t2 / (2.0 * (std::sqrt(1.0 + a2t2) + 1.0));  // (√(1 + x) − 1)/2 without the cancellation
}

// Masking G1 = 1/(1 + Λ) from Λ, and of a direction.
inline double ggx_g1_from_lambda(double lambda) { return 1.0 / (1.0 + lambda); }
inline double ggx_g1(const Vec3& w, double alpha) { return ggx_g1_from_lambda(ggx_lambda(w, alpha)); }

// Masking-shadowing G2 from the two Λ, in its two Smith forms.
inline double ggx_g2_separable_from_lambdas(double lambda_o, double lambda_i) {
  return ggx_g1_from_lambda(lambda_o) * ggx_g1_from_lambda(lambda_i);
}
inline double ggx_g2_height_correlated_from_lambdas(double lambda_o, double lambda_i) {
  return 1.0 / (1.0 + lambda_o + lambda_i);
}

// The visible-normal density D_ωo(m) = G1(ωo)·max(0, ωo·m)·D(m)/cos θo from
// its parts, so that a caller that computes G1 or D its own way (GgxBsdf and
// its negative controls) shares the formula; 0 for ωo_z ≤ 0 or m_z ≤ 0.
inline double ggx_visible_normal_density(double g1_wo, double distribution_m, const Vec3& wo, const Vec3& m) {
  if (!(wo.z > 0 && m.z > 0)) return 0.0;
  return g1_wo * std::max(0.0, dot(wo, m)) * distribution_m / wo.z;
}

// ---------------------------------------------------------------------------
// Visible normals, the trio. wo must be a unit vector with wo_z > 0.

namespace microfacet_detail {
// The view in the configuration stretched to α = 1: normalize(α wo_x, α wo_y, wo_z).
inline Vec3 stretched(const Vec3& w, double alpha) { return scene_normalize({alpha * w.x, alpha * w.y, w.z}); }
}  // namespace microfacet_detail

// A normal m drawn with density D_ωo(m) (exactly; Dupuy & Benyoub 2023, see
// above): c.z = 1 − u1·(1 + v_z) uniform on the cap, its azimuth 2π·u2.
// Returns a unit m with m_z > 0 and ωo·m ≥ 0 up to round-off.
inline Vec3 sample_ggx_visible_normal(const Vec3& wo, double alpha, double u1, double u2) {
  const Vec3 v = microfacet_detail::stretched(wo, alpha);
  const double one_plus_vz = 1.0 + v.z;
  const double one_minus_vz = (v.x * v.x + v.y * v.y) / one_plus_vz;  // difference of squares, no cancellation
  const double hz = (1.0 - u1) * one_plus_vz;                        // c_z + v_z ∈ (0, 1 + v_z]
  const double one_minus_cz = u1 * one_plus_vz;
  const double one_plus_cz = one_minus_vz + hz;
  const double sin_c = sampling_detail::safe_sqrt(one_minus_cz * one_plus_cz);
  const sampling_detail::SinCos phi = sampling_detail::sin_cos_two_pi(u2);
  const Vec3 h{sin_c * phi.cos + v.x, sin_c * phi.sin + v.y, hz};  // along the stretched normal
  return scene_normalize({alpha * h.x, alpha * h.y, h.z});            // unstretch
}
// Density in solid angle of m (sr⁻¹): D_ωo(m); 0 where m_z ≤ 0 or ωo·m ≤ 0.
inline double ggx_visible_normal_pdf(const Vec3& wo, const Vec3& m, double alpha) {
  return ggx_visible_normal_density(ggx_g1(wo, alpha), ggx_distribution(m, alpha), wo, m);
}
// The (u1, u2) that sample_ggx_visible_normal maps to m; empty where the pdf
// is 0. The stretched normal n of m reflects the stretched view v to the cap
// point c = 2(n·v)n − v, and c_z + v_z = 2(n·v)n_z = (1 − u1)(1 + v_z).
inline std::optional<std::array<double, 2>> invert_ggx_visible_normal(const Vec3& wo, const Vec3& m, double alpha) {
  if (!(ggx_visible_normal_pdf(wo, m, alpha) > 0)) return std::nullopt;
  const Vec3 v = microfacet_detail::stretched(wo, alpha);
  const Vec3 n = scene_normalize({m.x / alpha, m.y / alpha, m.z});
  const double n_dot_v = dot(n, v);
  if (!(n_dot_v > 0)) return std::nullopt;  // visible in the unstretched frame, not here: round-off at the rim
  const double hz = 2.0 * n_dot_v * n.z;
  const double u1 = std::clamp(1.0 - hz / (1.0 + v.z), 0.0, std::nextafter(1.0, 0.0));
  const double cx = 2.0 * n_dot_v * n.x - v.x, cy = 2.0 * n_dot_v * n.y - v.y;
  return std::array<double, 2>{u1, sampling_detail::azimuth_to_unit(cx, cy)};
}

// Mirror reflection of wo about the unit normal m: 2(wo·m)m − wo.
inline Vec3 reflect_about(const Vec3& wo, const Vec3& m) { return 2.0 * dot(wo, m) * m - wo; }

}  // namespace furnace
