#include "renderer/embree_scene.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <utility>
#include <limits>
#include <mutex>

#include <fmt/format.h>

#include "core/error.h"

namespace furnace {

namespace {

// A point counts as lying on a surface when its distance to the exact plane
// or sphere is at most this, relative to the magnitude of the coordinates
// involved: 2⁻³⁶ ≈ 1.5e-11 is ~10⁵ double ulps (points refined onto a surface
// or sampled on it are within a few), and far below any gap between two
// distinct objects that the scenes or the statistical tests could resolve.
constexpr double kOnSurfaceRelative = 0x1.0p-36;
// Two objects count as touching when one's shape comes this close to the
// other's exact surface, relative to their coordinates' magnitude: far above
// kOnSurfaceRelative and the single-precision error of an Embree hit (~2⁻²³),
// so a ray leaving one object can start on the other's surface only if the
// two touch. Generous on purpose: touching costs one on_surface test per ray.
constexpr double kTouchRelative = 0x1.0p-16;
// Objects 0…30 own one bit of Embree's 32-bit ray mask; all others share bit
// 31, so only the first 31 can be excluded from a query by the mask.
constexpr size_t kOwnMaskBits = 31;
// EmbreeScene ids, unique in the process (a later scene may reuse an earlier one's address).
std::atomic<uint64_t> scene_count{0};
unsigned mask_bit(size_t object) { return 1u << std::min(object, kOwnMaskBits); }

const char* error_name(RTCError code) {
  switch (code) {
    case RTC_ERROR_NONE: return "RTC_ERROR_NONE";
    case RTC_ERROR_UNKNOWN: return "RTC_ERROR_UNKNOWN";
    case RTC_ERROR_INVALID_ARGUMENT: return "RTC_ERROR_INVALID_ARGUMENT";
    case RTC_ERROR_INVALID_OPERATION: return "RTC_ERROR_INVALID_OPERATION";
    case RTC_ERROR_OUT_OF_MEMORY: return "RTC_ERROR_OUT_OF_MEMORY";
    case RTC_ERROR_UNSUPPORTED_CPU: return "RTC_ERROR_UNSUPPORTED_CPU";
    case RTC_ERROR_CANCELLED: return "RTC_ERROR_CANCELLED";
  }
  return "unknown RTCError";
}

float to_float(double x) { return static_cast<float>(x); }

double extent_of(const Shape& shape) {
  struct Visitor {
    double operator()(const Rectangle& r) const {
      double extent = 0;
      for (const Vec3& c : r.corners()) extent = std::fmax(extent, max_abs_component(c));
      return extent;
    }
    double operator()(const Disk& d) const { return max_abs_component(d.center) + d.radius; }
    double operator()(const Sphere& s) const { return max_abs_component(s.center) + s.radius; }
    double operator()(const Triangle& t) const {
      return std::fmax(max_abs_component(t.p0), std::fmax(max_abs_component(t.p1), max_abs_component(t.p2)));
    }
  };
  return std::visit(Visitor{}, shape);
}

void set_vertices3(RTCGeometry geom, const std::vector<Vec3>& vertices) {
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                        3 * sizeof(float), vertices.size()));
  for (size_t i = 0; i < vertices.size(); ++i) {
    v[3 * i + 0] = to_float(vertices[i].x);
    v[3 * i + 1] = to_float(vertices[i].y);
    v[3 * i + 2] = to_float(vertices[i].z);
  }
}

void set_point_with_radius(RTCGeometry geom, const Vec3& center, double radius) {
  auto* v = static_cast<float*>(
      rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), 1));
  v[0] = to_float(center.x);
  v[1] = to_float(center.y);
  v[2] = to_float(center.z);
  v[3] = to_float(radius);
}

