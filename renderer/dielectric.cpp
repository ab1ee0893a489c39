#include "renderer/dielectric.h"

#include <cmath>

#include "core/fresnel.h"

namespace furnace {

namespace {
// The direction below the surface mirrored above it, for Λ (a function of |cos θ|).
Vec3 upper(const Vec3& w) { return {w.x, w.y, std::fabs(w.z)}; }
}  // namespace

std::optional<Vec3> refract_through(const Vec3& wo, const Vec3& m, double eta) {
  const double cos_o = dot(wo, m);
  if (total_internal_reflection(cos_o, eta)) return std::nullopt;
  const double cos_t = refracted_cos(cos_o, eta);
  return scene_normalize(-wo / eta + (cos_o / eta - cos_t) * m);
}

double DielectricBsdf::transmission_scale() const {
  // DEFECT(dielectric_no_radiance_scaling): the radiance convention's 1/η² dropped.
  if (convention == TransportConvention::kNone || defect == Defect::kDielectricNoRadianceScaling) return 1.0;
  return 1.0 / (eta * eta);
}

double DielectricBsdf::fresnel(const Vec3& wo_local, const Vec3& m) const {
  // DEFECT(dielectric_macro_fresnel): F at the macro normal for every microfacet.
  const double c = defect == Defect::kDielectricMacroFresnel ? wo_local.z : dot(wo_local, m);
  return fresnel_dielectric(c, eta);
}

std::optional<Vec3> DielectricBsdf::transmission_half_vector(const Vec3& wo_local, const Vec3& wi_local) const {
  Vec3 h = wo_local + eta * wi_local;
  const double len = scene_length(h);
  if (!(len > 0)) return std::nullopt;
  h = h / len;
  if (h.z < 0) h = -h;
  // Each direction on its own side of the microfacet (pbrt-v3 #228).
  if (!(h.z > 0 && dot(wo_local, h) > 0 && dot(wi_local, h) < 0)) return std::nullopt;
  return h;
}

double DielectricBsdf::transmission_jacobian(const Vec3& wo_local, const Vec3& wi_local, const Vec3& m) const {
  const double wi_m = dot(wi_local, m), wo_m = dot(wo_local, m);
  // DEFECT(dielectric_reflection_jacobian): reflection's 1/(4|ωi·m|) for a refraction.
  if (defect == Defect::kDielectricReflectionJacobian) return 1.0 / (4.0 * std::fabs(wi_m));
  const double denom = eta * wi_m + wo_m;
  // DEFECT(dielectric_transmission_without_eta2): the Jacobian's η² left out (f and pdf alike).
  const double eta2 = defect == Defect::kDielectricTransmissionWithoutEta2 ? 1.0 : eta * eta;
  return eta2 * std::fabs(wi_m) / (denom * denom);
}

double DielectricBsdf::g2(const Vec3& wo_local, const Vec3& wi_local) const {
  const double lambda_o = ggx_lambda(wo_local, alpha), lambda_i = ggx_lambda(upper(wi_local), alpha);
  return shadowing == MicrofacetShadowing::kSeparable ? ggx_g2_separable_from_lambdas(lambda_o, lambda_i)
                                                      : ggx_g2_height_correlated_from_lambdas(lambda_o, lambda_i);
}

namespace {
// DEFECT(dielectric_tir_absorbs): a reflection whose F is 1 by total internal
// reflection is dropped, as if the missing transmission were absorbed.
bool tir_absorbed(const DielectricBsdf& b, double cos_o) {
  return b.defect == Defect::kDielectricTirAbsorbs && total_internal_reflection(cos_o, b.eta);
}
}  // namespace

double DielectricBsdf::eval(const Vec3& wo_local, const Vec3& wi_local) const {
  if (smooth() || !(wo_local.z > 0) || wi_local.z == 0) return 0.0;
  if (wi_local.z > 0) {
    const Vec3 h = scene_normalize(wo_local + wi_local);
    if (tir_absorbed(*this, dot(wo_local, h))) return 0.0;
    return albedo * fresnel(wo_local, h) * ggx_distribution(h, alpha) * g2(wo_local, wi_local) /
           (4.0 * wo_local.z * wi_local.z);
  }
  const std::optional<Vec3> m = transmission_half_vector(wo_local, wi_local);
  if (!m) return 0.0;
  const double t = 1.0 - fresnel(wo_local, *m);
  if (!(t > 0)) return 0.0;
  return albedo * transmission_scale() * t * ggx_distribution(*m, alpha) * g2(wo_local, wi_local) *
         dot(wo_local, *m) * transmission_jacobian(wo_local, wi_local, *m) / (wo_local.z * -wi_local.z);
}

double DielectricBsdf::pdf(const Vec3& wo_local, const Vec3& wi_local) const {
  if (smooth() || !(wo_local.z > 0) || wi_local.z == 0) return 0.0;
  const double g1_o = ggx_g1(wo_local, alpha);
  if (wi_local.z > 0) {
    const Vec3 h = scene_normalize(wo_local + wi_local);
    const double wo_h = dot(wo_local, h);
    if (!(wo_h > 0) || tir_absorbed(*this, wo_h)) return 0.0;
    return fresnel(wo_local, h) * ggx_visible_normal_density(g1_o, ggx_distribution(h, alpha), wo_local, h) /
           (4.0 * wo_h);
  }
  const std::optional<Vec3> m = transmission_half_vector(wo_local, wi_local);
  if (!m) return 0.0;
  const double t = 1.0 - fresnel(wo_local, *m);
  if (!(t > 0)) return 0.0;
  return t * ggx_visible_normal_density(g1_o, ggx_distribution(*m, alpha), wo_local, *m) *
         transmission_jacobian(wo_local, wi_local, *m);
}

std::optional<BsdfSample> DielectricBsdf::sample(const Vec3& wo_local, double u1, double u2, double u_lobe) const {
  if (!(wo_local.z > 0)) return std::nullopt;
  BsdfSample s;
  if (smooth()) {
    const Vec3 n{0, 0, 1};
    const double f = fresnel(wo_local, n);
    s.delta = true;
    s.pdf_solid_angle = 0;
    // Reflection with probability F.
    if (u_lobe < f) {
      if (tir_absorbed(*this, wo_local.z)) return std::nullopt;
      s.wi_local = {-wo_local.x, -wo_local.y, wo_local.z};
      s.weight = albedo;
      return s;
    }
    const std::optional<Vec3> wi = refract_through(wo_local, n, eta);
    if (!wi) return std::nullopt;  // F = 1 under TIR: not reached
    s.wi_local = *wi;
    s.radiance_scale = transmission_scale();
    s.weight = albedo * s.radiance_scale;
    s.transmitted = true;
    return s;
  }
  // Rough: a visible normal from (u1, u2), then the lobe from u_lobe.
  const Vec3 m = sample_ggx_visible_normal(wo_local, alpha, u1, u2);
  const double wo_m = dot(wo_local, m);
  if (!(wo_m > 0)) return std::nullopt;
  const double f = fresnel(wo_local, m);
  if (u_lobe < f) {
    s.wi_local = reflect_about(wo_local, m);
    if (!(s.wi_local.z > 0)) return std::nullopt;  // below the horizon: failed sample
  } else {
    const std::optional<Vec3> wi = refract_through(wo_local, m, eta);
    if (!wi || !(wi->z < 0)) return std::nullopt;  // refracted back above the macrosurface: failed sample
    s.wi_local = *wi;
    s.transmitted = true;
    s.radiance_scale = transmission_scale();
  }
  s.pdf_solid_angle = pdf(wo_local, s.wi_local);
  if (!(s.pdf_solid_angle > 0)) return std::nullopt;
  s.weight = eval(wo_local, s.wi_local) * std::fabs(s.wi_local.z) / s.pdf_solid_angle;
  return s;
}

}  // namespace furnace
