// The lat-long environment map references (analytic/environment_map.h)
// against an independent brute-force quadrature over the sphere, texel by
// texel in (θ, φ) with the integrand max(n·ω, 0)^p·sin θ written from the
// definition (no closed form; the horizon kinks located numerically by TOMS
// 748 root finding, not by the reference's formulas), for vertical, tilted, grazing and
// texel-edge-aligned normals; plus the exact limits: a constant map gives π·L
// (and 2π/3·L² for the cos² kernel) at every normal, like the constant
// environment, and texels wholly below the horizon give exactly 0.
#include "analytic/environment_map.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <ostream>
#include <string>
#include <vector>

#include <boost/math/tools/toms748_solve.hpp>
#include <gtest/gtest.h>

#include "analytic/environment.h"
#include "analytic/moments.h"
#include "analytic/reference.h"
#include "core/adaptive_quadrature.h"
#include "core/error.h"

namespace furnace::analytic {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();
// Brute force: nested bisecting Gauss–Kronrod, the outer integral to this
// tolerance times the texel's solid angle (the inner 100× tighter).
constexpr double kBruteTolerance = 1e-12;
// Agreement required between reference and brute force, relative to the sum.
// 1e-11: an order above the brute force's own tolerance (1e-12 of each
// texel's solid angle) summed over the texels; far below anything a wrong
// kernel gives. Measured agreement is ≤ 7e-16 (printed per case).
constexpr double kAgreement = 1e-11;
// Sums of H·W closed-form terms against a constant-map identity: each term
// carries a few ulps; 4·texels·ε bounds the accumulated round-off.
double identity_tolerance(const LatLongMap& m) { return 4.0 * m.width * m.height * kEps; }

double cosine_at(const Vec3& n, double theta, double phi) {
  return n.x * std::sin(theta) * std::cos(phi) + n.y * std::sin(theta) * std::sin(phi) + n.z * std::cos(theta);
}

// Zeros of f on [a, b]: sign changes bracketed on a grid of kBracketSteps
// cells, refined by TOMS 748 to full precision. A cell whose two sign
// changes both fall inside it would be missed: with 64 cells of a texel
// spanning ≤ 2π/7 that needs a zero pair closer than 0.7°, i.e. a horizon
// tangency, where the missed kink is itself of measure ~0.
constexpr int kBracketSteps = 64;
template <class F>
std::vector<double> zeros(const F& f, double a, double b) {
  std::vector<double> out;
  double x0 = a, f0 = f(a);
  for (int k = 1; k <= kBracketSteps; ++k) {
    const double x1 = a + (b - a) * k / kBracketSteps, f1 = f(x1);
    if ((f0 < 0) != (f1 < 0) && f0 != 0 && f1 != 0) {
      boost::uintmax_t iterations = 200;
      const auto root = boost::math::tools::toms748_solve(f, x0, x1, f0, f1,
                                                           boost::math::tools::eps_tolerance<double>(), iterations);
      out.push_back((root.first + root.second) / 2);
    }
    x0 = x1, f0 = f1;
  }
  return out;
}

// Splits [a, b] at the given interior points and sums core/adaptive_quadrature.h over the pieces.
template <class F>
double split_quadrature(const F& f, double a, double b, std::vector<double> cuts, double abs_tolerance) {
  cuts.push_back(a);
  cuts.push_back(b);
  std::sort(cuts.begin(), cuts.end());
  double sum = 0;
  for (size_t k = 0; k + 1 < cuts.size(); ++k)
    if (cuts[k + 1] > cuts[k]) sum += adaptive_gauss_kronrod(f, cuts[k], cuts[k + 1], abs_tolerance, 60);
  return sum;
}

// ∫_texel max(n·ω, 0)^power dω from the definition, nested in (φ, θ); the
// horizon kinks (zeros of n·ω along θ, and along φ on the row edges) are
// found numerically and split at, so every piece is smooth.
double brute_texel(int i, int j, int width, int height, const Vec3& n, int power) {
  const double t0 = i * kPi / height, t1 = (i + 1) * kPi / height;
  const double p0 = j * 2 * kPi / width, p1 = (j + 1) * 2 * kPi / width;
  const double omega = (p1 - p0) * (std::cos(t0) - std::cos(t1));
  auto inner = [&](double phi) {
    auto f = [&](double theta) { return std::pow(std::fmax(cosine_at(n, theta, phi), 0.0), power) * std::sin(theta); };
    const auto kinks = zeros([&](double theta) { return cosine_at(n, theta, phi); }, t0, t1);
    return split_quadrature(f, t0, t1, kinks, kBruteTolerance * 1e-2 * omega / (p1 - p0));
  };
  std::vector<double> outer_kinks;
  for (double theta : {t0, t1})
    for (double phi : zeros([&](double x) { return cosine_at(n, theta, x); }, p0, p1)) outer_kinks.push_back(phi);
  return split_quadrature(inner, p0, p1, outer_kinks, kBruteTolerance * omega);
}

double brute_map(const LatLongMap& m, const Vec3& n, int cos_power, int value_power) {
  double sum = 0;
  for (int i = 0; i < m.height; ++i)
    for (int j = 0; j < m.width; ++j) {
      const double l = m.texel(i, j);
      if (l != 0) sum += std::pow(l, value_power) * brute_texel(i, j, m.width, m.height, n, cos_power);
    }
  return sum;
}

// Deterministic pseudo-random texels in [0.05, 2) with a few black ones.
LatLongMap synthetic_map(int width, int height) {
  LatLongMap m;
  m.width = width;
  m.height = height;
  uint64_t state = 0x9e3779b97f4a7c15ull;  // fixed seed
  for (int t = 0; t < width * height; ++t) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    const double u = double(state >> 11) * 0x1.0p-53;
    m.texels.push_back(u < 0.1 ? 0.0 : 0.05 + 1.95 * u);
  }
  return m;
}

