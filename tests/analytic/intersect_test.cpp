// Ray–shape intersection in double precision: hit distances from the
// geometry's construction, misses, t_min, both faces, non-unit directions.
#include "analytic/intersect.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "analytic/reference.h"

namespace furnace::analytic {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

TEST(IntersectRectangle, HitsInsideFromBothSidesAndMissesOutside) {
  const Rectangle r{{-2, -2, 0}, {4, 0, 0}, {0, 4, 0}};
  EXPECT_EQ(intersect_rectangle(r, {0.5, 1.5, 3}, {0, 0, -1}, 0).value(), 3.0);
  EXPECT_EQ(intersect_rectangle(r, {0.5, 1.5, -3}, {0, 0, 1}, 0).value(), 3.0);
  EXPECT_FALSE(intersect_rectangle(r, {2.5, 0, 3}, {0, 0, -1}, 0));
  EXPECT_FALSE(intersect_rectangle(r, {0, 0, 3}, {0, 0, 1}, 0));   // pointing away
  EXPECT_FALSE(intersect_rectangle(r, {0, 0, 3}, {1, 0, 0}, 0));   // parallel
  EXPECT_FALSE(intersect_rectangle(r, {0, 0, 3}, {0, 0, -1}, 3));  // t_min excludes the hit
}

TEST(IntersectRectangle, SkewedParallelogramAndNonUnitDirection) {
  const Rectangle r{{0, 0, 1}, {2, 0, 0}, {1, 1, 0}};
  // (2.9, 0.95) = 1.45·(2,0)... inside: s = (2.9 − 0.95)/2 = 0.975, t = 0.95.
  EXPECT_EQ(intersect_rectangle(r, {2.9, 0.95, 5}, {0, 0, -2}, 0).value(), 2.0);
  EXPECT_FALSE(intersect_rectangle(r, {0.5, 0.95, 5}, {0, 0, -2}, 0));  // s < 0
}

TEST(IntersectDisk, RadiusBoundsTheHit) {
  const Disk d{{0, 0, 2}, {0, 0, -1}, 0.75};
  EXPECT_EQ(intersect_disk(d, {0.7, 0, 0}, {0, 0, 1}, 0).value(), 2.0);
  EXPECT_FALSE(intersect_disk(d, {0.8, 0, 0}, {0, 0, 1}, 0));
  const double oblique = intersect_disk(d, {0, 0, 0}, {0.25, 0, 1}, 0).value();
  EXPECT_NEAR(oblique, 2.0, 2 * kEps);
}

TEST(IntersectSphere, NearAndFarRootsAndInsideOrigin) {
  const Sphere s{{1, 2, 3}, 0.5};
  const double dist = 10.0;
  EXPECT_NEAR(intersect_sphere(s, {1 - dist, 2, 3}, {1, 0, 0}, 0).value(), dist - 0.5, 4 * kEps * dist);
  EXPECT_NEAR(intersect_sphere(s, {1, 2, 3}, {0, 0, 3}, 0).value(), 0.5 / 3, 4 * kEps);
  EXPECT_FALSE(intersect_sphere(s, {1 - dist, 2.6, 3}, {1, 0, 0}, 0));
  // Far root once t_min passes the near one.
  EXPECT_NEAR(intersect_sphere(s, {1 - dist, 2, 3}, {1, 0, 0}, dist).value(), dist + 0.5, 4 * kEps * dist);
}

TEST(IntersectSphere, TinySphereFarAwayKeepsRelativePrecision) {
  // The textbook quadratic loses all digits here (b² ≫ c); the stable form does not.
  const Sphere s{{1e6, 0, 0}, 1e-3};
  EXPECT_NEAR(intersect_sphere(s, {0, 0, 0}, {1, 0, 0}, 0).value(), 1e6 - 1e-3, 4 * kEps * 1e6);
}

TEST(IntersectTriangle, InsideEdgeAndOutside) {
  const Triangle t{{0, 0, 1}, {1, 0, 1}, {0, 1, 1}};
  EXPECT_EQ(intersect_triangle(t, {0.25, 0.25, 0}, {0, 0, 1}, 0).value(), 1.0);
  EXPECT_EQ(intersect_triangle(t, {0.25, 0.25, 2}, {0, 0, -1}, 0).value(), 1.0);
  EXPECT_FALSE(intersect_triangle(t, {0.75, 0.75, 0}, {0, 0, 1}, 0));
}

TEST(IntersectScene, NearestObjectAndItsFrontNormal) {
  Scene scene;
  scene.objects.push_back({"floor", Rectangle{{-2, -2, 0}, {4, 0, 0}, {0, 4, 0}}, {}, 0});
  scene.objects.push_back({"blocker", Disk{{0, 0, 1}, {0, 0, 1}, 0.35}, {}, 0});
  const auto hit = intersect(scene, {0, 0, 5}, {0, 0, -1});
  ASSERT_TRUE(hit);
  EXPECT_EQ(hit->object_index, 1u);
  EXPECT_EQ(hit->t, 4.0);
  EXPECT_EQ(hit->normal, Vec3(0, 0, 1));
  const auto below = intersect(scene, {0.5, 0, 5}, {0, 0, -1});
  ASSERT_TRUE(below);
  EXPECT_EQ(below->object_index, 0u);
  EXPECT_FALSE(intersect(scene, {3, 0, 5}, {0, 0, -1}));
}

}  // namespace
}  // namespace furnace::analytic
