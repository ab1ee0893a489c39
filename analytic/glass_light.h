// Exact direct lighting through a rough dielectric interface: planar lights
// on the far side of rough glass in one plane (a light inside the glass seen
// from outside, or outside seen from inside), the environment black. The
// third kind of glass scene (glass.h has the other two); the case that shows
// a rough transmission whose f and pdf both lack η′² (pbrt-v4 before
// dfa11074), which BSDF sampling cannot see and light sampling and MIS can.
//
// The BTDF, written here from its definition (Walter, Marschner, Li &
// Torrance 2007, eqs. 16, 17, 21; the visible normals of Heitz 2018),
// independently of renderer/dielectric.cpp: at a point with unit normal n on
// the viewer's side, view ωo (μo = n·ωo > 0), an incident direction ωi on the
// far side (|n·ωi| = μi), and η the far side's index relative to the
// viewer's,
//     H = ωo + η ωi,  m = ±H/|H| with n·m > 0   (Walter eq. 16),
// valid when ωo·m > 0 and ωi·m < 0 (each direction on its own side of the
// microfacet; else f = 0), J = |dωm/dωi| = η²|ωi·m|/(η ωi·m + ωo·m)²
// (eq. 17), and
//     f·μi = a·s·(1 − F(ωo·m, η))·D(m)·G2(ωo, ωi)·(ωo·m)·J/μo,
//     p_b  = (1 − F)·G1(ωo)·(ωo·m)·D(m)·J/μo   (visible normals × refraction's
//                                               probability × Jacobian, sr⁻¹),
//     (f·μi)²/p_b = a²s²·(1 − F)·D·(ωo·m)·J·(G2²/G1(ωo))/μo,
// s = transmission_scale(η, convention) (glass.h: 1/η² for radiance, 1 for
// none), F the exact dielectric Fresnel (fresnel.h), D, Λ of GGX (ggx.h), G2
// separable or height-correlated with Λ(ωi) of |n·ωi|.
//
// The mirror map: reflecting ωi through the tangent plane, ω′ = ωi −
// 2(n·ωi)n, puts it above the horizon with n·ω′ = μi, and with r = 2μo n − ωo
// the mirror direction, r·ω′ = −ωo·ωi. Reflecting a light on the far side
// through the same plane keeps the solid angle, the distance and the
// emission cosine of every direction (an isometry fixing p), hence every
// light density. So the receiver model (receiver.h) integrates this BTDF
// over the mirrored light, its Receiver's at(cos θ = μi, cos α = −ωo·ωi)
// being the BTDF above, in the two cosines:
//     ωo·ωi = −cos α,  |H|² = (η − 1)² + 2η(1 − cos α),
//     σ = sign(1 − η):  |H|·n·m = σ(μo − η μi),  |H|·ωo·m = σ(1 − η cos α),
//                       |H|·ωi·m = σ(η − cos α),  so η ωi·m + ωo·m = σ|H|,
//                       J = η²|η − cos α|/|H|³,
//     |H⊥|² = (sin θo − η sin θi)² + 2η(cos(θo − θi) − cos α),
//     D(m) = α²|H|⁴/(π(α²(|H| n·m)² + |H⊥|²)²).
// f vanishes unless cos α > min(η, 1/η) > 0 (ωo·m > 0 and ωi·m < 0): below
// the mirror plane it is 0. Its peak (m = n, Snell's direction) is not at r:
// the planar lights' polar coordinates are centred on the mirrored Snell
// direction (lobe_centre).
//
// Scene (glass_light_scene_refusal): an orthographic camera, every
// dielectric rough and planar, all in one plane; at least one emitter; every
// other object a disk, rectangle or triangle wholly on the far side of that
// plane from the camera with albedo 0 (its material bounces nothing back, so
// every path is camera → interface → light: the path tracers' answer is the
// direct one, at depth ≥ 2 segments; at 1 it is 0); the environment black,
// no point lights. A light is solved past disks parallel to it
// (planar_emitter, receiver_planar.h). The reflection lobe sees only the
// black environment: direct lighting is the transmission alone.
//
// Accuracy: the receiver model's kReceiverQuadratureTolerance (relative),
// its error estimates reported to the open ErrorLedger. Units: radiance
// W·m⁻²·sr⁻¹, second moments its square.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "analytic/receiver.h"
#include "core/scene.h"
#include "core/strategy.h"

