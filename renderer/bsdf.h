// BSDFs of the scene materials, in the local shading frame: z is the
// geometric normal face-forwarded towards the viewer, so wo.z > 0 for a valid
// query. All are reflection-only and two-sided.
//
// Return convention (the one the whole renderer uses, see estimator.h):
// a sample carries weight = f(wo, wi)·cos θi / pdf(wi), so the estimate of
// ∫ f Li cos θi dωi is weight·Li(wi).
//
// Delta lobes (the perfect mirror) set `delta`, report pdf() == 0 and f == 0
// for every query; their sample weight is the reflectance.
#pragma once

#include <optional>

#include "core/scene.h"
#include "core/strategy.h"
#include "renderer/sampling.h"

namespace furnace {

struct BsdfSample {
  Vec3 wi_local;
  double weight = 0;           // f·cos θi / pdf (for a delta lobe: the reflectance)
  double pdf_solid_angle = 0;  // 0 for a delta lobe
  bool delta = false;
};

// Lambertian: f = ρ/π; cosine-weighted sampling, exact: weight = ρ.
struct LambertianBsdf {
  double albedo = 0;
  double eval(const Vec3& wo_local, const Vec3& wi_local) const;
  std::optional<BsdfSample> sample(const Vec3& wo_local, double u1, double u2) const;
  // Density in solid angle (sr⁻¹).
  double pdf(const Vec3& wo_local, const Vec3& wi_local) const;
};

// Perfect mirror with reflectance R: f = R·δ(wi − reflect(wo))/cos θi.
struct MirrorBsdf {
  double reflectance = 0;
  double eval(const Vec3& wo_local, const Vec3& wi_local) const { return 0.0; }
  std::optional<BsdfSample> sample(const Vec3& wo_local, double u1, double u2) const;
  double pdf(const Vec3& wo_local, const Vec3& wi_local) const { return 0.0; }
};

// Normalised (energy-conserving) Phong, Lafortune & Willems 1994:
// f = ρ·(n+2)/(2π)·cos^n α, α the angle between wi and the mirror direction of
// wo; its albedo at normal incidence is exactly ρ. Sampling: the lobe
// (n+1)/(2π)·cos^n α around the mirror direction; directions below the horizon
// are a failed sample. DEFECT(phong_wrong_normalisation) evaluates f with
// (n+1)/(2π), the sampling density's constant, in place of (n+2)/(2π).
struct PhongBsdf {
  double albedo = 0;
  double exponent = 1;
  Defect defect = Defect::kNone;
  double eval(const Vec3& wo_local, const Vec3& wi_local) const;
  std::optional<BsdfSample> sample(const Vec3& wo_local, double u1, double u2) const;
  // Density in solid angle (sr⁻¹): the lobe density on wi.z > 0, 0 below.
  double pdf(const Vec3& wo_local, const Vec3& wi_local) const;
};

// Dispatch over the scene's material types.
struct Bsdf {
  const Material* material = nullptr;
  Defect defect = Defect::kNone;  // negative controls only (PhongBsdf)

  bool is_delta() const { return material->type == BsdfType::kMirror; }
  bool is_black() const { return !(material->albedo > 0); }
  double eval(const Vec3& wo_local, const Vec3& wi_local) const;
  std::optional<BsdfSample> sample(const Vec3& wo_local, double u1, double u2) const;
  double pdf(const Vec3& wo_local, const Vec3& wi_local) const;
};

inline Vec3 reflect_about_normal(const Vec3& w_local) { return {-w_local.x, -w_local.y, w_local.z}; }

}  // namespace furnace
