// The receiver model: direct lighting of one surface point whose BSDF is
// given by two functions, its value f and its sampling density p_b, for one
// view direction. From those two alone this file gives the reflected radiance
// and the second moment E[Y²] of every direct strategy's single-sample
// estimator, by one light-integral machinery (cap quadrature, below;
// receiver_integrals.h). A new BSDF supplies a Receiver (and its closed forms
// where it has them), never a strategy switch: the one switch over the
// estimators is second_moment_of in receiver_integrals.h.
//
// Why two cosines suffice: an isotropic BRDF at a fixed ωo is a function of
// ωi through n·ωi and ωo·ωi, and with r = 2(n·ωo)n − ωo the mirror direction,
//     ωo·ωi = 2(n·ωo)(n·ωi) − r·ωi,
// so f and p_b are functions of cos θ = n·ωi and cos α = r·ωi.
//
// The estimators (only the names are shared with the renderer), each of
// h(ω) = f(ωo, ω)·(n·ω)·Li(ω), Li the light's radiance along ω:
//  - bsdf: ω drawn from p_b, Y = h/p_b (a direction below the horizon is a
//    failed sample, Y = 0, which the integral over n·ω > 0 accounts for);
//  - uniform_hemisphere (p = 1/(2π)), cosine_hemisphere (p = (n·ω)/π): Y = h/p;
//  - light_solid_angle: a light chosen with pmf P, a sphere's cone uniformly
//    (p_l = P/Ω), a triangle's or a rectangle's whole spherical polygon
//    uniformly where the renderer has that map (p_l = P/Ω, Ω unclipped and
//    unoccluded; core/strategy.h's contract: Ω ≥ kMinSampledSolidAngle,
//    rectangles with perpendicular edges), other planar lights (disks) by
//    area as light_area, the constant environment cosine-weighted
//    (p_l = P·(n·ω)/π);
//  - light_area: a light's surface uniformly, p_l = P·d²/(A cos θ') with d
//    the distance to the (near) point hit, θ' the emission angle, A the
//    whole area; the environment as for light_solid_angle;
//  - mis_balance, mis_power: one bsdf and one light_solid_angle sample,
//    Veach's heuristic w_s = p_s^β/(p_b^β + p_l^β) (β = 1, 2):
//      E[Y²] = E[Y_b²] + E[Y_l²] + 2 E[Y_b] E[Y_l],
//      E[Y_s²] = ∫ w_s² h²/p_s dω, E[Y_s] = ∫ w_s h dω;
//  - mis_one_sample: bsdf with probability c = kOneSampleBsdfProbability, else
//    light_solid_angle, q = c·p_b + (1 − c)·p_l, E[Y²] = ∫ h²/q dω.
// Every single-technique estimator has E[Y²] = ∫ h²/p dω over the support of
// h, summed over the lights (whose solid angles do not overlap).
//
// Method: each light's directions are a spherical cap (a sphere's cone, or
// for the environment a hemisphere: about r when the receiver's f vanishes
// for cos α ≤ 0, as a lobe about the mirror direction does, else about n),
// integrated in coordinates centred on the cap's axis: outer polar angle,
// inner azimuth over the exact arcs where n·ω > 0 (n·ω = A + B cos ψ +
// C sin ψ on a ring). Adaptive Gauss–Kronrod (core/adaptive_quadrature.h),
// relative tolerance kReceiverQuadratureTolerance, with the outer interval
// cut where the horizon starts to cut the rings and at the ring through the
// mirror direction, and the inner arcs cut at the mirror direction's azimuth
// (a lobe's peak). For a sphere the outer variable is v with
// sin γ = (R/D)·sin v, so √(R² − D² sin²γ) = R cos v is smooth at the rim
// (the light-area density's emission cosine).
// A planar light (disk, rectangle, triangle; receiver_planar.h) is
// integrated over its exact visible region in its own plane (the light, cut
// by the horizon, minus the central projections of parallel disk
// occluders), in polar coordinates about the mirror direction's hit point
// on that plane, where a narrow lobe peaks (receiver_integrals.h,
// plane_integral).
// Error: every nested integral reports the error it reached to the open
// ErrorLedger (error_ledger.h): its outer rule's error estimates plus the
// worst relative estimate of an inner integral times the whole. Gauss–Kronrod
// estimates are pessimistic: against 50-digit values the GGX errors are at
// most 0.046 of the bound, which is at most 3.9e-9 relative
// (tests/analytic/ggx_precision_test.cpp).
//
// Domain: receiver points outside every sphere light; sphere lights that
// nothing may block, planar lights past disks parallel to them (nothing
// else that may block them), an unblocked constant environment
// (receiver_lights refuses the rest); viewer above the receiver
// (n·ωo > 0). Units: radiance W·m⁻²·sr⁻¹, second moments its square.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "analytic/receiver_planar.h"
#include "core/scene.h"
#include "core/strategy.h"

