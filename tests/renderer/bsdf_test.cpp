// BSDFs: sample() agrees with pdf() and eval() under the return convention
// (weight = f·cos/pdf), the pdf integrates to the probability that a sample
// succeeds, energy is conserved (albedo ρ at normal incidence for normalised
// Phong and at every angle for Lambertian), and the mirror is a flagged delta.
#include <gtest/gtest.h>

#include <functional>
#include <iostream>
#include <ostream>
#include <string>
#include <tuple>

#include "renderer/bsdf.h"
#include "renderer/rng.h"
#include "test_support.h"

namespace furnace {
namespace {


constexpr uint64_t kSeed = 0xb5df;
constexpr int kSamples = 1 << 15;
// sample() and pdf()/eval() compute the same quantities by the same helper;
// only the frame round trip of wi differs: a few ulps.
constexpr double kConsistencyRelTol = 1e-10;
constexpr double kQuadratureTol = 1e-8;

struct MaterialCase {
  std::string name;
  Material material;
};

void PrintTo(const MaterialCase& c, std::ostream* os) { *os << c.name; }

Material make_ggx(double albedo, double alpha, MicrofacetShadowing shadowing) {
  return Material{albedo, Ggx{alpha, shadowing, std::nullopt}};
}

Vec3 wo_at(double theta_deg) {
  const double t = theta_deg * kPi / 180;
  return {std::sin(t), 0, std::cos(t)};
}

using BsdfParam = std::tuple<MaterialCase, double>;
class BsdfTest : public testing::TestWithParam<BsdfParam> {
 protected:
  Bsdf bsdf() const { return Bsdf(std::get<0>(GetParam()).material); }
  Vec3 wo() const { return wo_at(std::get<1>(GetParam())); }
};

TEST_P(BsdfTest, SampleAgreesWithPdfAndEval) {
  const Bsdf b = bsdf();
  for (int i = 0; i < 4096; ++i) {
    Rng rng(kSeed, 0, uint64_t(i));
    const double u1 = rng.next_double(), u2 = rng.next_double();
    const auto s = b.sample(wo(), u1, u2);
    if (!s) continue;
    EXPECT_GT(s->wi_local.z, 0.0);
    EXPECT_NEAR(length(s->wi_local), 1.0, 1e-12);
    const double pdf = b.pdf(wo(), s->wi_local);
    EXPECT_NEAR(s->pdf_solid_angle / pdf, 1.0, kConsistencyRelTol);
    EXPECT_NEAR(s->weight / (b.eval(wo(), s->wi_local) * s->wi_local.z / pdf), 1.0, kConsistencyRelTol);
  }
}

// Uniform-hemisphere Monte Carlo estimate of ∫_H g(wi) dωi (E[2π·g]); the
// BSDF lobes have kinks (cos α = 0, the horizon) that make nested adaptive
// quadrature crawl, and an estimate with a data-derived variance is all the
// two-sample tests below need.
RunningMoments hemisphere_integral(const std::function<double(const Vec3&)>& g, uint64_t stream) {
  RunningMoments w;
  for (int i = 0; i < kSamples; ++i) {
    Rng rng(kSeed, stream, uint64_t(i));
    const double u1 = rng.next_double(), u2 = rng.next_double();
    w.add(g(sample_uniform_hemisphere(u1, u2)) / uniform_hemisphere_pdf({0, 0, 1}));
  }
  return w;
}

TEST_P(BsdfTest, PdfIntegratesToSuccessProbability) {
  // ∫_H pdf dω (the lobe mass above the horizon) = P(sample() succeeds).
  const Bsdf b = bsdf();
  const RunningMoments mass = hemisphere_integral([&](const Vec3& wi) { return b.pdf(wo(), wi); }, 10);
  RunningMoments success;
  for (int i = 0; i < kSamples; ++i) {
    Rng rng(kSeed, 1, uint64_t(i));
    const double u1 = rng.next_double(), u2 = rng.next_double();
    success.add(b.sample(wo(), u1, u2).has_value() ? 1.0 : 0.0);
  }
  EXPECT_TRUE(testing_support::means_consistent(mass, success)) << mass.mean << " vs " << success.mean;
  const BsdfType type = std::get<0>(GetParam()).material.type();
  // GGX reflects part of every lobe below the horizon, even at normal incidence.
  if (type == BsdfType::kLambertian || (type == BsdfType::kPhong && std::get<1>(GetParam()) == 0.0)) {
    EXPECT_EQ(success.mean, 1.0);  // nothing of the lobe lies below the horizon
  }
}

TEST_P(BsdfTest, MeanWeightIsDirectionalAlbedo) {
  // E[weight] = ∫ f cos dωi, the directional albedo, ≤ ρ.
  const Bsdf b = bsdf();
  const RunningMoments albedo = hemisphere_integral([&](const Vec3& wi) { return b.eval(wo(), wi) * wi.z; }, 11);
  RunningMoments weight;
  for (int i = 0; i < kSamples; ++i) {
    Rng rng(kSeed, 2, uint64_t(i));
    const double u1 = rng.next_double(), u2 = rng.next_double();
    const auto s = b.sample(wo(), u1, u2);
    weight.add(s ? s->weight : 0.0);
  }
  EXPECT_TRUE(testing_support::means_consistent(albedo, weight)) << albedo.mean << " vs " << weight.mean;
  EXPECT_LE(weight.mean, std::get<0>(GetParam()).material.albedo * (1 + testing_support::kConstantMeanRelTol) +
                             testing_support::z_critical(testing_support::kAlpha) * weight.mean_standard_error());
}

TEST_P(BsdfTest, ZeroBelowTheHorizon) {
  const Bsdf b = bsdf();
  const Vec3 below = normalize(Vec3{0.3, -0.2, -0.5});
  EXPECT_EQ(b.eval(wo(), below), 0.0);
  EXPECT_EQ(b.pdf(wo(), below), 0.0);
  EXPECT_FALSE(b.sample({0.2, 0, -0.9}, 0.3, 0.4).has_value());  // wo below: no sample
}

std::string case_name(const testing::TestParamInfo<BsdfParam>& info) {
  return std::get<0>(info.param).name + "Theta" + std::to_string(int(std::get<1>(info.param)));
}

INSTANTIATE_TEST_SUITE_P(
    Materials, BsdfTest,
    testing::Combine(testing::Values(MaterialCase{"Lambertian", Material{0.7, Lambertian{}}},
                                     MaterialCase{"Phong1", Material{0.8, Phong{1}}},
                                     MaterialCase{"Phong10", Material{0.8, Phong{10}}},
                                     MaterialCase{"Phong200", Material{0.9, Phong{200}}},
                                     // GGX lobes wide enough for the uniform-hemisphere estimates below.
                                     MaterialCase{"GgxAlpha0p2HeightCorrelated",
                                                  make_ggx(0.8, 0.2, MicrofacetShadowing::kHeightCorrelated)},
                                     MaterialCase{"GgxAlpha0p5Separable",
                                                  make_ggx(0.8, 0.5, MicrofacetShadowing::kSeparable)},
                                     MaterialCase{"GgxAlpha1HeightCorrelated",
                                                  make_ggx(0.8, 1.0, MicrofacetShadowing::kHeightCorrelated)}),
                     testing::Values(0.0, 30.0, 60.0, 85.0)),
    case_name);

TEST(PhongBsdf, AlbedoAtNormalIncidenceIsRho) {
  for (double n : {0.0, 1.0, 10.0, 200.0}) {
    const PhongBsdf b{0.8, n};
    const double albedo =
        testing_support::integrate_directions([&](const Vec3& wi) { return b.eval({0, 0, 1}, wi) * wi.z; }, 0, 1);
    EXPECT_NEAR(albedo, 0.8, kQuadratureTol) << "n = " << n;
  }
}

// Negative control of the two tests above: with DEFECT(ggx_vndf_pdf_without_g1)
// the pdf integrates to 1/G1(wo) times the success probability, and the
// weight (computed from that pdf) falls short of the directional albedo by G1(wo).
TEST(GgxBsdf, PdfWithoutG1FailsNormalisationAndAlbedo) {
  Material m = make_ggx(0.8, 0.5, MicrofacetShadowing::kHeightCorrelated);
  const Bsdf b(m, Defect::kGgxVndfPdfWithoutG1);
  const Vec3 wo = wo_at(60);
  const RunningMoments mass = hemisphere_integral([&](const Vec3& wi) { return b.pdf(wo, wi); }, 10);
  const RunningMoments albedo = hemisphere_integral([&](const Vec3& wi) { return b.eval(wo, wi) * wi.z; }, 11);
  RunningMoments success, weight;
  for (int i = 0; i < kSamples; ++i) {
    Rng rng(kSeed, 1, uint64_t(i));
    const double u1 = rng.next_double(), u2 = rng.next_double();
    const auto s = b.sample(wo, u1, u2);
    success.add(s ? 1.0 : 0.0);
    weight.add(s ? s->weight : 0.0);
  }
  std::cout << "  ggx_vndf_pdf_without_g1: int pdf " << mass.mean << " vs success " << success.mean
            << "; albedo " << albedo.mean << " vs mean weight " << weight.mean << "\n";
  EXPECT_FALSE(testing_support::means_consistent(mass, success));
  EXPECT_FALSE(testing_support::means_consistent(albedo, weight));
}

TEST(LambertianBsdf, CosineSamplingIsExact) {
  const LambertianBsdf b{0.6};
  for (int i = 0; i < 100; ++i) {
    Rng rng(kSeed, 3, uint64_t(i));
    const double u1 = rng.next_double(), u2 = rng.next_double();
    const auto s = b.sample(wo_at(40), u1, u2);
    ASSERT_TRUE(s.has_value());
    EXPECT_NEAR(s->weight, 0.6, 1e-15);  // zero variance: f·cos/pdf = ρ
  }
}

TEST(MirrorBsdf, IsAFlaggedDelta) {
  const Material m{0.9, Mirror{}};
  const Bsdf b(m);
  EXPECT_TRUE(b.is_delta());
  const Vec3 wo = normalize(Vec3{0.3, -0.4, 0.8});
  const auto s = b.sample(wo, 0.1, 0.2);
  ASSERT_TRUE(s.has_value());
  EXPECT_TRUE(s->delta);
  EXPECT_EQ(s->pdf_solid_angle, 0.0);
  EXPECT_EQ(s->weight, 0.9);
  EXPECT_EQ(s->wi_local, (Vec3{-wo.x, -wo.y, wo.z}));
  EXPECT_EQ(b.pdf(wo, s->wi_local), 0.0);
  EXPECT_EQ(b.eval(wo, s->wi_local), 0.0);
}

}  // namespace
}  // namespace furnace