RTCGeometry make_geometry(RTCDevice device, const Shape& shape) {
  struct Visitor {
    RTCDevice device;
    RTCGeometry operator()(const Rectangle& r) const {
      RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_QUAD);
      const auto corners = r.corners();
      set_vertices3(g, std::vector<Vec3>(corners.begin(), corners.end()));
      auto* idx = static_cast<unsigned*>(
          rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT4, 4 * sizeof(unsigned), 1));
      for (unsigned i = 0; i < 4; ++i) idx[i] = i;
      return g;
    }
    RTCGeometry operator()(const Disk& d) const {
      RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_ORIENTED_DISC_POINT);
      set_point_with_radius(g, d.center, d.radius);
      auto* n = static_cast<float*>(
          rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_NORMAL, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 1));
      n[0] = to_float(d.normal.x);
      n[1] = to_float(d.normal.y);
      n[2] = to_float(d.normal.z);
      return g;
    }
    RTCGeometry operator()(const Sphere& s) const {
      RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
      set_point_with_radius(g, s.center, s.radius);
      return g;
    }
    RTCGeometry operator()(const Triangle& t) const {
      RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
      set_vertices3(g, {t.p0, t.p1, t.p2});
      auto* idx = static_cast<unsigned*>(
          rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), 1));
      for (unsigned i = 0; i < 3; ++i) idx[i] = i;
      return g;
    }
  };
  return std::visit(Visitor{device}, shape);
}

// [lo, hi] bounds the signed distance of the shape's points to the plane.
struct Interval {
  double lo, hi;
};
Interval signed_distances(const Shape& shape, const Vec3& q, const Vec3& n) {
  const auto of = [&](const auto& points) {
    Interval r{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
    for (const Vec3& p : points) {
      r.lo = std::fmin(r.lo, dot(p - q, n));
      r.hi = std::fmax(r.hi, dot(p - q, n));
    }
    return r;
  };
  return std::visit(
      overloaded{[&](const Rectangle& r) { return of(r.corners()); },
                 [&](const Triangle& t) { return of(std::array<Vec3, 3>{t.p0, t.p1, t.p2}); },
                 [&](const Disk& d) {
                   const double c = dot(d.center - q, n), cos_angle = dot(d.normal, n);
                   const double reach = d.radius * std::sqrt(std::fmax(0.0, 1.0 - cos_angle * cos_angle));
                   return Interval{c - reach, c + reach};
                 },
                 [&](const Sphere& s) {
                   const double c = dot(s.center - q, n);
                   return Interval{c - s.radius, c + s.radius};
                 }},
      shape);
}

// A sphere that holds the shape: its centre and radius.
std::pair<Vec3, double> bounding_sphere(const Shape& shape) {
  const auto of = [](const auto& points) {
    Vec3 c;
    for (const Vec3& p : points) c += p / double(points.size());
    double r = 0;
    for (const Vec3& p : points) r = std::fmax(r, length(p - c));
    return std::pair{c, r};
  };
  return std::visit(
      overloaded{[&](const Rectangle& r) { return of(r.corners()); },
                 [&](const Triangle& t) { return of(std::array<Vec3, 3>{t.p0, t.p1, t.p2}); },
                 [](const Disk& d) { return std::pair{d.center, d.radius}; },
                 [](const Sphere& s) { return std::pair{s.center, s.radius}; }},
      shape);
}

// The exact surface a shape's hits are refined against: its plane (a point
// on it and the front normal) or its sphere.
EmbreeScene::ExactSurface exact_surface(const Shape& shape) {
  if (const std::optional<Plane> plane = plane_of(shape)) return *plane;
  return std::get<Sphere>(shape);
}

RTCRay make_ray(const Vec3& origin, const Vec3& direction, double t_max) {
  FURNACE_DCHECK(is_finite(origin));
  FURNACE_DCHECK(std::fabs(length_squared(direction) - 1.0) < 1e-9);
  RTCRay ray;
  ray.org_x = to_float(origin.x);
  ray.org_y = to_float(origin.y);
  ray.org_z = to_float(origin.z);
  ray.tnear = 0.0f;
  ray.dir_x = to_float(direction.x);
  ray.dir_y = to_float(direction.y);
  ray.dir_z = to_float(direction.z);
  ray.time = 0.0f;
  ray.tfar = std::isinf(t_max) ? std::numeric_limits<float>::infinity() : to_float(t_max);
  ray.mask = 0xFFFFFFFFu;
  ray.id = 0;
  ray.flags = 0;
  return ray;
}

}  // namespace