namespace furnace::analytic {

// Relative tolerance of the nested quadratures (far below any test's power:
// the suite detects relative biases of 1e-4 at best).
inline constexpr double kReceiverQuadratureTolerance = 1e-9;

// A receiver's BSDF at one incident direction ωi above its horizon.
// Contract: pdf_solid_angle > 0 wherever f_cos > 0 (bsdf sampling covers f's
// support, so it is unbiased); f_cos2_over_pdf is 0 where pdf_solid_angle is.
struct BsdfValue {
  double f_cos = 0;            // f(ωo, ωi)·(n·ωi), sr⁻¹
  double pdf_solid_angle = 0;  // p_b(ωi), the BSDF's own sampling density, sr⁻¹
  double f_cos2_over_pdf = 0;  // (f·(n·ωi))²/p_b, written by the BSDF without cancelling factors, sr⁻¹
};

// A circle on the sphere of directions where a receiver's f stops being
// smooth (an edge of its support, where f falls to 0 with a kink or a jump):
// the directions ω with axis·ω = cos_angle (axis n or r, unit).
struct SupportEdge {
  Vec3 axis;
  double cos_angle = 0;
};

// One light as the receiver integrals see it: a sphere (centre relative to
// the receiving point, which lies outside it), the constant environment, or,
// when `planar` is set, a disk, rectangle or triangle light (its visible
// region and sampling constants, receiver_planar.h; center and radius unused).
struct ReceiverLight {
  ReceiverLight() = default;
  ReceiverLight(bool environment, const Vec3& center, double radius, double radiance, double pmf,
                std::optional<PlanarEmitter> planar = std::nullopt)
      : environment(environment), center(center), radius(radius), radiance(radiance), pmf(pmf),
        planar(std::move(planar)) {}
  bool environment = false;
  Vec3 center;
  double radius = 0;
  double radiance = 0;
  double pmf = 1;  // selection probability (light-sampling strategies)
  std::optional<PlanarEmitter> planar;
};

// A receiving point's frame and BSDF for one view direction: what a BSDF
// supplies to be integrated (see the file comment).
class Receiver {
 public:
  Receiver(const Vec3& n, const Vec3& wo) : n(n), wo(wo) {}
  virtual ~Receiver() = default;

  Vec3 n;   // unit normal on the viewer's side
  Vec3 wo;  // unit direction toward the viewer, n·ωo > 0

  Vec3 mirror() const;  // r = 2(n·ωo)n − ωo

  // The BSDF at the direction with n·ωi = cos_theta > 0 and r·ωi = cos_alpha.
  virtual BsdfValue at(double cos_theta, double cos_alpha) const = 0;
  // Whether f = 0 wherever cos α ≤ 0 (a lobe about r): the environment is
  // then integrated over the hemisphere about r, else over the one about n.
  virtual bool vanishes_below_mirror_plane() const = 0;
  // Every number at() depends on besides the frame (BsdfType first): with
  // the frame, the key of the environment memo in receiver.cpp.
  virtual std::vector<double> parameters() const = 0;
  // "a Phong receiver": how refusals name it.
  virtual std::string name() const = 0;
  // The material it models (type, albedo and the type's own parameters):
  // how `furnace analytic` shows it.
  virtual Material material() const = 0;