LatLongMap constant_map(int width, int height, double value) {
  LatLongMap m;
  m.width = width;
  m.height = height;
  m.texels.assign(size_t(width) * height, value);
  return m;
}

struct NormalCase {
  std::string name;
  Vec3 n;
};

void PrintTo(const NormalCase& c, std::ostream* os) { *os << c.name; }

std::vector<NormalCase> normals() {
  const double grazing = 89.9 * kPi / 180;
  return {
      {"Up", {0, 0, 1}},
      {"Down", {0, 0, -1}},
      {"AlongX", {1, 0, 0}},                 // horizon along column edges φ = π/2, 3π/2
      {"AlongY", {0, 1, 0}},
      {"Tilted30", normalize(Vec3(std::sin(0.5236), 0.2, std::cos(0.5236)))},
      {"Tilted", normalize(Vec3(-2, -0.3, 4))},  // the environment_map_tilted receiver
      {"Steep", normalize(Vec3(0.7, -0.6, -0.3))},
      {"Grazing", {std::sin(grazing), 0, std::cos(grazing)}},
      {"GrazingSkew", normalize(Vec3(std::sin(grazing) * 0.6, std::sin(grazing) * 0.8, std::cos(grazing)))},
  };
}

class MapKernels : public testing::TestWithParam<NormalCase> {};

TEST_P(MapKernels, MatchBruteForceOnSyntheticMap) {
  const LatLongMap m = synthetic_map(12, 7);  // odd height: the equator cuts a row
  const Vec3 n = GetParam().n;
  for (int power : {1, 2})
    for (int value_power : {1, 2}) {
      const double exact = map_cosine_integral(m, n, power, value_power);
      const double brute = brute_map(m, n, power, value_power);
      EXPECT_NEAR(exact, brute, kAgreement * brute) << "cos^" << power << " L^" << value_power;
      RecordProperty("rel_error_cos" + std::to_string(power) + "_L" + std::to_string(value_power),
                     std::to_string(std::fabs(exact - brute) / brute));
      std::printf("%-12s cos^%d L^%d  exact %.15g  brute %.15g  rel %.2e\n", GetParam().name.c_str(), power,
                  value_power, exact, brute, std::fabs(exact - brute) / brute);
    }
}

TEST_P(MapKernels, ConstantMapIsTheConstantEnvironment) {
  const Vec3 n = GetParam().n;
  for (const LatLongMap& m : {constant_map(64, 32, 1.0), constant_map(9, 5, 1.0)}) {
    EXPECT_NEAR(map_irradiance(m, n), kPi, identity_tolerance(m) * kPi);
    EXPECT_NEAR(map_cosine_integral(m, n, 2, 1), 2 * kPi / 3, identity_tolerance(m) * 2 * kPi / 3);
  }
}

INSTANTIATE_TEST_SUITE_P(Normals, MapKernels, testing::ValuesIn(normals()),
                         [](const testing::TestParamInfo<NormalCase>& info) { return info.param.name; });

