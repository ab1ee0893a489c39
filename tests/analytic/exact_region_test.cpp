// The CGAL-backed exact path: region areas and orientation, agreement with
// the hand-rolled circle Booleans, exact decompositions (complementary
// occluders, holes whose solid angle is known independently), and tilted
// receivers against an independent polar quadrature over the disk.
#include "analytic/exact_region.h"

#include <cmath>
#include <limits>
#include <ostream>
#include <string>

#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <boost/math/quadrature/tanh_sinh.hpp>
#include <gtest/gtest.h>

#include "analytic/circle_region.h"
#include "analytic/planar_light.h"
#include "analytic/polygon.h"
#include "analytic/reference.h"
#include "core/error.h"

namespace furnace::analytic {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();
const Vec3 kUp{0, 0, 1};

double relative_error(double value, double expected) { return std::fabs(value - expected) / std::fabs(expected); }

// Signed area enclosed by a boundary: ½∮(x dy − y dx), per piece in closed form.
double boundary_area(const std::vector<Curve2>& boundary) {
  double twice = 0;
  for (const Curve2& c : boundary) {
    if (!c.is_arc) {
      twice += c.start.x * c.end.y - c.end.x * c.start.y;
      continue;
    }
    const Circle2& k = c.circle;
    const double t1 = c.t0 + c.sweep;
    twice += k.radius * k.radius * c.sweep +
             k.radius * (k.cx * (std::sin(t1) - std::sin(c.t0)) - k.cy * (std::cos(t1) - std::cos(c.t0)));
  }
  return 0.5 * twice;
}

Region2 square(double x0, double y0, double x1, double y1) { return {{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}, {}}; }
Region2 circle(double cx, double cy, double r) { return {{}, Circle2{cx, cy, r}}; }

TEST(ExactRegion, AreasAndOrientation) {
  // Square minus an interior disk: a hole, traversed clockwise.
  EXPECT_NEAR(boundary_area(exact_visible_boundary(square(0, 0, 2, 2), {circle(1, 1, 0.5)}, std::nullopt)),
              4 - kPi * 0.25, 1e-14);
  // Disk minus the right half-plane box: a half disk.
  EXPECT_NEAR(boundary_area(exact_visible_boundary(circle(0, 0, 1), {square(0, -2, 2, 2)}, std::nullopt)), kPi / 2,
              1e-14);
  // Clockwise input polygons are accepted.
  EXPECT_NEAR(boundary_area(exact_visible_boundary({{{0, 0}, {0, 1}, {1, 1}, {1, 0}}, {}}, {}, std::nullopt)), 1.0,
              1e-15);
  // Half-plane x ≤ 0.25 keeps a 0.25 × 1 strip of the unit square.
  EXPECT_NEAR(boundary_area(exact_visible_boundary(square(0, 0, 1, 1), {}, HalfPlane2{-1, 0, 0.25})), 0.25, 1e-15);
  // Fully covered: nothing.
  EXPECT_TRUE(exact_visible_boundary(circle(0, 0, 1), {square(-2, -2, 2, 2)}, std::nullopt).empty());
}

TEST(ExactRegion, RejectsDegeneratePolygons) {
  EXPECT_THROW(exact_visible_boundary({{{0, 0}, {1, 1}}, {}}, {}, std::nullopt), Error);
  EXPECT_THROW(exact_visible_boundary(circle(0, 0, 0), {}, std::nullopt), Error);
  const Region2 bow_tie{{{0, 0}, {2, 2}, {2, 0}, {0, 1}}, {}};  // self-intersecting, area ≠ 0
  EXPECT_THROW(exact_visible_boundary(square(0, 0, 2, 2), {bow_tie}, std::nullopt), Error);
}

// Parallel planes, receiver normal along the plane normal: the exact path's
// vector contour must reproduce the hand-rolled circle path (closed-form
// arcs). Tolerance 1e-13 relative: two different quadrature-free and
// quadrature-based evaluations of the same integral.
struct CircleCase {
  std::string name;
  double h;
  Circle2 light;
  std::vector<Circle2> occluders;
};

void PrintTo(const CircleCase& c, std::ostream* os) { *os << c.name; }

class ExactVsCircleBooleans : public testing::TestWithParam<CircleCase> {};

TEST_P(ExactVsCircleBooleans, SameIrradiance) {
  const CircleCase& c = GetParam();
  std::vector<Region2> occluders;
  for (const Circle2& o : c.occluders) occluders.push_back({{}, o});
  const std::vector<Curve2> boundary = exact_visible_boundary({{}, c.light}, occluders, std::nullopt);
  // Light plane z = h above p = origin, 2-D axes x, y.
  const double exact_path = contour_irradiance({0, 0, c.h}, {1, 0, 0}, {0, 1, 0}, boundary, {0, 0, 0}, kUp);
  const double circle_path = occluded_disk_irradiance(c.h, c.light, c.occluders);
  EXPECT_LE(relative_error(exact_path, circle_path), 1e-13) << exact_path << " vs " << circle_path;
}

INSTANTIATE_TEST_SUITE_P(
    Configurations, ExactVsCircleBooleans,
    testing::Values(CircleCase{"Unoccluded", 2.0, {0.3, -0.1, 0.75}, {}},
                    CircleCase{"DefaultSceneAnnulus", 2.0, {0, 0, 0.75}, {{0, 0, 0.7}}},
                    CircleCase{"DefaultScenePartial", 2.0, {-0.3, 0, 0.75}, {{-0.6, 0, 0.7}}},
                    CircleCase{"ThreeOccluders", 0.7, {0.3, 0, 1.2}, {{0.0, 0.0, 0.6}, {0.7, 0.3, 0.6}, {1.2, -0.4, 0.5}}},
                    CircleCase{"NearPlane", 0.05, {0, 0, 1.0}, {{0.6, 0.2, 0.5}}}),
    [](const auto& info) { return info.param.name; });

Scene light_scene(const Shape& light_shape, double le) {
  Scene scene;
  scene.name = "exact";
  scene.source = "exact_region_test";
  scene.objects.push_back({"floor", Rectangle{{-5, -5, 0}, {10, 0, 0}, {0, 10, 0}}, {0.5, Lambertian{}}, 0});
  scene.objects.push_back({"light", light_shape, {}, le});
  return scene;
}

// Two occluders that split space in two along x = x_s (between p's plane and
// the light) hide complementary parts: E(light \ A) + E(light \ B) = E(light).
TEST(ExactPath, ComplementaryOccludersAddUpToTheLight) {
  const Vec3 p{0.1, 0.2, 0};
  for (const Shape& light : {Shape(Disk{{0, 0, 2}, {0, 0, -1}, 0.75}),
                             Shape(Rectangle{{-0.5, -0.4, 2}, {0, 0.9, 0}, {1.1, 0, 0}}),
                             Shape(Triangle{{-0.6, -0.5, 2}, {0.2, 0.9, 2}, {0.7, -0.3, 2}})}) {
    const double full = irradiance(light_scene(light, 1.0), p, kUp, size_t(0));
    // Occluder plane z = 1: the image of x = x_s is x_p + 2(x_s − x_p).
    Scene left = light_scene(light, 1.0), right = light_scene(light, 1.0);
    left.objects.push_back({"left", Rectangle{{-3, -3, 1}, {3.15, 0, 0}, {0, 6, 0}}, {}, 0});
    right.objects.push_back({"right", Rectangle{{0.15, -3, 1}, {3, 0, 0}, {0, 6, 0}}, {}, 0});
    const double sum = irradiance(left, p, kUp, size_t(0)) + irradiance(right, p, kUp, size_t(0));
    EXPECT_LE(relative_error(sum, full), 1e-13) << sum << " vs " << full;
  }
}

// Central projection preserves solid angle, so a polygon occluder whose image
// lies inside the light removes exactly its own projected solid angle
// (Lambert on the occluder itself, no projection involved).
TEST(ExactPath, InteriorPolygonOccluderRemovesItsOwnSolidAngle) {
  const Vec3 p{0.05, -0.1, 0};
  const Triangle blocker{{-0.1, -0.1, 1}, {0.15, 0.0, 1.1}, {0.0, 0.2, 0.9}};
  for (const Shape& light : {Shape(Disk{{0, 0, 2}, {0, 0, -1}, 0.75}),
                             Shape(Rectangle{{-0.7, -0.6, 2}, {0, 1.3, 0}, {1.4, 0, 0}})}) {
    Scene scene = light_scene(light, 1.0);
    const double full = irradiance(scene, p, kUp, size_t(0));
    scene.objects.push_back({"blocker", blocker, {}, 0});
    const double hidden = polygon_irradiance({blocker.p0 - p, blocker.p1 - p, blocker.p2 - p}, kUp);
    EXPECT_LE(relative_error(irradiance(scene, p, kUp, size_t(0)), full - hidden), 1e-13);
  }
}

TEST(ExactPath, OccluderCoveringTheLightGivesExactZero) {
  Scene scene = light_scene(Disk{{0, 0, 2}, {0, 0, -1}, 0.75}, 4.0);
  scene.objects.push_back({"lid", Rectangle{{-1, -1, 1}, {2, 0, 0}, {0, 2, 0}}, {}, 0});
  EXPECT_EQ(irradiance(scene, {0, 0, 0}, kUp, size_t(0)), 0.0);
}

// Independent: ∫_disk max(cos θ, 0)·cos θ'/r² dA in polar coordinates about
// the disk's centre; cos θ's sign is linear in the plane, so for each radius
// the positive angles form one interval, found analytically.
double disk_quadrature(const Vec3& center, double R, const Vec3& p, const Vec3& n) {
  const Vec3 e1{1, 0, 0}, e2{0, 1, 0};  // the disk lies in a plane z = const, normal −z
  auto inner = [&](double rho) {
    // n·(x − p) = A + ρ(B cos φ + C sin φ) = A + ρ·M·cos(φ − φ0)
    const double A = dot(n, center - p), B = dot(n, e1), C = dot(n, e2);
    const double M = std::hypot(B, C), phi0 = std::atan2(C, B);
    double lo = -kPi, hi = kPi;
    if (rho * M > std::fabs(A)) {
      const double half = std::acos(-A / (rho * M));
      lo = phi0 - half, hi = phi0 + half;
    } else if (A < 0) {
      return 0.0;
    }
    auto f = [&](double phi) {
      const Vec3 x = center + (e1 * std::cos(phi) + e2 * std::sin(phi)) * rho - p;
      const double r2 = length_squared(x);
      return std::fmax(dot(n, x), 0.0) * std::fabs(x.z) / (r2 * r2);
    };
    return rho * boost::math::quadrature::gauss_kronrod<double, 61>::integrate(f, lo, hi, 7, 1e-13);
  };
  boost::math::quadrature::tanh_sinh<double> outer;
  return outer.integrate(inner, 0.0, R, 1e-13);
}

// Inside a closed box the five other walls tile the hemisphere of a floor
// point, so their irradiance is exactly π·Le whatever the point: the walls
// touching the lit wall along an edge must not count as occluders (they
// reach the light only along a zero-area sliver).
TEST(ExactPath, ClosedBoxWallsTileTheHemisphere) {
  Scene scene;
  scene.name = "box";
  scene.source = "exact_region_test";
  const double le = 1.0;
  auto wall = [&](const std::string& name, Vec3 corner, Vec3 u, Vec3 v) {
    scene.objects.push_back({name, Rectangle{corner, u, v}, {0.9, Lambertian{}}, le});
  };
  wall("floor", {-1, -1, -1}, {2, 0, 0}, {0, 2, 0});
  wall("ceiling", {-1, -1, 1}, {0, 2, 0}, {2, 0, 0});
  wall("west", {-1, -1, -1}, {0, 2, 0}, {0, 0, 2});
  wall("east", {1, -1, -1}, {0, 0, 2}, {0, 2, 0});
  wall("south", {-1, -1, -1}, {0, 0, 2}, {2, 0, 0});
  wall("north", {-1, 1, -1}, {2, 0, 0}, {0, 0, 2});
  for (const Vec3& p : {Vec3{0, 0, -1}, Vec3{0.3, -0.2, -1}, Vec3{0.95, 0.9, -1}})
    EXPECT_LE(relative_error(irradiance(scene, p, kUp, size_t(0)), kPi * le), 1e-12) << p.x << " " << p.y;
}

struct TiltCase {
  std::string name;
  Vec3 n;
};

void PrintTo(const TiltCase& c, std::ostream* os) { *os << c.name; }

class TiltedReceiverUnderDisk : public testing::TestWithParam<TiltCase> {};

// Tolerance 1e-10: the quadrature's, limited by the √-type kink where the
// horizon enters the disk.
TEST_P(TiltedReceiverUnderDisk, ExactPathMatchesPolarQuadrature) {
  const Vec3 n = normalize(GetParam().n);
  const Disk light{{0.2, -0.1, 1.0}, {0, 0, -1}, 0.8};
  Scene scene = light_scene(light, 1.0);
  scene.objects.erase(scene.objects.begin());  // no floor: p floats
  const Vec3 p{0, 0, 0};
  const double expected = disk_quadrature(light.center, light.radius, p, n);
  EXPECT_LE(relative_error(irradiance(scene, p, n, std::nullopt), expected), 1e-10) << expected;
}

INSTANTIATE_TEST_SUITE_P(Normals, TiltedReceiverUnderDisk,
                         testing::Values(TiltCase{"SlightTilt", {0.1, 0.05, 1}}, TiltCase{"StrongTilt", {1, 0.3, 0.6}},
                                         TiltCase{"StraddlingHorizon", {1, 0, 0.2}},
                                         TiltCase{"VerticalWall", {0, -1, 0}}),
                         [](const auto& info) { return info.param.name; });

}  // namespace
}  // namespace furnace::analytic