  // The machinery (receiver_integrals.h) instantiated for this BSDF:
  // ReceiverModel<R> defines both; see light_reflectance and
  // receiver_second_moment below.
  virtual double light_reflectance(const ReceiverLight& light) const = 0;
  virtual double second_moment(Strategy strategy, const std::vector<ReceiverLight>& lights) const = 0;
};

// A BSDF's receiver: class MyReceiver final : public ReceiverModel<MyReceiver>
// with at(), vanishes_below_mirror_plane(), parameters(), name() and
// material(); glossy_receiver (glossy.h) makes it for its material type; its .cpp
// includes receiver_integrals.h and instantiates template class
// ReceiverModel<MyReceiver>, so the machinery calls MyReceiver::at inline.
template <class R>
class ReceiverModel : public Receiver {
 public:
  using Receiver::Receiver;
  // at() where the machinery also has 1 − cos α accurate relative to itself
  // (|ω − r|²/2): R hides this to use it (a lobe narrow about r, such as GGX at
  // small α, whose f read from cos α alone is off by ~ε/(1 − cos α)).
  BsdfValue at_direction(double cos_theta, double cos_alpha, double /*one_minus_cos_alpha*/) const {
    return static_cast<const R&>(*this).R::at(cos_theta, cos_alpha);
  }
  // The angular width (rad) of a lobe about r that the cap quadrature should
  // resolve by graded cuts; 0 (the default) for none.
  double lobe_width() const { return 0; }
  // The unit direction where the lobe peaks, about whose hit point a planar
  // light's polar coordinates are centred (plane_integral): r by default; R
  // hides this when its peak is elsewhere (a refraction lobe seen through
  // the mirror map, glass_light.h).
  Vec3 lobe_centre() const { return this->mirror(); }
  // The circles where f is not smooth inside the light's region: a planar
  // light's rays are cut where they cross one, and its outer angle where a
  // ray touches one or passes where one meets the region's boundary or
  // another (plane_integral), so that no piece spans an edge. None
  // by default (f smooth above the horizon); R hides this to name them (a
  // refraction's support, glass_light.h).
  std::vector<SupportEdge> support_edges() const { return {}; }
  double light_reflectance(const ReceiverLight& light) const final;
  double second_moment(Strategy strategy, const std::vector<ReceiverLight>& lights) const final;
};

// The lights the receiver model solves at point p (normal n) of object
// `receiver`, with their selection pmf: sphere emitters nothing may block
// (no object above p's horizon meets the cone from p over the sphere), disk,
// rectangle and triangle emitters past disks parallel to them
// (planar_emitter, receiver_planar.h; a planar light none of which reaches
// p is left out), and the constant environment with nothing above p's
// horizon. Throws furnace::Error naming the scene and the configuration for
// anything else (point lights, an environment map, other occluders, p on or
// inside a sphere light); `who` names the receiver.
std::vector<ReceiverLight> receiver_lights(const Scene& scene, const Vec3& p, const Vec3& n, size_t receiver,
                                           LightSelection selection, const std::string& who);

// ∫ f·(n·ω) dω over the light's directions: the reflected radiance per unit
// emitted radiance (the light's radiance and pmf are not used).
double light_reflectance(const Receiver& receiver, const ReceiverLight& light);

// Σ L·light_reflectance over the lights: the reflected radiance.
double reflected_radiance(const Receiver& receiver, const std::vector<ReceiverLight>& lights);

// E[Y²] of the direct strategy's single-sample estimator of that radiance.
// Throws furnace::Error for a path tracer.
double receiver_second_moment(Strategy strategy, const Receiver& receiver, const std::vector<ReceiverLight>& lights);

// The scene-level forms: the radiance reflected toward receiver.wo at point p
// of object `index` (direct lighting, emission excluded), and its estimators'
// E[Y²]. Under the environment alone every point of a flat receiver asks the
// same question: a small per-thread memo keyed on every input returns the
// very double the quadrature returned, so results do not depend on it.
double receiver_reflected_radiance(const Scene& scene, const Vec3& p, const Receiver& receiver, size_t index);
double receiver_second_moment(Strategy strategy, const Scene& scene, const Vec3& p, const Receiver& receiver,
                              size_t index, LightSelection selection);

}  // namespace furnace::analytic
