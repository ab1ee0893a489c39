// A renderer's sampler tests written with furnace: two toy cosine-weighted
// hemisphere warps, one correct and one subtly wrong, each tested by
//  - furnace's chi-square test of the directions against the claimed pdf;
//  - the consistency test of pdf and weight = eval·cos θ/pdf;
//  - a mean test of the irradiance estimate it gives against furnace's exact
//    reference for a built-in scene.
// Each test asserts on the result object: the correct warp passes, the wrong
// one is reported failing, so this suite passes in both cases.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <iostream>
#include <optional>
#include <string>

#include "analytic/reference.h"
#include "core/scene.h"
#include "stats/estimator_tests.h"
#include "stats/sampler_tests.h"

namespace {

using furnace::Vec3;
using furnace::stats::DirectionSample;

constexpr double kPi = 3.14159265358979323846;
constexpr double kAlbedo = 0.8;  // the toy Lambertian BSDF, f = ρ/π

// Malley's method: a uniform point on the unit disk lifted to the hemisphere.
Vec3 sample_cosine_hemisphere(const std::array<double, 2>& u) {
  const double r = std::sqrt(u[0]), phi = 2 * kPi * u[1];
  return {r * std::cos(phi), r * std::sin(phi), std::sqrt(1 - u[0])};
}
// Density in solid angle: cos θ/π on the upper hemisphere, 0 below.
double cosine_hemisphere_pdf(const Vec3& w) { return w.z > 0 ? w.z / kPi : 0.0; }

// The subtly wrong warp: it keeps θ below 84° "to avoid grazing directions"
// by squeezing u1 into [0, 0.99), but its pdf still claims the whole
// hemisphere. Every sample is a unit vector above the horizon, sample().pdf
// equals pdf(direction), the weight is eval·cos/pdf: only the distribution is
// wrong (1 % of the mass is missing near the horizon, 1 % too much elsewhere).
constexpr double kGrazingCut = 0.99;
Vec3 sample_cosine_hemisphere_no_grazing(const std::array<double, 2>& u) {
  return sample_cosine_hemisphere({kGrazingCut * u[0], u[1]});
}

// The two samplers in furnace's callable form: direction, pdf, weight.
DirectionSample lambertian_sample(const Vec3& w) {
  const double pdf = cosine_hemisphere_pdf(w);
  return {w, pdf, (kAlbedo / kPi) * w.z / pdf, false};
}
std::optional<DirectionSample> correct_sampler(const std::array<double, 2>& u) {
  return lambertian_sample(sample_cosine_hemisphere(u));
}
std::optional<DirectionSample> wrong_sampler(const std::array<double, 2>& u) {
  return lambertian_sample(sample_cosine_hemisphere_no_grazing(u));
}
double lambertian_eval(const Vec3& w) { return w.z > 0 ? kAlbedo / kPi : 0.0; }

// Both warps are tested three ways in one family: Šidák over 6 tests.
furnace::stats::SamplerChi2Options chi2_options() {
  furnace::stats::SamplerChi2Options o;
  o.n_tests = 6;
  return o;
}

TEST(CosineWarp, CorrectWarpPassesChiSquare) {
  const auto r = furnace::stats::chi2_test_sampler(correct_sampler, cosine_hemisphere_pdf, chi2_options());
  std::cout << "correct warp: " << describe(r) << "\n";
  EXPECT_TRUE(r.pass) << r.chi2.message;
}

TEST(CosineWarp, WrongWarpFailsChiSquare) {
  const auto r = furnace::stats::chi2_test_sampler(wrong_sampler, cosine_hemisphere_pdf, chi2_options());
  std::cout << "wrong warp:   " << describe(r) << "\n";
  EXPECT_FALSE(r.pass);
  EXPECT_LT(r.chi2.p_value, r.chi2.alpha);
}

// Consistency cannot see a wrong distribution: both warps pass it.
TEST(CosineWarp, BothWarpsAreConsistent) {
  const auto correct = furnace::stats::check_sample_consistency(correct_sampler, cosine_hemisphere_pdf,
                                                                lambertian_eval);
  const auto wrong = furnace::stats::check_sample_consistency(wrong_sampler, cosine_hemisphere_pdf, lambertian_eval);
  std::cout << "correct warp: " << describe(correct) << "\nwrong warp:   " << describe(wrong) << "\n";
  EXPECT_TRUE(correct.pass) << correct.message;
  EXPECT_TRUE(wrong.pass) << wrong.message;
}

// A weight made with a stale pdf (the cosine forgotten in eval·cos/pdf) is
// what the consistency test is for.
TEST(CosineWarp, StaleWeightFailsConsistency) {
  const auto stale = [](const std::array<double, 2>& u) -> std::optional<DirectionSample> {
    DirectionSample s = lambertian_sample(sample_cosine_hemisphere(u));
    s.weight = (kAlbedo / kPi) / s.pdf_solid_angle;
    return s;
  };
  const auto r = furnace::stats::check_sample_consistency(stale, cosine_hemisphere_pdf, lambertian_eval);
  std::cout << "stale weight: " << describe(r) << "\n";
  EXPECT_FALSE(r.pass);
  EXPECT_EQ(r.weight_mismatches, r.checked);
}

// The irradiance at the receiver's centre under furnace's built-in sphere
// light: each warp's estimate Li·cos θ/pdf against the exact reference.
struct IrradianceCase {
  furnace::Scene scene = furnace::load_scene(std::string(FURNACE_SCENE_DIR) + "/sphere_light.json");
  Vec3 point{0, 0, 0}, normal{0, 0, 1};
  size_t receiver = 0;  // objects[0], the floor the point lies on
  double reference = furnace::analytic::irradiance(scene, point, normal, receiver);

  // Radiance arriving along w: the emission of the first object hit. Here
  // furnace's own double-precision intersector stands in for the renderer's.
  double incident_radiance(const Vec3& w) const {
    const auto hit = furnace::analytic::intersect(scene, point, w, 1e-9);
    return hit ? scene.objects[hit->object_index].emitted_radiance : scene.environment.radiance;
  }
  template <class Warp>
  furnace::stats::EstimatorMeanTestResult test(Warp warp) const {
    furnace::stats::EstimatorTestOptions o;
    o.samples = 4'000'000;  // detects a 0.4 % bias with power 0.9
    o.n_tests = 6;
    return furnace::stats::estimator_mean_test(
        [&](furnace::stats::UniformStream& u) {
          const Vec3 w = warp(u.next2());
          return incident_radiance(w) * w.z / cosine_hemisphere_pdf(w);
        },
        reference, o);
  }
};

TEST(CosineWarp, CorrectWarpMatchesTheExactIrradiance) {
  const IrradianceCase c;
  const auto r = c.test(sample_cosine_hemisphere);
  std::cout << "correct warp: " << describe(r) << "\n";
  EXPECT_TRUE(r.pass()) << r.message;
}

TEST(CosineWarp, WrongWarpIsBiased) {
  const IrradianceCase c;
  const auto r = c.test(sample_cosine_hemisphere_no_grazing);
  std::cout << "wrong warp:   " << describe(r) << "\n";
  EXPECT_EQ(r.verdict, furnace::stats::Verdict::kFail) << r.message;
  // The test could see a bias far smaller than the 1/0.99 − 1 ≈ 1 % the cut causes.
  EXPECT_LT(r.test.detectable_relative_bias, 0.01);
}

}  // namespace
