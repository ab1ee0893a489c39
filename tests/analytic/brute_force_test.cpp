// The exact planar path (CGAL Booleans of projected polygon occluders +
// vector contour) against a brute-force area integral over the light (a disk,
// or a rectangle with axis-aligned edges) whose visibility comes from ray
// casting (analytic::intersect), with the visibility jumps along each line
// located by bisection. Nothing is shared
// with the path under test but the scene and the intersector.
#include <algorithm>
#include <cmath>
#include <optional>
#include <ostream>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <boost/math/quadrature/tanh_sinh.hpp>
#include <gtest/gtest.h>

#include "analytic/moments.h"
#include "analytic/reference.h"

namespace furnace::analytic {
namespace {

// Shadow lines: each straight occluder edge (A, B) casts, from p, the line
// where the plane through p, A, B meets the light plane z = z_l; written
// a·x + b·y = c. Visibility along a column x = const can change only where
// it crosses one of these lines or the light's rim.
struct Line2 {
  double a, b, c;
};

std::vector<Line2> shadow_lines(const Scene& scene, size_t light_index, const Vec3& p, double z_light) {
  std::vector<Line2> lines;
  for (size_t j = 0; j < scene.objects.size(); ++j) {
    if (j == light_index) continue;
    std::vector<Vec3> v;
    if (const auto* t = std::get_if<Triangle>(&scene.objects[j].shape)) v = {t->p0, t->p1, t->p2};
    if (const auto* r = std::get_if<Rectangle>(&scene.objects[j].shape))
      v = {r->corner, r->corner + r->edge_u, r->corner + r->edge_u + r->edge_v, r->corner + r->edge_v};
    for (size_t i = 0; i < v.size(); ++i) {
      const Vec3 m = cross(v[i] - p, v[(i + 1) % v.size()] - p);
      // m·(X − p) = 0 with X = (x, y, z_l).
      lines.push_back({m.x, m.y, m.x * p.x + m.y * p.y - m.z * (z_light - p.z)});
    }
  }
  return lines;
}

// What the brute force integrates over the visible light, per unit area:
// cos θ·cos θ'/r² (E/L), cos²θ·cos θ'/r² (∫ cos²θ dω, the uniform-hemisphere
// kernel) or (cos θ·cos θ'/r²)² (the light-area kernel).
enum class Kernel { kIrradiance, kCos2SolidAngle, kArea };

// The light's footprint in its plane z = z_light: a disk, or a rectangle with
// edges along x and y. Columns x = const span [y_lo(x), y_hi(x)].
struct Footprint {
  double z = 0, x_lo = 0, x_hi = 0;
  std::optional<Disk> disk;
  double y0 = 0, y1 = 0;  // rectangle
  std::pair<double, double> column(double x) const {
    if (!disk) return {y0, y1};
    const double cx = disk->center.x, cy = disk->center.y, R = disk->radius;
    const double half = std::sqrt(std::fmax(0.0, (R - (x - cx)) * (R + (x - cx))));
    return {cy - half, cy + half};
  }
  // The x where shadow line l crosses the rim (other than the columns' ends).
  void rim_crossings(const Line2& l, std::vector<double>& xs) const {
    if (!disk) {
      if (l.a != 0)
        for (double y : {y0, y1}) xs.push_back((l.c - l.b * y) / l.a);
      return;
    }
    // a x + b y = c with (x − cx)² + (y − cy)² = R²: parametrise along the line.
    const double cx = disk->center.x, cy = disk->center.y, R = disk->radius;
    const double norm = std::hypot(l.a, l.b);
    const double dist = (l.c - l.a * cx - l.b * cy) / norm;  // signed distance from the centre
    if (std::fabs(dist) < R) {
      const double foot_x = cx + l.a / norm * dist, along = std::sqrt((R - dist) * (R + dist));
      xs.push_back(foot_x - l.b / norm * along);
      xs.push_back(foot_x + l.b / norm * along);
    }
  }
};

Footprint footprint_of(const Shape& shape) {
  Footprint f;
  if (const auto* d = std::get_if<Disk>(&shape)) {
    f.disk = *d;
    f.z = d->center.z;
    f.x_lo = d->center.x - d->radius;
    f.x_hi = d->center.x + d->radius;
    return f;
  }
  const Rectangle& r = std::get<Rectangle>(shape);  // edges along x and y, in a plane z = const
  const Vec3 far = r.corner + r.edge_u + r.edge_v;
  f.z = r.corner.z;
  f.x_lo = std::fmin(r.corner.x, far.x);
  f.x_hi = std::fmax(r.corner.x, far.x);
  f.y0 = std::fmin(r.corner.y, far.y);
  f.y1 = std::fmax(r.corner.y, far.y);
  return f;
}

// Light (a disk, or a rectangle with edges along x and y) in a plane z =
// const, facing p; receiver at p with normal n. Includes one factor Le.
double brute_force(const Scene& scene, size_t light_index, const Vec3& p, const Vec3& n,
                   Kernel kind = Kernel::kIrradiance) {
  const Footprint light = footprint_of(scene.objects[light_index].shape);
  const double le = scene.objects[light_index].emitted_radiance;
  const std::vector<Line2> lines = shadow_lines(scene, light_index, p, light.z);
  auto visible = [&](double x, double y) {
    const Vec3 target{x, y, light.z};
    const auto hit = intersect(scene, p, target - p, 1e-12);
    return !hit || hit->t >= 1 - 1e-12 || hit->object_index == light_index;
  };
  auto kernel = [&](double x, double y) {
    const Vec3 d = Vec3{x, y, light.z} - p;
    const double r2 = length_squared(d), r = std::sqrt(r2);
    const double cos_theta = std::fmax(dot(n, d), 0.0) / r, cos_light = std::fabs(d.z) / r;
    switch (kind) {
      case Kernel::kIrradiance: return cos_theta * cos_light / r2;
      case Kernel::kCos2SolidAngle: return cos_theta * cos_theta * cos_light / r2;
      case Kernel::kArea: return cos_theta * cos_theta * cos_light * cos_light / (r2 * r2);
    }
    return 0.0;
  };
  auto column = [&](double x) {
    const auto [y0, y1] = light.column(x);
    std::vector<double> cuts{y0, y1};
    for (const Line2& l : lines)
      if (l.b != 0) {
        const double y = (l.c - l.a * x) / l.b;
        if (y > y0 && y < y1) cuts.push_back(y);
      }
    std::sort(cuts.begin(), cuts.end());
    double sum = 0;
    for (size_t i = 0; i + 1 < cuts.size(); ++i) {
      if (!(cuts[i + 1] > cuts[i]) || !visible(x, 0.5 * (cuts[i] + cuts[i + 1]))) continue;
      sum += boost::math::quadrature::gauss_kronrod<double, 31>::integrate([&](double y) { return kernel(x, y); },
                                                                          cuts[i], cuts[i + 1], 8, 1e-13);
    }
    return sum;
  };
  // Column kinks: where shadow lines cross each other or the rim.
  std::vector<double> xs{light.x_lo, light.x_hi};
  for (size_t i = 0; i < lines.size(); ++i) {
    for (size_t j = i + 1; j < lines.size(); ++j) {
      const double det = lines[i].a * lines[j].b - lines[j].a * lines[i].b;
      if (det != 0) xs.push_back((lines[i].c * lines[j].b - lines[j].c * lines[i].b) / det);
    }
    light.rim_crossings(lines[i], xs);
  }
  std::vector<double> inside;
  for (double x : xs)
    if (x >= light.x_lo && x <= light.x_hi) inside.push_back(x);
  std::sort(inside.begin(), inside.end());
  boost::math::quadrature::tanh_sinh<double> outer;
  double sum = 0;
  for (size_t i = 0; i + 1 < inside.size(); ++i)
    if (inside[i + 1] > inside[i]) sum += outer.integrate(column, inside[i], inside[i + 1], 1e-12);
  return le * sum;
}

struct BruteCase {
  std::string name;
  Vec3 p, n;
};

void PrintTo(const BruteCase& c, std::ostream* os) { *os << c.name; }

class ExactPathBruteForce : public testing::TestWithParam<BruteCase> {};

// Default light (R = 0.75 at z = 2) behind a tilted triangle and a
// horizontal rectangle occluder that overlap each other and the light partially.
// Tolerance 1e-10 relative: every jump and kink of the brute force's
// integrands is split out, so it is limited by its requested tolerances.
TEST_P(ExactPathBruteForce, MatchesRayCastAreaIntegral) {
  const BruteCase& c = GetParam();
  Scene scene;
  scene.name = "brute";
  scene.source = "brute_force_test";
  scene.objects.push_back({"floor", Rectangle{{-3, -3, 0}, {6, 0, 0}, {0, 6, 0}}, {0.5, Lambertian{}}, 0});
  scene.objects.push_back({"light", Disk{{0, 0, 2}, {0, 0, -1}, 0.75}, {}, 4.0});
  scene.objects.push_back({"wedge", Triangle{{-0.5, -0.2, 1.0}, {0.3, -0.35, 1.2}, {0.1, 0.4, 0.9}}, {}, 0});
  scene.objects.push_back({"plate", Rectangle{{0.05, 0.0, 1.4}, {0.5, 0.1, 0}, {-0.1, 0.4, 0}}, {}, 0});
  const Vec3 n = normalize(c.n);
  const double exact = irradiance(scene, c.p, n, size_t(0));
  const double expected = brute_force(scene, 1, c.p, n);
  ASSERT_GT(expected, 0);
  EXPECT_LE(std::fabs(exact - expected) / expected, 1e-10) << exact << " vs " << expected;
  // Uniform-hemisphere second moment: E[Y²] = 2π L² ∫_visible cos²θ dω.
  const double moment = second_moment(Strategy::kUniformHemisphere, scene, c.p, n, size_t(0));
  const double le = scene.objects[1].emitted_radiance;
  const double expected_moment = 2 * kPi * le * brute_force(scene, 1, c.p, n, Kernel::kCos2SolidAngle);  // brute_force includes one L
  EXPECT_LE(std::fabs(moment - expected_moment) / expected_moment, 1e-10) << moment << " vs " << expected_moment;
}

// The light-area second moment of a rectangle light and of the disk light
// past the same occluders: E[Y²] = A·L²·∫_visible (cos θ cos θ'/r²)² dA
// (one light, pmf 1), the exact planar path's area kernel against the brute
// force. Tolerance 1e-10 relative, as above.
TEST_P(ExactPathBruteForce, LightAreaSecondMomentMatchesRayCastAreaIntegral) {
  const BruteCase& c = GetParam();
  const Vec3 n = normalize(c.n);
  for (const Shape& light : {Shape{Rectangle{{-0.6, -0.7, 2}, {0, 1.3, 0}, {1.1, 0, 0}}},
                             Shape{Disk{{0, 0, 2}, {0, 0, -1}, 0.75}}}) {
    Scene scene;
    scene.name = "brute";
    scene.source = "brute_force_test";
    scene.objects.push_back({"floor", Rectangle{{-3, -3, 0}, {6, 0, 0}, {0, 6, 0}}, {0.5, Lambertian{}}, 0});
    scene.objects.push_back({"light", light, {}, 4.0});
    scene.objects.push_back({"wedge", Triangle{{-0.5, -0.2, 1.0}, {0.3, -0.35, 1.2}, {0.1, 0.4, 0.9}}, {}, 0});
    scene.objects.push_back({"plate", Rectangle{{0.05, 0.0, 1.4}, {0.5, 0.1, 0}, {-0.1, 0.4, 0}}, {}, 0});
    const double le = scene.objects[1].emitted_radiance;
    const double expected = shape_area(light) * le * brute_force(scene, 1, c.p, n, Kernel::kArea);
    ASSERT_GT(expected, 0);
    for (Strategy s : {Strategy::kLightArea, Strategy::kLightSolidAngle}) {
      if (s == Strategy::kLightSolidAngle && std::holds_alternative<Rectangle>(light)) continue;  // spherical map
      const double moment = second_moment(s, scene, c.p, n, size_t(0));
      EXPECT_LE(std::fabs(moment - expected) / expected, 1e-10)
          << strategy_name(s) << (std::holds_alternative<Disk>(light) ? " disk: " : " rectangle: ") << moment << " vs "
          << expected;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Points, ExactPathBruteForce,
                         testing::Values(BruteCase{"UnderTheAxis", {0, 0, 0}, {0, 0, 1}},
                                         BruteCase{"OffAxis", {0.4, -0.3, 0}, {0, 0, 1}},
                                         BruteCase{"TiltedReceiver", {-0.2, 0.3, 0}, {0.5, 0.2, 1}},
                                         BruteCase{"HorizonCutsLight", {0.1, 0.1, 0}, {1, 0.2, 0.15}}),
                         [](const auto& info) { return info.param.name; });

// A wall standing on the receiver plane next to p: its projection from p is
// unbounded, so the exact path clips it to the pyramid over the light first.
TEST(ExactPathBruteForceWall, WallOnTheFloorMatchesRayCastAreaIntegral) {
  Scene scene;
  scene.name = "wall";
  scene.source = "brute_force_test";
  scene.objects.push_back({"floor", Rectangle{{-3, -3, 0}, {6, 0, 0}, {0, 6, 0}}, {0.5, Lambertian{}}, 0});
  scene.objects.push_back({"light", Disk{{0, 0, 2}, {0, 0, -1}, 0.75}, {}, 4.0});
  const double unblocked = irradiance(scene, {0.1, 0, 0}, {0, 0, 1}, size_t(0));
  scene.objects.push_back({"wall", Rectangle{{0.3, -1, 0}, {0, 2, 0}, {0.1, 0, 1.5}}, {}, 0});
  EXPECT_LT(irradiance(scene, {0.1, 0, 0}, {0, 0, 1}, size_t(0)), 0.9 * unblocked);  // the wall does hide light
  for (const Vec3& p : {Vec3{0.1, 0, 0}, Vec3{-0.4, 0.6, 0}, Vec3{0.2, 0.95, 0}}) {
    const double exact = irradiance(scene, p, {0, 0, 1}, size_t(0));
    const double expected = brute_force(scene, 1, p, {0, 0, 1});
    EXPECT_LE(std::fabs(exact - expected) / expected, 1e-10) << exact << " vs " << expected;
  }
}

}  // namespace
}  // namespace furnace::analytic
