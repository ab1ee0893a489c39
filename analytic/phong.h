// Exact direct lighting of a glossy (normalised Phong) receiver: the lobe as
// a Receiver (receiver.h), whose light-integral machinery gives the radiance
// it reflects toward a viewer and the second moments of every direct
// strategy's single-sample estimator of it.
//
// The lobe, written here from its definition (Lafortune & Willems 1994,
// "Using the modified Phong reflectance model for physically based
// rendering"; the same convention core/scene.h's Material names): with n the
// receiver's unit normal facing the viewer, ωo the unit direction toward the
// viewer, r = 2(n·ωo)n − ωo the mirror direction and cos α = max(r·ωi, 0),
//     f(ωo, ωi) = ρ·(e+2)/(2π)·cos^e α        for n·ωi > 0, n·ωo > 0,
// e the exponent, ρ the material's albedo. The constant (e+2)/(2π) is the one
// that makes the albedo at normal incidence (r = n, no horizon cut) exactly ρ:
//     ∫ (e+2)/(2π) cos^e α cos α dω = (e+2)·∫₀^{π/2} cos^{e+1} α sin α dα = 1.
// Away from normal incidence the horizon cuts the lobe and the albedo is
// ρ·∫_{n·ω>0} (e+2)/(2π) cos^e α (n·ω) dω < ρ (the quadrature of receiver.h;
// the closed form ρ·(n·r) holds only where no lobe direction with cos α > 0
// is below the horizon, i.e. r = n).
//
// Its sampling (bsdf): ω from the lobe density p_b(ω) = (e+1)/(2π)·cos^e α
// about r, directions below the horizon a failed sample (Y = 0). So
//     (f·cos θ)²/p_b = ρ²(e+2)²/(2π(e+1))·cos^e α·cos²θ,
// written without the cancelling cos^e α.
//
// Domain: as receiver.h (sphere and planar lights, the occluded disk, the constant sky),
// exponent ≥ 0. Units: radiance W·m⁻²·sr⁻¹, second moments its square.
#pragma once

#include <string>
#include <vector>

#include "analytic/receiver.h"
#include "core/scene.h"
#include "core/strategy.h"

namespace furnace::analytic {

// The claimed accuracy of the Phong references: the receiver model's
// quadrature tolerance.
inline constexpr double kPhongQuadratureTolerance = kReceiverQuadratureTolerance;

// f(ωo, ωi) of the normalised Phong lobe above; `cos_alpha` = r·ωi. 0 for
// cos α ≤ 0 (the caller excludes directions below the horizon).
double phong_brdf(double albedo, double exponent, double cos_alpha);

// The glossy receiver at one point: its frame and lobe.
class PhongReceiver final : public ReceiverModel<PhongReceiver> {
 public:
  PhongReceiver(const Vec3& n, const Vec3& wo, double albedo, double exponent);
  double albedo = 0;
  double exponent = 0;

  BsdfValue at(double cos_theta, double cos_alpha) const override;
  bool vanishes_below_mirror_plane() const override { return true; }
  std::vector<double> parameters() const override;
  std::string name() const override { return "a Phong receiver"; }
  Material material() const override { return Material{albedo, Phong{exponent}}; }

 private:
  double bsdf_ratio_;  // ρ²(e+2)²/(2π(e+1)): (f·cos θ)²/p_b per cos^e α·cos²θ
};
// Instantiated once, in phong.cpp.
extern template class ReceiverModel<PhongReceiver>;

}  // namespace furnace::analytic
