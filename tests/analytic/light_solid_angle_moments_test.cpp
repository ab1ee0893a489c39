// second_moment(kLightSolidAngle) against (1) independent quadrature over
// the light's surface (Ω = ∫ cos θ'/r² dA over the part facing p, no horizon;
// ∫cos² = ∫ max(cos θ, 0)² cos θ'/r² dA), and (2) a direct Monte Carlo
// simulation of the estimator Y = K·L·max(cos θ, 0)·Ω written here: ω uniform
// in the light's solid angle by rejection from a bounding cap (a ray test
// against the shape), which shares nothing with the closed forms.
#include "analytic/moments.h"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <ostream>
#include <string>

#include <gtest/gtest.h>

#include "analytic/intersect.h"
#include "analytic/reference.h"
#include "core/error.h"
#include "core/running_moments.h"
#include "solid_angle_quadrature.h"
#include "stats/statistics.h"

namespace furnace::analytic {
namespace {

double relative_error(double value, double expected) { return std::fabs(value - expected) / std::fabs(expected); }

// A scene of lights only (p floats, receiver = nullopt), so K = number of lights.
Scene lights_scene(std::vector<Object> lights, double environment = 0) {
  Scene scene;
  scene.name = "light_solid_angle_test";
  scene.source = "light_solid_angle_moments_test";
  scene.objects = std::move(lights);
  scene.environment.radiance = environment;
  return scene;
}

Object light(const std::string& name, const Shape& shape, double le, bool two_sided = false) {
  Object o{name, shape, {}, le};
  o.two_sided = two_sided;
  return o;
}

struct Case {
  std::string name;
  Shape shape;
  double le;
  Vec3 p, n;
  bool two_sided = false;
};

// Sphere and polygons, above and straddling the horizon, a two-sided
// rectangle seen from behind.
std::vector<Case> cases() {
  return {
      {"SphereOverhead", Sphere{{0.3, -0.2, 2.0}, 0.6}, 3.0, {0, 0, 0}, {0, 0, 1}},
      {"SphereStraddling", Sphere{{1.5, 0.2, 0.3}, 0.7}, 2.0, {0, 0, 0}, {0, 0, 1}},
      {"SphereTiltedReceiver", Sphere{{0.4, 0.9, 1.1}, 0.35}, 5.0, {0.1, 0, 0}, normalize(Vec3{0.3, -0.2, 1})},
      {"Triangle", Triangle{{0.9, 0.8, 1.2}, {1.3, 1.5, 1.2}, {1.7, 0.7, 1.2}}, 10.0, {0, 0, 0}, {0, 0, 1}},
      {"TiltedRectangle", Rectangle{{-0.6, -0.4, 1.5}, {0, 0.8, 0.3}, {1.2, 0, 0}}, 5.0, {0.2, 0.1, 0}, {0, 0, 1}},
      // A wall facing −x that reaches below p's horizon: the renderer samples
      // all of its spherical rectangle, and the part below gives Y = 0.
      {"StraddlingRectangle", Rectangle{{1, -0.5, -0.5}, {0, 0, 1.5}, {0, 1, 0}}, 4.0, {0, 0, 0}, {0, 0, 1}},
      {"StraddlingTriangle", Triangle{{0.8, -0.6, -0.5}, {0.8, 0.0, 1.0}, {0.8, 0.7, -0.2}}, 3.0, {0, 0, 0}, {0, 0, 1}},
      {"TwoSidedFromBehind", Rectangle{{-0.5, -0.5, 1.0}, {1, 0, 0}, {0, 1, 0}}, 2.5, {0.1, 0.2, 0}, {0, 0, 1}, true},
  };
}

// Ω and ∫ max(cos θ, 0)² dω by quadrature over the light's surface.
struct Brute {
  double omega, cos2;
};
Brute brute_force(const Case& c) {
  auto omega_weight = [](double, double cl, double r) { return std::fabs(cl) / (r * r); };
  auto cos2_weight = [](double cs, double cl, double r) { return cs * cs * std::fabs(cl) / (r * r); };
  if (const auto* s = std::get_if<Sphere>(&c.shape)) {
    // The whole facing cap lies above the plane normal to the centre
    // direction (x·ĉ ≥ D − R > 0): that "horizon" clips nothing.
    const Vec3 center = s->center - c.p;
    return {testing_support::sphere_surface_integral(center, s->radius, normalize(center), omega_weight),
            testing_support::sphere_surface_integral(center, s->radius, c.n, cos2_weight)};
  }
  const testing_support::Patch patch =
      std::holds_alternative<Rectangle>(c.shape)
          ? testing_support::rectangle_patch(std::get<Rectangle>(c.shape).corner, std::get<Rectangle>(c.shape).edge_u,
                                             std::get<Rectangle>(c.shape).edge_v)
          : testing_support::triangle_patch(std::get<Triangle>(c.shape).p0, std::get<Triangle>(c.shape).p1,
                                            std::get<Triangle>(c.shape).p2);
  // The whole polygon: a "horizon" normal towards the polygon's plane, so nothing is clipped.
  const Vec3 to_plane = patch.normal * (dot(patch.normal, patch.a0 - c.p) > 0 ? 1.0 : -1.0);
  return {testing_support::patch_integral(patch, c.p, to_plane, omega_weight),
          testing_support::patch_integral(patch, c.p, c.n, cos2_weight)};
}

void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

class LightSolidAngleMoment : public testing::TestWithParam<Case> {};

// One light, K = 1: E[Y²] = Ω·L²·∫cos². Tolerance 1e-9: the quadratures'.
TEST_P(LightSolidAngleMoment, MatchesSurfaceQuadrature) {
  const Case& c = GetParam();
  const Scene scene = lights_scene({light("light", c.shape, c.le, c.two_sided)});
  const double value = second_moment(Strategy::kLightSolidAngle, scene, c.p, c.n, std::nullopt);
  const Brute b = brute_force(c);
  const double expected = b.omega * c.le * c.le * b.cos2;
  ASSERT_GT(expected, 0);
  std::printf("[ quadrature ] %s: E[Y^2] %.15g, brute force %.15g, relative error %.3g\n", c.name.c_str(), value,
              expected, relative_error(value, expected));
  EXPECT_LE(relative_error(value, expected), 1e-9) << value << " vs " << expected;
  const double e = irradiance(scene, c.p, c.n, std::nullopt);
  EXPECT_GE(value, e * e);  // Cauchy–Schwarz
}

INSTANTIATE_TEST_SUITE_P(Lights, LightSolidAngleMoment, testing::ValuesIn(cases()),
                         [](const auto& info) { return info.param.name; });

// Two emitters and the environment: K = 3, each term K·Ω_l·L_l²·∫cos², the
// environment K·π·L_env·E_env (cosine sampling, as for light_area).
TEST(LightSolidAngleMomentScene, SumsTermsWithSelectionCount) {
  const std::vector<Case> all = cases();
  const Case& a = all[0];  // sphere overhead
  const Case& b = all[3];  // triangle
  const double l_env = 0.3;
  const Scene scene = lights_scene({light("a", a.shape, a.le), light("b", b.shape, b.le)}, l_env);
  const Vec3 p{0, 0, 0}, n{0, 0, 1};
  const Brute ba = brute_force(a), bb = brute_force(b);
  // E_env = L_env·(π − projected solid angles of the two lights), by quadrature.
  const double hidden = ba.omega > 0 ? testing_support::sphere_projected_solid_angle(
                                           std::get<Sphere>(a.shape).center, std::get<Sphere>(a.shape).radius, n)
                                     : 0.0;
  const auto& t = std::get<Triangle>(b.shape);
  const double hidden_b =
      testing_support::patch_projected_solid_angle(testing_support::triangle_patch(t.p0, t.p1, t.p2), p, n);
  const double e_env = l_env * (kPi - hidden - hidden_b);
  const double expected = 3 * (ba.omega * a.le * a.le * ba.cos2 + bb.omega * b.le * b.le * bb.cos2) + 3 * kPi * l_env * e_env;
  const double value = second_moment(Strategy::kLightSolidAngle, scene, p, n, std::nullopt);
  EXPECT_LE(relative_error(value, expected), 1e-9) << value << " vs " << expected;
}

// Where the renderer falls back to area sampling the moment is kLightArea's:
// disks, sheared parallelograms, and polygons under 1e-6 sr.
TEST(LightSolidAngleMomentScene, AreaFallbacksEqualLightArea) {
  const Vec3 p{0.1, -0.2, 0}, n{0, 0, 1};
  for (const Shape& shape : {Shape{Disk{{0.3, 0.2, 1.5}, {0, 0, -1}, 0.4}},
                             Shape{Rectangle{{-0.5, -0.5, 1.2}, {0, 1, 0}, {1, 0.3, 0}}},
                             Shape{Triangle{{0, 0, 1000}, {0, 1e-3, 1000}, {1e-3, 0, 1000}}}}) {
    const Scene scene = lights_scene({light("light", shape, 2.0)});
    const double area = second_moment(Strategy::kLightArea, scene, p, n, std::nullopt);
    ASSERT_GT(area, 0);
    EXPECT_EQ(second_moment(Strategy::kLightSolidAngle, scene, p, n, std::nullopt), area);
  }
}

// A sphere light behind a blocker is refused (the cone moment needs it unoccluded).
TEST(LightSolidAngleMomentScene, RefusesOccludedSphere) {
  Scene scene = lights_scene({light("light", Sphere{{0, 0, 2}, 0.5}, 2.0)});
  scene.objects.push_back({"blocker", Sphere{{0, 0, 1}, 0.2}, {}, 0});
  EXPECT_THROW(second_moment(Strategy::kLightSolidAngle, scene, {0, 0, 0}, {0, 0, 1}, std::nullopt), Error);
}

// ---------------------------------------------------------------------------
// Direct Monte Carlo of the estimator.

// SplitMix64: a fixed, portable stream for the test's own sampling.
struct SplitMix64 {
  uint64_t state;
  double next() {
    uint64_t z = (state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    z ^= z >> 31;
    return double(z >> 11) * 0x1p-53;
  }
};
constexpr uint64_t kMonteCarloSeed = 20261125;
constexpr int kMonteCarloSamples = 200000;
// Family-wise α over the MC cases × 2 tests (mean, variance), Šidák.
constexpr double kFamilyAlpha = 1e-3;

// A cap about `axis` (half-angle acos(cos_cap)) containing every direction to the shape.
struct Cap {
  Vec3 axis;
  double cos_cap;
};
Cap bounding_cap(const Shape& shape, const Vec3& p) {
  if (const auto* s = std::get_if<Sphere>(&shape)) {
    const double D = length(s->center - p);
    return {(s->center - p) / D, std::sqrt(1 - (s->radius / D) * (s->radius / D))};
  }
  std::vector<Vec3> v;
  if (const auto* r = std::get_if<Rectangle>(&shape))
    v = {r->corner, r->corner + r->edge_u, r->corner + r->edge_v, r->corner + r->edge_u + r->edge_v};
  else {
    const auto& t = std::get<Triangle>(shape);
    v = {t.p0, t.p1, t.p2};
  }
  Vec3 axis{0, 0, 0};
  for (const Vec3& x : v) axis = axis + normalize(x - p);
  axis = normalize(axis);
  double c = 1;
  for (const Vec3& x : v) c = std::fmin(c, dot(axis, normalize(x - p)));
  return {axis, c};
}

struct MonteCarlo {
  double mean, variance, variance_se, mean_se;
};
// Y = L·max(cos θ, 0)·Ω with ω uniform on the light's solid angle (rejection
// from the cap, whose area 2π(1 − cos_cap) times the acceptance rate also
// estimates Ω; the simulation uses `omega` as the estimator's constant).
MonteCarlo simulate(const Case& c, double omega) {
  const Cap cap = bounding_cap(c.shape, c.p);
  const Frame frame = Frame::from_normal(cap.axis);
  SplitMix64 rng{kMonteCarloSeed};
  RunningMoments moments;
  while (moments.count < uint64_t(kMonteCarloSamples)) {
    const double cos_g = 1 - rng.next() * (1 - cap.cos_cap);
    const double sin_g = std::sqrt(std::fmax(0.0, (1 - cos_g) * (1 + cos_g)));
    const double phi = 2 * kPi * rng.next();
    const Vec3 w = frame.s * (sin_g * std::cos(phi)) + frame.t * (sin_g * std::sin(phi)) + frame.n * cos_g;
    if (!intersect_shape(c.shape, c.p, w, 0)) continue;
    const double y = c.le * std::fmax(dot(c.n, w), 0.0) * omega;
    moments.add(y);
  }
  return {moments.mean, moments.sample_variance(), std::sqrt(stats::sample_variance_variance(moments)),
          moments.mean_standard_error()};
}

class LightSolidAngleMonteCarlo : public testing::TestWithParam<Case> {};

// Predicted Var Y = E[Y²] − E² against the simulated estimator's s².
// Negative control below: the moment of a sampler restricted to the part of
// the light above the horizon (Ω clipped) must be rejected on the straddling
// lights.
TEST_P(LightSolidAngleMonteCarlo, VarianceMatchesSimulation) {
  const Case& c = GetParam();
  const Scene scene = lights_scene({light("light", c.shape, c.le, c.two_sided)});
  const double m2 = second_moment(Strategy::kLightSolidAngle, scene, c.p, c.n, std::nullopt);
  const double e = irradiance(scene, c.p, c.n, std::nullopt);
  const Brute b = brute_force(c);
  const MonteCarlo mc = simulate(c, b.omega);
  const double predicted = m2 - e * e;
  const size_t family = 2 * cases().size();
  const double z_crit = stats::normal_upper_quantile(stats::sidak_alpha(kFamilyAlpha, family) / 2);
  const double z_mean = (mc.mean - e) / mc.mean_se;
  const double z_var = (mc.variance - predicted) / mc.variance_se;
  std::printf("[ MC ] %s: N %d, E %.8g mean %.8g z %.3f; Var predicted %.8g measured %.8g z %.3f (crit %.3f, "
              "detectable %.3g%%)\n",
              c.name.c_str(), kMonteCarloSamples, e, mc.mean, z_mean, predicted, mc.variance, z_var, z_crit,
              100 * (z_crit + 1.645) * mc.variance_se / predicted);
  EXPECT_LE(std::fabs(z_mean), z_crit);
  EXPECT_LE(std::fabs(z_var), z_crit);
}

INSTANTIATE_TEST_SUITE_P(Lights, LightSolidAngleMonteCarlo, testing::ValuesIn(cases()),
                         [](const auto& info) { return info.param.name; });

// Negative control: predicting with Ω of the part above the horizon (a
// sampler that skipped the hidden part) is rejected on a straddling light.
TEST(LightSolidAngleMonteCarloControl, ClippedSolidAngleIsRejected) {
  for (const Case& c : cases()) {
    if (c.name != "StraddlingRectangle" && c.name != "SphereStraddling") continue;
    const Scene scene = lights_scene({light("light", c.shape, c.le)});
    const Brute b = brute_force(c);
    const double omega_above = [&] {
      if (const auto* s = std::get_if<Sphere>(&c.shape))
        return testing_support::sphere_surface_integral(s->center - c.p, s->radius, c.n,
                                                        [](double, double cl, double r) { return cl / (r * r); });
      const auto& r = std::get<Rectangle>(c.shape);
      return testing_support::patch_integral(testing_support::rectangle_patch(r.corner, r.edge_u, r.edge_v), c.p, c.n,
                                             [](double, double cl, double rr) { return cl / (rr * rr); });
    }();
    ASSERT_LT(omega_above, b.omega);
    const double e = irradiance(scene, c.p, c.n, std::nullopt);
    const double wrong = omega_above * c.le * c.le * b.cos2 - e * e;
    const MonteCarlo mc = simulate(c, b.omega);
    const double z = (mc.variance - wrong) / mc.variance_se;
    const double z_crit = stats::normal_upper_quantile(kFamilyAlpha / 2);
    std::printf("[ MC control ] %s: clipped-Ω variance %.8g vs measured %.8g, z %.3f (crit %.3f)\n", c.name.c_str(),
                wrong, mc.variance, z, z_crit);
    EXPECT_GT(std::fabs(z), z_crit);
  }
}

}  // namespace
}  // namespace furnace::analytic
