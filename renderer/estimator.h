// Shared vocabulary of the renderer's estimators.
//
// THE RETURN CONVENTION (every strategy, BSDF and light sampler uses it):
//   a sample of direction ωi carries  weight = f(ωo, ωi)·cos θi / pdf(ωi),
//   pdf in solid angle, so that the single-sample estimate of the reflected
//   radiance ∫ f·Li·cos θi dωi is  weight · Li(ωi)  (Li including visibility).
// Failure (no usable direction) is an empty optional, never a zero sentinel.
// Delta samples carry delta = true and pdf 0; their weight is finite.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>

#include <array>

#include "core/scene.h"
#include "core/strategy.h"
#include "renderer/bsdf.h"
#include "renderer/embree_scene.h"
#include "renderer/rng.h"

namespace furnace {

// A shading point: the frame's z is the geometric normal face-forwarded
// towards ωo (the direction back to the viewer), so BSDF queries see wo.z ≥ 0.
struct ShadingContext {
  size_t object = 0;
  Vec3 point;
  Vec3 normal;  // front geometric normal of the object
  Frame frame;  // local z = normal face-forwarded towards wo
  Vec3 wo_world;
  Vec3 wo_local;
  Bsdf bsdf;

  // `defect`: a negative control that lives in the BSDF (none by default);
  // `convention`: how a dielectric scales the radiance it transmits.
  static ShadingContext at(const SurfaceHit& hit, const Vec3& wo_world, const Material& material,
                           Defect defect = Defect::kNone,
                           TransportConvention convention = TransportConvention::kRadiance) {
    ShadingContext c;
    c.object = hit.object;
    c.point = hit.point;
    c.normal = hit.normal;
    const bool in_front = dot(hit.normal, wo_world) >= 0;
    c.frame = Frame::from_normal(in_front ? hit.normal : -hit.normal);
    c.wo_world = wo_world;
    c.wo_local = c.frame.local_from_world(wo_world);
    c.bsdf = Bsdf(material, BsdfSetting(defect, convention, in_front));
    return c;
  }
};

// A sampled direction (hemisphere strategies, BSDF sampling).
struct DirectionSample {
  Vec3 wi_world;
  double pdf_solid_angle = 0;  // the strategy's true density (0 for delta)
  double weight = 0;           // f·cos θi / pdf, see the convention above
  bool delta = false;
  double radiance_scale = 1;   // BsdfSample::radiance_scale (BSDF sampling only)
};

// Radiance arriving along a ray of unit direction `direction` that found `hit`
// (or nothing): emission of a front-facing emitter, the environment along
// `direction` on a miss, 0 otherwise. Emitters are
// one-sided: they emit along their front normal (spheres: outward), unless
// the object is two_sided, which emits the same radiance from both sides.
inline double emitted_radiance_towards(const Scene& scene, const std::optional<SurfaceHit>& hit,
                                       const Vec3& direction) {
  if (!hit) return environment_radiance(scene.environment, direction);
  const Object& o = scene.objects[hit->object];
  return hit->front_facing || o.two_sided ? o.emitted_radiance : 0.0;
}

// Counters a worker accumulates without sharing (one per thread).
struct TraceCounters {
  uint64_t rays = 0;
};

// Uniform numbers for one sample() call: u[0] picks among lights, u[1], u[2] drive a warp.
using Uniform3 = std::array<double, 3>;
inline Uniform3 next_uniform3(Rng& rng) {
  const double u0 = rng.next_double();
  const double u1 = rng.next_double();
  const double u2 = rng.next_double();
  return {u0, u1, u2};
}

// DEFECT(pdf_off_by_constant): the pdf used in a weight is 1.1× the true one.
inline constexpr double kDefectPdfFactor = 1.1;
inline double pdf_in_weight(double pdf_solid_angle, Defect defect) {
  return defect == Defect::kPdfOffByConstant ? kDefectPdfFactor * pdf_solid_angle : pdf_solid_angle;
}

// DEFECT(ray_offset_1e4): rays leave a surface from a point moved this far
// along its normal (face-forwarded towards the ray), a fixed absolute epsilon,
// so they pass over anything closer to the surface than that.
inline constexpr double kDefectRayOffset = 1e-4;
// Origin of a ray (a continuation or a shadow ray) leaving `point`, on a
// surface of front normal `normal`, towards `direction`: the point itself
// (the intersection filters keep the ray off its own surface).
inline Vec3 ray_origin(const Vec3& point, const Vec3& normal, const Vec3& direction, Defect defect) {
  if (defect != Defect::kRayOffset1e4) return point;
  return point + (dot(normal, direction) >= 0 ? normal : -normal) * kDefectRayOffset;
}

// The ray of a sampled direction from the shading point, unbounded.
inline RayArgs ray_from(const ShadingContext& ctx, const Vec3& wi_world, Defect defect) {
  return {ray_origin(ctx.point, ctx.normal, wi_world, defect), wi_world, std::numeric_limits<double>::infinity(),
          RayEnds{ctx.object, RayEnds::kNone}};
}

// Traces the ray of a sampled direction from the shading point; returns the
// first hit (empty on escape). Counts one ray.
inline std::optional<SurfaceHit> trace_from(const EmbreeScene& scene, const ShadingContext& ctx, const Vec3& wi_world,
                                            TraceCounters& counters, Defect defect = Defect::kNone) {
  ++counters.rays;
  const RayArgs ray = ray_from(ctx, wi_world, defect);
  return scene.intersect(ray.origin, ray.direction, ray.t_max, ray.ends);
}

// MIS weight of strategy a against b (one sample each), β = 1 (balance) or 2 (power).
inline double mis_weight(double pdf_a, double pdf_b, int beta) {
  if (!(pdf_a > 0)) return 0.0;
  const double a = beta == 2 ? pdf_a * pdf_a : pdf_a;
  const double b = beta == 2 ? pdf_b * pdf_b : pdf_b;
  return a / (a + b);
}

}  // namespace furnace