TEST(MapKernels, CommittedMapMatchesBruteForce) {
  const Scene scene = load_scene(std::string(FURNACE_SCENE_DIR) + "/environment_map.json");
  const LatLongMap& m = *scene.environment.map;
  for (const Vec3& n : {Vec3(0, 0, 1), normalize(Vec3(-2, -0.3, 4))}) {
    const double exact = map_irradiance(m, n), brute = brute_map(m, n, 1, 1);
    std::printf("committed map n=(%g,%g,%g): exact %.15g brute %.15g rel %.2e\n", n.x, n.y, n.z, exact, brute,
                std::fabs(exact - brute) / brute);
    EXPECT_NEAR(exact, brute, kAgreement * brute);
  }
}

TEST(MapKernels, TexelsWhollyBelowTheHorizonGiveZero) {
  // Light only on the upper hemisphere (even height: the equator is a row edge).
  LatLongMap m = constant_map(16, 8, 0.0);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 16; ++j) m.texels[size_t(i) * 16 + j] = 1.0 + i + 0.1 * j;
  for (int power : {1, 2}) {
    EXPECT_EQ(map_cosine_integral(m, {0, 0, -1}, power, 1), 0.0);
    for (int i = 0; i < 8; ++i)
      for (int j = 0; j < 16; ++j) {
        EXPECT_EQ(texel_cosine_integral(i, j, 16, 8, {0, 0, -1}, power) == 0.0, i < 4) << i << "," << j;
        EXPECT_EQ(texel_cosine_integral(i, j, 16, 8, {0, 0, 1}, power) == 0.0, i >= 4) << i << "," << j;
      }
  }
  // Horizontal normal −x: the texels of φ ∈ [0, π/8] (x > 0) face away from it.
  for (int i = 0; i < 8; ++i) EXPECT_EQ(texel_cosine_integral(i, 0, 16, 8, {-1, 0, 0}, 1), 0.0) << i;
}

TEST(MapKernels, SolidAnglesSumToTheSphere) {
  const LatLongMap m = constant_map(64, 32, 1.0);
  EXPECT_NEAR(map_solid_angle_integral(m), 4 * kPi, identity_tolerance(m) * 4 * kPi);
}

// Scene level: the reference adds the map's irradiance; blockers are refused.
TEST(EnvironmentMapScene, IrradianceIsRadianceTimesMapIntegral) {
  const Scene scene = load_scene(std::string(FURNACE_SCENE_DIR) + "/environment_map.json");
  const double e = environment_irradiance(scene, {0.3, -0.2, 0}, {0, 0, 1}, 0);
  EXPECT_EQ(e, scene.environment.radiance * map_irradiance(*scene.environment.map, {0, 0, 1}));
  EXPECT_GT(e, 0);
}

TEST(EnvironmentMapScene, RefusesBlockers) {
  Scene scene = load_scene(std::string(FURNACE_SCENE_DIR) + "/environment_map.json");
  scene.objects.push_back({"blocker", Disk{{0, 0, 1}, {0, 0, 1}, 0.3}, {}, 0});
  try {
    environment_irradiance(scene, {0, 0, 0}, {0, 0, 1}, 0);
    FAIL() << "a map blocked by a disk was accepted";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("environment_map"), std::string::npos) << msg;
    EXPECT_NE(msg.find("'blocker'"), std::string::npos) << msg;
  }
  EXPECT_THROW(reference_image(scene), Error);
  EXPECT_THROW(second_moment(Strategy::kLightArea, scene, {0, 0, 0}, {0, 0, 1}, 0), Error);
}

// The moments are the kernels scaled as environment_map.h states; the
// light-sampling moment of a constant map is that of any importance sampler
// of a constant sphere: Y = K·R·4π·cos₊, E[Y²] = K·R²·4π·2π/3.
TEST(EnvironmentMapScene, ConstantMapMomentsAreTheConstantEnvironments) {
  Environment env;
  env.radiance = 1.5;
  env.map = std::make_shared<const LatLongMap>(constant_map(32, 16, 1.0));
  const Vec3 n = normalize(Vec3(0.3, 0.1, 1));
  const double tol = identity_tolerance(*env.map);
  EXPECT_NEAR(map_cosine_moment(env, n), kPi * 1.5 * 1.5 * kPi, tol * 30);
  EXPECT_NEAR(map_uniform_hemisphere_moment(env, n), 2 * kPi * 1.5 * 1.5 * 2 * kPi / 3, tol * 30);
  EXPECT_NEAR(map_light_sampling_moment(env, n, 2), 2 * 1.5 * 1.5 * 4 * kPi * 2 * kPi / 3, tol * 100);
}

}  // namespace
}  // namespace furnace::analytic
