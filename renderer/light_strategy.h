// Light sampling: choose a light by the LightSet pmf (every emitter, every
// point light, and the environment when it shines), then sample a direction towards it, by area
// (a point uniform on the emitter) or by solid angle where an exact map exists
// (cone for spheres, Arvo 1995 for triangles, Ureña et al. 2013 for
// rectangles; disks and parallelograms fall back to area sampling). sample()
// and pdf() compute the density through one helper; samples follow the return
// convention of estimator.h (weight = f·cos θi/pdf).
//
// NEGATIVE CONTROLS: DEFECT(drop_light_cosine), DEFECT(skip_shadow_ray),
// DEFECT(grazing_emitter_cosine), DEFECT(cone_sampling_float),
// DEFECT(pdf_off_by_constant), DEFECT(power_selection_uniform_pmf) and
// DEFECT(point_light_mis_weighted) are implemented here at lines so marked.
#pragma once

#include <optional>
#include <variant>
#include <vector>

#include "renderer/estimator.h"
#include "renderer/lights.h"
#include "renderer/sampling.h"
#include "renderer/spherical_sampling.h"

namespace furnace {

// A light-sampling draw: a direction towards a chosen light, the radiance the
// light emits along it, and the shadow ray that decides visibility.
struct LightSample {
  Vec3 wi_world;
  double pdf_solid_angle = 0;  // true density of the strategy (selection pmf included); 0 for delta
  double weight = 0;           // f·cos θi / pdf; for a delta (point) light f·cos θi / pmf
  double radiance = 0;         // Le of the light towards the shading point; I/r² for a point light
  bool delta = false;          // a point light: a delta in position, which no other strategy can sample
  double selection_pmf = 0;    // probability of choosing this sample's light
  Vec3 shadow_origin;
  Vec3 shadow_direction;       // unit
  double shadow_t_max = 0;     // +inf for the environment
  RayEnds shadow_ends;         // the shading point's object and the emitter's
  bool assume_visible = false;  // only DEFECT(skip_shadow_ray) sets it
};

// How a light strategy samples one emitter.
enum class EmitterSampling {
  kArea,        // a point uniform on the emitter's area
  kSolidAngle,  // uniform in the solid angle the emitter subtends where an exact map exists
};

// How one emitter is sampled from one shading point: by area (monostate), by
// the cone of a sphere, or by the spherical triangle or rectangle map. A
// function of (emitter, point, EmitterSampling, defect) only, decided in one
// place (LightStrategy::method_at), so sample() and pdf() agree.
struct ConeSetup {
  Sphere sphere;
  Frame frame;  // z towards the sphere's centre
  ConeAperture aperture;
};
using EmitterMethod = std::variant<std::monostate, ConeSetup, SphericalTriangleSampler, SphericalRectangleSampler>;

// The emitters' EmitterMethods at one shading point, each computed on first
// use and kept for every later query from the same point: all of a pixel's
// direct-lighting samples, and the first vertex of all its paths, shade the
// camera ray's one hit. Bound to one point (bind()) and used with one
// LightStrategy; a query from any other point computes its own method and
// leaves the store alone, so results are the same bit for bit with or without
// it. Allocates only when the scene has more objects than the last bind saw.
class EmitterSetups {
 public:
  void bind(const ShadingContext& ctx, size_t n_objects) {
    object_ = ctx.object;
    point_ = ctx.point;
    ready_.assign(n_objects, 0);
    if (methods_.size() < n_objects) methods_.resize(n_objects);
  }
  // Bound (a scene has objects) to ctx's point.
  bool holds(const ShadingContext& ctx) const { return !ready_.empty() && ctx.object == object_ && ctx.point == point_; }

 private:
  friend struct LightStrategy;
  size_t object_ = 0;
  Vec3 point_;
  std::vector<EmitterMethod> methods_;
  std::vector<unsigned char> ready_;
  EmitterMethod scratch_;  // a query from another point
};

// Choose a light among LightSet by its pmf, then sample it: an emitter by
// EmitterSampling, a constant environment by cosine-weighted directions, an
// environment map by its texels' importance (environment_sampler.h; directions
// below the receiver's horizon get weight 0), a point light by the direction
// to it (a delta sample: pdf 0, weight f·cos θi/pmf, radiance I/r²). pdf()
// never gives a point light a density: no ray hits one.
struct LightStrategy {
  const EmbreeScene* scene = nullptr;
  const LightSet* lights = nullptr;
  EmitterSampling emitter_sampling = EmitterSampling::kArea;
  Defect defect = Defect::kNone;

  // `setups`, when given and bound to ctx's point, keeps the emitters' methods
  // between calls (EmitterSetups); it never changes a result.
  std::optional<LightSample> sample(const ShadingContext& ctx, const Uniform3& u, EmitterSetups* setups = nullptr) const;
  // The same sample filled in place into `s`, which must be default-constructed
  // (for callers that keep several); false: no sample (`s` then unspecified).
  bool sample(const ShadingContext& ctx, const Uniform3& u, EmitterSetups* setups, LightSample& s) const;
  // Density in solid angle of sampling direction wi, whose ray found `hit`
  // (empty: it escaped). Used by MIS for directions drawn by another strategy.
  double pdf(const ShadingContext& ctx, const Vec3& wi_world, const std::optional<SurfaceHit>& hit,
             EmitterSetups* setups = nullptr) const;

 private:
  // sample() into `s`, which must be default-constructed; false: no sample.
  bool sample_into(const ShadingContext& ctx, const Uniform3& u, EmitterSetups& setups, LightSample& s) const;
  // The method of emitter `object` at ctx: the area method as a constant,
  // else from `setups` when it holds ctx's point (computed there on first
  // use), else computed into the setups' scratch slot. A reference to it is
  // good until the next call.
  const EmitterMethod& method_at(size_t object, const ShadingContext& ctx, EmitterSetups& setups) const;
};

// The MIS weight of a delta (point-light) light sample against BSDF sampling:
// 1, since no BSDF sample can find a point light (the light sample is the only
// strategy that covers it). DEFECT(point_light_mis_weighted) weighs it like an
// area sample instead, pmf/(pmf + p_bsdf), as if its density were its pmf.
double delta_light_mis_weight(const LightSample& s, double p_bsdf, Defect defect);

// Whether a light sample's light is visible (always true under DEFECT(skip_shadow_ray)).
bool light_visible(const EmbreeScene& scene, const LightSample& s, TraceCounters& counters);
// The shadow ray light_visible() traces for `s` (unless s.assume_visible).
inline RayArgs shadow_ray(const LightSample& s) {
  return {s.shadow_origin, s.shadow_direction, s.shadow_t_max, s.shadow_ends};
}

}  // namespace furnace
