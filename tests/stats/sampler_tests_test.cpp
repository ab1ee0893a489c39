// The caller-facing sampler tests of stats/sampler_tests.h: the chi-square
// test of a sampler given as callables (with its bin of failed and delta
// draws) and the pdf/weight consistency test, each with negative controls.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <iostream>
#include <optional>
#include <stdexcept>

#include "core/vec3.h"
#include "stats/sampler_tests.h"

namespace furnace::stats {
namespace {

constexpr double kAlbedo = 0.5;
// The tests of this file form one family at α = 0.01: Šidák over them.
constexpr size_t kFamilyTests = 6;

Vec3 cosine_warp(const std::array<double, 2>& u) {
  const double r = std::sqrt(u[0]), phi = 2 * kPi * u[1];
  return {r * std::cos(phi), r * std::sin(phi), std::sqrt(1 - u[0])};
}
double cosine_pdf(const Vec3& w) { return w.z > 0 ? w.z * kInvPi : 0.0; }
double lambertian_eval(const Vec3& w) { return w.z > 0 ? kAlbedo * kInvPi : 0.0; }

DirectionSample lambertian_sample(const Vec3& w) {
  const double pdf = cosine_pdf(w);
  return {w, pdf, kAlbedo * kInvPi * w.z / pdf, false};
}
std::optional<DirectionSample> cosine_sampler(const std::array<double, 2>& u) {
  return lambertian_sample(cosine_warp(u));
}

SamplerChi2Options family_options() {
  SamplerChi2Options o;
  o.n_tests = kFamilyTests;
  return o;
}

TEST(SamplerChi2, CorrectCosineWarpPasses) {
  const SamplerChi2Result r = chi2_test_sampler(cosine_sampler, cosine_pdf, family_options());
  std::cout << "  " << describe(r) << "\n";
  EXPECT_TRUE(r.pass) << r.chi2.message;
  EXPECT_EQ(r.draws, 1'000'000u);
  EXPECT_EQ(r.failed_draws, 0u);
  EXPECT_EQ(r.chi2.cells, 41u * 20u);
  EXPECT_EQ(r.chi2.alpha, sidak_alpha(0.01, kFamilyTests));
  EXPECT_NEAR(r.chi2.pdf_integral, 1.0, 1e-8);
  // 820 cells of ~1200 expected samples: the stated power must be real.
  EXPECT_GT(r.chi2.detectable_effect, 0);
  EXPECT_LT(r.chi2.detectable_effect, 0.02);
}

// Negative controls: a warp that skips the last 1 % of its support near the
// horizon, and a pdf 10 % too large.
TEST(SamplerChi2, WarpMissingTheGrazingDirectionsFails) {
  const auto cut = [](const std::array<double, 2>& u) -> std::optional<DirectionSample> {
    return lambertian_sample(cosine_warp({0.99 * u[0], u[1]}));
  };
  const SamplerChi2Result r = chi2_test_sampler(cut, cosine_pdf, family_options());
  std::cout << "  " << describe(r) << "\n";
  EXPECT_FALSE(r.pass);
  EXPECT_LT(r.chi2.p_value, r.chi2.alpha);
}

TEST(SamplerChi2, PdfOffByConstantFails) {
  const auto pdf = [](const Vec3& w) { return 1.1 * cosine_pdf(w); };
  const SamplerChi2Result r = chi2_test_sampler(cosine_sampler, pdf, family_options());
  std::cout << "  " << describe(r) << "\n";
  EXPECT_FALSE(r.pass);
  EXPECT_NEAR(r.chi2.pdf_integral, 1.1, 1e-8);
}

TEST(SamplerChi2, DirectionThatIsNotAUnitVectorFails) {
  const auto sloppy = [](const std::array<double, 2>& u) -> std::optional<DirectionSample> {
    DirectionSample s = lambertian_sample(cosine_warp(u));
    s.direction = s.direction * 1.001;
    return s;
  };
  const SamplerChi2Result r = chi2_test_sampler(sloppy, cosine_pdf, family_options());
  EXPECT_FALSE(r.pass);
  EXPECT_NE(r.chi2.message.find("unit length"), std::string::npos) << r.chi2.message;
}

// A sampler that fails on 9 % of its draws (the cosine lobe with θ > acos 0.3
// cut away) and whose pdf says so passes; with the full cosine pdf, which
// leaves no mass for failures, it fails at once.
std::optional<DirectionSample> truncated_sampler(const std::array<double, 2>& u) {
  if (u[0] >= 0.91) return std::nullopt;
  return lambertian_sample(cosine_warp(u));
}
double truncated_pdf(const Vec3& w) { return w.z > 0.3 ? cosine_pdf(w) : 0.0; }

TEST(SamplerChi2, FailedDrawsAreTheMassThePdfLacks) {
  const SamplerChi2Result r = chi2_test_sampler(truncated_sampler, truncated_pdf, family_options());
  std::cout << "  " << describe(r) << "\n";
  EXPECT_TRUE(r.pass) << r.chi2.message;
  EXPECT_NEAR(r.chi2.pdf_integral, 0.91, 1e-7);
  EXPECT_GT(r.failed_draws, 80'000u);

  // The full cosine pdf leaves (up to quadrature error) no mass for 9 % failures.
  const SamplerChi2Result wrong = chi2_test_sampler(truncated_sampler, cosine_pdf, family_options());
  EXPECT_FALSE(wrong.pass);
  EXPECT_LT(wrong.chi2.p_value, wrong.chi2.alpha);
  // A pdf integrating to more than 1 leaves none at all: the first failure fails the test.
  const auto heavy = [](const Vec3& w) { return 1.05 * cosine_pdf(w); };
  const SamplerChi2Result none = chi2_test_sampler(truncated_sampler, heavy, family_options());
  EXPECT_FALSE(none.pass);
  EXPECT_NE(none.chi2.message.find("returned no sample"), std::string::npos) << none.chi2.message;
}

// A mirror-plus-diffuse mixture: 20 % delta samples, the diffuse lobe 0.8·cos/π.
TEST(SamplerChi2, DeltaSamplesAreCountedWithTheFailures) {
  const auto mixture = [](const std::array<double, 2>& u) -> std::optional<DirectionSample> {
    if (u[0] < 0.2) return DirectionSample{Vec3(0, 0, 1), 0.0, 1.0, true};
    return lambertian_sample(cosine_warp({(u[0] - 0.2) / 0.8, u[1]}));
  };
  const auto pdf = [](const Vec3& w) { return 0.8 * cosine_pdf(w); };
  const SamplerChi2Result r = chi2_test_sampler(mixture, pdf, family_options());
  std::cout << "  " << describe(r) << "\n";
  EXPECT_TRUE(r.pass) << r.chi2.message;
  EXPECT_GT(r.delta_samples, 190'000u);
  EXPECT_EQ(r.failed_draws, 0u);
}

TEST(SamplerChi2, SameSeedSameResultOtherSeedOtherSample) {
  SamplerChi2Options o = family_options();
  o.samples = 20'000;
  const SamplerChi2Result a = chi2_test_sampler(cosine_sampler, cosine_pdf, o);
  const SamplerChi2Result b = chi2_test_sampler(cosine_sampler, cosine_pdf, o);
  o.seed += 1;
  const SamplerChi2Result c = chi2_test_sampler(cosine_sampler, cosine_pdf, o);
  EXPECT_EQ(a.chi2.statistic, b.chi2.statistic);
  EXPECT_NE(a.chi2.statistic, c.chi2.statistic);
}

TEST(SamplerChi2, RefusesInvalidOptions) {
  SamplerChi2Options o;
  o.alpha_family = 1;
  EXPECT_THROW(chi2_test_sampler(cosine_sampler, cosine_pdf, o), std::invalid_argument);
  o = {};
  o.n_tests = 0;
  EXPECT_THROW(chi2_test_sampler(cosine_sampler, cosine_pdf, o), std::invalid_argument);
  o = {};
  o.grid.phi_bins = 40;
  EXPECT_THROW(chi2_test_sampler(cosine_sampler, cosine_pdf, o), std::invalid_argument);
  o = {};
  o.samples = 0;
  EXPECT_THROW(chi2_test_sampler(cosine_sampler, cosine_pdf, o), std::invalid_argument);
}

// ---------------------------------------------------------------------------

TEST(SampleConsistency, CorrectSamplerPasses) {
  const ConsistencyResult r = check_sample_consistency(cosine_sampler, cosine_pdf, lambertian_eval);
  std::cout << "  " << describe(r) << "\n";
  EXPECT_TRUE(r.pass) << r.message;
  EXPECT_EQ(r.checked, 100'000u);
  EXPECT_TRUE(r.weights_checked);
  EXPECT_LE(r.max_weight_relative_error, kDefaultConsistencyRelTolerance);
}

TEST(SampleConsistency, PdfOffByConstantIsAMismatchEverywhere) {
  const auto pdf = [](const Vec3& w) { return 1.1 * cosine_pdf(w); };
  const ConsistencyResult r = check_sample_consistency(cosine_sampler, pdf, lambertian_eval);
  std::cout << "  " << describe(r) << "\n";
  EXPECT_FALSE(r.pass);
  EXPECT_EQ(r.pdf_mismatches, r.checked);
  EXPECT_NEAR(r.max_pdf_relative_error, 0.1 / 1.1, 1e-12);
}

TEST(SampleConsistency, StaleWeightIsAMismatch) {
  const auto stale = [](const std::array<double, 2>& u) -> std::optional<DirectionSample> {
    DirectionSample s = lambertian_sample(cosine_warp(u));
    s.weight = kAlbedo * kInvPi / s.pdf_solid_angle;  // cos θ forgotten
    return s;
  };
  const ConsistencyResult r = check_sample_consistency(stale, cosine_pdf, lambertian_eval);
  EXPECT_FALSE(r.pass);
  EXPECT_EQ(r.weight_mismatches, r.checked);
  EXPECT_EQ(r.pdf_mismatches, 0u);
}

TEST(SampleConsistency, WithoutEvalOnlyPdfsAreCompared) {
  const auto no_weight = [](const std::array<double, 2>& u) -> std::optional<DirectionSample> {
    const Vec3 w = cosine_warp(u);
    return DirectionSample{w, cosine_pdf(w), std::nullopt, false};
  };
  const ConsistencyResult r = check_sample_consistency(no_weight, cosine_pdf, nullptr);
  EXPECT_TRUE(r.pass) << r.message;
  EXPECT_FALSE(r.weights_checked);
  // With an eval, a missing weight is invalid.
  const ConsistencyResult missing = check_sample_consistency(no_weight, cosine_pdf, lambertian_eval);
  EXPECT_FALSE(missing.pass);
  EXPECT_EQ(missing.invalid, missing.checked);
}

TEST(SampleConsistency, DeltaAndFailedDrawsAreSkipped) {
  const auto mixture = [](const std::array<double, 2>& u) -> std::optional<DirectionSample> {
    if (u[0] < 0.1) return std::nullopt;
    if (u[0] < 0.3) return DirectionSample{Vec3(0, 0, 1), 0.0, 1.0, true};
    return lambertian_sample(cosine_warp(u));
  };
  const ConsistencyResult r = check_sample_consistency(mixture, cosine_pdf, lambertian_eval);
  EXPECT_TRUE(r.pass) << r.message;
  EXPECT_EQ(r.checked + r.failed_draws + r.delta_samples, r.draws);
  EXPECT_GT(r.failed_draws, 0u);
  EXPECT_GT(r.delta_samples, 0u);
}

}  // namespace
}  // namespace furnace::stats
