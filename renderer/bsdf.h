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
#include <variant>

#include "core/scene.h"
#include "core/strategy.h"
#include "renderer/microfacet.h"
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

// Isotropic GGX (Trowbridge–Reitz) microfacet reflection with Fresnel ≡ 1
// (renderer/microfacet.h has the formulas and their citations):
//   f = albedo·D(h)·G2(wo, wi)/(4 cos θo cos θi),  h = normalize(wo + wi),
// for wo and wi above the horizon, else 0; G2 separable or height-correlated
// as the material says. Sampling: a visible normal m ~ D_wo (exact), then
// wi = reflect(wo, m), whose density is D_wo(h)/(4 wo·h); a wi at or below
// the horizon is a failed sample (the directional albedo then falls short of
// the albedo: that energy is lost by the model, not by the sampler).
//
// Negative controls (core/strategy.h, kDefectTable), each acting only when
// `defect` is that value, inside the parts below so that eval, sample and pdf
// all see them:
//  - DEFECT(ggx_vndf_pdf_without_g1): visible_normal_pdf drops G1(wo);
//  - DEFECT(ggx_sample_alpha_squared): sample_visible_normal stretches by α²;
//  - DEFECT(ggx_lambda_other_alpha): lambda uses α² (D keeps α);
//  - DEFECT(ggx_separable_as_height_correlated): g2 is separable for a
//    height-correlated material;
//  - DEFECT(ggx_d_without_inv_pi): distribution is π·D.
struct GgxBsdf {
  double albedo = 0;
  double alpha = 1;
  MicrofacetShadowing shadowing = MicrofacetShadowing::kHeightCorrelated;
  Defect defect = Defect::kNone;

  double eval(const Vec3& wo_local, const Vec3& wi_local) const;
  std::optional<BsdfSample> sample(const Vec3& wo_local, double u1, double u2) const;
  // Density in solid angle (sr⁻¹) of sample()'s wi: D_wo(h)/(4 wo·h) on
  // wi.z > 0 (wo.z > 0), 0 elsewhere.
  double pdf(const Vec3& wo_local, const Vec3& wi_local) const;

  // The parts, defects applied (the free functions of microfacet.h when defect is kNone).
  double distribution(const Vec3& m) const;                  // D(m), sr⁻¹
  double lambda(const Vec3& w) const;                        // Smith Λ(w)
  double g1(const Vec3& w) const { return ggx_g1_from_lambda(lambda(w)); }
  double g2(const Vec3& wo_local, const Vec3& wi_local) const;
  double visible_normal_pdf(const Vec3& wo_local, const Vec3& m) const;  // D_wo(m), sr⁻¹ of m
  Vec3 sample_visible_normal(const Vec3& wo_local, double u1, double u2) const;
};

// A scene material's BSDF: one of the above, made by the renderer's one
// visit over the material types (make_bsdf), then dispatched by std::visit.
using AnyBsdf = std::variant<LambertianBsdf, MirrorBsdf, PhongBsdf, GgxBsdf>;
// `defect`: a negative control that lives in the BSDF (PhongBsdf, GgxBsdf).
AnyBsdf make_bsdf(const Material& material, Defect defect = Defect::kNone);

class Bsdf {
  // std::visit by a chain of index tests the compiler inlines (GCC 12's
  // std::visit calls through a table of function pointers: measured 12 %
  // slower on bench/bsdf_bench.cpp's Lambertian sampling). Defined before
  // its callers, which deduce its return type.
  template <size_t I = 0, class F>
  auto dispatch(F&& f) const {
    if constexpr (I + 1 == std::variant_size_v<AnyBsdf>) {
      return f(*std::get_if<I>(&bsdf_));
    } else {
      if (bsdf_.index() == I) return f(*std::get_if<I>(&bsdf_));
      return dispatch<I + 1>(f);
    }
  }

 public:
  Bsdf() = default;
  explicit Bsdf(const Material& material, Defect defect = Defect::kNone)
      : bsdf_(make_bsdf(material, defect)), black_(!(material.albedo > 0)) {}

  bool is_delta() const { return std::holds_alternative<MirrorBsdf>(bsdf_); }
  bool is_black() const { return black_; }
  double eval(const Vec3& wo_local, const Vec3& wi_local) const {
    return dispatch([&](const auto& b) { return b.eval(wo_local, wi_local); });
  }
  std::optional<BsdfSample> sample(const Vec3& wo_local, double u1, double u2) const {
    return dispatch([&](const auto& b) { return b.sample(wo_local, u1, u2); });
  }
  double pdf(const Vec3& wo_local, const Vec3& wi_local) const {
    return dispatch([&](const auto& b) { return b.pdf(wo_local, wi_local); });
  }

 private:

  AnyBsdf bsdf_;
  bool black_ = true;
};

inline Vec3 reflect_about_normal(const Vec3& w_local) { return {-w_local.x, -w_local.y, w_local.z}; }

}  // namespace furnace
