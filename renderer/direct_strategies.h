// Direct-lighting strategies: single-sample estimators of the reflected
// radiance ∫ f·Li·cos θi dωi at a shading point, Li the radiance emitted by
// the first surface along ωi (or the environment).
//
// Each strategy is a small struct whose sample() and pdf() compute the density
// through one shared helper; samples follow the return convention of
// estimator.h (weight = f·cos θi/pdf). Light strategies additionally carry the
// shadow ray the estimator must trace.
//
// NEGATIVE CONTROLS: the Defect values of render.h are implemented here, each
// at a line marked "DEFECT(...)". With Defect::kNone none of them is active.
#pragma once

#include <array>
#include <optional>

#include "renderer/estimator.h"
#include "renderer/lights.h"
#include "renderer/render.h"
#include "renderer/rng.h"

namespace furnace {

using Uniform3 = std::array<double, 3>;

// Directions uniform on the hemisphere around the face-forwarded normal.
struct UniformHemisphereStrategy {
  Defect defect = Defect::kNone;
  std::optional<DirectionSample> sample(const ShadingContext& ctx, const Uniform3& u) const;
  // Density in solid angle (sr⁻¹) of world direction wi.
  double pdf(const ShadingContext& ctx, const Vec3& wi_world) const;
};

// Cosine-weighted directions around the face-forwarded normal.
struct CosineHemisphereStrategy {
  Defect defect = Defect::kNone;
  std::optional<DirectionSample> sample(const ShadingContext& ctx, const Uniform3& u) const;
  double pdf(const ShadingContext& ctx, const Vec3& wi_world) const;
};

// The surface's own BSDF sampling (may be a delta sample).
struct BsdfStrategy {
  Defect defect = Defect::kNone;
  std::optional<DirectionSample> sample(const ShadingContext& ctx, const Uniform3& u) const;
  double pdf(const ShadingContext& ctx, const Vec3& wi_world) const;
};

// A light-sampling draw: a direction towards a chosen light, the radiance the
// light emits along it, and the shadow ray that decides visibility.
struct LightSample {
  Vec3 wi_world;
  double pdf_solid_angle = 0;  // true density of the strategy (selection pmf included)
  double weight = 0;           // f·cos θi / pdf
  double radiance = 0;         // Le of the light towards the shading point
  Vec3 shadow_origin;
  Vec3 shadow_direction;       // unit
  double shadow_t_max = 0;     // +inf for the environment
  bool assume_visible = false;  // only DEFECT(skip_shadow_ray) sets it
};

// How a light strategy samples one emitter.
enum class EmitterSampling {
  kArea,        // a point uniform on the emitter's area
  kSolidAngle,  // uniform in the solid angle the emitter subtends where an exact map exists
};

// Choose a light uniformly among LightSet, then sample it: an emitter by
// EmitterSampling, the environment by cosine-weighted directions.
struct LightStrategy {
  const EmbreeScene* scene = nullptr;
  const LightSet* lights = nullptr;
  EmitterSampling emitter_sampling = EmitterSampling::kArea;
  Defect defect = Defect::kNone;

  std::optional<LightSample> sample(const ShadingContext& ctx, const Uniform3& u) const;
  // Density in solid angle of sampling direction wi, whose ray found `hit`
  // (empty: it escaped). Used by MIS for directions drawn by another strategy.
  double pdf(const ShadingContext& ctx, const Vec3& wi_world, const std::optional<SurfaceHit>& hit) const;
};

// Traces the ray of a direction sample from the shading point; returns the
// first hit (empty on escape). Counts one ray.
std::optional<SurfaceHit> trace_from(const EmbreeScene& scene, const ShadingContext& ctx, const Vec3& wi_world,
                                     TraceCounters& counters);
// Whether a light sample's light is visible (always true under DEFECT(skip_shadow_ray)).
bool light_visible(const EmbreeScene& scene, const LightSample& s, TraceCounters& counters);

// MIS weight of strategy a against b (one sample each), β = 1 (balance) or 2 (power).
double mis_weight(double pdf_a, double pdf_b, int beta);

// The single-sample estimate of ∫ f·Li·cos θi dωi at ctx by `strategy`
// (one of the direct-lighting strategies).
class DirectLighting {
 public:
  DirectLighting(const EmbreeScene& scene, const LightSet& lights, Strategy strategy, Defect defect);
  double estimate(const ShadingContext& ctx, Rng& rng, TraceCounters& counters) const;

 private:
  template <typename DirectionStrategy>
  double estimate_direction(const DirectionStrategy& s, const ShadingContext& ctx, Rng& rng,
                            TraceCounters& counters) const;
  double estimate_light(const ShadingContext& ctx, Rng& rng, TraceCounters& counters) const;
  double estimate_mis(const ShadingContext& ctx, Rng& rng, TraceCounters& counters, int beta) const;

  const EmbreeScene& scene_;
  const LightSet& lights_;
  Strategy strategy_;
  Defect defect_;
  LightStrategy light_;
};

// Uniform numbers for one sample() call.
inline Uniform3 next_uniform3(Rng& rng) {
  const double u0 = rng.next_double();
  const double u1 = rng.next_double();
  const double u2 = rng.next_double();
  return {u0, u1, u2};
}

}  // namespace furnace
