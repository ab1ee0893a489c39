// The GGX microfacet BRDF as a Receiver (ggx.h); the integrals are the
// receiver model's (receiver.cpp).
//
// The closed forms at α = 1 (ggx.h), derived: Λ(ω) = (√(1 + tan²θ) − 1)/2 =
// (1/μ − 1)/2 = (1 − μ)/(2μ), so 1 + Λ = (1 + μ)/(2μ) and G1 = 2μ/(1 + μ);
// D(m) = 1/(π(m_z² + m_x² + m_y²)²) = 1/π. Then
//  - separable: f = ρ/π·G1(μo)G1(μi)/(4μoμi) = ρ/(π(1 + μo)(1 + μi)), and
//    ∫ f μi dω = 2πρ/(π(1 + μo))·∫₀¹ μ/(1 + μ) dμ = 2(1 − ln 2)ρ/(1 + μo);
//  - height-correlated: 1 + Λo + Λi = (μo + μi)/(2μoμi), f = ρ/(2π(μo + μi)),
//    and ∫ f μi dω = ρ·∫₀¹ μ/(μo + μ) dμ = ρ(1 − μo ln((1 + μo)/μo)).
// And p_b = G1(μo)/(4πμo) = 1/(2π(1 + μo)) is constant over the directions
// above the horizon: the fraction of bsdf samples that are not failed is
// 2π/(2π(1 + μo)) = 1/(1 + μo).
#include "analytic/ggx.h"

#include <cmath>
#include <string>
#include <vector>

#include "analytic/fresnel.h"
#include "analytic/receiver_integrals.h"

namespace furnace::analytic {

namespace {

// The microfacet terms at one incident direction, from the two cosines
// (ggx.h): everything f, p_b and their ratio need, computed once.
struct Microfacet {
  double d = 0;         // D(h), sr⁻¹
  double lambda_i = 0;  // Λ(ωi)
};

// D(h) = α²|H|⁴/(π(α²(n·H)² + |H⊥|²)²) with |H|² = 2(1 − cos α + 2μoμi),
// n·H = μo + μi, |H⊥|² = 2(1 − cos α) − (μi − μo)² (clamped at 0: the two
// terms are equal to round-off at the mirror direction, where |H⊥| = 0);
// gap = 1 − cos α = 1 − r·ωi ≥ 0.
double ggx_d(double alpha2, double mu_o, double mu_i, double gap) {
  const double h2 = 2 * (gap + 2 * mu_o * mu_i);
  const double nh = mu_o + mu_i;
  const double dmu = mu_i - mu_o;
  const double h_perp2 = std::fmax(2 * gap - dmu * dmu, 0.0);
  const double denom = alpha2 * nh * nh + h_perp2;
  return alpha2 * h2 * h2 / (kPi * denom * denom);
}

// G2 and G2²/G1(ωo) of the Smith form from Λ(ωo), Λ(ωi).
double smith_g2(MicrofacetShadowing shadowing, double lambda_o, double lambda_i) {
  switch (shadowing) {
    case MicrofacetShadowing::kSeparable:
      return 1 / ((1 + lambda_o) * (1 + lambda_i));
    case MicrofacetShadowing::kHeightCorrelated:
      return 1 / (1 + lambda_o + lambda_i);
  }
  return 0;  // not an enumerator (-Werror=switch lists them all)
}
double smith_g2_squared_over_g1o(MicrofacetShadowing shadowing, double lambda_o, double lambda_i) {
  switch (shadowing) {
    case MicrofacetShadowing::kSeparable: {
      const double g1i = 1 / (1 + lambda_i);
      return g1i * g1i / (1 + lambda_o);
    }
    case MicrofacetShadowing::kHeightCorrelated: {
      const double s = 1 + lambda_o + lambda_i;
      return (1 + lambda_o) / (s * s);
    }
  }
  return 0;
}

// F(ωo·h) with ωo·h = |H|/2 = √((1 − cos α + 2μoμi)/2) (|H|² above); 1 without an index.
double fresnel_at(const std::optional<ConductorIndex>& index, double mu_o, double mu_i, double gap) {
  if (!index) return 1.0;
  return fresnel_conductor_reference(std::sqrt(0.5 * (gap + 2 * mu_o * mu_i)), index->eta, index->k);
}

}  // namespace

double ggx_lambda(double alpha, double cos_theta) {
  // α²tan²θ with sin²θ = (1 − μ)(1 + μ) (no cancellation near μ = 1).
  const double a = alpha * alpha * (1 - cos_theta) * (1 + cos_theta) / (cos_theta * cos_theta);
  return a / (2 * (std::sqrt(1 + a) + 1));
}

double ggx_brdf(double albedo, double alpha, MicrofacetShadowing shadowing, double cos_theta_o, double cos_theta_i,
                double cos_alpha, std::optional<ConductorIndex> fresnel) {
  if (!(cos_theta_o > 0) || !(cos_theta_i > 0)) return 0.0;
  const double d = ggx_d(alpha * alpha, cos_theta_o, cos_theta_i, 1 - cos_alpha);
  const double g2 = smith_g2(shadowing, ggx_lambda(alpha, cos_theta_o), ggx_lambda(alpha, cos_theta_i));
  return albedo * fresnel_at(fresnel, cos_theta_o, cos_theta_i, 1 - cos_alpha) * d * g2 /
         (4 * cos_theta_o * cos_theta_i);
}

GgxReceiver::GgxReceiver(const Vec3& n, const Vec3& wo, double albedo, double alpha, MicrofacetShadowing shadowing,
                         std::optional<ConductorIndex> fresnel)
    : ReceiverModel(n, wo),
      albedo(albedo),
      alpha(alpha),
      shadowing(shadowing),
      fresnel(fresnel),
      cos_theta_o_(dot(n, wo)),
      lambda_o_(ggx_lambda(alpha, dot(n, wo))),
      alpha2_(alpha * alpha) {}

BsdfValue GgxReceiver::at(double cos_theta, double cos_alpha) const {
  return at_direction(cos_theta, cos_alpha, 1 - cos_alpha);
}

// The machinery (receiver_integrals.h, instantiated below, in this file)
// calls it at every quadrature node, where the compiler sees its definition.
BsdfValue GgxReceiver::at_direction(double cos_theta, double, double one_minus_cos_alpha) const {
  const double mu_o = cos_theta_o_;
  const double d = ggx_d(alpha2_, mu_o, cos_theta, one_minus_cos_alpha);
  const double lambda_i = ggx_lambda(alpha, cos_theta);
  const double g1o = 1 / (1 + lambda_o_);
  const double f = fresnel_at(fresnel, mu_o, cos_theta, one_minus_cos_alpha);
  BsdfValue value;
  value.f_cos = albedo * f * d * smith_g2(shadowing, lambda_o_, lambda_i) / (4 * mu_o);
  value.pdf_solid_angle = g1o * d / (4 * mu_o);
  value.f_cos2_over_pdf =
      albedo * albedo * f * f * d * smith_g2_squared_over_g1o(shadowing, lambda_o_, lambda_i) / (4 * mu_o);
  return value;
}

std::vector<double> GgxReceiver::parameters() const {
  if (fresnel) return {double(BsdfType::kGgx), albedo, alpha, double(shadowing), fresnel->eta, fresnel->k};
  return {double(BsdfType::kGgx), albedo, alpha, double(shadowing)};
}

template class ReceiverModel<GgxReceiver>;

}  // namespace furnace::analytic