struct EmbreeDevice::ErrorRecord {
  mutable std::mutex mutex;
  RTCError code = RTC_ERROR_NONE;
  std::string message;
};

void EmbreeDevice::on_error(void* user, RTCError code, const char* message) {
  auto* record = static_cast<ErrorRecord*>(user);
  std::lock_guard<std::mutex> lock(record->mutex);
  if (record->code != RTC_ERROR_NONE) return;  // keep the first error: later ones are usually consequences
  record->code = code;
  record->message = message ? message : "";
}

// The double-precision ray behind an Embree query, handed to the filter
// functions through the intersect context (Embree 3's documented extension:
// the RTCIntersectContext comes first, the filter casts it back).
struct EmbreeScene::RayQuery {
  RayQuery(const EmbreeScene* scene_, const Vec3& origin_, const Vec3& direction_, double t_max_)
      : scene(scene_), origin(origin_), direction(direction_), t_max(t_max_), segment(std::isfinite(t_max_)) {
    rtcInitIntersectContext(&context);
    if (segment) end = origin + direction * t_max;
  }
  RTCIntersectContext context;
  const EmbreeScene* scene;
  Vec3 origin, direction;
  double t_max;
  bool segment;  // a finite segment, ending at `end`
  Vec3 end;      // computed once per query: the filter may run for several candidates
};

EmbreeDevice::EmbreeDevice() : error_(std::make_unique<ErrorRecord>()) {
  // Default configuration: a device created with threads=1 would throttle TBB
  // for the whole process; render() uses tbb::global_control.
  device_ = rtcNewDevice(nullptr);
  if (!device_) {
    throw Error(fmt::format("cannot create the Embree device: {}.", error_name(rtcGetDeviceError(nullptr))));
  }
  rtcSetDeviceErrorFunction(device_, &EmbreeDevice::on_error, error_.get());
}

EmbreeDevice::~EmbreeDevice() {
  if (device_) rtcReleaseDevice(device_);
}

void EmbreeDevice::check(const std::string& what) const {
  std::lock_guard<std::mutex> lock(error_->mutex);
  if (error_->code == RTC_ERROR_NONE) return;
  throw Error(fmt::format("Embree failed while {}: {} ({}).", what, error_name(error_->code), error_->message));
}

