// Chi-square goodness of fit of the environment-map sampler
// (renderer/environment_sampler.h) against its own pdf, on the committed
// scenes/environment_map.exr and on synthetic maps (constant, one hot texel,
// black rows); its normalisation (∫pdf = 1 by the exact texel sum, and the
// mean of 1/pdf against the support's solid angle); the agreement of
// sample() with pdf(); and
// the negative control DEFECT(env_missing_sin_theta), which must fail.
//
// Cells: every texel split into kSplit × kSplit cells of equal steps in φ and
// in cos θ (equal solid angle: dΩ = dφ·d cos θ), so cell edges follow the
// pdf's discontinuities and the expected count of a cell is exact,
// N·pdf(cell centre)·Ω_cell (the pdf is constant on a texel). The sub-texel
// split also tests that samples are uniform in solid angle inside a texel.
// Cells expected below 5 are pooled (stats/chi2.h); a sample in a cell of
// zero expectation (a black texel) fails at once.
//
// Budget and levels: kSamples samples per map from the fixed seed kSeed (one
// stream per map); the kCorrectMaps correct-sampler tests share the
// family-wise level kFamilyAlpha by the Šidák correction, and the negative
// control runs at the same per-test level. Each test prints its statistic,
// p-value and detectable effect (Cohen's w at kDefaultPower).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include "core/running_moments.h"
#include "core/scene.h"
#include "renderer/environment_sampler.h"
#include "renderer/rng.h"
#include "stats/chi2.h"
#include "stats/statistics.h"

