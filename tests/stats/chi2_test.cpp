// The chi-square machinery of stats/chi2.h on its own: Pearson statistic,
// pooling, zero-expectation failures, the quadrature of expected counts, and
// the reported power.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <string>

#include <boost/math/distributions/chi_squared.hpp>

#include "core/vec3.h"
#include "renderer/rng.h"
#include "stats/chi2.h"

namespace furnace::stats {
namespace {

constexpr uint64_t kSeed = 0xc412;  // fixed: verdicts are reproducible
constexpr double kAlpha = 1e-3;     // per test, uncorrected: each test here is a separate claim

TEST(Chi2FromCounts, PerfectFitHasZeroStatistic) {
  const std::vector<double> counts = {10, 20, 30, 40};
  const Chi2Result r = chi2_from_counts(counts, counts, kAlpha);
  EXPECT_EQ(r.statistic, 0.0);
  EXPECT_EQ(r.dof, 3);
  EXPECT_DOUBLE_EQ(r.p_value, 1.0);
  EXPECT_TRUE(r.pass);
}

TEST(Chi2FromCounts, StatisticAndPValueMatchTheDefinition) {
  const std::vector<double> observed = {12, 25, 28, 35};
  const std::vector<double> expected = {10, 20, 30, 40};
  double chi2 = 0;
  for (size_t i = 0; i < 4; ++i) chi2 += (observed[i] - expected[i]) * (observed[i] - expected[i]) / expected[i];
  const Chi2Result r = chi2_from_counts(observed, expected, kAlpha);
  EXPECT_NEAR(r.statistic, chi2, 1e-14 * chi2);
  EXPECT_NEAR(r.p_value, boost::math::cdf(boost::math::complement(boost::math::chi_squared_distribution<double>(3), chi2)), 1e-14);
}

TEST(Chi2FromCounts, SmallCellsArePooled) {
  // Two cells below kMinExpectedCount (2 + 3.5 = 5.5 ≥ 5): one pooled bin.
  const Chi2Result r = chi2_from_counts({2, 4, 50, 50}, {2, 3.5, 50, 50}, kAlpha);
  EXPECT_EQ(r.pooled_cells, 2u);
  EXPECT_EQ(r.dof, 2);
  // A pool still below 5 merges into the smallest regular bin.
  const Chi2Result merged = chi2_from_counts({1, 50, 60}, {1, 50, 60}, kAlpha);
  EXPECT_EQ(merged.pooled_cells, 1u);
  EXPECT_EQ(merged.dof, 1);
}

TEST(Chi2FromCounts, SampleInZeroExpectationCellFailsImmediately) {
  const Chi2Result r = chi2_from_counts({1, 50, 50}, {0, 50.5, 50.5}, kAlpha);
  EXPECT_FALSE(r.pass);
  EXPECT_NE(r.message.find("integrates to 0"), std::string::npos) << r.message;
}

TEST(Chi2FromCounts, TooFewBinsFail) {
  EXPECT_FALSE(chi2_from_counts({3, 3}, {3, 3}, kAlpha).pass);
}

TEST(DirectionalChi2, GridIsEqualAreaAndIntegratesUniformPdfToOne) {
  const auto uniform_sphere = [](const Vec3&) { return 1.0 / (4 * kPi); };
  const DirectionalChi2 chi2(uniform_sphere, SphericalGrid::sphere(10));
  const auto& p = chi2.cell_probabilities();
  ASSERT_EQ(p.size(), 21u * 10u);
  for (double q : p) EXPECT_NEAR(q, 1.0 / 210.0, 1e-14);
  EXPECT_NEAR(chi2.pdf_integral(), 1.0, 1e-13);
}

TEST(DirectionalChi2, QuadratureOfASmoothPdf) {
  // cos θ/π on the hemisphere: the row between t0 and t1 holds
  // (1 − t0)² − (1 − t1)² of the probability.
  const auto cosine = [](const Vec3& w) { return w.z > 0 ? w.z / kPi : 0.0; };
  const SphericalGrid grid = SphericalGrid::hemisphere(8);
  const DirectionalChi2 chi2(cosine, grid);
  for (int row = 0; row < grid.t_bins; ++row) {
    double sum = 0;
    for (int col = 0; col < grid.phi_bins; ++col) sum += chi2.cell_probabilities()[size_t(row) * grid.phi_bins + col];
    const double c0 = 1 - double(row) / grid.t_bins, c1 = 1 - double(row + 1) / grid.t_bins;
    EXPECT_NEAR(sum, c0 * c0 - c1 * c1, 1e-12) << "row " << row;
  }
  EXPECT_NEAR(chi2.pdf_integral(), 1.0, 1e-12);
}

TEST(DirectionalChi2, RejectsEvenAzimuthResolution) {
  const auto pdf = [](const Vec3&) { return 1.0; };
  EXPECT_THROW(DirectionalChi2(pdf, SphericalGrid{20, 10, 2.0}), std::invalid_argument);
}

TEST(DirectionalChi2, NonUnitAndOutsideSamplesFail) {
  const auto hemisphere = [](const Vec3& w) { return w.z >= 0 ? 1 / (2 * kPi) : 0.0; };
  const DirectionalChi2 chi2(hemisphere, SphericalGrid::hemisphere(5));
  EXPECT_EQ(chi2.cell_of(Vec3(0, 0, 1.001)), -1);
  EXPECT_EQ(chi2.cell_of(Vec3(0, 0, -1)), -1);  // below the hemisphere grid
  EXPECT_GE(chi2.cell_of(Vec3(1, 0, 0)), 0);    // the rim belongs to the last row
  const Chi2Result r = chi2.test({Vec3(0, 0, 1), Vec3(0.6, 0, 0.6)}, kAlpha, 1);
  EXPECT_FALSE(r.pass);
  EXPECT_NE(r.message.find("Sample 1"), std::string::npos) << r.message;
}

// Uniform sphere samples drawn inline (independent of renderer/sampling.h):
// 200 000 samples, 41×20 cells, α = kAlpha. The reported detectable effect w
// is printed; a 1 % tilt of the density is well inside it.
TEST(DirectionalChi2, InlineUniformSpherePassesAndReportsPower) {
  Rng rng(kSeed, 1, 0);
  std::vector<Vec3> samples;
  for (int i = 0; i < 200000; ++i) {
    const double z = 1 - 2 * rng.next_double();
    const double r = std::sqrt(std::max(0.0, 1 - z * z));
    const double phi = 2 * kPi * rng.next_double();
    samples.push_back(normalize(Vec3(r * std::cos(phi), r * std::sin(phi), z)));
  }
  const Chi2Result r =
      chi2_test_directions(samples, [](const Vec3&) { return 1 / (4 * kPi); }, SphericalGrid::sphere(20), kAlpha, 1);
  std::cout << "  " << r.message << " detectable w = " << r.detectable_effect << "\n";
  testing::Test::RecordProperty("detectable_effect_w", std::to_string(r.detectable_effect));
  EXPECT_TRUE(r.pass) << r.message;
  EXPECT_GT(r.detectable_effect, 0.0);
  EXPECT_LT(r.detectable_effect, 0.1);
}

TEST(PlanarChi2, UniformSquareIntegratesToOne) {
  const PlanarChi2 chi2([](const std::array<double, 2>&) { return 1.0; }, PlanarGrid{});
  EXPECT_NEAR(chi2.pdf_integral(), 1.0, 1e-13);
  EXPECT_EQ(chi2.cell_of({1.5, 0.5}), -1);
  EXPECT_EQ(chi2.cell_of({std::nan(""), 0.5}), -1);
}

// x = max(u1, u2) has density 2x on [0, 1]; 200 000 samples, 21 bins, α = kAlpha.
TEST(IntervalChi2, MaxOfTwoUniformsHasLinearDensity) {
  Rng rng(kSeed, 2, 0);
  std::vector<double> max_samples, plain_samples;
  for (int i = 0; i < 200000; ++i) {
    const double u1 = rng.next_double();
    max_samples.push_back(std::max(u1, rng.next_double()));
    plain_samples.push_back(u1);
  }
  const auto linear = [](double x) { return x >= 0 && x <= 1 ? 2 * x : 0.0; };
  const Chi2Result ok = chi2_test_interval(max_samples, linear, 0, 1, 21, kAlpha, 1);
  std::cout << "  " << ok.message << " detectable w = " << ok.detectable_effect << "\n";
  EXPECT_TRUE(ok.pass) << ok.message;
  EXPECT_NEAR(ok.pdf_integral, 1.0, 1e-12);
  // Negative control: plain uniforms are not linearly distributed.
  EXPECT_FALSE(chi2_test_interval(plain_samples, linear, 0, 1, 21, kAlpha, 1).pass);
}

}  // namespace
}  // namespace furnace::stats