namespace furnace::analytic {

// The rough dielectric's transmission, seen through the mirror map, as a Receiver.
class GlassTransmissionReceiver final : public ReceiverModel<GlassTransmissionReceiver> {
 public:
  // n: the unit normal on the viewer's side; eta: the far side's index relative to the viewer's (≠ 1).
  GlassTransmissionReceiver(const Vec3& n, const Vec3& wo, double albedo, double eta, double alpha,
                            MicrofacetShadowing shadowing, TransportConvention convention);
  double albedo = 1;
  double eta = 1.5;
  double alpha = 0.1;
  MicrofacetShadowing shadowing = MicrofacetShadowing::kHeightCorrelated;
  TransportConvention convention = TransportConvention::kRadiance;

  // cos_theta = |n·ωi|, cos_alpha = −ωo·ωi (the mirrored direction's cosines).
  BsdfValue at(double cos_theta, double cos_alpha) const override;
  // The same with 1 − cos α accurate relative to itself (receiver.h).
  BsdfValue at_direction(double cos_theta, double cos_alpha, double one_minus_cos_alpha) const;
  // The mirrored Snell direction of ωo (the lobe's peak, m = n); r when the
  // macro interface reflects ωo totally.
  Vec3 lobe_centre() const;
  // The support's edges: the cone cos α = min(η, 1/η) about r (ωo·m = 0
  // for η > 1, total internal reflection of ωi for η < 1: f falls to 0 at
  // it) and, when μo/η < 1, the microfacets' rim cos θ = μo/η about n
  // (n·m = 0: f jumps to 0).
  std::vector<SupportEdge> support_edges() const;
  bool vanishes_below_mirror_plane() const override { return true; }
  std::vector<double> parameters() const override;
  std::string name() const override { return "a rough dielectric's transmission"; }
  Material material() const override;

 private:
  double mu_o_, sin_o_;  // cos θo, sin θo
  double lambda_o_;      // Λ(ωo)
  double scale_;         // s
};
extern template class ReceiverModel<GlassTransmissionReceiver>;

// A dielectric scene with an emitter: the candidate for this kind.
bool has_glass_light(const Scene& scene);

// Whether the scene is of the kind above (the reason it is not, otherwise).
std::optional<std::string> glass_light_scene_refusal(const Scene& scene);

// The answer at one point p of the planar dielectric `receiver` seen along
// the unit direction wo (toward the viewer, either side): the radiance it
// sends toward wo (direct lighting; the path tracers' answer too) and, when
// `strategy` is set, E[Y²] of that direct strategy's single-sample estimator.
// Throws furnace::Error naming the scene for a path tracer or a
// configuration outside the kind above.
double glass_light_radiance(const Scene& scene, const Vec3& p, const Vec3& wo, size_t receiver,
                            TransportConvention convention);
double glass_light_second_moment(Strategy strategy, const Scene& scene, const Vec3& p, const Vec3& wo,
                                 size_t receiver, TransportConvention convention, LightSelection selection);

// Per pixel centre (row-major): the radiance (0 for max_segments < 2), and
// E[Y²] of a direct strategy. Throw furnace::Error naming the scene and the
// reason when it is not of this kind.
std::vector<double> glass_light_reference_image(const Scene& scene, int max_segments, TransportConvention convention);
std::vector<double> glass_light_second_moment_image(const Scene& scene, Strategy strategy,
                                                    TransportConvention convention, LightSelection selection);

}  // namespace furnace::analytic
