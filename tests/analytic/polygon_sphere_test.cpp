// Polygon (Lambert) and sphere (Snyder) projected solid angles against
// independent quadrature, the parallel-rectangle catalogue formula, limits,
// and their use as emitters and as environment blockers in whole scenes.
#include <cmath>
#include <limits>
#include <ostream>
#include <string>

#include <boost/multiprecision/cpp_bin_float.hpp>
#include <gtest/gtest.h>

#include "analytic/disk.h"
#include "analytic/environment.h"
#include "analytic/moments.h"
#include "analytic/polygon.h"
#include "analytic/reference.h"
#include "analytic/sphere.h"
#include "core/error.h"
#include "solid_angle_quadrature.h"

namespace furnace::analytic {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();
const Vec3 kUp{0, 0, 1};

double relative_error(double value, double expected) { return std::fabs(value - expected) / std::fabs(expected); }

// ---- polygons ---------------------------------------------------------------

// Howell's catalogue, differential element to a parallel rectangle a × b at
// distance c with one corner above the element (factor B-3):
//   F = 1/(2π)·[A/√(1+A²)·atan(B/√(1+A²)) + B/√(1+B²)·atan(A/√(1+B²))],
// A = a/c, B = b/c; E/L = π F.
double howell_corner_rectangle(double a, double b, double c) {
  const double A = a / c, B = b / c;
  const double sa = std::sqrt(1 + A * A), sb = std::sqrt(1 + B * B);
  return 0.5 * (A / sa * std::atan(B / sa) + B / sb * std::atan(A / sb));
}

TEST(PolygonIrradiance, ParallelCornerRectangleMatchesHowell) {
  for (double a : {0.1, 1.0, 3.0})
    for (double b : {0.5, 2.0})
      for (double c : {0.2, 1.0, 10.0}) {
        const std::vector<Vec3> rect{{0, 0, c}, {a, 0, c}, {a, b, c}, {0, b, c}};
        EXPECT_LE(relative_error(polygon_irradiance(rect, kUp), howell_corner_rectangle(a, b, c)), 32 * kEps)
            << a << " " << b << " " << c;
      }
}

TEST(PolygonIrradiance, WindingDoesNotMatter) {
  const std::vector<Vec3> ccw{{0.1, 0, 1}, {1, 0.2, 1.3}, {0.3, 1, 0.8}};
  const std::vector<Vec3> cw{ccw[2], ccw[1], ccw[0]};
  EXPECT_EQ(polygon_irradiance(ccw, kUp), polygon_irradiance(cw, kUp));
}

struct PatchCase {
  std::string name;
  bool triangle;
  Vec3 a, b, c;  // rectangle: corner, edge_u, edge_v; triangle: p0, p1, p2
  Vec3 n;
};

void PrintTo(const PatchCase& c, std::ostream* os) { *os << c.name; }

class PolygonVsQuadrature : public testing::TestWithParam<PatchCase> {};

// Tolerance 1e-11: the nested quadrature's; Lambert's sum itself is good to
// a few ulps times the edge-term cancellation factor (≤ 10 here).
TEST_P(PolygonVsQuadrature, ClippedLambertMatchesAreaIntegral) {
  const PatchCase& c = GetParam();
  std::vector<Vec3> vertices;
  testing_support::Patch patch;
  if (c.triangle) {
    vertices = {c.a, c.b, c.c};
    patch = testing_support::triangle_patch(c.a, c.b, c.c);
  } else {
    vertices = {c.a, c.a + c.b, c.a + c.b + c.c, c.a + c.c};
    patch = testing_support::rectangle_patch(c.a, c.b, c.c);
  }
  const Vec3 n = normalize(c.n);
  const double expected = testing_support::patch_projected_solid_angle(patch, {0, 0, 0}, n);
  ASSERT_GT(expected, 0);
  EXPECT_LE(relative_error(polygon_irradiance(vertices, n), expected), 1e-11) << expected;
}

INSTANTIATE_TEST_SUITE_P(
    Patches, PolygonVsQuadrature,
    testing::Values(PatchCase{"ParallelRectangleAbove", false, {-0.5, -0.3, 1}, {1, 0, 0}, {0, 0.8, 0}, {0, 0, 1}},
                    PatchCase{"TiltedRectangleAbove", false, {-0.5, -0.3, 1}, {1, 0, 0.3}, {0, 0.8, -0.2}, {0.1, 0.2, 1}},
                    PatchCase{"RectangleStraddlingHorizon", false, {1, -0.5, -0.5}, {0, 1, 0}, {0, 0, 1.5}, {0, 0, 1}},
                    PatchCase{"WallBesideReceiver", false, {0.3, -1, -1}, {0, 2, 0}, {0.2, 0, 2}, {0.3, 0, 1}},
                    PatchCase{"TriangleAbove", true, {0.2, 0.1, 1}, {1, 0.3, 1.4}, {-0.2, 0.9, 0.7}, {0, 0, 1}},
                    PatchCase{"TriangleStraddlingHorizon", true, {0.5, -0.5, -0.4}, {0.6, 0.6, 0.9}, {1.2, 0, 0.3}, {0, 0, 1}},
                    PatchCase{"TriangleTiltedReceiver", true, {0.5, -0.5, 0.4}, {0.6, 0.6, 0.9}, {1.2, 0, 0.3}, {-0.6, 0.2, 1}}),
    [](const auto& info) { return info.param.name; });

TEST(PolygonIrradiance, BelowHorizonIsZero) {
  EXPECT_EQ(polygon_irradiance({{0, 0, -1}, {1, 0, -1}, {0, 1, -2}}, kUp), 0.0);
}

// ---- spheres ----------------------------------------------------------------

struct SphereCase {
  std::string name;
  double D, R, beta;  // centre distance, radius, angle between n and the centre direction
};

void PrintTo(const SphereCase& c, std::ostream* os) { *os << c.name; }

class SphereVsQuadrature : public testing::TestWithParam<SphereCase> {};

// Tolerance 1e-11: the quadrature's.
TEST_P(SphereVsQuadrature, SnyderFormMatchesConeIntegral) {
  const SphereCase& c = GetParam();
  const Vec3 center{c.D * std::sin(c.beta), 0, c.D * std::cos(c.beta)};
  const double expected = testing_support::sphere_projected_solid_angle(center, c.R, kUp);
  ASSERT_GT(expected, 0);
  EXPECT_LE(relative_error(sphere_irradiance(center, c.R, kUp), expected), 1e-11) << expected;
}

INSTANTIATE_TEST_SUITE_P(Spheres, SphereVsQuadrature,
                         testing::Values(SphereCase{"Overhead", 3, 1, 0}, SphereCase{"AboveOblique", 3, 1, 1.0},
                                         SphereCase{"StraddleUpper", 3, 1, 1.4}, SphereCase{"StraddleEquator", 3, 1, kPi / 2},
                                         SphereCase{"StraddleLower", 3, 1, 1.85}, SphereCase{"CloseStraddle", 1.01, 1, 2.0},
                                         SphereCase{"SmallStraddle", 100, 1, 1.58}),
                         [](const auto& info) { return info.param.name; });

TEST(SphereIrradiance, ContinuousAcrossTheHorizonBoundaries) {
  // At cos β = sin α the straddle form meets π sin²α cos β; at cos β = −sin α it meets 0.
  const double D = 2, R = 0.7, sin_a = R / D;
  for (double sign : {1.0, -1.0}) {
    const double beta = std::acos(sign * sin_a);
    const double above = sphere_irradiance({D * std::sin(beta - 1e-9), 0, D * std::cos(beta - 1e-9)}, R, kUp);
    const double below = sphere_irradiance({D * std::sin(beta + 1e-9), 0, D * std::cos(beta + 1e-9)}, R, kUp);
    EXPECT_NEAR(above, below, 1e-8);
  }
}

// The textbook straddle form evaluated in 50 digits (no cancellation issue
// there), as the spot reference for small spheres crossing the horizon, where
// its double evaluation loses ~1/α³ (2e-8 relative at α = 1e-4).
double snyder_50_digits(double D, double R, double beta) {
  using Big = boost::multiprecision::cpp_bin_float_50;
  const Big sa = Big(R) / D, s2 = sa * sa, cb = cos(Big(beta)), sb = sin(Big(beta));
  const Big x = sqrt(1 - s2) / sa, y = -x * cb / sb, root = sqrt(1 - y * y);
  return static_cast<double>((cb * acos(y) - x * sb * root) * s2 + atan(sb * root / x));
}

// Tolerance 64 ulps: the regrouped form's remaining cancellation (between
// O(α³) terms) is mild in the middle of the straddle range tested here.
TEST(SphereIrradiance, SmallStraddlingSphereKeepsRelativePrecision) {
  for (double D : {1e2, 1e4, 1e6})
    for (double k : {-0.5, 0.0, 0.5}) {
      const double R = 1, beta = kPi / 2 + k * R / D;
      const Vec3 center{D * std::sin(beta), 0, D * std::cos(beta)};
      EXPECT_LE(relative_error(sphere_irradiance(center, R, kUp), snyder_50_digits(D, R, beta)), 64 * kEps)
          << "D " << D << " k " << k;
    }
}

TEST(SphereIrradiance, TinySphereIsPointLight) {
  const double D = 1, R = 1e-8, beta = 0.3;
  const double point = kPi * R * R / (D * D) * std::cos(beta);
  EXPECT_LE(relative_error(sphere_irradiance({D * std::sin(beta), 0, D * std::cos(beta)}, R, kUp), point), 8 * kEps);
}

TEST(SphereIrradiance, BelowHorizonIsZeroAndInsideThrows) {
  EXPECT_EQ(sphere_irradiance({0, 0, -3}, 1, kUp), 0.0);
  EXPECT_THROW(sphere_irradiance({0, 0, 0.5}, 1, kUp), Error);
}

// ---- scenes -----------------------------------------------------------------

Scene floor_scene() {
  Scene scene;
  scene.name = "lights";
  scene.source = "polygon_sphere_test";
  scene.objects.push_back({"floor", Rectangle{{-5, -5, 0}, {10, 0, 0}, {0, 10, 0}}, {0.5, Lambertian{}}, 0});
  return scene;
}

TEST(SceneLights, RectangleLightFacingDownMatchesHowell) {
  Scene scene = floor_scene();
  const double le = 2.5;
  // Corner above p = origin, emitting face down (cross(edge_u, edge_v) = −z).
  scene.objects.push_back({"panel", Rectangle{{0, 0, 1}, {0, 0.5, 0}, {2, 0, 0}}, {}, le});
  const double e = irradiance(scene, {0, 0, 0}, kUp, size_t(0));
  EXPECT_LE(relative_error(e, le * howell_corner_rectangle(2, 0.5, 1)), 32 * kEps);
  // Flipped winding: the emitting face points up, away from p.
  scene.objects[1].shape = Rectangle{{0, 0, 1}, {2, 0, 0}, {0, 0.5, 0}};
  EXPECT_EQ(irradiance(scene, {0, 0, 0}, kUp, size_t(0)), 0.0);
  scene.objects[1].two_sided = true;
  EXPECT_LE(relative_error(irradiance(scene, {0, 0, 0}, kUp, size_t(0)), e), 4 * kEps);
}

TEST(SceneLights, SphereLightAndBlockerRefused) {
  Scene scene = floor_scene();
  scene.objects.push_back({"bulb", Sphere{{0.5, 0, 2}, 0.4}, {}, 3.0});
  const double e = irradiance(scene, {0, 0, 0}, kUp, size_t(0));
  EXPECT_EQ(e, 3.0 * sphere_irradiance({0.5, 0, 2}, 0.4, kUp));
  scene.objects.push_back({"far_ball", Sphere{{4, 4, 1}, 0.3}, {}, 0});  // outside the cone: ignored
  EXPECT_EQ(irradiance(scene, {0, 0, 0}, kUp, size_t(0)), e);
  // A sphere in front of the sphere light casts a conic shadow: not solved,
  // refused. (Planar blockers are solved by sphere_occluded.h.)
  scene.objects.push_back({"blocker", Sphere{{0.25, 0, 1}, 0.2}, {}, 0});
  EXPECT_THROW(irradiance(scene, {0, 0, 0}, kUp, size_t(0)), Error);
}

// Environment minus one blocker per type: E = L_env·(π − Ω⊥), Ω⊥ by quadrature.
TEST(SceneEnvironment, BlockersSubtractTheirProjectedSolidAngle) {
  const double l_env = 1.3;
  const Vec3 p{0.1, -0.2, 0};
  struct Blocker {
    Shape shape;
    double omega;
  };
  const std::vector<Blocker> blockers{
      {Sphere{{1, 0.5, 0.3}, 0.6}, testing_support::sphere_projected_solid_angle(Vec3{1, 0.5, 0.3} - p, 0.6, kUp)},
      {Rectangle{{-1, -1, 0.5}, {0.8, 0, 0.2}, {0, 0.7, 0}},
       testing_support::patch_projected_solid_angle(
           testing_support::rectangle_patch({-1, -1, 0.5}, {0.8, 0, 0.2}, {0, 0.7, 0}), p, kUp)},
      {Triangle{{-0.5, 1, -0.3}, {0.5, 1.5, 0.6}, {-1, 1.4, 0.9}},
       testing_support::patch_projected_solid_angle(
           testing_support::triangle_patch({-0.5, 1, -0.3}, {0.5, 1.5, 0.6}, {-1, 1.4, 0.9}), p, kUp)},
  };
  for (const Blocker& b : blockers) {
    Scene scene = floor_scene();
    scene.environment.radiance = l_env;
    scene.objects.push_back({"blocker", b.shape, {}, 0});
    const double e = irradiance(scene, p, kUp, size_t(0));
    EXPECT_LE(relative_error(e, l_env * (kPi - b.omega)), 1e-11);
    // Cosine sampling of a sky: E[Y²] = π·L_env·E_env.
    EXPECT_LE(relative_error(second_moment(Strategy::kCosineHemisphere, scene, p, kUp, size_t(0)), kPi * l_env * e),
              4 * kEps);
  }
}

TEST(SceneEnvironment, ParallelDiskBlockerIsHowellDisk) {
  Scene scene = floor_scene();
  scene.environment.radiance = 1.0;
  scene.objects.push_back({"lid", Disk{{0.3, 0.4, 1}, {0, 0, -1}, 0.5}, {}, 0});
  EXPECT_LE(relative_error(irradiance(scene, {0, 0, 0}, kUp, size_t(0)), kPi - disk_irradiance_parallel(0.5, 1, 0.5)),
            4 * kEps);
}

TEST(SceneEnvironment, OverlappingBlockersAreRefused) {
  Scene scene = floor_scene();
  scene.environment.radiance = 1.0;
  scene.objects.push_back({"near", Sphere{{0, 0, 1}, 0.3}, {}, 0});
  scene.objects.push_back({"far", Sphere{{0, 0.2, 3}, 0.5}, {}, 0});
  EXPECT_THROW(irradiance(scene, {0, 0, 0}, kUp, size_t(0)), Error);
}

}  // namespace
}  // namespace furnace::analytic
