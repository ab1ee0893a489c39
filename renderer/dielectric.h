// The dielectric interface (glass): smooth (two delta lobes) or rough (GGX
// microfacets, Walter, Marschner, Li & Torrance 2007, "Microfacet Models for
// Refraction through Rough Surfaces", EGSR), in the BSDF frame of bsdf.h:
// z faces the viewer, wo.z > 0, and `eta` is the index of the side below
// (wi.z < 0: transmission) relative to the viewer's side. The renderer
// builds it with η when the viewer is in front of the object's front normal
// and 1/η behind it (make_bsdf).
//
// Smooth: F = fresnel_dielectric(cos θo, η) (core/fresnel.h). Sampling
// reflects with probability F (weight ρ) and refracts with 1 − F (weight
// ρ·s), s = 1/η² in the radiance convention and 1 in none; under total
// internal reflection F = 1. pdf() and eval() are 0 (delta lobes).
//
// Rough, with m the microfacet normal (m.z > 0), D, Λ, G2 those of
// renderer/microfacet.h:
//  - reflection (wi.z > 0): m = normalize(wo + wi),
//      f_r = ρ·F(wo·m)·D(m)·G2/(4 cos θo cos θi),
//      pdf_r = F(wo·m)·D_wo(m)/(4 wo·m);
//  - transmission (wi.z < 0): m = ±normalize(wo + η wi) with m.z > 0
//    (Walter eq. 16), both directions on their own side of the microfacet
//    (wo·m > 0, wi·m < 0), else 0; the Jacobian (eq. 17)
//      J = |dωm/dωi| = η²|wi·m| / (η wi·m + wo·m)²,
//      f_t = ρ·s·(1 − F(wo·m))·D(m)·G2·|wo·m|·J / (cos θo |cos θi|),
//      pdf_t = (1 − F(wo·m))·D_wo(m)·J.
//    (The radiance-convention f_t is Walter's eq. 21; s = 1 gives its
//    adjoint, the form the none convention transports.)
// Sampling draws m ~ D_wo (exact visible normals), reflects with probability
// F(wo·m) and refracts otherwise; a direction on the wrong side of the
// macrosurface is a failed sample. Its weight is ρ·G2/G1(wo) (·s for
// transmission), computed as f·|cos θi|/pdf. Generalised reciprocity holds
// pointwise: f(wo, wi)/η_o² = f(wi, wo)/η_i² in the radiance convention
// (tests/renderer/dielectric_test.cpp).
//
// Negative controls (core/strategy.h), each acting only when `defect` is
// that value, in eval, sample and pdf alike:
//  - DEFECT(dielectric_transmission_without_eta2): J without its η²;
//  - DEFECT(dielectric_reflection_jacobian): J = 1/(4|wi·m|);
//  - DEFECT(dielectric_no_radiance_scaling): s = 1 in the radiance convention;
//  - DEFECT(dielectric_macro_fresnel): F(cos θo) for every microfacet;
//  - DEFECT(dielectric_tir_absorbs): where F = 1 by total internal
//    reflection, the reflection is dropped (absorbed);
//  - DEFECT(dielectric_eta_not_inverted) lives in make_bsdf.
#pragma once

#include <optional>

#include "core/material.h"
#include "core/strategy.h"
#include "core/vec3.h"
#include "renderer/bsdf_sample.h"
#include "renderer/microfacet.h"

namespace furnace {

struct DielectricBsdf {
  double albedo = 1;
  double eta = 1.5;  // below relative to above (the viewer's side)
  double alpha = 0;  // 0: smooth
  MicrofacetShadowing shadowing = MicrofacetShadowing::kHeightCorrelated;
  TransportConvention convention = TransportConvention::kRadiance;
  Defect defect = Defect::kNone;

  bool smooth() const { return alpha == 0; }
  double eval(const Vec3& wo_local, const Vec3& wi_local) const;
  // (u1, u2) draw the visible normal, u_lobe chooses the lobe.
  std::optional<BsdfSample> sample(const Vec3& wo_local, double u1, double u2, double u_lobe) const;
  // Density in solid angle (sr⁻¹) of sample()'s wi over the whole sphere; 0
  // for the smooth interface (delta lobes).
  double pdf(const Vec3& wo_local, const Vec3& wi_local) const;

  // The transmitted radiance's factor s (1/η² in the radiance convention).
  double transmission_scale() const;
  // The Fresnel reflectance the lobe choice uses at a microfacet (or the
  // smooth surface) of normal m, defects applied; 1 under total internal reflection.
  double fresnel(const Vec3& wo_local, const Vec3& m) const;
  // The generalised half vector of a transmission pair (m.z > 0), or
  // nullopt where it is undefined or either direction is on the wrong side
  // of it.
  std::optional<Vec3> transmission_half_vector(const Vec3& wo_local, const Vec3& wi_local) const;
  // |dωm/dωi| of a transmission pair at m, defects applied.
  double transmission_jacobian(const Vec3& wo_local, const Vec3& wi_local, const Vec3& m) const;
  double g2(const Vec3& wo_local, const Vec3& wi_local) const;
};

// The refracted direction of wo (wo·m > 0) through a surface of normal m and
// relative index η (below over above), or nullopt under total internal
// reflection: wi = −wo/η + (cos θ/η − cos θt)·m.
std::optional<Vec3> refract_through(const Vec3& wo, const Vec3& m, double eta);

}  // namespace furnace
