#include "renderer/bsdf.h"

#include <cmath>

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

double Bsdf::eval(const Vec3& wo_local, const Vec3& wi_local) const {
  switch (material->type) {
    case BsdfType::kLambertian: return LambertianBsdf{material->albedo}.eval(wo_local, wi_local);
    case BsdfType::kMirror: return MirrorBsdf{material->albedo}.eval(wo_local, wi_local);
    case BsdfType::kPhong: return PhongBsdf{material->albedo, material->phong_exponent, defect}.eval(wo_local, wi_local);
    case BsdfType::kGgx: return 0.0;  // TODO(issue 29)
  }
  return 0.0;
}
std::optional<BsdfSample> Bsdf::sample(const Vec3& wo_local, double u1, double u2) const {
  switch (material->type) {
    case BsdfType::kLambertian: return LambertianBsdf{material->albedo}.sample(wo_local, u1, u2);
    case BsdfType::kMirror: return MirrorBsdf{material->albedo}.sample(wo_local, u1, u2);
    case BsdfType::kPhong: return PhongBsdf{material->albedo, material->phong_exponent, defect}.sample(wo_local, u1, u2);
    case BsdfType::kGgx: return std::nullopt;  // TODO(issue 29)
  }
  return std::nullopt;
}
double Bsdf::pdf(const Vec3& wo_local, const Vec3& wi_local) const {
  switch (material->type) {
    case BsdfType::kLambertian: return LambertianBsdf{material->albedo}.pdf(wo_local, wi_local);
    case BsdfType::kMirror: return MirrorBsdf{material->albedo}.pdf(wo_local, wi_local);
    case BsdfType::kPhong: return PhongBsdf{material->albedo, material->phong_exponent, defect}.pdf(wo_local, wi_local);
    case BsdfType::kGgx: return 0.0;  // TODO(issue 29)
  }
  return 0.0;
}

}  // namespace furnace
