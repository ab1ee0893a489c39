// The warps of renderer/sampling.h: inverse round trips, the pdf integrates to
// 1 by quadrature, the Jacobian of the map equals 1/pdf, the mean of g/pdf
// equals ∫g, the pdf is 0 outside the support, and Malley's map has the
// density of the inversion map. (Their chi-square tests are in warp_chi2_test.cpp.)
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "renderer/rng.h"
#include "renderer/sampling.h"
#include "test_support.h"

namespace furnace {
namespace {


constexpr uint64_t kSeed = 0x5a3b1e;       // fixed: deterministic outcomes
constexpr int kMonteCarloSamples = 1 << 16;
constexpr int kGrid = 23;
// Shift of u2 in derivative tests: keeps grid points off the concentric map's
// kinks (u1 = u2, u1 + u2 = 1, where its Jacobian is continuous but not smooth).
constexpr double kOffDiagonal = 0.3 / kGrid;
// Round trip: a few ulps of the trigonometric/sqrt chain, relative to u ∈ [0,1).
constexpr double kRoundTripTol = 1e-9;
// Quadrature of a smooth density to 1: GK61 reaches ~1e-13; allow 1e-9.
constexpr double kQuadratureTol = 1e-9;
// Central differences with step kStep: truncation O(h²) ≈ 1e-12 and
// cancellation ε/h ≈ 1e-10 relative; 1e-6 leaves room for the lobes' curvature.
constexpr double kStep = 1e-6;
constexpr double kJacobianRelTol = 1e-6;

struct DirectionalWarp {
  std::string name;
  std::function<Vec3(double, double)> sample;
  std::function<double(const Vec3&)> pdf;
  std::function<std::optional<std::array<double, 2>>(const Vec3&)> invert;
  double t_max;  // support: t = 1 − cos θ ∈ [0, t_max]
  std::function<double(const Vec3&)> g;  // test function with finite-variance g/pdf
  double g_integral;                     // ∫ g dω over the support
};

ConeAperture cone_of(double theta_max) {
  const double s = std::sin(theta_max);
  return theta_max <= kPi / 2 ? ConeAperture::from_sin2(s * s) : ConeAperture::from_cos(std::cos(theta_max));
}

DirectionalWarp cone_warp(const std::string& name, double theta_max) {
  const ConeAperture cone = cone_of(theta_max);
  return {name,
          [cone](double u1, double u2) { return sample_uniform_cone(u1, u2, cone); },
          [cone](const Vec3& w) { return uniform_cone_pdf(w, cone); },
          [cone](const Vec3& w) { return invert_uniform_cone(w, cone); },
          cone.one_minus_cos_theta_max,
          [](const Vec3&) { return 1.0; },
          kTwoPi * cone.one_minus_cos_theta_max};
}

DirectionalWarp phong_warp(const std::string& name, double n) {
  return {name,
          [n](double u1, double u2) { return sample_phong_lobe(u1, u2, n); },
          [n](const Vec3& w) { return phong_lobe_pdf(w, n); },
          [n](const Vec3& w) { return invert_phong_lobe(w, n); },
          1.0,
          [n](const Vec3& w) { return std::pow(w.z, n + 1); },
          kTwoPi / (n + 2)};
}

std::vector<DirectionalWarp> directional_warps() {
  return {
      {"UniformHemisphere", sample_uniform_hemisphere, uniform_hemisphere_pdf, invert_uniform_hemisphere, 1.0,
       [](const Vec3& w) { return w.z; }, kPi},
      {"CosineHemisphere", sample_cosine_hemisphere, cosine_hemisphere_pdf, invert_cosine_hemisphere, 1.0,
       [](const Vec3& w) { return w.z * w.z; }, kTwoPi / 3},
      {"CosineHemisphereMalley", sample_cosine_hemisphere_malley, cosine_hemisphere_pdf,
       invert_cosine_hemisphere_malley, 1.0, [](const Vec3& w) { return w.z * w.z; }, kTwoPi / 3},
      {"UniformSphere", sample_uniform_sphere, uniform_sphere_pdf, invert_uniform_sphere, 2.0,
       [](const Vec3& w) { return w.z * w.z; }, 4 * kPi / 3},
      cone_warp("Cone120Deg", 2 * kPi / 3),
      cone_warp("Cone60Deg", kPi / 3),
      cone_warp("Cone1Deg", kPi / 180),
      cone_warp("ConeTheta1em4", 1e-4),
      cone_warp("ConeTheta1em7", 1e-7),
      phong_warp("PhongLobe1", 1),
      phong_warp("PhongLobe20", 20),
      phong_warp("PhongLobe500", 500),
  };
}

void PrintTo(const DirectionalWarp& w, std::ostream* os) { *os << w.name; }

class DirectionalWarpTest : public testing::TestWithParam<DirectionalWarp> {};

double grid_u(int i) { return (i + 0.5) / kGrid; }

TEST_P(DirectionalWarpTest, InverseRoundTrip) {
  const DirectionalWarp& w = GetParam();
  for (int i = 0; i < kGrid; ++i)
    for (int j = 0; j < kGrid; ++j) {
      const double u1 = grid_u(i), u2 = grid_u(j);
      const auto u = w.invert(w.sample(u1, u2));
      ASSERT_TRUE(u.has_value()) << u1 << ", " << u2;
      EXPECT_NEAR((*u)[0], u1, kRoundTripTol) << u1 << ", " << u2;
      EXPECT_NEAR((*u)[1], u2, kRoundTripTol) << u1 << ", " << u2;
    }
}

TEST_P(DirectionalWarpTest, SamplesAreUnitAndInsideSupport) {
  const DirectionalWarp& w = GetParam();
  for (int i = 0; i < kGrid; ++i)
    for (int j = 0; j < kGrid; ++j) {
      const Vec3 d = w.sample(grid_u(i), grid_u(j));
      EXPECT_NEAR(length(d), 1.0, 1e-14);
      EXPECT_GT(w.pdf(d), 0.0);
    }
  // The corners of [0,1)² too (u = 0 and the largest double below 1): unit
  // and finite, the pdf finite (it may be 0 where a corner maps onto the
  // support's boundary, e.g. Malley's corners onto the horizon).
  const double top = std::nextafter(1.0, 0.0);
  for (double u1 : {0.0, top})
    for (double u2 : {0.0, top}) {
      const Vec3 d = w.sample(u1, u2);
      EXPECT_NEAR(length(d), 1.0, 1e-14) << u1 << ", " << u2;
      EXPECT_TRUE(std::isfinite(w.pdf(d))) << u1 << ", " << u2;
    }
}

TEST_P(DirectionalWarpTest, PdfIntegratesToOne) {
  const DirectionalWarp& w = GetParam();
  const double total = testing_support::integrate_directions(w.pdf, 0.0, w.t_max);
  EXPECT_NEAR(total, 1.0, kQuadratureTol);
}

TEST_P(DirectionalWarpTest, PdfIsZeroOutsideSupport) {
  const DirectionalWarp& w = GetParam();
  if (w.t_max >= 2.0) GTEST_SKIP() << "the support is the whole sphere";
  // Directions strictly outside: t from just beyond t_max (1 % of the gap to 2) up to the pole.
  for (double f : {0.01, 0.3, 0.7, 1.0}) {
    const double t = w.t_max + f * (2.0 - w.t_max);
    const double s = std::sqrt(std::fmax(0.0, t * (2.0 - t)));
    for (double phi : {0.1, 2.0, 4.5}) {
      const Vec3 d{s * std::cos(phi), s * std::sin(phi), 1.0 - t};
      EXPECT_EQ(w.pdf(d), 0.0) << "t = " << t;
      EXPECT_FALSE(w.invert(d).has_value()) << "t = " << t;
    }
  }
}

TEST_P(DirectionalWarpTest, JacobianEqualsInversePdf) {
  const DirectionalWarp& w = GetParam();
  for (int i = 1; i < kGrid - 1; ++i)
    for (int j = 1; j < kGrid - 1; ++j) {
      const double u1 = grid_u(i), u2 = grid_u(j) + kOffDiagonal;
      const Vec3 d1 = (w.sample(u1 + kStep, u2) - w.sample(u1 - kStep, u2)) / (2 * kStep);
      const Vec3 d2 = (w.sample(u1, u2 + kStep) - w.sample(u1, u2 - kStep)) / (2 * kStep);
      const double jacobian = length(cross(d1, d2));  // dω = |∂ω/∂u1 × ∂ω/∂u2| du1 du2
      const double inverse_pdf = 1.0 / w.pdf(w.sample(u1, u2));
      EXPECT_NEAR(jacobian / inverse_pdf, 1.0, kJacobianRelTol) << u1 << ", " << u2;
    }
}

TEST_P(DirectionalWarpTest, MeanOfTestFunctionOverPdfEqualsIntegral) {
  const DirectionalWarp& w = GetParam();
  RunningMoments stats;
  for (int i = 0; i < kMonteCarloSamples; ++i) {
    Rng rng(kSeed, 0, uint64_t(i));
    const double u1 = rng.next_double(), u2 = rng.next_double();
    const Vec3 d = w.sample(u1, u2);
    stats.add(w.g(d) / w.pdf(d));
  }
  EXPECT_TRUE(testing_support::mean_consistent(stats, w.g_integral))
      << "mean " << stats.mean << " ± " << stats.mean_standard_error() << ", expected " << w.g_integral;
}

INSTANTIATE_TEST_SUITE_P(Warps, DirectionalWarpTest, testing::ValuesIn(directional_warps()),
                         [](const testing::TestParamInfo<DirectionalWarp>& info) { return info.param.name; });

TEST(CosineHemisphere, MalleyAndInversionHaveTheSameMoments) {
  // E[z], E[z²] and E[x²] under cos θ/π are 2/3, 1/2 and 1/4; both maps must agree with them.
  struct Moment {
    std::function<double(const Vec3&)> f;
    double expected;
  };
  const Moment moments[] = {{[](const Vec3& w) { return w.z; }, 2.0 / 3},
                            {[](const Vec3& w) { return w.z * w.z; }, 0.5},
                            {[](const Vec3& w) { return w.x * w.x; }, 0.25}};
  for (const auto& sampler : {sample_cosine_hemisphere, sample_cosine_hemisphere_malley}) {
    for (const Moment& m : moments) {
      RunningMoments stats;
      for (int i = 0; i < kMonteCarloSamples; ++i) {
        Rng rng(kSeed, 1, uint64_t(i));
        const double u1 = rng.next_double(), u2 = rng.next_double();
        stats.add(m.f(sampler(u1, u2)));
      }
      EXPECT_TRUE(testing_support::mean_consistent(stats, m.expected)) << stats.mean << " vs " << m.expected;
    }
  }
}

TEST(CosineHemisphere, MalleyJacobianMatchesInversionDensity) {
  // Same density: at every grid point the Malley map's Jacobian is π/cos θ.
  for (int i = 1; i < kGrid - 1; ++i)
    for (int j = 1; j < kGrid - 1; ++j) {
      const double u1 = grid_u(i), u2 = grid_u(j) + kOffDiagonal;
      const Vec3 d1 = (sample_cosine_hemisphere_malley(u1 + kStep, u2) - sample_cosine_hemisphere_malley(u1 - kStep, u2)) /
                      (2 * kStep);
      const Vec3 d2 = (sample_cosine_hemisphere_malley(u1, u2 + kStep) - sample_cosine_hemisphere_malley(u1, u2 - kStep)) /
                      (2 * kStep);
      const Vec3 w = sample_cosine_hemisphere_malley(u1, u2);
      EXPECT_NEAR(length(cross(d1, d2)) * cosine_hemisphere_pdf(w), 1.0, kJacobianRelTol);
    }
}

TEST(UniformCone, TinyConeKeepsFullPrecision) {
  // θmax = 1e-7: 1 − cos θmax = 5e-15 would keep one digit if computed as 1 − cos.
  const double theta = 1e-7;
  const ConeAperture cone = ConeAperture::from_sin2(std::sin(theta) * std::sin(theta));
  const double exact = 2 * std::sin(theta / 2) * std::sin(theta / 2);  // 1 − cos θ = 2 sin²(θ/2)
  EXPECT_NEAR(cone.one_minus_cos_theta_max / exact, 1.0, 1e-14);
  const Vec3 rim = sample_uniform_cone(std::nextafter(1.0, 0.0), 0.3, cone);
  EXPECT_NEAR(angle_between(rim, {0, 0, 1}) / theta, 1.0, 1e-9);
  EXPECT_GT(uniform_cone_pdf(rim, cone), 0.0);
}

// Planar warps: the concentric disk and barycentric triangle.
TEST(ConcentricDisk, InverseRoundTripAndJacobian) {
  for (int i = 0; i < kGrid; ++i)
    for (int j = 0; j < kGrid; ++j) {
      const double u1 = grid_u(i), u2 = grid_u(j);
      const auto p = sample_uniform_disk_concentric(u1, u2);
      EXPECT_GT(uniform_disk_pdf(p), 0.0);
      const auto u = invert_uniform_disk_concentric(p);
      ASSERT_TRUE(u.has_value());
      EXPECT_NEAR((*u)[0], u1, kRoundTripTol);
      EXPECT_NEAR((*u)[1], u2, kRoundTripTol);
      if (i == 0 || j == 0 || i == kGrid - 1 || j == kGrid - 1) continue;
      const double v2 = u2 + kOffDiagonal;
      const auto a = sample_uniform_disk_concentric(u1 + kStep, v2), b = sample_uniform_disk_concentric(u1 - kStep, v2);
      const auto c = sample_uniform_disk_concentric(u1, v2 + kStep), d = sample_uniform_disk_concentric(u1, v2 - kStep);
      const double jacobian = ((a[0] - b[0]) * (c[1] - d[1]) - (a[1] - b[1]) * (c[0] - d[0])) / (4 * kStep * kStep);
      EXPECT_NEAR(std::fabs(jacobian) * uniform_disk_pdf(sample_uniform_disk_concentric(u1, v2)), 1.0, kJacobianRelTol);
    }
  EXPECT_FALSE(invert_uniform_disk_concentric({0.8, 0.8}).has_value());
  EXPECT_EQ(uniform_disk_pdf({0.8, 0.8}), 0.0);
}

TEST(TriangleBarycentric, InverseRoundTripAndJacobian) {
  for (int i = 0; i < kGrid; ++i)
    for (int j = 0; j < kGrid; ++j) {
      const double u1 = grid_u(i), u2 = grid_u(j);
      const auto b = sample_uniform_triangle_barycentric(u1, u2);
      EXPECT_NEAR(b[0] + b[1] + b[2], 1.0, 1e-15);
      EXPECT_GT(uniform_triangle_barycentric_pdf(b), 0.0);
      const auto u = invert_uniform_triangle_barycentric(b);
      ASSERT_TRUE(u.has_value());
      EXPECT_NEAR((*u)[0], u1, kRoundTripTol);
      EXPECT_NEAR((*u)[1], u2, kRoundTripTol);
      if (i == 0 || j == 0 || i == kGrid - 1 || j == kGrid - 1) continue;
      const auto a = sample_uniform_triangle_barycentric(u1 + kStep, u2);
      const auto bb = sample_uniform_triangle_barycentric(u1 - kStep, u2);
      const auto c = sample_uniform_triangle_barycentric(u1, u2 + kStep);
      const auto d = sample_uniform_triangle_barycentric(u1, u2 - kStep);
      // Jacobian of (b1, b2) with respect to (u1, u2).
      const double jacobian = ((a[1] - bb[1]) * (c[2] - d[2]) - (a[2] - bb[2]) * (c[1] - d[1])) / (4 * kStep * kStep);
      EXPECT_NEAR(std::fabs(jacobian) * uniform_triangle_barycentric_pdf(b), 1.0, kJacobianRelTol);
    }
  EXPECT_EQ(uniform_triangle_barycentric_pdf({-0.1, 0.6, 0.5}), 0.0);
}

// The polynomial sin/cos behind every φ = 2π·u and the concentric map,
// against long double (64-bit mantissa) references, over the whole unit
// interval: 2^16 draws plus every multiple of 1/64 and its neighbours (the
// quarter-turn seams of the reduction lie at odd multiples of 1/8).
constexpr double kSinCosAbsTol = 4e-16;  // ~2 ulp at 1; glibc's sincos is within ~0.5 ulp
TEST(SinCos, TwoPiUMatchesLongDoubleReferences) {
  const long double two_pi = 6.283185307179586476925286766559L;
  std::vector<double> us;
  Rng rng(kSeed, 0, 0);
  for (int i = 0; i < kMonteCarloSamples; ++i) us.push_back(rng.next_double());
  for (int k = 0; k <= 64; ++k) {
    const double u = k / 64.0;
    us.insert(us.end(), {u, std::nextafter(u, 0.0), std::nextafter(u, 1.0)});
  }
  double worst = 0;
  for (double u : us) {
    if (!(u >= 0 && u <= 1)) continue;
    const auto sc = sampling_detail::sin_cos_two_pi(u);
    const long double phi = two_pi * (long double)u;
    const double e = std::fmax(std::fabs(double(sc.sin - sinl(phi))), std::fabs(double(sc.cos - cosl(phi))));
    worst = std::fmax(worst, e);
    ASSERT_LE(e, kSinCosAbsTol) << "u = " << u;
  }
  std::printf("sin_cos_two_pi: %zu values, worst absolute error %.3g (bound %.3g)\n", us.size(), worst, kSinCosAbsTol);
}

TEST(SinCos, QuarterTurnHasSmallRelativeErrorAndTheBoundCatchesOneTermLess) {
  const double quarter = kPiOver4;
  double worst_sin = 0, worst_cos = 0;
  for (int i = -4000; i <= 4000; ++i) {
    const double x = quarter * i / 4000.0;
    const auto sc = sampling_detail::sin_cos_quarter(x);
    if (x != 0) worst_sin = std::fmax(worst_sin, std::fabs(double((sc.sin - sinl(x)) / sinl(x))));
    worst_cos = std::fmax(worst_cos, std::fabs(double(sc.cos - cosl(x))));
  }
  for (double tiny : {1e-300, 1e-20, 1e-8}) EXPECT_EQ(sampling_detail::sin_cos_quarter(tiny).sin, tiny);
  EXPECT_EQ(sampling_detail::sin_cos_quarter(0.0).cos, 1.0);
  EXPECT_LE(worst_sin, kSinCosAbsTol) << "relative error of sin";
  EXPECT_LE(worst_cos, kSinCosAbsTol);
  // Power: a polynomial one term shorter (sin to x^13) is off by x^15/15! ~ 2e-14 at π/4, far beyond the bound.
  const double z = quarter * quarter;
  double term = quarter, shorter = 0;
  for (int n = 1; n <= 13; n += 2) {
    shorter += term;
    term *= -z / double((n + 1) * (n + 2));
  }
  EXPECT_GT(std::fabs(double(shorter - sinl(quarter))), 10 * kSinCosAbsTol);
  std::printf("sin_cos_quarter: worst relative error of sin %.3g, absolute of cos %.3g\n", worst_sin, worst_cos);
}

TEST(Rng, PixelKeyStreamsAreTheTripleStreams) {
  // render() hashes a pixel's key once and derives each sample's stream from
  // it: the draws must be those of Rng(seed, pixel, sample).
  for (uint64_t seed : {uint64_t(0), uint64_t(7), uint64_t(20261125), ~uint64_t(0)})
    for (uint64_t pixel : {uint64_t(0), uint64_t(1), uint64_t(1023), uint64_t(1) << 40})
      for (uint64_t sample : {uint64_t(0), uint64_t(1), uint64_t(4095)}) {
        Rng triple(seed, pixel, sample);
        Rng keyed = Rng::for_sample(Rng::pixel_key(seed, pixel), sample);
        for (int k = 0; k < 8; ++k) ASSERT_EQ(triple.next_u64(), keyed.next_u64()) << seed << " " << pixel << " " << sample;
      }
  EXPECT_NE(Rng::for_sample(Rng::pixel_key(7, 3), 0).next_u64(), Rng::for_sample(Rng::pixel_key(7, 4), 0).next_u64());
}

}  // namespace
}  // namespace furnace
