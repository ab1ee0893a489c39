// Point lights in the analytic references: the inverse-square law with an
// exact segment test, the limit of a shrinking sphere light, the second
// moment of light sampling (a point light is sampled exactly), the power pmf,
// and the refusals.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "analytic/moments.h"
#include "analytic/point_light.h"
#include "analytic/reference.h"
#include "analytic/sphere.h"
#include "core/error.h"
#include "core/scene.h"

namespace furnace::analytic {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

// A unit-square floor at z = 0 (receiver 0), a black disk of radius 0.25
// centred at height 1 (object 1), and a point light at height 2 above the
// origin: the disk's shadow on the floor is the disk of radius 0.5 (similar
// triangles, 2/(2 − 1) = 2).
Scene shadow_scene() {
  Scene s;
  s.name = "shadow";
  s.objects.push_back({"floor", Rectangle{{-2, -2, 0}, {4, 0, 0}, {0, 4, 0}}, {0.5, Lambertian{}}, 0, false});
  s.objects.push_back({"blocker", Disk{{0, 0, 1}, {0, 0, 1}, 0.25}, {0, Lambertian{}}, 0, false});
  s.point_lights.push_back({"bulb", {0, 0, 2}, 3.0});
  return s;
}

TEST(PointLight, InverseSquareLawWithLambertCosine) {
  Scene s = shadow_scene();
  s.objects.pop_back();  // unoccluded
  const Vec3 p{1.2, -0.7, 0};
  const Vec3 d = s.point_lights[0].position - p;
  const double expected = 3.0 * (2.0 / length(d)) / length_squared(d);
  EXPECT_NEAR(point_light_irradiance(s, 0, p, {0, 0, 1}, 0), expected, 4 * kEps * expected);
  // Facing away: nothing arrives.
  EXPECT_EQ(point_light_irradiance(s, 0, p, {0, 0, -1}, 0), 0.0);
  // irradiance() includes it.
  EXPECT_NEAR(irradiance(s, p, {0, 0, 1}, 0), expected, 4 * kEps * expected);
}

TEST(PointLight, SharpShadowOfADiskBySimilarTriangles) {
  const Scene s = shadow_scene();
  const Vec3 n{0, 0, 1};
  // Inside the shadow radius 0.5: hidden; outside: lit. Points 1e-9 from the edge.
  for (double phi : {0.0, 1.0, 2.5, 4.0}) {
    const Vec3 dir{std::cos(phi), std::sin(phi), 0};
    EXPECT_EQ(point_light_irradiance(s, 0, dir * (0.5 - 1e-9), n, 0), 0.0) << phi;
    EXPECT_GT(point_light_irradiance(s, 0, dir * (0.5 + 1e-9), n, 0), 0.0) << phi;
  }
  // The receiver itself never blocks, whatever `receiver` says of other objects.
  EXPECT_GT(point_light_irradiance(s, 0, {1, 1, 0}, n, 0), 0.0);
}

// A sphere of radius ε and radiance L has intensity I = L·πε² towards every
// direction; Snyder's closed form must approach I·cos θ/r² as ε → 0, with a
// relative gap O(ε²/r²).
TEST(PointLight, LimitOfAShrinkingSphereLight) {
  const Vec3 p{0.3, -0.4, 0};
  const Vec3 n{0, 0, 1};
  const Vec3 c{0.8, 0.5, 1.7};
  Scene s;
  s.point_lights.push_back({"bulb", c, 1.0});
  const double e_point = point_light_irradiance(s, 0, p, n, std::nullopt);
  const double r2 = length_squared(c - p);
  for (double eps : {1e-1, 1e-2, 1e-3}) {
    const double L = 1.0 / (kPi * eps * eps);  // I = 1
    const double e_sphere = L * sphere_irradiance(c - p, eps, n);
    const double rel = std::fabs(e_sphere - e_point) / e_point;
    EXPECT_LT(rel, 4 * eps * eps / r2) << "eps " << eps;
  }
}

TEST(PointLight, LightAreaSecondMomentIsESquaredOverPmf) {
  Scene s = shadow_scene();
  s.point_lights.push_back({"second", {1, 0.5, 1.5}, 9.0});
  const Vec3 p{1.1, 0.9, 0};
  const Vec3 n{0, 0, 1};
  const double e0 = point_light_irradiance(s, 0, p, n, 0);
  const double e1 = point_light_irradiance(s, 1, p, n, 0);
  ASSERT_GT(e0, 0.0);
  ASSERT_GT(e1, 0.0);
  // Uniform: pmf 1/2 each; the estimator is 2·E_l with probability 1/2.
  EXPECT_NEAR(second_moment(Strategy::kLightArea, s, p, n, 0), 2 * (e0 * e0 + e1 * e1), 8 * kEps * (e0 * e0 + e1 * e1));
  // Power: pmf I_l/ΣI (both point lights: Φ = 4π·I).
  const double p0 = 3.0 / 12.0, p1 = 9.0 / 12.0;
  const double expected = e0 * e0 / p0 + e1 * e1 / p1;
  EXPECT_NEAR(second_moment(Strategy::kLightArea, s, p, n, 0, LightSelection::kPower), expected, 8 * kEps * expected);
  // A single point light is sampled exactly: E[Y²] = E².
  s.point_lights.pop_back();
  EXPECT_NEAR(second_moment(Strategy::kLightArea, s, p, n, 0), e0 * e0, 4 * kEps * e0 * e0);
}

TEST(PointLight, HemisphereMomentsRefusePointLights) {
  const Scene s = shadow_scene();
  EXPECT_THROW(second_moment(Strategy::kUniformHemisphere, s, {1, 1, 0}, {0, 0, 1}, 0), Error);
  EXPECT_THROW(second_moment(Strategy::kCosineHemisphere, s, {1, 1, 0}, {0, 0, 1}, 0), Error);
}

TEST(PointLight, PowerPmfOfEveryKindOfLight) {
  Scene s = shadow_scene();
  s.objects.push_back({"disk_light", Disk{{0, 1, 1.5}, {0, 0, -1}, 0.5}, {}, 4.0, false});
  s.objects.push_back({"panel", Rectangle{{1, 1, 0.5}, {0.5, 0, 0}, {0, 0.2, 0}}, {}, 3.0, true});
  s.environment.radiance = 0.5;
  const std::vector<double> pmf = light_selection_pmf(s, LightSelection::kPower);
  ASSERT_EQ(pmf.size(), 4u);  // disk light, panel, point light, environment
  // Box: x, y ∈ [-2, 2] (floor), z ∈ [0, 2] (the point light): R = ½·√(16 + 16 + 4) = 3.
  const double power[4] = {kPi * 4.0 * kPi * 0.25, 2 * kPi * 3.0 * 0.1, 4 * kPi * 3.0, 0.5 * kPi * kPi * 9.0};
  const double total = power[0] + power[1] + power[2] + power[3];
  double sum = 0;
  for (size_t l = 0; l < 4; ++l) {
    EXPECT_NEAR(pmf[l], power[l] / total, 8 * kEps) << l;
    sum += pmf[l];
  }
  EXPECT_NEAR(sum, 1.0, 8 * kEps);
  for (double q : light_selection_pmf(s, LightSelection::kUniform)) EXPECT_EQ(q, 0.25);
}

}  // namespace
}  // namespace furnace::analytic
