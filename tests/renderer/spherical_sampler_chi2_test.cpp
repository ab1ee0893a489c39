// Chi-square goodness of fit of the renderer's solid-angle samplers of
// triangles (Arvo 1995) and rectangles (Ureña et al. 2013),
// renderer/spherical_sampling.h: the sampled directions must be uniform in
// solid angle, density 1/Ω.
//
// The test bins the hit point in the shape's own coordinates (barycentric
// (b1, b2), or (u, v) along the rectangle's edges), on a grid whose cell
// edges follow the shape's boundary, so no cell holds a sliver of support
// that quadrature could miss. The density there is the claimed 1/Ω times the
// Jacobian dω/dA = |cos θ'|/d², computed here independently of the sampler;
// the quadrature of it over the grid is Ω_true/Ω_claimed, so the pdf-integral
// check also tests the sampler's solid-angle formula.
//
// Budget and levels: kSamples samples per case from a fixed named seed; the
// correct cases share kFamilyAlpha by Šidák; the negative control runs at the
// same per-test level. Each test prints its detectable effect w.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <ostream>
#include <string>

#include "core/scene.h"
#include "renderer/rng.h"
#include "renderer/spherical_sampling.h"
#include "stats/chi2.h"

namespace furnace::stats {
namespace {

constexpr uint64_t kSeed = 0x5fe41ca1;  // fixed: verdicts are reproducible
constexpr size_t kSamples = 1000000;
constexpr double kFamilyAlpha = 0.01;
constexpr int kBins = 21;  // odd; the triangle's hypotenuse b1 + b2 = 1 runs through cell corners
// Hit points on an edge may land a few ulps outside [0, 1] after the plane
// intersection; excursions below this are clamped, larger ones fail the test.
constexpr double kEdgeRoundOff = 1e-9;
// ∫pdf over the grid = Ω_true/Ω_claimed. Cells cut by the hypotenuse
// converge to ~1e-7 (see warp_chi2_test.cpp); 1e-6 is far below what the
// chi-square resolves and would still catch a solid-angle formula off by 1 ppm.
constexpr double kSolidAngleRatioTolerance = 1e-6;

double clamp_round_off(double x) {
  if (x < 0 && x > -kEdgeRoundOff) return 0;
  if (x > 1 && x < 1 + kEdgeRoundOff) return 1;
  return x;
}

// |cos θ'|/d² at point p seen from `origin` on a plane of unit normal n: dω/dA.
double solid_angle_per_area(const Vec3& origin, const Vec3& p, const Vec3& n) {
  const Vec3 d = p - origin;
  const double d2 = length_squared(d);
  return std::fabs(dot(n, d)) / (d2 * std::sqrt(d2));
}

struct TriangleCase {
  std::string name;
  Triangle triangle;
  Vec3 origin;
};

void PrintTo(const TriangleCase& c, std::ostream* os) { *os << c.name; }

// Barycentric (b1, b2) of the point where the ray origin + t·w meets the triangle's plane.
std::array<double, 2> barycentric_of_hit(const Triangle& tri, const Vec3& origin, const Vec3& w) {
  const Vec3 n = tri.normal();
  const Vec3 p = origin + w * (dot(tri.p0 - origin, n) / dot(w, n));
  const Vec3 e1 = tri.p1 - tri.p0, e2 = tri.p2 - tri.p0, q = p - tri.p0;
  const double d11 = dot(e1, e1), d12 = dot(e1, e2), d22 = dot(e2, e2);
  const double q1 = dot(q, e1), q2 = dot(q, e2);
  const double det = d11 * d22 - d12 * d12;
  return {clamp_round_off((d22 * q1 - d12 * q2) / det), clamp_round_off((d11 * q2 - d12 * q1) / det)};
}

// Density in (b1, b2) of directions uniform with density 1/Ω in solid angle:
// (1/Ω)·dω/dA·dA/d(b1, b2), dA = 2·area·db1·db2.
PlanarPdf triangle_pdf(const Triangle& tri, const Vec3& origin, double solid_angle) {
  return [=](const std::array<double, 2>& b) {
    if (!(b[0] >= 0 && b[1] >= 0 && b[0] + b[1] <= 1)) return 0.0;
    const Vec3 p = tri.p0 + (tri.p1 - tri.p0) * b[0] + (tri.p2 - tri.p0) * b[1];
    return 2 * tri.area() * solid_angle_per_area(origin, p, tri.normal()) / solid_angle;
  };
}

std::vector<std::array<double, 2>> draw_triangle(const SphericalTriangleSampler& s, const TriangleCase& c,
                                                 uint64_t stream) {
  Rng rng(kSeed, stream, 0);
  std::vector<std::array<double, 2>> out(kSamples);
  for (auto& b : out) {
    const double u1 = rng.next_double();
    b = barycentric_of_hit(c.triangle, c.origin, s.sample(u1, rng.next_double()));
  }
  return out;
}

// The unit triangle's normal is +z (cross((2,0,0), (1,2,0))); viewpoints above it.
const Triangle kTriangle{{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}};

std::vector<TriangleCase> triangle_cases() {
  return {
      {"Overhead", kTriangle, {0.2, 0.1, 1.5}},
      {"Close", kTriangle, {0.1, -0.3, 0.05}},   // Ω near 2π·(a large fraction): strongly non-uniform in area
      {"Grazing", kTriangle, {3.0, 0.5, 0.2}},
      {"Small", kTriangle, {0.0, 0.0, 100.0}},   // Ω ≈ 2e-4 sr
  };
}

struct RectangleCase {
  std::string name;
  Rectangle rectangle;
  Vec3 origin;
};

void PrintTo(const RectangleCase& c, std::ostream* os) { *os << c.name; }

// A 2 × 1 rectangle in z = 0, normal +z, and a tilted one.
const Rectangle kRectangle{{-1, -0.5, 0}, {2, 0, 0}, {0, 1, 0}};
const Rectangle kTilted{{0, 0, 0}, {1, 1, 0}, {-0.5, 0.5, 1}};

std::vector<RectangleCase> rectangle_cases() {
  return {
      {"Overhead", kRectangle, {0.3, 0.2, 1.0}},
      {"Close", kRectangle, {-0.7, 0.1, 0.05}},
      {"Grazing", kRectangle, {4.0, -1.0, 0.3}},
      {"Tilted", kTilted, {0.5, -1.0, 0.8}},
  };
}

size_t family_size() { return triangle_cases().size() + rectangle_cases().size(); }

void report(const Chi2Result& r, double solid_angle) {
  std::cout << "  Omega = " << solid_angle << " sr, N = " << r.samples << ", " << r.message
            << " Omega_true/Omega_claimed - 1 = " << r.pdf_integral - 1 << ", detectable effect w = " << r.detectable_effect
            << "\n";
  testing::Test::RecordProperty("detectable_effect_w", std::to_string(r.detectable_effect));
}

class SphericalTriangleChi2 : public testing::TestWithParam<TriangleCase> {};

TEST_P(SphericalTriangleChi2, UniformInSolidAngle) {
  const TriangleCase& c = GetParam();
  const auto sampler = SphericalTriangleSampler::make(c.triangle, c.origin);
  ASSERT_TRUE(sampler.has_value()) << "viewpoint not in front of the triangle";
  const PlanarChi2 chi2(triangle_pdf(c.triangle, c.origin, sampler->solid_angle), PlanarGrid{0, 1, 0, 1, kBins, kBins});
  const Chi2Result r = chi2.test(draw_triangle(*sampler, c, 1), kFamilyAlpha, family_size());
  report(r, sampler->solid_angle);
  EXPECT_TRUE(r.pass) << r.message;
  EXPECT_NEAR(r.pdf_integral, 1.0, kSolidAngleRatioTolerance) << "the sampler's solid angle is off";
}

INSTANTIATE_TEST_SUITE_P(Shapes, SphericalTriangleChi2, testing::ValuesIn(triangle_cases()),
                         [](const testing::TestParamInfo<TriangleCase>& info) { return info.param.name; });

// Negative control: solid-angle samples from close by tested against the
// area-uniform density (2 on the parameter triangle) must fail.
TEST(SphericalTriangleChi2NegativeControl, SolidAngleSamplesVsAreaPdf) {
  const TriangleCase c = triangle_cases()[1];
  const auto sampler = SphericalTriangleSampler::make(c.triangle, c.origin);
  ASSERT_TRUE(sampler.has_value());
  const PlanarPdf area_uniform = [](const std::array<double, 2>& b) {
    return b[0] >= 0 && b[1] >= 0 && b[0] + b[1] <= 1 ? 2.0 : 0.0;
  };
  const PlanarChi2 chi2(area_uniform, PlanarGrid{0, 1, 0, 1, kBins, kBins});
  const Chi2Result r = chi2.test(draw_triangle(*sampler, c, 2), kFamilyAlpha, family_size());
  report(r, sampler->solid_angle);
  EXPECT_FALSE(r.pass) << "area-uniform density accepted for solid-angle samples: " << r.message;
}

// (u, v) ∈ [0, 1]² of a point on the rectangle.
std::array<double, 2> rectangle_coordinates(const Rectangle& rect, const Vec3& p) {
  const Vec3 q = p - rect.corner;
  return {clamp_round_off(dot(q, rect.edge_u) / length_squared(rect.edge_u)),
          clamp_round_off(dot(q, rect.edge_v) / length_squared(rect.edge_v))};
}

class SphericalRectangleChi2 : public testing::TestWithParam<RectangleCase> {};

TEST_P(SphericalRectangleChi2, UniformInSolidAngle) {
  const RectangleCase& c = GetParam();
  const auto sampler = SphericalRectangleSampler::make(c.rectangle, c.origin);
  ASSERT_TRUE(sampler.has_value()) << "viewpoint not in front of the rectangle";
  const Rectangle rect = c.rectangle;
  const Vec3 origin = c.origin;
  const double solid_angle = sampler->solid_angle;
  // dA = area·du·dv.
  const PlanarPdf pdf = [rect, origin, solid_angle](const std::array<double, 2>& uv) {
    const Vec3 p = rect.corner + rect.edge_u * uv[0] + rect.edge_v * uv[1];
    return rect.area() * solid_angle_per_area(origin, p, rect.normal()) / solid_angle;
  };
  const PlanarChi2 chi2(pdf, PlanarGrid{0, 1, 0, 1, kBins, kBins});
  Rng rng(kSeed, 3, 0);
  std::vector<std::array<double, 2>> samples(kSamples);
  for (auto& uv : samples) {
    const double u1 = rng.next_double();
    uv = rectangle_coordinates(rect, sampler->sample_point(u1, rng.next_double()));
  }
  const Chi2Result r = chi2.test(samples, kFamilyAlpha, family_size());
  report(r, solid_angle);
  EXPECT_TRUE(r.pass) << r.message;
  EXPECT_NEAR(r.pdf_integral, 1.0, kSolidAngleRatioTolerance) << "the sampler's solid angle is off";
}

INSTANTIATE_TEST_SUITE_P(Shapes, SphericalRectangleChi2, testing::ValuesIn(rectangle_cases()),
                         [](const testing::TestParamInfo<RectangleCase>& info) { return info.param.name; });

}  // namespace
}  // namespace furnace::stats
