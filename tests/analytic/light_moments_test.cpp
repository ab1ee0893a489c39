// Moment kernels of unoccluded spheres and polygons (light_moments.h)
// against independent quadrature in other parametrisations.
#include "analytic/light_moments.h"

#include <cmath>
#include <ostream>
#include <string>

#include <gtest/gtest.h>

#include "solid_angle_quadrature.h"

namespace furnace::analytic {
namespace {

const Vec3 kUp{0, 0, 1};

double relative_error(double value, double expected) { return std::fabs(value - expected) / std::fabs(expected); }

struct SphereCase {
  std::string name;
  double D, R, beta;
};

void PrintTo(const SphereCase& c, std::ostream* os) { *os << c.name; }

const std::vector<SphereCase> kSpheres{{"Overhead", 3, 1, 0}, {"Oblique", 2, 0.5, 0.9},
                                       {"StraddleUpper", 3, 1, 1.4}, {"StraddleLower", 2, 0.8, 1.9},
                                       {"Close", 1.05, 1, 0.3}};

Vec3 centre_of(const SphereCase& c) { return {c.D * std::sin(c.beta), 0, c.D * std::cos(c.beta)}; }

class SphereMoments : public testing::TestWithParam<SphereCase> {};

// Tolerance 1e-10: the reference quadratures' (tanh–sinh outside, GK inside).
TEST_P(SphereMoments, Cos2SolidAngleMatchesConeQuadrature) {
  const SphereCase& c = GetParam();
  const double expected = testing_support::sphere_projected_solid_angle(centre_of(c), c.R, kUp, 2);
  EXPECT_LE(relative_error(sphere_cos2_solid_angle(centre_of(c), c.R, kUp), expected), 1e-10) << expected;
}

TEST_P(SphereMoments, AreaKernelMatchesSurfaceQuadrature) {
  const SphereCase& c = GetParam();
  const double expected = testing_support::sphere_area_kernel_quadrature(centre_of(c), c.R, kUp);
  EXPECT_LE(relative_error(sphere_area_kernel(centre_of(c), c.R, kUp), expected), 1e-9) << expected;
}

INSTANTIATE_TEST_SUITE_P(Spheres, SphereMoments, testing::ValuesIn(kSpheres),
                         [](const auto& info) { return info.param.name; });

struct PolygonCase {
  std::string name;
  bool triangle;
  Vec3 a, b, c;  // rectangle: corner, edge_u, edge_v; triangle: vertices
  Vec3 n;
};

void PrintTo(const PolygonCase& c, std::ostream* os) { *os << c.name; }

class PolygonMoments : public testing::TestWithParam<PolygonCase> {};

std::vector<Vec3> vertices_of(const PolygonCase& c) {
  if (c.triangle) return {c.a, c.b, c.c};
  return {c.a, c.a + c.b, c.a + c.b + c.c, c.a + c.c};
}
testing_support::Patch patch_of(const PolygonCase& c) {
  return c.triangle ? testing_support::triangle_patch(c.a, c.b, c.c) : testing_support::rectangle_patch(c.a, c.b, c.c);
}

// Arvo's closed form vs the area integral of cos²θ·|cos θ'|/r²: 1e-10.
TEST_P(PolygonMoments, ArvoCos2MatchesAreaQuadrature) {
  const PolygonCase& c = GetParam();
  const Vec3 n = normalize(c.n);
  const double expected = testing_support::patch_integral(
      patch_of(c), {0, 0, 0}, n, [](double cs, double cl, double r) { return cs * cs * cl / (r * r); });
  EXPECT_LE(relative_error(polygon_cos2_solid_angle(vertices_of(c), n), expected), 1e-10) << expected;
}

TEST_P(PolygonMoments, AreaKernelMatchesAreaQuadrature) {
  const PolygonCase& c = GetParam();
  const Vec3 n = normalize(c.n);
  const double expected = testing_support::patch_integral(patch_of(c), {0, 0, 0}, n, [](double cs, double cl, double r) {
    const double g = cs * cl / (r * r);
    return g * g;
  });
  EXPECT_LE(relative_error(polygon_area_kernel(vertices_of(c), n), expected), 1e-9) << expected;
}

INSTANTIATE_TEST_SUITE_P(
    Polygons, PolygonMoments,
    testing::Values(PolygonCase{"ParallelRectangle", false, {-0.5, -0.3, 1}, {1, 0, 0}, {0, 0.8, 0}, {0, 0, 1}},
                    PolygonCase{"TiltedRectangle", false, {-0.6, -0.4, 1.5}, {0, 0.8, 0.3}, {1.2, 0, 0}, {0.2, 0.1, 1}},
                    PolygonCase{"StraddlingRectangle", false, {1, -0.5, -0.5}, {0, 1, 0}, {0, 0, 1.5}, {0, 0, 1}},
                    PolygonCase{"Triangle", true, {0.9, 0.8, 1.2}, {1.3, 1.5, 1.2}, {1.7, 0.7, 1.2}, {0, 0, 1}},
                    PolygonCase{"StraddlingTriangle", true, {0.5, -0.5, -0.4}, {0.6, 0.6, 0.9}, {1.2, 0, 0.3}, {0, 0, 1}}),
    [](const auto& info) { return info.param.name; });

// The hemisphere's own limit: a huge square far above p tends to ∫cos² = 2π/3.
TEST(PolygonMomentsLimit, HugeCeilingApproachesHemisphere) {
  const double L = 1e7;
  const std::vector<Vec3> ceiling{{-L, -L, 1}, {L, -L, 1}, {L, L, 1}, {-L, L, 1}};
  EXPECT_NEAR(polygon_cos2_solid_angle(ceiling, kUp), 2 * kPi / 3, 1e-6);
}

}  // namespace
}  // namespace furnace::analytic
