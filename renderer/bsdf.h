// BSDFs of the scene materials, in the local shading frame: z is the
// geometric normal face-forwarded towards the viewer, so wo.z > 0 for a valid
// query. All but the dielectric (dielectric.h) are reflection-only and
// two-sided; the dielectric also transmits (wi.z < 0) and is told which side
// the viewer is on (make_bsdf).
//
// Return convention (the one the whole renderer uses, see estimator.h):
// a sample carries weight = f(wo, wi)·cos θi / pdf(wi), so the estimate of
// ∫ f Li cos θi dωi is weight·Li(wi).
//
// Delta lobes (the perfect mirror, the smooth dielectric) set `delta`,
// report pdf() == 0 and f == 0 for every query; their sample weight is the
// lobe's (the reflectance; a transmission's scaled by the convention).
#pragma once

#include <optional>
#include <type_traits>
#include <variant>

#include "core/error.h"
#include "core/scene.h"
#include "core/strategy.h"
#include "renderer/bsdf_sample.h"
#include "renderer/dielectric.h"
#include "renderer/microfacet.h"
#include "renderer/sampling.h"

namespace furnace {

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

// Isotropic GGX (Trowbridge–Reitz) microfacet reflection
// (renderer/microfacet.h has the formulas and their citations):
//   f = albedo·F(wo·h)·D(h)·G2(wo, wi)/(4 cos θo cos θi),  h = normalize(wo + wi),
// F ≡ 1, or the exact conductor Fresnel of core/fresnel.h when the material
// gives an index (DEFECT(conductor_fresnel_approximate): the approximation),
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
  std::optional<ConductorIndex> index = std::nullopt;  // none: F ≡ 1

  double eval(const Vec3& wo_local, const Vec3& wi_local) const;
  // F(wo·h), defect applied.
  double fresnel(double cos_wo_h) const;
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
using AnyBsdf = std::variant<LambertianBsdf, MirrorBsdf, PhongBsdf, GgxBsdf, DielectricBsdf>;
// How a BSDF is made at a shading point besides its material: the negative
// control that lives in the BSDF (Phong, GGX, dielectric), the transport
// convention and which side of the surface the viewer is on (a dielectric's
// η is inverted behind the front normal).
struct BsdfSetting {
  BsdfSetting() = default;
  // From a defect alone (the usual case: radiance convention, viewer in front).
  BsdfSetting(Defect defect_, TransportConvention convention_ = TransportConvention::kRadiance,
              bool viewer_in_front_ = true)
      : defect(defect_), convention(convention_), viewer_in_front(viewer_in_front_) {}
  Defect defect = Defect::kNone;
  TransportConvention convention = TransportConvention::kRadiance;
  bool viewer_in_front = true;
};
AnyBsdf make_bsdf(const Material& material, const BsdfSetting& setting = {});

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
  explicit Bsdf(const Material& material, const BsdfSetting& setting = {})
      : bsdf_(make_bsdf(material, setting)),
        black_(!(material.albedo > 0)),
        delta_(std::holds_alternative<MirrorBsdf>(bsdf_) ||
               (std::holds_alternative<DielectricBsdf>(bsdf_) && std::get<DielectricBsdf>(bsdf_).smooth())),
        transmits_(std::holds_alternative<DielectricBsdf>(bsdf_)) {}

  // Every lobe is a delta (a mirror, a smooth dielectric).
  bool is_delta() const { return delta_; }
  bool is_black() const { return black_; }
  // Scatters light to the other side of the surface as well (wi.z < 0).
  bool transmits() const { return transmits_; }
  double eval(const Vec3& wo_local, const Vec3& wi_local) const {
    return dispatch([&](const auto& b) { return b.eval(wo_local, wi_local); });
  }
  // A BSDF that does not transmit (every type but the dielectric), whose one
  // lobe needs no choice: (u1, u2) drive its warp.
  std::optional<BsdfSample> sample(const Vec3& wo_local, double u1, double u2) const {
    FURNACE_CHECK(!transmits_ && "a dielectric's sample needs u_lobe");
    return sample(wo_local, u1, u2, 0.5);
  }
  // (u1, u2) drive the lobe's warp; u_lobe chooses between a dielectric's lobes.
  std::optional<BsdfSample> sample(const Vec3& wo_local, double u1, double u2, double u_lobe) const {
    return dispatch([&](const auto& b) {
      if constexpr (std::is_same_v<std::decay_t<decltype(b)>, DielectricBsdf>) return b.sample(wo_local, u1, u2, u_lobe);
      else return b.sample(wo_local, u1, u2);
    });
  }
  double pdf(const Vec3& wo_local, const Vec3& wi_local) const {
    return dispatch([&](const auto& b) { return b.pdf(wo_local, wi_local); });
  }

 private:

  AnyBsdf bsdf_;
  bool black_ = true;
  bool delta_ = false;
  bool transmits_ = false;
};

inline Vec3 reflect_about_normal(const Vec3& w_local) { return {-w_local.x, -w_local.y, w_local.z}; }

}  // namespace furnace