EmbreeScene::EmbreeScene(const EmbreeDevice& device, const Scene& scene, EndpointFilter endpoint_filter)
    : device_(device), scene_(scene), endpoint_filter_(endpoint_filter), scene_id_(++scene_count) {
  rtc_scene_ = rtcNewScene(device.get());
  // Robust mode: watertight traversal, so rays through shared quad edges are not lost.
  // The exact endpoint filter is a context filter, installed per query only
  // when the ray mask cannot exclude the endpoint surfaces (endpoint_mask).
  rtcSetSceneFlags(rtc_scene_, endpoint_filter == EndpointFilter::kExactEndpoints
                                   ? RTC_SCENE_FLAG_ROBUST | RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION
                                   : RTC_SCENE_FLAG_ROBUST);
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    RTCGeometry geom = make_geometry(device.get(), scene.objects[i].shape);
    rtcSetGeometryMask(geom, mask_bit(i));
    rtcCommitGeometry(geom);
    rtcAttachGeometryByID(rtc_scene_, geom, static_cast<unsigned>(i));  // geomID == object index
    rtcReleaseGeometry(geom);
    object_extent_.push_back(extent_of(scene.objects[i].shape));
    surface_.push_back(exact_surface(scene.objects[i].shape));
  }
  touching_.resize(scene.objects.size());
  for (size_t a = 0; a < scene.objects.size(); ++a) {
    const Shape& shape = scene.objects[a].shape;
    for (size_t b = 0; b < scene.objects.size(); ++b) {
      if (b == a) continue;
      const double margin = kTouchRelative * (object_extent_[a] + object_extent_[b]);
      const bool touches = std::visit(
          overloaded{[&](const Plane& plane) {
                       const Interval d = signed_distances(shape, plane.point, plane.normal);
                       return d.lo <= margin && d.hi >= -margin;
                     },
                     [&](const Sphere& s) {
                       const auto [centre, radius] = bounding_sphere(shape);
                       const double d = length(centre - s.center);
                       return std::fmax(0.0, d - radius) <= s.radius + margin && d + radius >= s.radius - margin;
                     }},
          surface_[b]);
      if (touches) touching_[a].push_back(b);
    }
  }
  rtcCommitScene(rtc_scene_);
  try {
    device.check(fmt::format("building the scene '{}'", scene.name));
  } catch (...) {
    rtcReleaseScene(rtc_scene_);
    throw;
  }
}

EmbreeScene::~EmbreeScene() {
  if (rtc_scene_) rtcReleaseScene(rtc_scene_);
}

std::optional<unsigned> EmbreeScene::endpoint_mask(const RayQuery& query, const RayEnds& ends) const {
  if (endpoint_filter_ != EndpointFilter::kExactEndpoints) return ~0u;
  unsigned mask = ~0u;
  // Excludes every object filter() would reject because `x` (the origin, or
  // the end of a segment) lies on its surface: `object` and those of the
  // objects touching it whose surface holds x. Objects that do not touch
  // `object` cannot hold a point of it (kTouchRelative). False when `x` is
  // not on `object` (the hint does not hold), or when a rejection depends on
  // the candidate's distance (a ray entering a sphere from its surface meets
  // it again at the chord's far end) or an object has no mask bit of its own.
  bool origin_on_sphere = false;  // a sphere's surface holds the origin: the direction decides
  const auto exclude_surfaces_through = [&](size_t object, const Vec3& x, bool is_origin) {
    if (object >= surface_.size() || !on_surface(object, x)) return false;
    const auto exclude = [&](size_t b) {
      const Sphere* s = std::get_if<Sphere>(&surface_[b]);
      if (is_origin && s) origin_on_sphere = true;
      if (is_origin && s && dot(query.origin - s->center, query.direction) < 0) return false;
      if (b >= kOwnMaskBits) return false;
      mask &= ~mask_bit(b);
      return true;
    };
    if (!exclude(object)) return false;
    for (size_t b : touching_[object])
      if (on_surface(b, x) && !exclude(b)) return false;
    return true;
  };
  // The origin's part of the mask, kept per thread for the last origin: the
  // rays of a pixel's samples (and the two rays of a path vertex) leave the
  // same shading point. Kept only when no sphere is among the excluded
  // surfaces, the one case where the ray's direction enters the decision.
  struct OriginMemo {
    uint64_t scene_id = 0;  // 0: empty (scene ids start at 1)
    size_t object = RayEnds::kNone;
    Vec3 point;
    unsigned mask = ~0u;
    bool excluded = false;  // exclude_surfaces_through's result
  };
  thread_local OriginMemo memo;
  // (A query without an origin object, a camera ray, neither uses nor replaces it.)
  const bool named = ends.origin_object < surface_.size();
  const bool remembered =
      named && memo.scene_id == scene_id_ && memo.object == ends.origin_object && memo.point == query.origin;
  if (remembered) {
    if (!memo.excluded) return std::nullopt;
    mask = memo.mask;
  } else {
    const bool excluded = exclude_surfaces_through(ends.origin_object, query.origin, true);
    if (named && !origin_on_sphere) memo = {scene_id_, ends.origin_object, query.origin, mask, excluded};
    if (!excluded) return std::nullopt;
  }
  if (query.segment && !exclude_surfaces_through(ends.end_object, query.end, false)) return std::nullopt;
  return mask;
}

