// Spherical triangle (Arvo 1995) and spherical rectangle (Ureña et al. 2013)
// samplers: known solid angles, Jacobian of the map = Ω (uniform density
// 1/Ω), samples land on the shape, and the documented empty cases.
#include <gtest/gtest.h>

#include <ostream>
#include <string>

#include "renderer/sampling.h"
#include "renderer/spherical_sampling.h"

namespace furnace {
namespace {

constexpr int kGrid = 17;
// Central differences: the maps carry ~1e-11 relative internal round-off for
// small shapes (their angle differences cancel), amplified by 1/h; h = 1e-4
// keeps that below 1e-7 while the O(h²) truncation stays near 1e-8.
constexpr double kStep = 1e-4;
constexpr double kJacobianRelTol = 1e-5;
// Ureña's Ω is a sum of angles minus 2π: it loses log10(2π/Ω) digits. The
// allowance is 64 ulps of 2π, relative to Ω.
// Round trips through the maps: the ~1e-11 relative internal round-off of
// small shapes (see kStep) bounds how well u comes back.
constexpr double kInverseTol = 1e-8;

double solid_angle_rel_tol(double omega) { return 64 * 0x1.0p-52 * kTwoPi / omega; }

double grid_u(int i) { return (i + 0.5) / kGrid; }

TEST(SphericalTriangle, OctantHasSolidAngleHalfPi) {
  EXPECT_NEAR(spherical_triangle_solid_angle({1, 0, 0}, {0, 1, 0}, {0, 0, 1}), kPi / 2, 4e-16);
  EXPECT_NEAR(spherical_triangle_solid_angle({1, 0, 0}, {0, 0, 1}, {0, 1, 0}), kPi / 2, 4e-16);
}

struct TriangleCase {
  std::string name;
  Triangle triangle;
  Vec3 viewpoint;
};

void PrintTo(const TriangleCase& c, std::ostream* os) { *os << c.name; }

class SphericalTriangleTest : public testing::TestWithParam<TriangleCase> {};

TEST_P(SphericalTriangleTest, JacobianIsSolidAngle) {
  const auto s = SphericalTriangleSampler::make(GetParam().triangle, GetParam().viewpoint);
  ASSERT_TRUE(s.has_value());
  for (int i = 1; i < kGrid - 1; ++i)
    for (int j = 1; j < kGrid - 1; ++j) {
      const double u1 = grid_u(i), u2 = grid_u(j);
      const Vec3 d1 = (s->sample(u1 + kStep, u2) - s->sample(u1 - kStep, u2)) / (2 * kStep);
      const Vec3 d2 = (s->sample(u1, u2 + kStep) - s->sample(u1, u2 - kStep)) / (2 * kStep);
      EXPECT_NEAR(length(cross(d1, d2)) * s->pdf(), 1.0, kJacobianRelTol) << u1 << ", " << u2;
    }
}

TEST_P(SphericalTriangleTest, SamplesHitTheTriangle) {
  const TriangleCase& c = GetParam();
  const auto s = SphericalTriangleSampler::make(c.triangle, c.viewpoint);
  ASSERT_TRUE(s.has_value());
  const Vec3 n = c.triangle.normal();
  for (int i = 0; i < kGrid; ++i)
    for (int j = 0; j < kGrid; ++j) {
      const Vec3 w = s->sample(grid_u(i), grid_u(j));
      EXPECT_NEAR(length(w), 1.0, 1e-12);
      const double t = dot(c.triangle.p0 - c.viewpoint, n) / dot(w, n);
      ASSERT_GT(t, 0);
      const Vec3 p = c.viewpoint + w * t;
      // Barycentric coordinates by sub-triangle areas; each ≥ 0 up to round-off.
      const double area = 2 * c.triangle.area();
      const double b1 = dot(cross(p - c.triangle.p0, c.triangle.p2 - c.triangle.p0), n) / area;
      const double b2 = dot(cross(c.triangle.p1 - c.triangle.p0, p - c.triangle.p0), n) / area;
      EXPECT_GE(b1, -1e-9);
      EXPECT_GE(b2, -1e-9);
      EXPECT_LE(b1 + b2, 1 + 1e-9);
    }
}

TEST_P(SphericalTriangleTest, InverseRoundTrip) {
  const auto s = SphericalTriangleSampler::make(GetParam().triangle, GetParam().viewpoint);
  ASSERT_TRUE(s.has_value());
  for (int i = 0; i < kGrid; ++i)
    for (int j = 0; j < kGrid; ++j) {
      const auto u = s->invert(s->sample(grid_u(i), grid_u(j)));
      EXPECT_NEAR(u[0], grid_u(i), kInverseTol) << i << ", " << j;
      EXPECT_NEAR(u[1], grid_u(j), kInverseTol) << i << ", " << j;
    }
}

INSTANTIATE_TEST_SUITE_P(
    Triangles, SphericalTriangleTest,
    testing::Values(TriangleCase{"Octant", {{1, 0, 0}, {0, 0, 1}, {0, 1, 0}}, {0, 0, 0}},
                    TriangleCase{"Overhead", {{-1, -1, 2}, {-1, 1, 2}, {1, 0, 2}}, {0.2, 0.1, 0}},
                    TriangleCase{"Oblique", {{3, 0, 1}, {3, 0.5, 1.5}, {4, 0.2, 1}}, {0, 0, 0}},
                    TriangleCase{"Small", {{0, 0, 10}, {0, 0.05, 10}, {0.05, 0, 10}}, {0.01, 0.02, 0}}),
    [](const testing::TestParamInfo<TriangleCase>& info) { return info.param.name; });

TEST(SphericalTriangle, BehindEdgeOnAndTinyAreEmpty) {
  const Triangle t{{-1, -1, 2}, {-1, 1, 2}, {1, 0, 2}};  // normal −z: visible from below
  EXPECT_TRUE(SphericalTriangleSampler::make(t, {0, 0, 0}).has_value());
  EXPECT_FALSE(SphericalTriangleSampler::make(t, {0, 0, 3}).has_value());  // behind
  EXPECT_FALSE(SphericalTriangleSampler::make(t, {5, 0, 2}).has_value());  // in its plane
  const Triangle tiny{{0, 0, 1e4}, {1e-3, 0, 1e4}, {0, 1e-3, 1e4}};
  EXPECT_FALSE(SphericalTriangleSampler::make({tiny.p0, tiny.p2, tiny.p1}, {0, 0, 0}).has_value());
}

struct RectangleCase {
  std::string name;
  Rectangle rectangle;
  Vec3 viewpoint;
};

void PrintTo(const RectangleCase& c, std::ostream* os) { *os << c.name; }

class SphericalRectangleTest : public testing::TestWithParam<RectangleCase> {};

TEST_P(SphericalRectangleTest, SolidAngleEqualsTwoTriangles) {
  const RectangleCase& c = GetParam();
  const auto s = SphericalRectangleSampler::make(c.rectangle, c.viewpoint);
  ASSERT_TRUE(s.has_value());
  const Rectangle& r = c.rectangle;
  const auto dir = [&](const Vec3& p) { return normalize(p - c.viewpoint); };
  const Vec3 a = dir(r.corner), b = dir(r.corner + r.edge_u), cc = dir(r.corner + r.edge_u + r.edge_v),
             d = dir(r.corner + r.edge_v);
  const double expected = spherical_triangle_solid_angle(a, b, cc) + spherical_triangle_solid_angle(a, cc, d);
  EXPECT_NEAR(s->solid_angle / expected, 1.0, solid_angle_rel_tol(expected));
}

TEST_P(SphericalRectangleTest, JacobianIsSolidAngleAndPointsLieOnRectangle) {
  const RectangleCase& c = GetParam();
  const auto s = SphericalRectangleSampler::make(c.rectangle, c.viewpoint);
  ASSERT_TRUE(s.has_value());
  const auto direction = [&](double u1, double u2) { return normalize(s->sample_point(u1, u2) - c.viewpoint); };
  const Rectangle& r = c.rectangle;
  for (int i = 1; i < kGrid - 1; ++i)
    for (int j = 1; j < kGrid - 1; ++j) {
      const double u1 = grid_u(i), u2 = grid_u(j);
      const Vec3 d1 = (direction(u1 + kStep, u2) - direction(u1 - kStep, u2)) / (2 * kStep);
      const Vec3 d2 = (direction(u1, u2 + kStep) - direction(u1, u2 - kStep)) / (2 * kStep);
      EXPECT_NEAR(length(cross(d1, d2)) * s->pdf(), 1.0, kJacobianRelTol) << u1 << ", " << u2;
      const Vec3 local = s->sample_point(u1, u2) - r.corner;
      const double su = dot(local, r.edge_u) / length_squared(r.edge_u);
      const double sv = dot(local, r.edge_v) / length_squared(r.edge_v);
      EXPECT_NEAR(dot(local, r.normal()), 0.0, 1e-12);
      EXPECT_GE(su, -1e-12);
      EXPECT_LE(su, 1 + 1e-12);
      EXPECT_GE(sv, -1e-12);
      EXPECT_LE(sv, 1 + 1e-12);
    }
}

TEST_P(SphericalRectangleTest, InverseRoundTrip) {
  const auto s = SphericalRectangleSampler::make(GetParam().rectangle, GetParam().viewpoint);
  ASSERT_TRUE(s.has_value());
  for (int i = 0; i < kGrid; ++i)
    for (int j = 0; j < kGrid; ++j) {
      const auto u = s->invert(s->sample_point(grid_u(i), grid_u(j)));
      EXPECT_NEAR(u[0], grid_u(i), kInverseTol) << i << ", " << j;
      EXPECT_NEAR(u[1], grid_u(j), kInverseTol) << i << ", " << j;
    }
}

INSTANTIATE_TEST_SUITE_P(
    Rectangles, SphericalRectangleTest,
    testing::Values(RectangleCase{"Overhead", {{-1, -1, 2}, {0, 2, 0}, {2, 0, 0}}, {0, 0, 0}},
                    RectangleCase{"OffsetLong", {{1, -3, 1}, {0, 6, 0}, {0.5, 0, 0}}, {0, 0, 0}},
                    RectangleCase{"Tilted", {{0, 0, 2}, {0, 1.5, 0}, {1, 0, 1}}, {-1, 0.3, 0}},
                    RectangleCase{"Distant", {{-0.1, -0.1, 50}, {0, 0.2, 0}, {0.2, 0, 0}}, {0, 0, 0}}),
    [](const testing::TestParamInfo<RectangleCase>& info) { return info.param.name; });

TEST(SphericalRectangle, ParallelogramBehindAndEdgeOnAreEmpty) {
  const Rectangle r{{-1, -1, 2}, {0, 2, 0}, {2, 0, 0}};  // normal = (0,2,0)×(2,0,0) ∝ −z
  EXPECT_TRUE(SphericalRectangleSampler::make(r, {0, 0, 0}).has_value());
  EXPECT_FALSE(SphericalRectangleSampler::make(r, {0, 0, 5}).has_value());
  EXPECT_FALSE(SphericalRectangleSampler::make(r, {7, 0, 2}).has_value());
  const Rectangle sheared{{-1, -1, 2}, {0, 2, 0}, {2, 0.5, 0}};
  EXPECT_FALSE(SphericalRectangleSampler::make(sheared, {0, 0, 0}).has_value());
}

}  // namespace
}  // namespace furnace
