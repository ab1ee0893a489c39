// The caller-facing mean test of stats/estimator_tests.h against furnace's
// exact references (analytic/reference.h), with negative controls: a biased
// estimator fails, a constant one must match exactly, a too-skewed one is
// inconclusive, a non-finite sample fails.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <limits>
#include <stdexcept>
#include <string>

#include "analytic/reference.h"
#include "core/scene.h"
#include "stats/estimator_tests.h"

namespace furnace::stats {
namespace {

constexpr size_t kFamilyTests = 4;  // the mean tests of this file that should pass or fail on bias

EstimatorTestOptions family_options() {
  EstimatorTestOptions o;
  o.n_tests = kFamilyTests;
  return o;
}

// Irradiance at the floor's centre under the built-in sphere light, estimated
// by cosine-weighted hemisphere sampling (Li·cos θ/pdf = π·Li).
struct SphereLight {
  Scene scene = load_scene(std::string(FURNACE_SCENE_DIR) + "/sphere_light.json");
  Vec3 point{0, 0, 0}, normal{0, 0, 1};
  double reference = analytic::irradiance(scene, point, normal, size_t(0));

  // u1_scale < 1 cuts the directions near the horizon away: a biased estimator.
  Estimator estimator(double u1_scale) const {
    return [this, u1_scale](UniformStream& u) {
      const double u1 = u1_scale * u.next(), phi = 2 * kPi * u.next();
      const double r = std::sqrt(u1);
      const Vec3 w(r * std::cos(phi), r * std::sin(phi), std::sqrt(1 - u1));
      const auto hit = analytic::intersect(scene, point, w, 1e-9);
      return kPi * (hit ? scene.objects[hit->object_index].emitted_radiance : 0.0);
    };
  }
};

TEST(EstimatorMeanTest, UnbiasedEstimatorPasses) {
  const SphereLight c;
  const EstimatorMeanTestResult r = estimator_mean_test(c.estimator(1.0), c.reference, family_options());
  std::cout << "  " << describe(r) << "\n";
  EXPECT_TRUE(r.pass()) << r.message;
  EXPECT_EQ(r.test.count, 100'000u);
  EXPECT_EQ(r.test.alpha, sidak_alpha(0.01, kFamilyTests));
  EXPECT_GT(r.test.detectable_relative_bias, 0);
  EXPECT_LT(r.test.detectable_relative_bias, 0.05);
}

// Cutting 2 % of the cosine-weighted mass near the horizon raises the
// estimate by 1/0.98 − 1 ≈ 2 %, above the detectable bias.
TEST(EstimatorMeanTest, BiasedEstimatorFails) {
  const SphereLight c;
  EstimatorTestOptions o = family_options();
  o.samples = 400'000;
  const EstimatorMeanTestResult r = estimator_mean_test(c.estimator(0.98), c.reference, o);
  std::cout << "  " << describe(r) << "\n";
  EXPECT_EQ(r.verdict, Verdict::kFail);
  EXPECT_LT(r.test.detectable_relative_bias, 1 / 0.98 - 1);
}

TEST(EstimatorMeanTest, ConstantEstimatorMustMatchExactly) {
  // The white sky: cosine sampling of a constant environment is exact, E = π·L.
  const auto constant = [](UniformStream&) { return kPi * 1.0; };
  const EstimatorMeanTestResult r = estimator_mean_test(constant, kPi, family_options());
  EXPECT_TRUE(r.pass()) << r.message;
  EXPECT_TRUE(r.test.zero_variance);
  const EstimatorMeanTestResult off = estimator_mean_test(constant, kPi * (1 + 1e-4), family_options());
  EXPECT_EQ(off.verdict, Verdict::kFail);
}

TEST(EstimatorMeanTest, TooSkewedIsInconclusive) {
  // Bernoulli(1e-3)·1000: skewness ≈ 31.6, Cochran asks for ~25 000 samples.
  const auto rare = [](UniformStream& u) { return u.next() < 1e-3 ? 1000.0 : 0.0; };
  EstimatorTestOptions o = family_options();
  o.samples = 5'000;
  const EstimatorMeanTestResult r = estimator_mean_test(rare, 1.0, o);
  std::cout << "  " << describe(r) << "\n";
  EXPECT_EQ(r.verdict, Verdict::kInconclusive) << r.message;
  EXPECT_FALSE(r.test.clt_adequate);
  EXPECT_GT(r.test.standard_error, 0);
}

TEST(EstimatorMeanTest, NonFiniteSampleFails) {
  int calls = 0;
  const auto nan_once = [&](UniformStream& u) {
    return ++calls == 10 ? std::numeric_limits<double>::quiet_NaN() : u.next();
  };
  const EstimatorMeanTestResult r = estimator_mean_test(nan_once, 0.5, family_options());
  EXPECT_EQ(r.verdict, Verdict::kFail);
  EXPECT_EQ(r.nonfinite, 1u);
}

TEST(EstimatorMeanTest, MomentsOverloadGivesTheSameVerdict) {
  const SphereLight c;
  EstimatorTestOptions o = family_options();
  o.samples = 20'000;
  const Estimator e = c.estimator(1.0);
  UniformStream stream(o.seed);
  RunningMoments m;
  for (size_t i = 0; i < o.samples; ++i) m.add(e(stream));
  const EstimatorMeanTestResult a = estimator_mean_test(e, c.reference, o);
  const EstimatorMeanTestResult b = estimator_mean_test(m, c.reference, o);
  EXPECT_EQ(a.test.statistic, b.test.statistic);
  EXPECT_EQ(a.verdict, b.verdict);
}

TEST(EstimatorMeanTest, RefusesInvalidOptions) {
  const auto one = [](UniformStream&) { return 1.0; };
  EstimatorTestOptions o;
  o.samples = 1;
  EXPECT_THROW(estimator_mean_test(one, 1.0, o), std::invalid_argument);
  o = {};
  o.alpha_family = 0;
  EXPECT_THROW(estimator_mean_test(one, 1.0, o), std::invalid_argument);
  EXPECT_THROW(estimator_mean_test(one, std::numeric_limits<double>::infinity()), std::invalid_argument);
}

}  // namespace
}  // namespace furnace::stats
