// Embree 3 behind RAII: one device, one committed scene built from a furnace
// Scene with exact primitives (quads, oriented discs, sphere points,
// triangles; never tessellations). Geometry IDs equal object indices.
//
// Embree intersects in single precision; every hit is refined in double
// precision against the exact shape (plane or sphere) before shading. Rays
// leave a surface from the exact surface point, not from an offset origin:
// the surface a ray starts on (and the one a shadow ray ends on) is rejected
// by an exact test in double precision, so no epsilon scaled by the
// coordinates' magnitude moves the ray (an offset of 32 float ulps of |p|
// would bias scenes far from the origin by several percent;
// tests/integration/stability_test.cpp renders such scenes). Where the
// caller names the objects a ray starts and ends on (RayEnds) and no other
// surface passes through those points, the test is made once per query and
// Embree's ray mask excludes the rejected objects; otherwise an intersection
// filter (a context filter function) makes it on every candidate hit. Both
// give the same result, bit for bit (tests/renderer/embree_scene_test.cpp).
#pragma once

#include <cstddef>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include <embree3/rtcore.h>

#include "core/scene.h"

namespace furnace {

// Owns an RTCDevice. The error callback is installed right after
// rtcNewDevice; it records the first error (it never throws, Embree calls it
// from its own threads) and check() turns a recorded error into an exception.
class EmbreeDevice {
 public:
  EmbreeDevice();
  ~EmbreeDevice();
  EmbreeDevice(const EmbreeDevice&) = delete;
  EmbreeDevice& operator=(const EmbreeDevice&) = delete;

  RTCDevice get() const { return device_; }
  // Throws furnace::Error naming `what` and the recorded Embree error, if any.
  void check(const std::string& what) const;

 private:
  struct ErrorRecord;
  static void on_error(void* user, RTCError code, const char* message);
  std::unique_ptr<ErrorRecord> error_;
  RTCDevice device_ = nullptr;
};

// A first hit, refined to double precision on the exact shape.
struct SurfaceHit {
  double t = 0;             // distance along the unit ray direction
  size_t object = 0;        // index into Scene::objects
  Vec3 point;               // on the exact surface
  Vec3 normal;              // front (geometric) normal at `point`, unit
  bool front_facing = false;  // the ray arrived on the front side: dot(direction, normal) < 0
};

// The objects a query's ray starts and ends on, as the caller knows them (a
// shading point's object, a light sample's emitter). A hint never changes a
// result: the query checks that the origin (end) lies on the named object and
// otherwise ignores the hint. It lets the query exclude the endpoint surfaces
// by Embree's ray mask instead of a filter callback on every candidate hit.
struct RayEnds {
  static constexpr size_t kNone = std::numeric_limits<size_t>::max();
  size_t origin_object = kNone;
  size_t end_object = kNone;  // for a finite segment only
};

// A ray as the renderer asked Embree for it, recorded for benchmarks that
// replay the same rays through Embree alone (bench/renderer_bench.cpp).
struct TracedRay {
  Vec3 origin, direction;
  double t_max = 0;     // +inf for an intersection query without a bound
  bool shadow = false;  // an occlusion query (rtcOccluded1), else rtcIntersect1
  RayEnds ends;
};

// The arguments of one intersect() or occluded() query (the batch occluded()).
struct RayArgs {
  Vec3 origin, direction;  // direction unit, origin finite
  double t_max = std::numeric_limits<double>::infinity();
  RayEnds ends;
};
// The most queries a batch takes: one Embree packet of 8 rays.
inline constexpr size_t kRayPacket = 8;

// Whether the scene rejects the surfaces a ray starts and ends on (see the
// file comment). Only kExactEndpoints is correct for rendering; kNone leaves
// Embree's geometry without filter functions, for raw-throughput benchmarks
// that call rtcIntersect1/rtcOccluded1 on rtc_scene() with their own context.
enum class EndpointFilter { kExactEndpoints, kNone };

class EmbreeScene {
 public:
  // Builds and commits; throws furnace::Error on an Embree error.
  EmbreeScene(const EmbreeDevice& device, const Scene& scene,
              EndpointFilter endpoint_filter = EndpointFilter::kExactEndpoints);
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  // First hit with t in (0, t_max]. `direction` must be unit, `origin` finite.
  std::optional<SurfaceHit> intersect(const Vec3& origin, const Vec3& direction,
                                      double t_max = std::numeric_limits<double>::infinity(),
                                      const RayEnds& ends = {}) const;
  // True if anything lies on the open segment origin + t·direction, t in (0, t_max).
  bool occluded(const Vec3& origin, const Vec3& direction, double t_max, const RayEnds& ends = {}) const;
  // occluded() of n ≤ kRayPacket segments at once: those whose endpoint
  // surfaces the ray mask excludes go to Embree as one packet (rtcOccluded8;
  // shadow rays from one shading point to the lights are coherent), the
  // others one at a time through the filter, as does a batch of one. Results
  // equal those of n single queries (tests/renderer/embree_scene_test.cpp).
  void occluded(const RayArgs* rays, size_t n, bool* occluded) const;

  const Scene& scene() const { return scene_; }
  // The committed Embree scene, for raw-throughput benchmarks only: a plain
  // RTCIntersectContext sees no endpoint filter, so it is meant for a scene
  // built with EndpointFilter::kNone. Object i has the ray-mask bit
  // 1 << min(i, 31).
  RTCScene rtc_scene() const { return rtc_scene_; }
  EndpointFilter endpoint_filter() const { return endpoint_filter_; }

  // Appends every query intersect() and occluded() receive to `log` (nullptr:
  // stop). Not thread-safe: for single-threaded renders that benchmarks replay.
  void record_rays(std::vector<TracedRay>* log) { ray_log_ = log; }

  // The exact surface hits are refined against: a flat shape's plane
  // (core/scene.h: a point on it and its front normal) or a sphere.
  using ExactSurface = std::variant<Plane, Sphere>;

 private:
  SurfaceHit refine(size_t object, const Vec3& origin, const Vec3& direction, double t_float) const;
  struct RayQuery;
  // Whether a candidate hit at distance t_candidate on `object` is the
  // surface the query's ray starts on (or, for a finite segment, ends on).
  bool is_endpoint_surface(size_t object, const RayQuery& query, double t_candidate) const;
  bool on_surface(size_t object, const Vec3& x) const;
  static void filter(const RTCFilterFunctionNArguments* args);
  // The ray mask that excludes exactly the surfaces filter() would reject for
  // this query, or nothing when only the filter can decide (embree_scene.cpp).
  std::optional<unsigned> endpoint_mask(const RayQuery& query, const RayEnds& ends) const;
  // Sets the ray's mask, or installs filter() on the query's context.
  void prepare(RayQuery& query, RTCRay& ray, const RayEnds& ends) const;

  const EmbreeDevice& device_;
  const Scene& scene_;
  EndpointFilter endpoint_filter_;
  RTCScene rtc_scene_ = nullptr;
  std::vector<TracedRay>* ray_log_ = nullptr;
  uint64_t scene_id_;  // unique per scene built in this process: the key of endpoint_mask's per-thread memo
  std::vector<double> object_extent_;  // largest |coordinate| of each object's bounding box
  std::vector<ExactSurface> surface_;  // each object's exact surface, computed once
  // touching_[i]: the other objects whose exact surface comes near object i's
  // shape (coplanar, meeting at an edge, resting on it); only these can
  // contain a point a ray leaves object i from.
  std::vector<std::vector<size_t>> touching_;
};

}  // namespace furnace