void EmbreeScene::prepare(RayQuery& query, RTCRay& ray, const RayEnds& ends) const {
  if (const std::optional<unsigned> mask = endpoint_mask(query, ends)) {
    ray.mask = *mask;
  } else {
    query.context.filter = &EmbreeScene::filter;  // the exact test on every candidate hit
  }
}

std::optional<SurfaceHit> EmbreeScene::intersect(const Vec3& origin, const Vec3& direction, double t_max,
                                                 const RayEnds& ends) const {
  if (ray_log_) ray_log_->push_back({origin, direction, t_max, false, ends});
  RayQuery query(this, origin, direction, t_max);
  RTCRayHit rayhit;
  rayhit.ray = make_ray(origin, direction, t_max);
  prepare(query, rayhit.ray, ends);
  rayhit.hit.Ng_x = rayhit.hit.Ng_y = rayhit.hit.Ng_z = 0.0f;
  rayhit.hit.u = rayhit.hit.v = 0.0f;
  rayhit.hit.primID = RTC_INVALID_GEOMETRY_ID;
  rayhit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rayhit.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(rtc_scene_, &query.context, &rayhit);
  if (rayhit.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
  return refine(rayhit.hit.geomID, origin, direction, rayhit.ray.tfar);
}

bool EmbreeScene::occluded(const Vec3& origin, const Vec3& direction, double t_max, const RayEnds& ends) const {
  if (ray_log_) ray_log_->push_back({origin, direction, t_max, true, ends});
  RayQuery query(this, origin, direction, t_max);
  RTCRay ray = make_ray(origin, direction, t_max);
  prepare(query, ray, ends);
  rtcOccluded1(rtc_scene_, &query.context, &ray);
  return ray.tfar == -std::numeric_limits<float>::infinity();
}

namespace {

// Lane `i` of an Embree packet from a single ray.
void set_lane(RTCRay8& p, size_t i, const RTCRay& r) {
  p.org_x[i] = r.org_x;
  p.org_y[i] = r.org_y;
  p.org_z[i] = r.org_z;
  p.tnear[i] = r.tnear;
  p.dir_x[i] = r.dir_x;
  p.dir_y[i] = r.dir_y;
  p.dir_z[i] = r.dir_z;
  p.time[i] = r.time;
  p.tfar[i] = r.tfar;
  p.mask[i] = r.mask;
  p.id[i] = r.id;
  p.flags[i] = r.flags;
}

}  // namespace

void EmbreeScene::occluded(const RayArgs* rays, size_t n, bool* occluded) const {
  FURNACE_CHECK(n <= kRayPacket);
  if (n == 1) {  // a packet of one lane costs Embree more than a single ray
    occluded[0] = this->occluded(rays[0].origin, rays[0].direction, rays[0].t_max, rays[0].ends);
    return;
  }
  alignas(32) int valid[kRayPacket] = {};
  RTCRay8 packet;
  RTCIntersectContext context;  // no filter: the packet's lanes exclude their endpoint surfaces by mask
  rtcInitIntersectContext(&context);
  bool any = false;
  for (size_t i = 0; i < n; ++i) {
    const RayArgs& r = rays[i];
    if (ray_log_) ray_log_->push_back({r.origin, r.direction, r.t_max, true, r.ends});
    RayQuery query(this, r.origin, r.direction, r.t_max);
    RTCRay ray = make_ray(r.origin, r.direction, r.t_max);
    prepare(query, ray, r.ends);
    if (query.context.filter) {  // only the filter can decide: this lane alone
      rtcOccluded1(rtc_scene_, &query.context, &ray);
      occluded[i] = ray.tfar == -std::numeric_limits<float>::infinity();
      continue;
    }
    set_lane(packet, i, ray);
    valid[i] = -1;
    any = true;
  }
  if (!any) return;
  rtcOccluded8(valid, rtc_scene_, &context, &packet);
  for (size_t i = 0; i < n; ++i)
    if (valid[i]) occluded[i] = packet.tfar[i] == -std::numeric_limits<float>::infinity();
}

SurfaceHit EmbreeScene::refine(size_t object, const Vec3& origin, const Vec3& direction, double t_float) const {
  SurfaceHit hit;
  hit.object = object;
  hit.t = t_float;
  std::visit(overloaded{[&](const Plane& plane) {
                          // Recompute the distance to the exact plane in double precision.
                          const Vec3& q = plane.point;
                          const Vec3& n = plane.normal;
                          const double denom = dot(direction, n);
                          if (denom != 0) hit.t = dot(q - origin, n) / denom;
                          hit.point = origin + direction * hit.t;
                          hit.point -= n * dot(hit.point - q, n);  // remove the last rounding off the plane
                          hit.normal = n;
                        },
                        [&](const Sphere& s) {
                          // Both roots in double precision (the discriminant as
                          // r² − |oc − (oc·d)d|², which does not cancel), keeping the one
                          // Embree found; then a radial projection removes the last
                          // rounding off the sphere.
                          const Vec3 oc = origin - s.center;
                          const double b = dot(oc, direction);
                          const double disc = s.radius * s.radius - length_squared(oc - direction * b);
                          const double root = std::sqrt(std::fmax(disc, 0.0));  // grazing hits: round-off below 0
                          const double t_near = -b - root, t_far = -b + root;
                          hit.t = std::fabs(t_near - t_float) <= std::fabs(t_far - t_float) ? t_near : t_far;
                          const Vec3 n = scene_normalize(origin + direction * hit.t - s.center);
                          hit.point = s.center + n * s.radius;
                          hit.normal = n;
                        }},
             surface_[object]);
  hit.front_facing = dot(direction, hit.normal) < 0;
  return hit;
}

bool EmbreeScene::on_surface(size_t object, const Vec3& x) const {
  const double tolerance = kOnSurfaceRelative * (max_abs_component(x) + object_extent_[object]);
  return std::visit(
      overloaded{[&](const Plane& plane) { return std::fabs(dot(x - plane.point, plane.normal)) <= tolerance; },
                 [&](const Sphere& s) { return std::fabs(scene_length(x - s.center) - s.radius) <= tolerance; }},
      surface_[object]);
}

bool EmbreeScene::is_endpoint_surface(size_t object, const RayQuery& query, double t_candidate) const {
  // A segment ending on a surface (a shadow ray to a light point) meets that
  // surface only at its end: the sampled point faces the segment's origin, so
  // it is the surface's first crossing (planes are crossed once; a sphere's
  // near side is its first).
  if (query.segment && on_surface(object, query.end)) return true;
  if (!on_surface(object, query.origin)) return false;
  // A ray leaving a plane never meets it again, nor one leaving a sphere
  // outwards; a ray entering a sphere meets it again only at the far end of
  // its chord, at t = −2·(o − c)·d: reject what lies before the chord's middle.
  const Sphere* s = std::get_if<Sphere>(&surface_[object]);
  if (!s) return true;
  const double half_chord = -dot(query.origin - s->center, query.direction);
  return !(half_chord > 0 && t_candidate > half_chord);
}

void EmbreeScene::filter(const RTCFilterFunctionNArguments* args) {
  const auto* query = reinterpret_cast<const RayQuery*>(args->context);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    const unsigned object = RTCHitN_geomID(args->hit, args->N, i);
    const double t = RTCRayN_tfar(args->ray, args->N, i);  // the candidate's distance
    if (query->scene->is_endpoint_surface(object, *query, t)) args->valid[i] = 0;
  }
}

}  // namespace furnace