namespace furnace {
namespace {

constexpr uint64_t kSeed = 0xe4f1a9c3;  // fixed: verdicts are reproducible
constexpr size_t kSamples = 2000000;
constexpr double kFamilyAlpha = 0.01;
constexpr size_t kCorrectMaps = 4;
constexpr int kSplit = 3;  // odd: no cell edge at a texel's centre lines
// Σ pdf·Ω over the texels is 1 up to the round-off of ~H·W terms.
constexpr double kNormalisationTolerance = 1e-12;

std::shared_ptr<const LatLongMap> committed_map() {
  return load_scene(std::string(FURNACE_SCENE_DIR) + "/environment_map.json").environment.map;
}

std::shared_ptr<const LatLongMap> synthetic(int width, int height, const std::vector<double>& texels) {
  auto m = std::make_shared<LatLongMap>();
  m->width = width;
  m->height = height;
  m->texels = texels;
  return m;
}

std::shared_ptr<const LatLongMap> constant_map() { return synthetic(16, 8, std::vector<double>(16 * 8, 1.0)); }

std::shared_ptr<const LatLongMap> one_hot_map() {
  std::vector<double> t(16 * 8, 0.0);
  t[3 * 16 + 5] = 7.0;
  return synthetic(16, 8, t);
}

// Rows 0, 1 and 5 black, the rest a gradient with a bright texel.
std::shared_ptr<const LatLongMap> black_rows_map() {
  std::vector<double> t(12 * 7, 0.0);
  for (int i = 0; i < 7; ++i)
    for (int j = 0; j < 12; ++j)
      if (i != 0 && i != 1 && i != 5) t[size_t(i) * 12 + j] = 0.2 + 0.1 * i + 0.05 * j + (i == 3 && j == 4 ? 30 : 0);
  return synthetic(12, 7, t);
}

// The test's own texel geometry (written from the map convention, not the sampler's).
double cos_edge(int i, int height) { return std::cos(i * kPi / height); }

long cell_of(const LatLongMap& m, const Vec3& w) {
  const int i = m.row_of(w), j = m.column_of(w);
  double phi = std::atan2(w.y, w.x);
  if (phi < 0) phi += 2 * kPi;
  const double f_phi = phi / (2 * kPi) * m.width - j;
  const double f_cos = (cos_edge(i, m.height) - w.z) / (cos_edge(i, m.height) - cos_edge(i + 1, m.height));
  const int a = std::clamp(int(f_phi * kSplit), 0, kSplit - 1), b = std::clamp(int(f_cos * kSplit), 0, kSplit - 1);
  return ((long(i) * m.width + j) * kSplit + b) * kSplit + a;
}

struct Binned {
  std::vector<double> observed, expected;
};

Binned bin(const LatLongMap& m, const EnvironmentSampler& sampler, Defect defect, uint64_t stream) {
  const size_t cells = size_t(m.width) * m.height * kSplit * kSplit;
  Binned out{std::vector<double>(cells, 0.0), std::vector<double>(cells, 0.0)};
  for (int i = 0; i < m.height; ++i)
    for (int j = 0; j < m.width; ++j) {
      const double theta = (i + 0.5) * kPi / m.height, phi = (j + 0.5) * 2 * kPi / m.width;
      const Vec3 centre{std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
      const double cell_solid_angle =
          (2 * kPi / m.width / kSplit) * (cos_edge(i, m.height) - cos_edge(i + 1, m.height)) / kSplit;
      for (int k = 0; k < kSplit * kSplit; ++k)
        out.expected[(size_t(i) * m.width + j) * kSplit * kSplit + k] =
            double(kSamples) * sampler.pdf_solid_angle(centre) * cell_solid_angle;
    }
  for (size_t s = 0; s < kSamples; ++s) {
    Rng rng(kSeed, stream, s);
    const double u1 = rng.next_double(), u2 = rng.next_double();
    const auto e = sampler.sample(u1, u2, defect);
    if (e) out.observed[size_t(cell_of(m, e->wi_world))] += 1;
  }
  return out;
}

struct MapCase {
  std::string name;
  std::shared_ptr<const LatLongMap> (*make)();
};

void PrintTo(const MapCase& c, std::ostream* os) { *os << c.name; }

class EnvironmentSamplerChi2 : public testing::TestWithParam<MapCase> {};

TEST_P(EnvironmentSamplerChi2, FollowsItsPdf) {
  const auto map = GetParam().make();
  const EnvironmentSampler sampler(map);
  const Binned b = bin(*map, sampler, Defect::kNone, 1);
  const double alpha = stats::sidak_alpha(kFamilyAlpha, kCorrectMaps);
  const stats::Chi2Result r = stats::chi2_from_counts(b.observed, b.expected, alpha);
  std::printf("%-10s chi2 %.1f dof %d p %.4f (alpha %.2e) detectable w %.4f pooled %zu: %s\n",
              GetParam().name.c_str(), r.statistic, r.dof, r.p_value, r.alpha, r.detectable_effect, r.pooled_cells,
              r.message.c_str());
  RecordProperty("p_value", std::to_string(r.p_value));
  EXPECT_TRUE(r.pass) << r.message;
}

// ∫pdf dΩ = Σ_texels pdf·Ω_texel = 1, with Ω from the test's own geometry.
TEST_P(EnvironmentSamplerChi2, PdfIntegratesToOne) {
  const auto map = GetParam().make();
  const EnvironmentSampler sampler(map);
  double integral = 0;
  for (int i = 0; i < map->height; ++i)
    for (int j = 0; j < map->width; ++j) {
      const double theta = (i + 0.5) * kPi / map->height, phi = (j + 0.5) * 2 * kPi / map->width;
      const Vec3 centre{std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
      integral += sampler.pdf_solid_angle(centre) * (2 * kPi / map->width) *
                  (cos_edge(i, map->height) - cos_edge(i + 1, map->height));
    }
  EXPECT_NEAR(integral, 1.0, kNormalisationTolerance);
}

// Every sample carries the density pdf() gives for its direction, which is
// L_ij/Σ L·Ω of the texel it lies in (never a black one).
TEST_P(EnvironmentSamplerChi2, SampleCarriesPdfOfItsDirection) {
  const auto map = GetParam().make();
  const EnvironmentSampler sampler(map);
  double sum = 0;
  for (int i = 0; i < map->height; ++i) {
    double row = 0;
    for (int j = 0; j < map->width; ++j) row += map->texel(i, j);
    sum += row * (2 * kPi / map->width) * (cos_edge(i, map->height) - cos_edge(i + 1, map->height));
  }
  for (size_t s = 0; s < 100000; ++s) {
    Rng rng(kSeed, 2, s);
    const double u1 = rng.next_double(), u2 = rng.next_double();
    const auto e = sampler.sample(u1, u2);
    ASSERT_TRUE(e.has_value());
    EXPECT_NEAR(length(e->wi_world), 1.0, stats::kUnitLengthTolerance);
    EXPECT_EQ(e->pdf_solid_angle, sampler.pdf_solid_angle(e->wi_world));
    const double texel = map->lookup(e->wi_world);
    ASSERT_GT(texel, 0.0);
    EXPECT_NEAR(e->pdf_solid_angle, texel / sum, 1e-12 * texel / sum);
  }
}

// The mean of 1/pdf over samples estimates the measure of the support,
// Σ_{L_ij > 0} Ω_ij (the normalisation check): a z-test with the sample
// standard deviation at the same per-test level as the chi-square (for the
// constant map 1/pdf = 4π exactly and the check is exact up to round-off).
TEST_P(EnvironmentSamplerChi2, MeanInversePdfIsSupportSolidAngle) {
  const auto map = GetParam().make();
  const EnvironmentSampler sampler(map);
  double support = 0;
  for (int i = 0; i < map->height; ++i)
    for (int j = 0; j < map->width; ++j)
      if (map->texel(i, j) > 0)
        support += (2 * kPi / map->width) * (cos_edge(i, map->height) - cos_edge(i + 1, map->height));
  constexpr size_t kInversePdfSamples = 200000;
  RunningMoments inverse_pdf;
  for (size_t s = 0; s < kInversePdfSamples; ++s) {
    Rng rng(kSeed, 4, s);
    const double u1 = rng.next_double(), u2 = rng.next_double();
    const auto e = sampler.sample(u1, u2);
    ASSERT_TRUE(e.has_value());
    inverse_pdf.add(1.0 / e->pdf_solid_angle);
  }
  const double mean = inverse_pdf.mean, standard_error = inverse_pdf.mean_standard_error();
  const double alpha = stats::sidak_alpha(kFamilyAlpha, kCorrectMaps);
  const double critical = stats::normal_upper_quantile(alpha / 2);
  std::printf("%-10s mean 1/pdf %.6f support %.6f standard error %.3g\n", GetParam().name.c_str(), mean, support,
              standard_error);
  if (standard_error <= 1e-12 * support) {
    EXPECT_NEAR(mean, support, 1e-12 * support);
  }
  else EXPECT_LT(std::fabs(mean - support) / standard_error, critical);
}

INSTANTIATE_TEST_SUITE_P(Maps, EnvironmentSamplerChi2,
                         testing::Values(MapCase{"Committed", committed_map}, MapCase{"Constant", constant_map},
                                         MapCase{"OneHot", one_hot_map}, MapCase{"BlackRows", black_rows_map}),
                         [](const testing::TestParamInfo<MapCase>& info) { return info.param.name; });

// DEFECT(env_missing_sin_theta): rows chosen without the sin θ Jacobian while
// the stated pdf is unchanged must fail the test at the same per-test level.
TEST(EnvironmentSamplerChi2Control, MissingSinThetaFails) {
  for (const auto& make : {committed_map, constant_map, black_rows_map}) {
    const auto map = make();
    const EnvironmentSampler sampler(map);
    const Binned b = bin(*map, sampler, Defect::kEnvMissingSinTheta, 3);
    const stats::Chi2Result r =
        stats::chi2_from_counts(b.observed, b.expected, stats::sidak_alpha(kFamilyAlpha, kCorrectMaps));
    std::printf("env_missing_sin_theta %dx%d: chi2 %.1f dof %d p %.3g detectable w %.4f\n", map->width, map->height,
                r.statistic, r.dof, r.p_value, r.detectable_effect);
    EXPECT_FALSE(r.pass) << r.message;
  }
}

}  // namespace
}  // namespace furnace
