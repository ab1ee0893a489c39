#include "renderer/bsdf.h"

#include <cmath>

#include "core/fresnel.h"
#include "core/overloaded.h"

namespace furnace {

namespace {

// Lobe frame around the mirror direction of wo: z = reflect(wo).
Frame lobe_frame(const Vec3& wo_local) { return Frame::from_normal(scene_normalize(reflect_about_normal(wo_local))); }

// The Phong lobe's cos α for a query, in the lobe frame (shared by eval, sample and pdf).
double phong_cos_alpha(const Vec3& wo_local, const Vec3& wi_local) {
  return dot(scene_normalize(reflect_about_normal(wo_local)), wi_local);
}

}  // namespace

double LambertianBsdf::eval(const Vec3& wo_local, const Vec3& wi_local) const {
  return wo_local.z > 0 && wi_local.z > 0 ? albedo * kInvPi : 0.0;
}
std::optional<BsdfSample> LambertianBsdf::sample(const Vec3& wo_local, double u1, double u2) const {
  if (!(wo_local.z > 0)) return std::nullopt;
  BsdfSample s;
  s.wi_local = sample_cosine_hemisphere(u1, u2);
  s.pdf_solid_angle = pdf(wo_local, s.wi_local);
  if (!(s.pdf_solid_angle > 0)) return std::nullopt;
  s.weight = eval(wo_local, s.wi_local) * s.wi_local.z / s.pdf_solid_angle;
  return s;
}
double LambertianBsdf::pdf(const Vec3& wo_local, const Vec3& wi_local) const {
  return wo_local.z > 0 ? cosine_hemisphere_pdf(wi_local) : 0.0;
}

std::optional<BsdfSample> MirrorBsdf::sample(const Vec3& wo_local, double u1, double u2) const {
  if (!(wo_local.z > 0)) return std::nullopt;
  BsdfSample s;
  s.wi_local = reflect_about_normal(wo_local);
  s.weight = reflectance;  // f·cos/pdf with the delta and the 1/cos cancelled
  s.pdf_solid_angle = 0;
  s.delta = true;
  return s;
}

double PhongBsdf::eval(const Vec3& wo_local, const Vec3& wi_local) const {
  if (!(wo_local.z > 0 && wi_local.z > 0)) return 0.0;
  const double cos_alpha = phong_cos_alpha(wo_local, wi_local);
  if (!(cos_alpha > 0)) return 0.0;
  // DEFECT(phong_wrong_normalisation): the lobe density's (n+1)/(2π), which loses 1/(n+2) of the albedo.
  const double normalisation = defect == Defect::kPhongWrongNormalisation ? (exponent + 1.0) / kTwoPi
                                                                          : (exponent + 2.0) / kTwoPi;
  return albedo * normalisation * std::pow(cos_alpha, exponent);
}
std::optional<BsdfSample> PhongBsdf::sample(const Vec3& wo_local, double u1, double u2) const {
  if (!(wo_local.z > 0)) return std::nullopt;
  BsdfSample s;
  s.wi_local = lobe_frame(wo_local).world_from_local(sample_phong_lobe(u1, u2, exponent));
  if (!(s.wi_local.z > 0)) return std::nullopt;  // lobe mass below the horizon: failed sample
  s.pdf_solid_angle = pdf(wo_local, s.wi_local);
  if (!(s.pdf_solid_angle > 0)) return std::nullopt;
  s.weight = eval(wo_local, s.wi_local) * s.wi_local.z / s.pdf_solid_angle;
  return s;
}
double PhongBsdf::pdf(const Vec3& wo_local, const Vec3& wi_local) const {
  if (!(wo_local.z > 0 && wi_local.z > 0)) return 0.0;
  return phong_lobe_pdf({0, 0, phong_cos_alpha(wo_local, wi_local)}, exponent);
}

double GgxBsdf::distribution(const Vec3& m) const {
  // DEFECT(ggx_d_without_inv_pi): π·D, whose ∫ D cos θm dωm is π.
  return defect == Defect::kGgxDWithoutInvPi ? kPi * ggx_distribution(m, alpha) : ggx_distribution(m, alpha);
}
double GgxBsdf::lambda(const Vec3& w) const {
  // DEFECT(ggx_lambda_other_alpha): Λ of roughness α² while D keeps α.
  return ggx_lambda(w, defect == Defect::kGgxLambdaOtherAlpha ? alpha * alpha : alpha);
}
double GgxBsdf::g2(const Vec3& wo_local, const Vec3& wi_local) const {
  const double lambda_o = lambda(wo_local), lambda_i = lambda(wi_local);
  switch (shadowing) {
    case MicrofacetShadowing::kSeparable: return ggx_g2_separable_from_lambdas(lambda_o, lambda_i);
    case MicrofacetShadowing::kHeightCorrelated:
      // DEFECT(ggx_separable_as_height_correlated): G1·G1 ≤ 1/(1 + Λo + Λi), a darker surface.
      return defect == Defect::kGgxSeparableAsHeightCorrelated
                 ? ggx_g2_separable_from_lambdas(lambda_o, lambda_i)
                 : ggx_g2_height_correlated_from_lambdas(lambda_o, lambda_i);
  }
  return 0.0;
}
double GgxBsdf::visible_normal_pdf(const Vec3& wo_local, const Vec3& m) const {
  // DEFECT(ggx_vndf_pdf_without_g1): D·max(0, wo·m)/cos θo, which integrates to 1/G1(wo) > 1.
  const double g1_wo = defect == Defect::kGgxVndfPdfWithoutG1 ? 1.0 : g1(wo_local);
  return ggx_visible_normal_density(g1_wo, distribution(m), wo_local, m);
}
Vec3 GgxBsdf::sample_visible_normal(const Vec3& wo_local, double u1, double u2) const {
  // DEFECT(ggx_sample_alpha_squared): normals of roughness α², a narrower lobe than eval and pdf claim.
  return sample_ggx_visible_normal(wo_local, defect == Defect::kGgxSampleAlphaSquared ? alpha * alpha : alpha, u1, u2);
}

double GgxBsdf::fresnel(double cos_wo_h) const {
  if (!index) return 1.0;
  // DEFECT(conductor_fresnel_approximate): the classic approximation (Cycles until 5.0).
  return defect == Defect::kConductorFresnelApproximate ? fresnel_conductor_approximate(cos_wo_h, index->eta, index->k)
                                                        : fresnel_conductor(cos_wo_h, index->eta, index->k);
}

double GgxBsdf::eval(const Vec3& wo_local, const Vec3& wi_local) const {
  if (!(wo_local.z > 0 && wi_local.z > 0)) return 0.0;
  const Vec3 h = scene_normalize(wo_local + wi_local);  // h.z > 0: both directions are above the horizon
  const double f = albedo * distribution(h) * g2(wo_local, wi_local) / (4.0 * wo_local.z * wi_local.z);
  return index ? f * fresnel(dot(wo_local, h)) : f;
}
std::optional<BsdfSample> GgxBsdf::sample(const Vec3& wo_local, double u1, double u2) const {
  if (!(wo_local.z > 0)) return std::nullopt;
  BsdfSample s;
  s.wi_local = reflect_about(wo_local, sample_visible_normal(wo_local, u1, u2));
  if (!(s.wi_local.z > 0)) return std::nullopt;  // reflected below the horizon: failed sample
  s.pdf_solid_angle = pdf(wo_local, s.wi_local);
  if (!(s.pdf_solid_angle > 0)) return std::nullopt;
  s.weight = eval(wo_local, s.wi_local) * s.wi_local.z / s.pdf_solid_angle;
  return s;
}
double GgxBsdf::pdf(const Vec3& wo_local, const Vec3& wi_local) const {
  if (!(wo_local.z > 0 && wi_local.z > 0)) return 0.0;
  const Vec3 h = scene_normalize(wo_local + wi_local);
  // dωi/dωh = 4 wo·h (reflection's Jacobian); wo·h ≥ 0 for h the half vector of two unit vectors.
  const double wo_dot_h = dot(wo_local, h);
  if (!(wo_dot_h > 0)) return 0.0;
  return visible_normal_pdf(wo_local, h) / (4.0 * wo_dot_h);
}

AnyBsdf make_bsdf(const Material& material, const BsdfSetting& setting) {
  const double albedo = material.albedo;
  const Defect defect = setting.defect;
  return std::visit(
      overloaded{[&](const Lambertian&) -> AnyBsdf { return LambertianBsdf{albedo}; },
                 [&](const Mirror&) -> AnyBsdf { return MirrorBsdf{albedo}; },
                 [&](const Phong& p) -> AnyBsdf { return PhongBsdf{albedo, p.exponent, defect}; },
                 [&](const Ggx& g) -> AnyBsdf { return GgxBsdf{albedo, g.alpha, g.shadowing, defect, g.fresnel}; },
                 [&](const Dielectric& d) -> AnyBsdf {
                   // Behind the front normal the viewer is inside: the far side's index relative
                   // to the viewer's is 1/η. DEFECT(dielectric_eta_not_inverted) keeps η.
                   const bool invert = !setting.viewer_in_front && defect != Defect::kDielectricEtaNotInverted;
                   return DielectricBsdf{albedo,        invert ? 1.0 / d.eta : d.eta, d.alpha, d.shadowing,
                                         setting.convention, defect};
                 }},
      material.bsdf);
}

}  // namespace furnace
