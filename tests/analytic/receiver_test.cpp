// The receiver model (receiver.h) is generic over the BSDF: a receiver that
// supplies only the two functions of a Lambertian surface (f = ρ/π, p_b =
// cos θ/π) must get, from the same machinery that serves Phong, the radiance
// and every direct strategy's second moment that the Lambertian closed forms
// and the Lambertian MIS quadrature give (reference.h, moments.h): a
// different method for every strategy. Negative controls: the same receiver
// with its density off by a constant, or its f·cos θ with a second cosine, must be
// caught. And the environment memo keys on every BSDF parameter.
#include "analytic/receiver.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "analytic/moments.h"
#include "analytic/phong.h"
#include "analytic/receiver_integrals.h"
#include "analytic/reference.h"
#include "core/error.h"
#include "lambertian_receiver.h"

namespace furnace::analytic {
namespace {

// Both sides are quadratures at relative tolerance ≤ 1e-9 per nested
// integral (receiver.h) or closed forms to ~1e-13; ten times the nested
// tolerance covers the two levels (as phong_test's kMomentTolerance).
constexpr double kMomentTolerance = 1e-8;

// What the negative controls get wrong: a factor far outside the tolerance.
constexpr double kWrongFactor = 1.1;

using receiver_testing::LambertianReceiver;

constexpr double kAlbedo = 0.6;

struct LightCase {
  std::string name;
  bool environment;  // else a sphere light of radius 0.5 at `center`
  Vec3 center;
};

Scene lambertian_scene(const LightCase& c) {
  Scene scene;
  scene.name = c.name;
  scene.source = "receiver_test";
  scene.objects.push_back({"floor", Rectangle{{-3, -3, 0}, {6, 0, 0}, {0, 6, 0}}, {kAlbedo, Lambertian{}}, 0});
  if (c.environment) scene.environment.radiance = 1.5;
  else scene.objects.push_back({"light", Sphere{c.center, 0.5}, {}, 4.0});
  return scene;
}

std::vector<LightCase> light_cases() {
  return {{"sky", true, {}},
          {"sphere overhead", false, {0.2, 0.1, 1.5}},
          {"sphere oblique", false, {1.2, -0.4, 0.9}},
          {"sphere straddling the horizon", false, {1.5, 0.3, 0.2}}};
}

// A view 50° from the normal: the mirror direction (the cap cuts) is not n.
const Vec3 kNormal{0, 0, 1};
const Vec3 kView = normalize(Vec3{-std::sin(50 * kPi / 180), 0, std::cos(50 * kPi / 180)});
const Vec3 kPoint{0, 0, 0};

// Relative error of every quantity the receiver model gives for `receiver`
// against the Lambertian forms, the worst over every light case: radiance,
// then each direct strategy's E[Y²] (Y_px = (ρ/π)·Y_irradiance, so
// E[Y²] = (ρ/π)²·second_moment).
double worst_error_against_lambertian(const Receiver& receiver, bool print) {
  const double k = kAlbedo / kPi;
  double worst = 0;
  for (const LightCase& c : light_cases()) {
    const Scene scene = lambertian_scene(c);
    const std::vector<ReceiverLight> lights =
        receiver_lights(scene, kPoint, kNormal, 0, LightSelection::kUniform, receiver.name());
    const double want_radiance = k * irradiance(scene, kPoint, kNormal, 0);
    const double got_radiance = reflected_radiance(receiver, lights);
    worst = std::max(worst, std::fabs(got_radiance / want_radiance - 1));
    for (Strategy s : direct_strategies()) {
      const double want = k * k * second_moment(s, scene, kPoint, kNormal, 0);
      const double got = receiver_second_moment(s, receiver, lights);
      const double rel = std::fabs(got / want - 1);
      worst = std::max(worst, rel);
      if (print && !(rel < kMomentTolerance))
        std::printf("  %s, %s: %.17g vs %.17g\n", c.name.c_str(), strategy_name(s).c_str(), got, want);
    }
  }
  return worst;
}

TEST(ReceiverModel, LambertianFromItsTwoFunctionsMatchesTheClosedForms) {
  const double worst = worst_error_against_lambertian(LambertianReceiver(kNormal, kView, kAlbedo), true);
  std::printf("Lambertian receiver model vs closed forms and MIS quadrature: worst relative error %.3g\n", worst);
  EXPECT_LT(worst, kMomentTolerance);
}

TEST(ReceiverModel, NegativeControlsAreCaught) {
  // A density off by a constant changes every estimator that draws from or
  // weighs with p_b (bsdf, MIS); a second cosine in f·cos θ changes everything.
  const double wrong_pdf = worst_error_against_lambertian(LambertianReceiver(kNormal, kView, kAlbedo, kWrongFactor), false);
  const double extra_cosine =
      worst_error_against_lambertian(LambertianReceiver(kNormal, kView, kAlbedo, 1, true), false);
  std::printf("negative controls: density x%.2g worst %.3g, f·cos²θ worst %.3g\n", kWrongFactor, wrong_pdf,
              extra_cosine);
  EXPECT_GT(wrong_pdf, kMomentTolerance);
  EXPECT_GT(extra_cosine, kMomentTolerance);
}

TEST(ReceiverModel, BsdfSamplingOfTheTrueDensityDependsOnlyOnItsRatio) {
  // bsdf sampling reads f·cos/p_b only through f_cos2_over_pdf: the wrong
  // density gives exactly 1/kWrongFactor of the true bsdf moment, a check
  // of which field the machinery reads for which estimator.
  const Scene scene = lambertian_scene(light_cases()[1]);
  const LambertianReceiver right(kNormal, kView, kAlbedo), wrong(kNormal, kView, kAlbedo, kWrongFactor);
  const auto lights = receiver_lights(scene, kPoint, kNormal, 0, LightSelection::kUniform, right.name());
  const double ratio = receiver_second_moment(Strategy::kBsdf, wrong, lights) /
                       receiver_second_moment(Strategy::kBsdf, right, lights);
  EXPECT_LT(std::fabs(ratio * kWrongFactor - 1), kMomentTolerance) << ratio;
  // The light strategies never read p_b: identical.
  EXPECT_EQ(receiver_second_moment(Strategy::kLightSolidAngle, wrong, lights),
            receiver_second_moment(Strategy::kLightSolidAngle, right, lights));
}

TEST(ReceiverModel, EnvironmentMemoKeysOnEveryBsdfParameter) {
  // Under the sky alone the scene-level forms memoise per (frame, BSDF): two
  // lobes asked in turn at the same frame must each get their own value,
  // equal to the un-memoised machinery's.
  Scene scene = lambertian_scene(light_cases()[0]);
  scene.objects[0].material = {0.8, Phong{10}};
  const auto lights = receiver_lights(scene, kPoint, kNormal, 0, LightSelection::kUniform, "a Phong receiver");
  for (int round = 0; round < 2; ++round)
    for (double exponent : {10.0, 100.0}) {
      const PhongReceiver phong(kNormal, kView, 0.8, exponent);
      EXPECT_EQ(receiver_reflected_radiance(scene, kPoint, phong, 0), reflected_radiance(phong, lights)) << exponent;
      EXPECT_EQ(receiver_second_moment(Strategy::kBsdf, scene, kPoint, phong, 0, LightSelection::kUniform),
                receiver_second_moment(Strategy::kBsdf, phong, lights))
          << exponent;
    }
  // Negative control of the check itself: the two lobes do differ.
  EXPECT_NE(reflected_radiance(PhongReceiver(kNormal, kView, 0.8, 10), lights),
            reflected_radiance(PhongReceiver(kNormal, kView, 0.8, 100), lights));
}

TEST(ReceiverModel, RefusesPathTracers) {
  const Scene scene = lambertian_scene(light_cases()[1]);
  const LambertianReceiver receiver(kNormal, kView, kAlbedo);
  const auto lights = receiver_lights(scene, kPoint, kNormal, 0, LightSelection::kUniform, receiver.name());
  for (Strategy s : path_tracing_strategies()) EXPECT_THROW(receiver_second_moment(s, receiver, lights), Error);
}

}  // namespace
}  // namespace furnace::analytic
