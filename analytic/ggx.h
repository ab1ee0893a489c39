// Exact direct lighting of a rough specular (isotropic GGX) receiver: the
// microfacet BRDF as a Receiver (receiver.h), whose light-integral machinery
// gives the radiance it reflects toward a viewer and the second moments of
// every direct strategy's single-sample estimator of it.
//
// The BRDF, written here from its definition (Walter et al. 2007,
// "Microfacet models for refraction through rough surfaces"; Heitz 2014,
// "Understanding the masking-shadowing function in microfacet-based BRDFs";
// the same convention core/scene.h's Material names), Fresnel ≡ 1 or the
// exact conductor Fresnel F(ωo·h) of the material's index: with n the
// unit normal facing the viewer, μo = n·ωo > 0, μi = n·ωi > 0 and the half
// vector h = H/|H|, H = ωo + ωi,
//     f(ωo, ωi) = ρ·D(h)·G2(ωo, ωi)/(4 μo μi),
//     D(m) = α²/(π (α² m_z² + m_x² + m_y²)²)                (unit m, local frame),
//     Λ(ω) = (√(1 + α² tan²θ) − 1)/2,  G1 = 1/(1 + Λ),
//     G2 = G1(ωo)·G1(ωi) (separable) or 1/(1 + Λ(ωo) + Λ(ωi)) (height-correlated),
// ρ the material's albedo (a constant factor), α its roughness.
//
// In the receiver model's two cosines (cos θ = μi, cos α = r·ωi, r the mirror
// direction of ωo), with ωo·ωi = 2μoμi − cos α:
//     |H|²  = 2(1 − cos α + 2μoμi)            (a sum of non-negative terms),
//     n·H   = μo + μi,
//     |H⊥|² = |H|² − (n·H)² = 2(1 − cos α) − (μi − μo)²,
// H⊥ the part of H in the tangent plane (H⊥ = (ωi − r)⊥, since ωo⊥ = −r⊥), so
//     D(h) = α²|H|⁴/(π (α²(n·H)² + |H⊥|²)²)
// without a normalisation of h; ωo·h = |H|/2 > 0 for every ωi above the horizon.
//
// Its sampling (bsdf): the visible normals of ωo (Heitz 2018), density
// D_ωo(m) = G1(ωo)·max(0, ωo·m)·D(m)/μo, and ωi = reflect(ωo, m), whose
// density in solid angle is D_ωo(h)/(4 ωo·h), so
//     p_b(ωi) = G1(ωo)·D(h)/(4μo)     (sr⁻¹; below the horizon: a failed sample),
//     f·μi = ρ·D·G2/(4μo),
//     (f·μi)²/p_b = ρ²·D·(G2²/G1(ωo))/(4μo),
// with G2²/G1(ωo) = G1(ωo)·G1(ωi)² (separable) or
// (1 + Λ(ωo))/(1 + Λ(ωo) + Λ(ωi))² (height-correlated): D cancels once, never
// divided. The lobe has no cut at the mirror plane (f > 0 on the whole upper
// hemisphere), so the environment is integrated about n.
//
// Closed forms used by the tests (derived in ggx.cpp): at α = 1, D = 1/π and
// G1(ω) = 2μ/(1 + μ), so f = ρ/(π(1 + μo)(1 + μi)) (separable) or
// ρ/(2π(μo + μi)) (height-correlated), both independent of the azimuth, and
// the directional albedo is 2(1 − ln 2)ρ/(1 + μo), resp. ρ(1 − μo ln((1 + μo)/μo)).
//
// Domain: as receiver.h (unoccluded sphere lights, the unblocked constant
// sky, disk, rectangle and triangle lights past parallel disk occluders),
// α in [scene_limits::kMinGgxAlpha, 1]. Units: radiance W·m⁻²·sr⁻¹, second
// moments its square.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "analytic/receiver.h"
#include "core/scene.h"
#include "core/strategy.h"

namespace furnace::analytic {

// The claimed accuracy of the GGX references: the receiver model's
// quadrature tolerance. Measured against 50-digit values
// (tests/analytic/ggx_precision_test.cpp): ≤ 1e-13 relative for the radiance
// and every direct strategy's E[Y²], α from kMinGgxAlpha to 1, views from
// normal to μo = 0.05, under the sky, sphere lights, planar lights and
// disk_occluder's occluded disk. That needs the receiver's two optional
// members below (receiver.h): from cos α alone, D at α = 1e-3 was off by
// ~1e-11. The error each value reached is reported to the open ErrorLedger
// (error_ledger.h; receiver_integrals.h), a bound the same tests check
// covers the error against those values.
inline constexpr double kGgxQuadratureTolerance = kReceiverQuadratureTolerance;

// f(ωo, ωi) of the GGX BRDF above at n·ωo = cos_theta_o > 0, n·ωi =
// cos_theta_i > 0 and r·ωi = cos_alpha (r the mirror direction of ωo), sr⁻¹.
// 0 when either cosine is ≤ 0.
// With `fresnel`, f carries the conductor's F(ωo·h) (analytic/fresnel.h), ωo·h = |H|/2.
double ggx_brdf(double albedo, double alpha, MicrofacetShadowing shadowing, double cos_theta_o, double cos_theta_i,
                double cos_alpha, std::optional<ConductorIndex> fresnel = std::nullopt);

// Λ(ω) of the GGX distribution at n·ω = cos_theta > 0 (the stable form
// α²tan²θ/(2(√(1 + α²tan²θ) + 1))), dimensionless.
double ggx_lambda(double alpha, double cos_theta);

// The GGX receiver at one point: its frame and microfacet parameters.
class GgxReceiver final : public ReceiverModel<GgxReceiver> {
 public:
  GgxReceiver(const Vec3& n, const Vec3& wo, double albedo, double alpha, MicrofacetShadowing shadowing,
              std::optional<ConductorIndex> fresnel = std::nullopt);
  double albedo = 0;
  double alpha = 0;
  MicrofacetShadowing shadowing = MicrofacetShadowing::kHeightCorrelated;
  std::optional<ConductorIndex> fresnel;  // none: F ≡ 1

  // at_direction with 1 − cos α computed from cos α (off by ~ε/(1 − cos α)
  // relative near the mirror direction: the machinery calls at_direction).
  BsdfValue at(double cos_theta, double cos_alpha) const override;
  // The BSDF from 1 − cos α accurate relative to itself (receiver.h): D reads
  // |H⊥|² = 2(1 − cos α) − (μi − μo)², whose scale at the peak is ~α².
  BsdfValue at_direction(double cos_theta, double cos_alpha, double one_minus_cos_alpha) const;
  // The lobe's angular scale about r: D halves within ~α of h = n, and
  // ωi turns by twice h's angle (receiver.h's graded cuts).
  double lobe_width() const { return alpha; }
  bool vanishes_below_mirror_plane() const override { return false; }
  std::vector<double> parameters() const override;
  std::string name() const override { return "a GGX receiver"; }
  Material material() const override { return Material{albedo, Ggx{alpha, shadowing, fresnel}}; }

 private:
  double cos_theta_o_;  // μo = n·ωo
  double lambda_o_;     // Λ(ωo)
  double alpha2_;       // α²
};
// Instantiated once, in ggx.cpp.
extern template class ReceiverModel<GgxReceiver>;

}  // namespace furnace::analytic
