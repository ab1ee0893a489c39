// Sphere light partly hidden by planar occluders (sphere_occluded.h) against
// Snyder's closed form (occluder off the cone or behind the light), an
// independent area quadrature over the occluder (partial occlusion, horizon
// cut), Lambert's polygon formula (occluder wholly inside the cone), the
// exact zero of a fully hidden light, and the scene-level dispatch.
#include <algorithm>
#include <cmath>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <gtest/gtest.h>

#include "analytic/polygon.h"
#include "analytic/reference.h"
#include "analytic/sphere.h"
#include "analytic/sphere_occluded.h"
#include "core/error.h"

namespace furnace::analytic {
namespace {

const Vec3 kUp{0, 0, 1};
const Sphere kLight{{0.2, -0.1, 2.0}, 0.5};

double relative_error(double value, double expected) { return std::fabs(value - expected) / std::fabs(expected); }

// ---- independent reference --------------------------------------------------
// With the occluder wholly between p and the sphere (every point of it nearer
// to p than |c − p| − R), the visible projected solid angle is Snyder's form
// minus ∫ over the occluder's points inside the cone and above the horizon of
// cos θ·|cos θ'|/r² dA. That area integral is written over the occluder's own
// parameters (not the cone's): for each outer parameter the inner line
// y(t) = y0 + t·d meets the cone (a·y)² ≥ cos²θmax·|y|², a·y ≥ 0, and the
// horizon n·y ≥ 0 in intervals found from a quadratic and two linear roots.
struct Cone {
  Vec3 a;
  double cos2;
};

Cone cone_of(const Sphere& s, const Vec3& p) {
  const Vec3 c = s.center - p;
  const double D = length(c);
  return {c / D, (D - s.radius) * (D + s.radius) / (D * D)};
}

// ∫_0^{t_end} [y(t) in cone and above horizon]·(n·y)|m·y|/|y|⁴·(j0 + j1·t) dt,
// y = y0 + t·d, m the occluder's unit normal, j0 + j1·t the area Jacobian.
double line_integral(const Cone& cone, const Vec3& n, const Vec3& m, const Vec3& y0, const Vec3& d, double t_end,
                     double j0, double j1) {
  std::vector<double> cuts{0, t_end};
  auto add_linear = [&](double f0, double f1) {  // root of f0 + t·f1
    if (f1 != 0) cuts.push_back(-f0 / f1);
  };
  add_linear(dot(cone.a, y0), dot(cone.a, d));
  add_linear(dot(n, y0), dot(n, d));
  const double qa = dot(cone.a, d) * dot(cone.a, d) - cone.cos2 * dot(d, d);
  const double qb = dot(cone.a, y0) * dot(cone.a, d) - cone.cos2 * dot(y0, d);
  const double qc = dot(cone.a, y0) * dot(cone.a, y0) - cone.cos2 * dot(y0, y0);
  const double disc = qb * qb - qa * qc;
  if (qa != 0 && disc >= 0) {
    cuts.push_back((-qb - std::sqrt(disc)) / qa);
    cuts.push_back((-qb + std::sqrt(disc)) / qa);
  }
  for (double& t : cuts) t = std::clamp(t, 0.0, t_end);
  std::sort(cuts.begin(), cuts.end());
  auto weight = [&](double t) {
    const Vec3 y = y0 + d * t;
    const double r2 = dot(y, y);
    return dot(n, y) * std::fabs(dot(m, y)) / (r2 * r2) * (j0 + j1 * t);
  };
  double sum = 0;
  for (size_t i = 0; i + 1 < cuts.size(); ++i) {
    if (cuts[i + 1] <= cuts[i]) continue;
    const Vec3 y = y0 + d * (0.5 * (cuts[i] + cuts[i + 1]));
    const double ay = dot(cone.a, y);
    if (ay < 0 || ay * ay < cone.cos2 * dot(y, y) || dot(n, y) < 0) continue;
    sum += boost::math::quadrature::gauss_kronrod<double, 31>::integrate(weight, cuts[i], cuts[i + 1], 8, 1e-15);
  }
  return sum;
}

// Per unit of the outer parameter. Near a tangency of the cone's conic the
// inner limits come from a near-double root and carry ~√ε noise, so a tighter
// target would bisect through noise down to the depth cap.
constexpr double kOuterTolerance = 1e-12;
constexpr int kOuterMaxDepth = 25;

// Adaptive bisection on the 15-point rule, depth-capped (the outer integrand
// has √-kinks where the cone's conic is tangent to the inner lines).
double outer_integral(const std::function<double(double)>& f, double lo, double hi, double tol, int depth = 0) {
  double error = 0;
  const double value = boost::math::quadrature::gauss_kronrod<double, 15>::integrate(f, lo, hi, 0, 0, &error);
  // Boost reports the error of the rule mapped to [−1, 1]: scale by (hi − lo)/2.
  if (0.5 * error <= tol || depth >= kOuterMaxDepth) return value;
  const double mid = 0.5 * (lo + hi);
  return outer_integral(f, lo, mid, tol, depth + 1) + outer_integral(f, mid, hi, tol, depth + 1);
}

// ∫ over the occluder ∩ cone ∩ upper hemisphere of cos θ·|cos θ'|/r² dA.
double occluded_part(const Shape& shape, const Sphere& light, const Vec3& p, const Vec3& n) {
  const Cone cone = cone_of(light, p);
  if (const auto* r = std::get_if<Rectangle>(&shape)) {
    auto f = [&](double s) {
      return line_integral(cone, n, r->normal(), r->corner + r->edge_u * s - p, r->edge_v, 1, r->area(), 0);
    };
    return outer_integral(f, 0, 1, kOuterTolerance);
  }
  if (const auto* t = std::get_if<Triangle>(&shape)) {
    // x = p0 + s·e1 + t·s·(e2 − e1), s, t ∈ [0, 1], Jacobian s·|e1 × e2|.
    const Vec3 e1 = t->p1 - t->p0, e2 = t->p2 - t->p0;
    auto f = [&](double s) {
      return line_integral(cone, n, t->normal(), t->p0 + e1 * s - p, (e2 - e1) * s, 1, 2 * t->area() * s, 0);
    };
    return outer_integral(f, 0, 1, kOuterTolerance);
  }
  // Disk in polar coordinates x = c + ρ·(cos ψ·s + sin ψ·t), dA = ρ dρ dψ.
  const auto& disk = std::get<Disk>(shape);
  const Frame frame = Frame::from_normal(disk.normal);
  auto f = [&](double psi) {
    const Vec3 d = frame.s * std::cos(psi) + frame.t * std::sin(psi);
    return line_integral(cone, n, disk.normal, disk.center - p, d, disk.radius, 0, 1);
  };
  return outer_integral(f, 0, 2 * kPi, kOuterTolerance);
}

// Every point of the occluder nearer to p than the sphere's nearest point:
// the area reference's assumption.
bool wholly_in_front(const Shape& shape, const Sphere& light, const Vec3& p) {
  const double near = length(light.center - p) - light.radius;
  std::vector<Vec3> points;
  if (const auto* r = std::get_if<Rectangle>(&shape))
    points = {r->corner, r->corner + r->edge_u, r->corner + r->edge_v, r->corner + r->edge_u + r->edge_v};
  else if (const auto* t = std::get_if<Triangle>(&shape))
    points = {t->p0, t->p1, t->p2};
  else
    return length(std::get<Disk>(shape).center - p) + std::get<Disk>(shape).radius < near;
  return std::all_of(points.begin(), points.end(), [&](const Vec3& x) { return length(x - p) < near; });
}

// ---- (1) occluders that hide nothing ------------------------------------------

// Tolerance 1e-12: the φ-quadrature's target is 1e-13 of the unoccluded value.
TEST(SphereOccluded, OccluderMissingTheConeGivesClosedForm) {
  for (const Vec3& n : {kUp, normalize(Vec3{0.9, 0.2, 0.3})}) {  // the second receiver cuts the cone
    const double closed = sphere_irradiance(kLight.center, kLight.radius, n);
    const std::vector<Shape> occluders{Rectangle{{1.0, 1.0, 1.0}, {0.5, 0, 0}, {0, 0.5, 0}},
                                       Triangle{{-1, -1, 0.5}, {-0.6, -1, 0.5}, {-1, -0.6, 0.7}},
                                       Disk{{-1.0, 1.0, 1.0}, {0, 0, 1}, 0.3}};
    EXPECT_LE(relative_error(occluded_sphere_irradiance(kLight, occluders, {0, 0, 0}, n), closed), 1e-12);
  }
}

TEST(SphereOccluded, OccluderBehindTheLightGivesClosedForm) {
  const double closed = sphere_irradiance(kLight.center, kLight.radius, kUp);
  const std::vector<Shape> behind{Rectangle{{-1, -1, 3}, {2, 0, 0}, {0, 2, 0}}};
  EXPECT_LE(relative_error(occluded_sphere_irradiance(kLight, behind, {0, 0, 0}, kUp), closed), 1e-12);
}

// ---- (2) partial occlusion against the area quadrature ------------------------

struct PartialCase {
  std::string name;
  Shape occluder;
  Vec3 n;
};

void PrintTo(const PartialCase& c, std::ostream* os) { *os << c.name; }

class SphereOccludedVsArea : public testing::TestWithParam<PartialCase> {};

// Tolerance 1e-10: the requested accuracy of both quadratures.
TEST_P(SphereOccludedVsArea, MatchesClosedFormMinusOccluderIntegral) {
  const PartialCase& c = GetParam();
  const Vec3 p{0, 0, 0}, n = normalize(c.n);
  ASSERT_TRUE(wholly_in_front(c.occluder, kLight, p));
  const double closed = sphere_irradiance(kLight.center - p, kLight.radius, n);
  const double hidden = occluded_part(c.occluder, kLight, p, n);
  ASSERT_GT(hidden, 0.02 * closed);       // a real partial occlusion,
  ASSERT_LT(hidden, 0.98 * closed);       // not a near-total one
  const double expected = closed - hidden;
  EXPECT_LE(relative_error(occluded_sphere_irradiance(kLight, {c.occluder}, p, n), expected), 1e-10)
      << expected << " hidden " << hidden;
}

INSTANTIATE_TEST_SUITE_P(
    Occluders, SphereOccludedVsArea,
    testing::Values(
        PartialCase{"Square", Rectangle{{0.1, -0.3, 1.0}, {0.4, 0.1, 0}, {-0.1, 0.4, 0.05}}, kUp},
        PartialCase{"Triangle", Triangle{{-0.2, -0.4, 0.9}, {0.5, -0.1, 1.0}, {0.0, 0.3, 0.8}}, kUp},
        PartialCase{"Disk", Disk{{0.25, 0.05, 1.1}, normalize(Vec3{0.2, -0.1, 1}), 0.2}, kUp},
        PartialCase{"SquareHorizonCut", Rectangle{{0.1, -0.3, 1.0}, {0.4, 0.1, 0}, {-0.1, 0.4, 0.05}},
                    Vec3{-0.95, 0.1, 0.08}},
        PartialCase{"DiskHorizonCut", Disk{{0.0, -0.1, 1.0}, normalize(Vec3{0.1, 0.1, 1}), 0.15},
                    Vec3{-0.95, 0.1, 0.08}}),
    [](const auto& info) { return info.param.name; });

// ---- (3) fully hidden -------------------------------------------------------------

TEST(SphereOccluded, FullyHiddenIsExactlyZero) {
  const std::vector<Shape> lids{Rectangle{{-2, -2, 1}, {4, 0, 0}, {0, 4, 0}},
                                Disk{{0.1, -0.05, 1}, {0, 0, 1}, 1.0},
                                Triangle{{-3, -3, 1}, {4, -3, 1}, {0, 4, 1}}};
  for (const Shape& lid : lids) {
    EXPECT_EQ(occluded_sphere_irradiance(kLight, {lid}, {0, 0, 0}, kUp), 0.0);
    EXPECT_EQ(occluded_sphere_irradiance(kLight, {lid}, {0, 0, 0}, normalize(Vec3{0.9, 0.2, 0.3})), 0.0);
  }
}

// ---- (4) occluder wholly inside the cone: Lambert ---------------------------------

// Tolerance 1e-10: Lambert's sum is good to ~1e-15 here; the rest is the quadrature's.
TEST(SphereOccluded, OccluderInsideTheConeSubtractsLambert) {
  const Vec3 p{0, 0, 0};
  for (const Vec3& n : {kUp, normalize(Vec3{0.3, -0.2, 1})}) {
    const double closed = sphere_irradiance(kLight.center - p, kLight.radius, n);
    const Rectangle square{{0.05, -0.1, 1.0}, {0.15, 0.02, 0}, {-0.02, 0.15, 0.01}};
    const Triangle tri{{0.1, -0.1, 1.2}, {0.25, -0.05, 1.2}, {0.15, 0.05, 1.1}};
    const double e_square = polygon_irradiance(
        {square.corner, square.corner + square.edge_u, square.corner + square.edge_u + square.edge_v,
         square.corner + square.edge_v},
        n);
    const double e_tri = polygon_irradiance({tri.p0, tri.p1, tri.p2}, n);
    EXPECT_LE(relative_error(occluded_sphere_irradiance(kLight, {square}, p, n), closed - e_square), 1e-10);
    EXPECT_LE(relative_error(occluded_sphere_irradiance(kLight, {tri}, p, n), closed - e_tri), 1e-10);
  }
}

// ---- scene-level dispatch -----------------------------------------------------------

Scene floor_and_bulb() {
  Scene scene;
  scene.name = "sphere_occluded_test";
  scene.objects.push_back({"floor", Rectangle{{-5, -5, 0}, {10, 0, 0}, {0, 10, 0}}, {0.5, Lambertian{}}, 0});
  scene.objects.push_back({"bulb", kLight, {}, 3.0});
  return scene;
}

TEST(SphereOccludedScene, PlanarBlockersUseTheQuadratureSpheresAreRefused) {
  Scene scene = floor_and_bulb();
  const Vec3 p{0, 0, 0};
  const double closed = 3.0 * sphere_irradiance(kLight.center, kLight.radius, kUp);
  EXPECT_EQ(irradiance(scene, p, kUp, size_t(0)), closed);  // nothing blocks: Snyder's form exactly
  const Rectangle square{{0.1, -0.3, 1.0}, {0.4, 0.1, 0}, {-0.1, 0.4, 0.05}};
  scene.objects.push_back({"square", square, {}, 0});
  EXPECT_LE(relative_error(irradiance(scene, p, kUp, size_t(0)),
                           3.0 * occluded_sphere_irradiance(kLight, {square}, p, kUp)),
            1e-15);
  scene.objects.push_back({"ball", Sphere{{0.2, 0.2, 1.0}, 0.1}, {}, 0});
  EXPECT_THROW(irradiance(scene, p, kUp, size_t(0)), Error);
}

TEST(SphereOccludedScene, SceneFileReferenceImageIsFinite) {
  const Scene scene = load_scene(std::string(FURNACE_SCENE_DIR) + "/sphere_occluder.json");
  const std::vector<double> image = reference_image(scene);
  double lo = image[0], hi = image[0];
  for (double v : image) {
    ASSERT_TRUE(std::isfinite(v));
    lo = std::fmin(lo, v);
    hi = std::fmax(hi, v);
  }
  EXPECT_GT(hi, 2 * lo);  // a visible shadow
}

}  // namespace
}  // namespace furnace::analytic
