// The Embree wrapper: exact primitives hit at the exact double-precision
// distance, geometry IDs map to objects, shadow rays report occlusion only on
// the open segment, rays leaving a surface point never hit that surface, and Embree
// errors are recorded and turned into furnace::Error.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <limits>
#include <ostream>
#include <string>
#include <vector>

#include "core/error.h"
#include "renderer/embree_scene.h"
#include "renderer/lights.h"
#include "renderer/rng.h"
#include "renderer/sampling.h"
#include "test_support.h"

namespace furnace {
namespace {

using testing_support::make_object;

constexpr uint64_t kSeed = 0xe3b;
// Refined hits are solved in double precision: a few ulps of the distance.
constexpr double kDistanceRelTol = 1e-13;

Scene four_shapes() {
  Scene s;
  s.name = "four_shapes";
  s.objects.push_back(make_object("quad", Rectangle{{-1, -1, 0}, {2, 0, 0}, {0, 2, 0}}));
  s.objects.push_back(make_object("disk", Disk{{3, 0, 1}, normalize(Vec3{0.2, 0, 1}), 0.7}));
  s.objects.push_back(make_object("ball", Sphere{{-3, 0, 1}, 0.8}));
  s.objects.push_back(make_object("tri", Triangle{{0, 3, 0.5}, {1, 3, 0.5}, {0, 4, 0.5}}));
  return s;
}

struct RayCase {
  std::string name;
  Vec3 origin, direction;
  size_t object;
  double distance;  // exact, from the closed form
  bool front_facing;
};

void PrintTo(const RayCase& c, std::ostream* os) { *os << c.name; }

std::vector<RayCase> ray_cases() {
  const Vec3 ball{-3, 0, 1};
  const Vec3 diag = normalize(Vec3{0.1, 0.2, -1});
  // Quad z = 0 from (0.3, -0.2, 5) along diag: t = 5/|diag.z|.
  const double t_quad = 5 / std::fabs(diag.z);
  const Vec3 disk_n = normalize(Vec3{0.2, 0, 1});
  const Vec3 disk_o{3.1, 0.1, 4};
  const double t_disk = dot(Vec3{3, 0, 1} - disk_o, disk_n) / dot(Vec3{0, 0, -1}, disk_n);
  return {
      {"QuadFromAbove", {0.3, -0.2, 5}, diag, 0, t_quad, true},
      {"QuadFromBelow", {0.3, 0.2, -2}, {0, 0, 1}, 0, 2.0, false},
      {"TiltedDisk", disk_o, {0, 0, -1}, 1, t_disk, true},
      {"SphereOutside", ball + Vec3{0, 0, 5}, {0, 0, -1}, 2, 5 - 0.8, true},
      {"SphereInside", ball + Vec3{0.1, 0, 0}, {1, 0, 0}, 2, 0.7, false},
      {"TriangleFromAbove", {0.2, 3.2, 2}, {0, 0, -1}, 3, 1.5, true},
  };
}

class RayHitTest : public testing::TestWithParam<RayCase> {};

TEST_P(RayHitTest, HitsTheExactShapeAtTheExactDistance) {
  const Scene scene = four_shapes();
  const EmbreeDevice device;
  const EmbreeScene rtc(device, scene);
  const RayCase& c = GetParam();
  const auto hit = rtc.intersect(c.origin, c.direction);
  ASSERT_TRUE(hit.has_value());
  EXPECT_EQ(hit->object, c.object);
  EXPECT_NEAR(hit->t / c.distance, 1.0, kDistanceRelTol);
  EXPECT_EQ(hit->front_facing, c.front_facing);
  EXPECT_NEAR(length(hit->point - (c.origin + c.direction * c.distance)), 0.0, 1e-12);
  // Shadow rays: blocked beyond the hit, clear before it.
  EXPECT_TRUE(rtc.occluded(c.origin, c.direction, c.distance * 1.01));
  EXPECT_FALSE(rtc.occluded(c.origin, c.direction, c.distance * 0.99));
}

INSTANTIATE_TEST_SUITE_P(Shapes, RayHitTest, testing::ValuesIn(ray_cases()),
                         [](const testing::TestParamInfo<RayCase>& info) { return info.param.name; });

TEST(EmbreeScene, MissReturnsNothing) {
  const Scene scene = four_shapes();
  const EmbreeDevice device;
  const EmbreeScene rtc(device, scene);
  EXPECT_FALSE(rtc.intersect({10, 10, 10}, {0, 0, 1}).has_value());
  EXPECT_FALSE(rtc.occluded({10, 10, 10}, {0, 0, 1}, std::numeric_limits<double>::infinity()));
}

TEST(EmbreeScene, SpawnedRaysNeverHitTheirOwnSurface) {
  // From points on the quad (far from the origin, where float spacing is
  // coarse) and on the sphere, rays into the upper/outer hemisphere, grazing
  // ones included, must not report the surface they leave.
  Scene scene;
  scene.name = "spawn";
  scene.objects.push_back(make_object("far_quad", Rectangle{{1000, 1000, 7}, {50, 0, 0}, {0, 50, 0}}));
  scene.objects.push_back(make_object("ball", Sphere{{-200, 30, 5}, 3}));
  const EmbreeDevice device;
  const EmbreeScene rtc(device, scene);
  for (int i = 0; i < 4000; ++i) {
    Rng rng(kSeed, 0, uint64_t(i));
    const double a = rng.next_double(), b = rng.next_double();
    // u1 near 0 gives grazing directions (cos θ = u1 for the uniform hemisphere).
    const Vec3 local = sample_uniform_hemisphere(i % 4 == 0 ? 1e-6 * rng.next_double() : rng.next_double(), b);
    const Vec3 quad_point{1000 + 50 * a, 1000 + 50 * b, 7};
    const Vec3 up = Frame::from_normal({0, 0, 1}).world_from_local(local);
    const auto quad_hit = rtc.intersect(quad_point, up);
    EXPECT_FALSE(quad_hit && quad_hit->object == 0) << i;
    const Vec3 n = sample_uniform_sphere(a, b);
    const Vec3 ball_point = Vec3{-200, 30, 5} + n * 3.0;
    const Vec3 out = Frame::from_normal(n).world_from_local(local);
    const auto ball_hit = rtc.intersect(ball_point, out);
    EXPECT_FALSE(ball_hit && ball_hit->object == 1) << i;
  }
}

TEST(EmbreeScene, RecordsEveryQueryInOrder) {
  const Scene scene = four_shapes();
  const EmbreeDevice device;
  EmbreeScene rtc(device, scene);
  std::vector<TracedRay> log;
  rtc.record_rays(&log);
  rtc.intersect({10, 10, 10}, {0, 0, 1});
  rtc.occluded({1, 2, 3}, {1, 0, 0}, 2.5);
  rtc.record_rays(nullptr);
  rtc.intersect({0, 0, 0}, {0, 1, 0});
  ASSERT_EQ(log.size(), 2u);
  EXPECT_FALSE(log[0].shadow);
  EXPECT_EQ(log[0].origin.z, 10.0);
  EXPECT_TRUE(std::isinf(log[0].t_max));
  EXPECT_TRUE(log[1].shadow);
  EXPECT_EQ(log[1].direction.x, 1.0);
  EXPECT_EQ(log[1].t_max, 2.5);
}

TEST(EmbreeScene, WithoutEndpointFiltersTakesAPlainContext) {
  // Raw queries on rtc_scene() with a plain RTCIntersectContext (what the
  // ceiling benchmark does): valid without the filters, and the same first
  // object as furnace's query for a ray that does not start on a surface.
  const Scene scene = four_shapes();
  const EmbreeDevice device;
  const EmbreeScene raw(device, scene, EndpointFilter::kNone);
  const EmbreeScene exact(device, scene);
  EXPECT_EQ(raw.endpoint_filter(), EndpointFilter::kNone);
  EXPECT_EQ(exact.endpoint_filter(), EndpointFilter::kExactEndpoints);
  int hits = 0;
  for (int i = 0; i < 200; ++i) {
    Rng rng(kSeed, 1, uint64_t(i));
    const Vec3 origin{8 * rng.next_double() - 4, 8 * rng.next_double() - 4, 9.0};
    const Vec3 direction = normalize(Vec3{0.2 * rng.next_double() - 0.1, 0.2 * rng.next_double() - 0.1, -1});
    const auto expected = exact.intersect(origin, direction);
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh;
    rh.ray.org_x = float(origin.x); rh.ray.org_y = float(origin.y); rh.ray.org_z = float(origin.z);
    rh.ray.dir_x = float(direction.x); rh.ray.dir_y = float(direction.y); rh.ray.dir_z = float(direction.z);
    rh.ray.tnear = 0.0f;
    rh.ray.tfar = std::numeric_limits<float>::infinity();
    rh.ray.time = 0.0f;
    rh.ray.mask = 0xFFFFFFFFu;
    rh.ray.id = rh.ray.flags = 0;
    rh.hit.geomID = rh.hit.primID = rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(raw.rtc_scene(), &context, &rh);
    ASSERT_EQ(rh.hit.geomID != RTC_INVALID_GEOMETRY_ID, expected.has_value()) << i;
    if (expected) {
      EXPECT_EQ(rh.hit.geomID, expected->object) << i;
      ++hits;
    }
  }
  EXPECT_GT(hits, 0);
}

// Scenes whose objects touch: a closed box (walls meeting at edges), a
// sphere resting on the floor, a disk lying on the floor, a triangle standing
// on it, and 40 small quads (objects 31 and up share one bit of the ray mask).
Scene touching_objects() {
  Scene s;
  s.name = "touching";
  const double a = 2;
  s.objects.push_back(make_object("floor", Rectangle{{0, 0, 0}, {a, 0, 0}, {0, a, 0}}));
  s.objects.push_back(make_object("ceiling", Rectangle{{0, 0, a}, {0, a, 0}, {a, 0, 0}}));
  s.objects.push_back(make_object("wall_x0", Rectangle{{0, 0, 0}, {0, a, 0}, {0, 0, a}}));
  s.objects.push_back(make_object("wall_x1", Rectangle{{a, 0, 0}, {0, 0, a}, {0, a, 0}}));
  s.objects.push_back(make_object("wall_y0", Rectangle{{0, 0, 0}, {0, 0, a}, {a, 0, 0}}));
  s.objects.push_back(make_object("wall_y1", Rectangle{{0, a, 0}, {a, 0, 0}, {0, 0, a}}));
  s.objects.push_back(make_object("ball", Sphere{{0.5, 0.5, 0.3}, 0.3}));
  s.objects.push_back(make_object("rug", Disk{{1.4, 0.6, 0}, {0, 0, 1}, 0.25}));
  s.objects.push_back(make_object("fin", Triangle{{0.4, 1.5, 0}, {1.2, 1.5, 0}, {0.8, 1.5, 0.7}}));
  for (int i = 0; i < 40; ++i) {
    const double x = 0.05 + 0.045 * i;
    s.objects.push_back(make_object(fmt::format("tile{}", i), Rectangle{{x, 1.8, 0}, {0.04, 0, 0}, {0, 0.1, 0}}));
  }
  return s;
}

std::vector<Scene> hint_test_scenes() {
  std::vector<Scene> scenes{four_shapes(), touching_objects()};
  for (const auto& entry : std::filesystem::directory_iterator(FURNACE_SCENE_DIR))
    if (entry.path().extension() == ".json") scenes.push_back(load_scene(entry.path().string()));
  return scenes;
}

// A point on the object, a third of them on or within 1e-12 of its boundary
// (edges where walls meet, the rim of a resting sphere's contact).
AreaSample point_on(const Object& object, Rng& rng, int i) {
  double u1 = rng.next_double(), u2 = rng.next_double();
  if (i % 3 == 1) u1 = (i % 2 ? 0.0 : 1.0);
  if (i % 3 == 2) u2 = 1e-12 * u2;
  return sample_shape_area(object.shape, u1, u2);
}

TEST(EmbreeScene, RayEndsNeverChangeAResult) {
  // The hint lets a query exclude its endpoint surfaces by ray mask; the
  // result must be bit for bit the exact filter's (the query without hints),
  // for rays leaving every object of every built-in scene and of scenes whose
  // objects touch, and for segments between points on two objects.
  const EmbreeDevice device;
  int rays = 0, hits = 0, blocked = 0;
  for (const Scene& scene : hint_test_scenes()) {
    const EmbreeScene rtc(device, scene);
    const size_t n = scene.objects.size();
    for (int i = 0; i < 600; ++i) {
      Rng rng(kSeed, 2, uint64_t(i));
      const size_t a = size_t(i) % n, b = (size_t(i) * 7 + 3) % n;
      const AreaSample p = point_on(scene.objects[a], rng, i);
      const AreaSample q = point_on(scene.objects[b], rng, i + 1);
      const Vec3 w = sample_uniform_sphere(rng.next_double(), rng.next_double());
      const auto exact = rtc.intersect(p.point, w);
      const auto hinted = rtc.intersect(p.point, w, std::numeric_limits<double>::infinity(), RayEnds{a, RayEnds::kNone});
      ASSERT_EQ(exact.has_value(), hinted.has_value()) << scene.name << " ray " << i;
      if (exact) {
        EXPECT_EQ(exact->object, hinted->object) << scene.name << " ray " << i;
        EXPECT_EQ(exact->t, hinted->t) << scene.name << " ray " << i;
        ++hits;
      }
      const Vec3 segment = q.point - p.point;
      const double length_pq = length(segment);
      if (!(length_pq > 0)) continue;
      const bool exact_blocked = rtc.occluded(p.point, segment / length_pq, length_pq);
      EXPECT_EQ(exact_blocked, rtc.occluded(p.point, segment / length_pq, length_pq, RayEnds{a, b}))
          << scene.name << " segment " << i;
      // A wrong hint is ignored, never believed.
      EXPECT_EQ(exact_blocked, rtc.occluded(p.point, segment / length_pq, length_pq, RayEnds{b, a}))
          << scene.name << " segment " << i;
      blocked += exact_blocked;
      ++rays;
    }
  }
  EXPECT_GT(hits, 1000);
  EXPECT_GT(blocked, 100);
  EXPECT_GT(rays, 10000);
}

// Many rays from one point, as a pixel's samples leave its shading point:
// endpoint_mask keeps the origin's part of the mask per thread for the last
// origin, so the repeats must answer as the exact filter does, in every
// direction (into a sphere from its surface too, where the direction
// decides), with right and wrong hints, and when a second scene, whose
// objects are the first's moved along their normals, is asked about the same
// origin and object index in between (the memo must not carry over).
Shape moved(const Shape& shape, const Vec3& offset) {
  return std::visit(overloaded{[&](const Rectangle& r) -> Shape { return Rectangle{r.corner + offset, r.edge_u, r.edge_v}; },
                               [&](const Disk& d) -> Shape { return Disk{d.center + offset, d.normal, d.radius}; },
                               [&](const Sphere& b) -> Shape { return Sphere{b.center + offset, b.radius}; },
                               [&](const Triangle& t) -> Shape {
                                 return Triangle{t.p0 + offset, t.p1 + offset, t.p2 + offset};
                               }},
                    shape);
}

TEST(EmbreeScene, RepeatedOriginsAnswerAsTheFilterDoes) {
  const EmbreeDevice device;
  int rays = 0, hits = 0, blocked = 0, moved_differs = 0;
  for (const Scene& scene : hint_test_scenes()) {
    Scene shifted = scene;
    for (Object& o : shifted.objects) o.shape = moved(o.shape, Vec3{1e-3, 2e-3, 3e-3});
    const EmbreeScene rtc(device, scene);
    const EmbreeScene rtc_shifted(device, shifted);
    const size_t n = scene.objects.size();
    for (size_t a = 0; a < n; ++a) {
      Rng rng(kSeed, 7, a);
      const Vec3 p = point_on(scene.objects[a], rng, int(a)).point;
      for (int i = 0; i < 64; ++i) {
        const Vec3 w = sample_uniform_sphere(rng.next_double(), rng.next_double());
        const size_t b = (a + 1 + size_t(i)) % n;
        const Vec3 q = point_on(scene.objects[b], rng, i).point;
        const Vec3 segment = q - p;
        const double length_pq = length(segment);
        for (const EmbreeScene* r : {&rtc, &rtc_shifted, &rtc}) {
          const auto exact = r->intersect(p, w);
          const auto hinted = r->intersect(p, w, std::numeric_limits<double>::infinity(), RayEnds{a, RayEnds::kNone});
          ASSERT_EQ(exact.has_value(), hinted.has_value()) << scene.name << " object " << a << " ray " << i;
          if (exact) {
            EXPECT_EQ(exact->object, hinted->object) << scene.name << " object " << a << " ray " << i;
            EXPECT_EQ(exact->t, hinted->t) << scene.name << " object " << a << " ray " << i;
            hits += r == &rtc;
          }
          if (!(length_pq > 0)) continue;
          const bool exact_blocked = r->occluded(p, segment / length_pq, length_pq);
          EXPECT_EQ(exact_blocked, r->occluded(p, segment / length_pq, length_pq, RayEnds{a, b}))
              << scene.name << " object " << a << " segment " << i;
          EXPECT_EQ(exact_blocked, r->occluded(p, segment / length_pq, length_pq, RayEnds{b, a}))
              << scene.name << " object " << a << " segment " << i;
          if (r == &rtc) {
            blocked += exact_blocked;
            ++rays;
          } else {
            // The moved object a no longer holds p: its answer may differ from the first scene's.
            moved_differs += exact_blocked != rtc.occluded(p, segment / length_pq, length_pq);
          }
        }
      }
    }
  }
  std::printf("repeated origins: %d segments, %d blocked, %d hits; %d segments answered otherwise in the moved scene\n",
              rays, blocked, hits, moved_differs);
  EXPECT_GT(rays, 1000);
  EXPECT_GT(blocked, 100);
  EXPECT_GT(moved_differs, 10);  // the moved scene asks a different question: a memo carried over would show
}

// Batches of 1 … kRayPacket shadow segments from one point on an object (a
// shading point) to points on the scene's objects, with right, wrong and no
// end hints, and unbounded rays (an environment's shadow rays), on every
// built-in scene and the scenes whose objects touch: the batch (one Embree
// packet for the lanes the ray mask settles, the filter for the others) must
// answer every lane exactly as a single occluded() query does.
struct BatchCount {
  int lanes = 0, blocked = 0, mismatched = 0;
};
BatchCount compare_batches_with_single_queries(
    const std::function<void(const EmbreeScene&, const RayArgs*, size_t, bool*)>& batch) {
  const EmbreeDevice device;
  BatchCount count;
  for (const Scene& scene : hint_test_scenes()) {
    const EmbreeScene rtc(device, scene);
    const size_t n_objects = scene.objects.size();
    for (int i = 0; i < 240; ++i) {
      Rng rng(kSeed, 4, uint64_t(i));
      const size_t a = size_t(i) % n_objects;
      const AreaSample p = point_on(scene.objects[a], rng, i);
      const size_t n = 1 + size_t(i) % kRayPacket;
      RayArgs rays[kRayPacket];
      for (size_t k = 0; k < n; ++k) {
        const size_t b = (size_t(i) * 5 + k * 3 + 1) % n_objects;
        const AreaSample q = point_on(scene.objects[b], rng, int(k) + i);
        const Vec3 segment = q.point - p.point;
        const double length_pq = length(segment);
        if (!(length_pq > 0) || k % 4 == 3) {
          // An unbounded ray leaving p (the environment's shadow ray).
          const Vec3 w = sample_uniform_sphere(rng.next_double(), rng.next_double());
          rays[k] = {p.point, w, std::numeric_limits<double>::infinity(), RayEnds{a, RayEnds::kNone}};
          continue;
        }
        const RayEnds ends = k % 4 == 0 ? RayEnds{a, b} : k % 4 == 1 ? RayEnds{b, a} : RayEnds{a, RayEnds::kNone};
        rays[k] = {p.point, segment / length_pq, length_pq, ends};
      }
      bool batched[kRayPacket];
      batch(rtc, rays, n, batched);
      for (size_t k = 0; k < n; ++k) {
        const bool single = rtc.occluded(rays[k].origin, rays[k].direction, rays[k].t_max, rays[k].ends);
        ++count.lanes;
        count.blocked += single;
        count.mismatched += single != batched[k];
      }
    }
  }
  return count;
}

TEST(EmbreeScene, BatchOccludedEqualsSingleQueries) {
  const BatchCount count = compare_batches_with_single_queries(
      [](const EmbreeScene& rtc, const RayArgs* rays, size_t n, bool* out) { rtc.occluded(rays, n, out); });
  std::printf("batch occluded(): %d lanes, %d blocked, %d differ from single queries\n", count.lanes, count.blocked,
              count.mismatched);
  EXPECT_EQ(count.mismatched, 0);
  EXPECT_GT(count.blocked, 500);
  EXPECT_GT(count.lanes, 20000);
}

TEST(EmbreeScene, BatchOccludedComparisonCatchesAPacketWithoutEndpointMasks) {
  // Negative control: the same packet on the same lanes but with every ray
  // mask left open (what a batch that forgot the endpoint surfaces would do)
  // finds the rays' own end surfaces, so the comparison above would fail.
  const BatchCount count = compare_batches_with_single_queries(
      [](const EmbreeScene& rtc, const RayArgs* rays, size_t n, bool* out) {
        alignas(32) int valid[kRayPacket] = {};
        RTCRay8 packet;
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        for (size_t k = 0; k < n; ++k) {
          const RayArgs& r = rays[k];
          packet.org_x[k] = float(r.origin.x), packet.org_y[k] = float(r.origin.y), packet.org_z[k] = float(r.origin.z);
          packet.dir_x[k] = float(r.direction.x), packet.dir_y[k] = float(r.direction.y),
          packet.dir_z[k] = float(r.direction.z);
          packet.tnear[k] = 0.0f;
          packet.tfar[k] = float(r.t_max);
          packet.time[k] = 0.0f;
          packet.mask[k] = ~0u;
          packet.id[k] = packet.flags[k] = 0;
          valid[k] = -1;
        }
        rtcOccluded8(valid, rtc.rtc_scene(), &context, &packet);
        for (size_t k = 0; k < n; ++k) out[k] = packet.tfar[k] == -std::numeric_limits<float>::infinity();
      });
  std::printf("packet without endpoint masks: %d of %d lanes differ\n", count.mismatched, count.lanes);
  EXPECT_GT(count.mismatched, 1000);
}

TEST(EmbreeScene, TouchingSurfacesNeedMoreThanTheOriginsOwnMask) {
  // The negative control of RayEndsNeverChangeAResult: in the touching scene,
  // excluding only the surface a ray leaves (the naive mask) finds a
  // neighbour at t ≈ 0 for rays leaving a wall from its edge, which the exact
  // filter, and so the hinted query, rejects. The comparison above covers them.
  const Scene scene = touching_objects();
  const EmbreeDevice device;
  const EmbreeScene raw(device, scene, EndpointFilter::kNone);
  const EmbreeScene rtc(device, scene);
  int naive_wrong = 0;
  for (int i = 0; i < 2000; ++i) {
    Rng rng(kSeed, 3, uint64_t(i));
    const size_t a = size_t(i) % 6;  // a wall, floor or ceiling
    const AreaSample p = sample_shape_area(scene.objects[a].shape, 0.0, rng.next_double());  // on an edge
    const Vec3 w = Frame::from_normal(p.normal).world_from_local(
        sample_uniform_hemisphere(rng.next_double(), rng.next_double()));
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh;
    rh.ray.org_x = float(p.point.x); rh.ray.org_y = float(p.point.y); rh.ray.org_z = float(p.point.z);
    rh.ray.dir_x = float(w.x); rh.ray.dir_y = float(w.y); rh.ray.dir_z = float(w.z);
    rh.ray.tnear = 0.0f;
    rh.ray.tfar = std::numeric_limits<float>::infinity();
    rh.ray.time = 0.0f;
    rh.ray.mask = ~(1u << a);
    rh.ray.id = rh.ray.flags = 0;
    rh.hit.geomID = rh.hit.primID = rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(raw.rtc_scene(), &context, &rh);
    const auto exact = rtc.intersect(p.point, w, std::numeric_limits<double>::infinity(), RayEnds{a, RayEnds::kNone});
    if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID && exact && rh.hit.geomID != exact->object) ++naive_wrong;
  }
  EXPECT_GT(naive_wrong, 0);
}

TEST(EmbreeDevice, ErrorsAreRecordedAndRaised) {
  const EmbreeDevice device;
  EXPECT_NO_THROW(device.check("doing nothing"));
  // An invalid geometry type: Embree reports RTC_ERROR_INVALID_ARGUMENT through the callback.
  RTCGeometry g = rtcNewGeometry(device.get(), static_cast<RTCGeometryType>(9999));
  EXPECT_EQ(g, nullptr);
  try {
    device.check("making a bad geometry");
    FAIL() << "no exception";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("making a bad geometry"), std::string::npos) << what;
    EXPECT_NE(what.find("RTC_ERROR"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace furnace
