// second_moment against independent polar area quadrature of each
// estimator's E[Y²] integrand over the visible region, plus the exact
// zero-variance and vanishing-variance limits.
#include "analytic/moments.h"

#include <cmath>
#include <limits>
#include <ostream>
#include <string>
#include <tuple>

#include <gtest/gtest.h>

#include "analytic/reference.h"
#include "region_quadrature.h"

namespace furnace::analytic {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

// Floor z = 0 (ρ = 0.5), disk light radius R at z = h facing down, emission
// le, and black parallel disk occluders (x, y, z, radius).
struct OccluderSpec {
  double x, y, z, radius;
};
struct SceneSpec {
  std::string name;
  double h, R, le;
  std::vector<OccluderSpec> occluders;
  Vec3 p;
};

void PrintTo(const SceneSpec& c, std::ostream* os) { *os << c.name; }

Scene build(const SceneSpec& s) {
  Scene scene;
  scene.name = s.name;
  scene.source = "moments_test";
  scene.objects.push_back({"floor", Rectangle{{-5, -5, 0}, {10, 0, 0}, {0, 10, 0}}, {0.5, Lambertian{}}, 0});
  scene.objects.push_back({"light", Disk{{0, 0, s.h}, {0, 0, -1}, s.R}, {}, s.le});
  for (const OccluderSpec& o : s.occluders)
    scene.objects.push_back({"occluder", Disk{{o.x, o.y, o.z}, {0, 0, 1}, o.radius}, {}, 0});
  return scene;
}

// The visible region as the test sees it: the light and the occluders'
// shadows on the light plane, written from the geometry directly (a point x
// of an occluder at height z maps to p + (x − p)·h/z).
void circles_for(const SceneSpec& s, Circle2* light, std::vector<Circle2>* images) {
  *light = {-s.p.x, -s.p.y, s.R};
  images->clear();
  for (const OccluderSpec& o : s.occluders) {
    const double k = s.h / o.z;
    images->push_back({(o.x - s.p.x) * k, (o.y - s.p.y) * k, o.radius * k});
  }
}

std::vector<SceneSpec> all_specs() {
  const std::vector<OccluderSpec> default_occluder{{0, 0, 1, 0.35}};
  return {
      {"DefaultSceneAxis", 2, 0.75, 4, default_occluder, {0, 0, 0}},
      {"DefaultScenePartial", 2, 0.75, 4, default_occluder, {0.3, 0, 0}},
      {"DefaultSceneOblique", 2, 0.75, 4, default_occluder, {0.9, 0.4, 0}},
      {"DefaultSceneUnoccluded", 2, 0.75, 4, default_occluder, {1.8, -1.1, 0}},
      {"TwoOccludersLowLight", 0.5, 1.0, 1, {{0.3, 0, 0.3, 0.2}, {0.1, 0.25, 0.2, 0.12}}, {0.05, 0.02, 0}},
  };
}

enum class Which { kUniformHemisphere, kCosineHemisphere, kLightArea };

Strategy to_estimator(Which w) {
  switch (w) {
    case Which::kUniformHemisphere: return Strategy::kUniformHemisphere;
    case Which::kCosineHemisphere: return Strategy::kCosineHemisphere;
    case Which::kLightArea: return Strategy::kLightArea;
  }
  return Strategy::kLightArea;
}
std::string which_name(Which w) {
  switch (w) {
    case Which::kUniformHemisphere: return "UniformHemisphere";
    case Which::kCosineHemisphere: return "CosineHemisphere";
    case Which::kLightArea: return "LightArea";
  }
  return "";
}

void PrintTo(Which w, std::ostream* os) { *os << which_name(w); }

// E[Y²] = ∫_light (Y(x))² p(x) dA_x written out per estimator on the light
// plane, with cos θ = cos θ' = h/r and dω = cos θ'/r² dA.
double expected_second_moment(Which w, const SceneSpec& s) {
  Circle2 light;
  std::vector<Circle2> images;
  circles_for(s, &light, &images);
  const double h = s.h, le = s.le, area = kPi * s.R * s.R;
  // At in-plane distance q from p's foot: r, both cosines, and dω/dA.
  auto r_of = [h](double q) { return std::hypot(h, q); };
  auto cos_theta = [&](double q) { return h / r_of(q); };
  auto cos_light = [&](double q) { return h / r_of(q); };
  auto solid_angle_per_area = [&](double q) { return cos_light(q) / (r_of(q) * r_of(q)); };
  switch (w) {
    case Which::kUniformHemisphere: {  // Y = L cos θ 2π, p = 1/(2π) per sr
      auto f = [&](double q) {
        const double y = le * cos_theta(q) * 2 * kPi;
        return y * y / (2 * kPi) * solid_angle_per_area(q);
      };
      return testing_support::region_quadrature(light, images, f);
    }
    case Which::kCosineHemisphere: {  // Y = L π, p = cos θ/π per sr
      auto f = [&](double q) {
        const double y = le * kPi;
        return y * y * cos_theta(q) / kPi * solid_angle_per_area(q);
      };
      return testing_support::region_quadrature(light, images, f);
    }
    case Which::kLightArea: {  // Y = L cos θ cos θ'/r² A, p = 1/A per m², one light
      auto f = [&](double q) {
        const double y = le * cos_theta(q) * cos_light(q) / (r_of(q) * r_of(q)) * area;
        return y * y / area;
      };
      return testing_support::region_quadrature(light, images, f);
    }
  }
  return 0;
}

class SecondMoment : public testing::TestWithParam<std::tuple<Which, SceneSpec>> {};

// Tolerance 1e-11 relative: the quadrature's (see circle_region_test).
TEST_P(SecondMoment, MatchesPolarAreaQuadrature) {
  const auto& [which, spec] = GetParam();
  const Scene scene = build(spec);
  const double value = second_moment(to_estimator(which), scene, spec.p, {0, 0, 1}, size_t(0));
  const double expected = expected_second_moment(which, spec);
  ASSERT_GT(expected, 0);
  EXPECT_LE(std::fabs(value - expected) / expected, 1e-11) << value << " vs " << expected;
  // Cauchy–Schwarz: E[Y²] ≥ (E[Y])².
  const double e = irradiance(scene, spec.p, {0, 0, 1}, size_t(0));
  EXPECT_GE(value, e * e * (1 - 8 * kEps));
}

INSTANTIATE_TEST_SUITE_P(
    Configurations, SecondMoment,
    testing::Combine(testing::Values(Which::kUniformHemisphere, Which::kCosineHemisphere, Which::kLightArea),
                     testing::ValuesIn(all_specs())),
    [](const auto& info) { return which_name(std::get<0>(info.param)) + std::get<1>(info.param).name; });

TEST(SecondMomentLimits, CosineSamplingOfConstantSkyHasZeroVariance) {
  Scene scene;
  scene.objects.push_back({"floor", Rectangle{{-1, -1, 0}, {2, 0, 0}, {0, 2, 0}}, {0.5, Lambertian{}}, 0});
  scene.environment.radiance = 1.7;
  const double e = irradiance(scene, {0, 0, 0}, {0, 0, 1}, size_t(0));
  EXPECT_EQ(second_moment(Strategy::kCosineHemisphere, scene, {0, 0, 0}, {0, 0, 1}, size_t(0)), e * e);
  // Uniform hemisphere: E[Y²] = 2π·L²·2π/3, so E[Y²]/E² = 4/3 exactly in form.
  const double m = second_moment(Strategy::kUniformHemisphere, scene, {0, 0, 0}, {0, 0, 1}, size_t(0));
  EXPECT_NEAR(m / (e * e), 4.0 / 3.0, 4 * kEps);
}

// A tiny unoccluded light: area sampling's Y is almost constant, so
// E[Y²]/E² − 1 = O((R/h)²); at R/h = 1e-4 that is ~1e-8.
TEST(SecondMomentLimits, AreaSamplingOfTinyLightHasVanishingVariance) {
  const SceneSpec spec{"Tiny", 1.0, 1e-4, 3.0, {}, {0.2, 0.1, 0}};
  const Scene scene = build(spec);
  const double e = irradiance(scene, spec.p, {0, 0, 1}, size_t(0));
  const double m = second_moment(Strategy::kLightArea, scene, spec.p, {0, 0, 1}, size_t(0));
  EXPECT_LT(m / (e * e) - 1, 1e-7);
  EXPECT_GE(m / (e * e) - 1, -1e-12);
}

// The pixel estimator Le + (ρ/π)·Y: at the default scene's receiver, Le = 0.
TEST(PixelSecondMoment, IsScaledIrradianceMoment) {
  const Scene scene = load_scene(std::string(FURNACE_SCENE_DIR) + "/disk_occluder.json");
  const Camera::Ray ray = scene.camera.pixel_center_ray(16, 16);
  const Vec3 p = ray.origin + ray.direction * (ray.origin.z / -ray.direction.z);
  const double k = 0.5 * kInvPi;
  for (Strategy est : {Strategy::kUniformHemisphere, Strategy::kCosineHemisphere, Strategy::kLightArea}) {
    const double m = second_moment(est, scene, p, {0, 0, 1}, size_t(0));
    EXPECT_NEAR(pixel_center_second_moment(est, scene, 16, 16), k * k * m, 4 * kEps * k * k * m);
  }
}

}  // namespace
}  // namespace furnace::analytic
