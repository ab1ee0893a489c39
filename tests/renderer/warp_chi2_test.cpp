// Chi-square goodness of fit of the renderer's sampling warps
// (renderer/sampling.h) against their own pdfs, and negative controls: a
// sampler tested against a wrong pdf must fail.
//
// Budget and levels: every case draws kSamples samples from a fixed named
// seed (one stream per case). The kCorrectCases.size() + kPlanarCases.size()
// correct-sampler tests share the family-wise level kFamilyAlpha by the Šidák
// correction; each negative control runs at that same per-test level. Each
// test prints its detectable effect w (Cohen's w at power kDefaultPower) and,
// for the controls, the control's own effect w computed by quadrature, which
// must exceed it: a control that fails by luck would prove nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <iostream>
#include <limits>
#include <ostream>
#include <string>

#include "core/vec3.h"
#include "renderer/rng.h"
#include "renderer/sampling.h"
#include "stats/chi2.h"

namespace furnace::stats {
namespace {

constexpr uint64_t kSeed = 0x3a49c0de;  // fixed: verdicts are reproducible
constexpr size_t kSamples = 1000000;
constexpr double kFamilyAlpha = 0.01;
constexpr int kGridK = 20;  // (2k+1)·k = 41×20 cells: ≥ 60 expected per cell for every pdf below at kSamples
// The negative controls' defects: small enough to show the test's power,
// large enough (effect w above the detectable w) that failing is certain.
constexpr double kWrongNormalisation = 1.02;  // the pdf claims 2 % too much everywhere
constexpr double kWiderCone = 1.02;           // the pdf's cone has 2 % more solid angle than the sampler's

// Check of ∫pdf = 1 over the grid. Cells cut diagonally by the support's edge
// (the triangle's hypotenuse) converge to ~1e-7 only; 1e-6 is still four
// orders below the normalisation errors the chi-square itself resolves.
constexpr double kPdfIntegralTolerance = 1e-6;

using Sampler = std::function<Vec3(double u1, double u2)>;

struct DirectionCase {
  std::string name;
  Sampler sample;
  DirectionPdf pdf;  // the pdf the samples are tested against
  SphericalGrid grid;
  DirectionPdf true_pdf = nullptr;  // controls only: the sampler's real density
};

void PrintTo(const DirectionCase& c, std::ostream* os) { *os << c.name; }

ConeAperture cone_from_angle(double theta_max) {
  const double s = std::sin(theta_max);
  return ConeAperture::from_sin2(s * s);  // keeps 1 − cos θmax exact for tiny cones
}

DirectionCase cone_case(const std::string& name, double theta_max) {
  const ConeAperture cone = cone_from_angle(theta_max);
  return {name, [cone](double u1, double u2) { return sample_uniform_cone(u1, u2, cone); },
          [cone](const Vec3& w) { return uniform_cone_pdf(w, cone); },
          SphericalGrid::cone(kGridK, cone.one_minus_cos_theta_max)};
}

DirectionCase phong_case(const std::string& name, double exponent) {
  return {name, [exponent](double u1, double u2) { return sample_phong_lobe(u1, u2, exponent); },
          [exponent](const Vec3& w) { return phong_lobe_pdf(w, exponent); }, SphericalGrid::hemisphere(kGridK)};
}

const std::vector<DirectionCase>& correct_cases() {
  static const std::vector<DirectionCase> cases = {
      {"UniformHemisphere", sample_uniform_hemisphere, uniform_hemisphere_pdf, SphericalGrid::hemisphere(kGridK)},
      {"CosineHemisphere", sample_cosine_hemisphere, cosine_hemisphere_pdf, SphericalGrid::hemisphere(kGridK)},
      {"CosineHemisphereMalley", sample_cosine_hemisphere_malley, cosine_hemisphere_pdf,
       SphericalGrid::hemisphere(kGridK)},
      {"UniformSphere", sample_uniform_sphere, uniform_sphere_pdf, SphericalGrid::sphere(kGridK)},
      // Cones: wide (θmax = 120°, beyond the hemisphere), 60°, 8°, and tiny
      // ones where 1 − cos θmax would cancel if computed naively.
      cone_case("Cone120Deg", 2 * kPi / 3),
      cone_case("Cone60Deg", kPi / 3),
      cone_case("Cone8Deg", 8 * kPi / 180),
      cone_case("ConeTheta1em3", 1e-3),
      cone_case("ConeTheta1em6", 1e-6),
      phong_case("PhongExponent1", 1),
      phong_case("PhongExponent30", 30),
  };
  return cases;
}

struct PlanarCase {
  std::string name;
  std::function<std::array<double, 2>(double u1, double u2)> sample;
  PlanarPdf pdf;
  PlanarGrid grid;
  PlanarPdf true_pdf = nullptr;
};

void PrintTo(const PlanarCase& c, std::ostream* os) { *os << c.name; }

// Disk points as q = (r², φ/2π), equal-area coordinates: dA = π·dq₀·dq₁,
// so a density in area times π is the density in q.
std::array<double, 2> to_polar(const std::array<double, 2>& p) {
  double phi = std::atan2(p[1], p[0]);
  if (phi < 0) phi += 2 * kPi;
  return {p[0] * p[0] + p[1] * p[1], std::min(phi / (2 * kPi), std::nextafter(1.0, 0.0))};
}
std::array<double, 2> from_polar(const std::array<double, 2>& q) {
  const double r = std::sqrt(q[0]), phi = 2 * kPi * q[1];
  return {r * std::cos(phi), r * std::sin(phi)};
}

const std::vector<PlanarCase>& planar_cases() {
  static const std::vector<PlanarCase> cases = {
      // The disk in polar coordinates (r², φ/2π): cell edges follow the rim.
      {"ConcentricDisk", [](double u1, double u2) { return to_polar(sample_uniform_disk_concentric(u1, u2)); },
       [](const std::array<double, 2>& q) { return kPi * uniform_disk_pdf(from_polar(q)); },
       PlanarGrid{0, 1, 0, 1, 21, 21}},
      // (b1, b2) of the barycentric sampler on the parameter triangle.
      {"TriangleBarycentric",
       [](double u1, double u2) {
         const auto b = sample_uniform_triangle_barycentric(u1, u2);
         return std::array<double, 2>{b[1], b[2]};
       },
       [](const std::array<double, 2>& p) {
         return uniform_triangle_barycentric_pdf({1 - p[0] - p[1], p[0], p[1]});
       },
       PlanarGrid{0, 1, 0, 1, 21, 21}},
  };
  return cases;
}

size_t family_size() { return correct_cases().size() + planar_cases().size(); }

template <class Out, class Sample>
std::vector<Out> draw(uint64_t stream, const Sample& sample) {
  Rng rng(kSeed, stream, 0);
  std::vector<Out> out;
  out.reserve(kSamples);
  for (size_t i = 0; i < kSamples; ++i) {
    const double u1 = rng.next_double();
    const double u2 = rng.next_double();
    out.push_back(sample(u1, u2));
  }
  return out;
}

// Stream id of a case: FNV-1a of its name (portable, unlike std::hash), so
// adding a case never changes another case's samples.
uint64_t stream_of(const std::string& name) {
  uint64_t h = 0xcbf29ce484222325ULL;
  for (unsigned char ch : name) h = (h ^ ch) * 0x100000001b3ULL;
  return h;
}

// Cohen's w of the difference between the sampler's true cell probabilities
// and the claimed ones: √(Σ (p' − p)²/p); +inf if p' > 0 where p = 0.
double effect_w(const std::vector<double>& truth, const std::vector<double>& claimed) {
  double w2 = 0;
  for (size_t i = 0; i < truth.size(); ++i) {
    if (claimed[i] == 0) {
      if (truth[i] > 0) return std::numeric_limits<double>::infinity();
      continue;
    }
    w2 += (truth[i] - claimed[i]) * (truth[i] - claimed[i]) / claimed[i];
  }
  return std::sqrt(w2);
}

void report(const Chi2Result& r) {
  std::cout << "  N = " << r.samples << ", " << r.message << " pdf integral " << r.pdf_integral
            << ", detectable effect w = " << r.detectable_effect << "\n";
  testing::Test::RecordProperty("detectable_effect_w", std::to_string(r.detectable_effect));
  testing::Test::RecordProperty("p_value", std::to_string(r.p_value));
}

std::string case_name(const testing::TestParamInfo<DirectionCase>& info) { return info.param.name; }
std::string planar_name(const testing::TestParamInfo<PlanarCase>& info) { return info.param.name; }

// --- correct samplers pass ---------------------------------------------------

class WarpChi2 : public testing::TestWithParam<DirectionCase> {};

TEST_P(WarpChi2, SamplesFollowTheirPdf) {
  const DirectionCase& c = GetParam();
  const DirectionalChi2 chi2(c.pdf, c.grid);
  const Chi2Result r = chi2.test(draw<Vec3>(stream_of(c.name), c.sample), kFamilyAlpha, family_size());
  report(r);
  EXPECT_TRUE(r.pass) << r.message;
  EXPECT_NEAR(r.pdf_integral, 1.0, kPdfIntegralTolerance) << "the pdf does not integrate to 1 over its support";
}

INSTANTIATE_TEST_SUITE_P(Warps, WarpChi2, testing::ValuesIn(correct_cases()), case_name);

class PlanarWarpChi2 : public testing::TestWithParam<PlanarCase> {};

TEST_P(PlanarWarpChi2, SamplesFollowTheirPdf) {
  const PlanarCase& c = GetParam();
  const PlanarChi2 chi2(c.pdf, c.grid);
  const Chi2Result r =
      chi2.test(draw<std::array<double, 2>>(stream_of(c.name), c.sample), kFamilyAlpha, family_size());
  report(r);
  EXPECT_TRUE(r.pass) << r.message;
  EXPECT_NEAR(r.pdf_integral, 1.0, kPdfIntegralTolerance) << "the pdf does not integrate to 1 over its support";
}

INSTANTIATE_TEST_SUITE_P(Warps, PlanarWarpChi2, testing::ValuesIn(planar_cases()), planar_name);

// --- negative controls fail --------------------------------------------------

DirectionCase wider_cone_control(const std::string& name, double theta_max) {
  const ConeAperture cone = cone_from_angle(theta_max);
  const ConeAperture wider{1 - kWiderCone * cone.one_minus_cos_theta_max, kWiderCone * cone.one_minus_cos_theta_max};
  return {name, [cone](double u1, double u2) { return sample_uniform_cone(u1, u2, cone); },
          [wider](const Vec3& w) { return uniform_cone_pdf(w, wider); },
          SphericalGrid::cone(kGridK, wider.one_minus_cos_theta_max),
          [cone](const Vec3& w) { return uniform_cone_pdf(w, cone); }};
}

const std::vector<DirectionCase>& control_cases() {
  static const std::vector<DirectionCase> cases = {
      {"CosineSamplesVsUniformPdf", sample_cosine_hemisphere, uniform_hemisphere_pdf,
       SphericalGrid::hemisphere(kGridK), cosine_hemisphere_pdf},
      {"UniformPdfWrongNormalisation", sample_uniform_hemisphere,
       [](const Vec3& w) { return kWrongNormalisation * uniform_hemisphere_pdf(w); },
       SphericalGrid::hemisphere(kGridK), uniform_hemisphere_pdf},
      {"SphereSamplesVsHemispherePdf", sample_uniform_sphere, uniform_hemisphere_pdf, SphericalGrid::sphere(kGridK),
       uniform_sphere_pdf},
      wider_cone_control("Cone30DegVsWiderPdf", kPi / 6),
      wider_cone_control("ConeTheta1em3VsWiderPdf", 1e-3),
      wider_cone_control("ConeTheta1em6VsWiderPdf", 1e-6),
  };
  return cases;
}

class WarpChi2NegativeControl : public testing::TestWithParam<DirectionCase> {};

TEST_P(WarpChi2NegativeControl, WrongPdfFails) {
  const DirectionCase& c = GetParam();
  const DirectionalChi2 chi2(c.pdf, c.grid);
  const Chi2Result r = chi2.test(draw<Vec3>(stream_of(c.name), c.sample), kFamilyAlpha, family_size());
  report(r);
  const double w = effect_w(DirectionalChi2(c.true_pdf, c.grid).cell_probabilities(), chi2.cell_probabilities());
  std::cout << "  control effect w = " << w << "\n";
  testing::Test::RecordProperty("control_effect_w", std::to_string(w));
  EXPECT_GT(w, r.detectable_effect) << "the control's defect is below the test's power: failing would be luck";
  EXPECT_FALSE(r.pass) << "a wrong pdf passed: " << r.message;
}

INSTANTIATE_TEST_SUITE_P(Warps, WarpChi2NegativeControl, testing::ValuesIn(control_cases()), case_name);

// Concentric-disk samples against the pdf of a disk of radius 1.02, in the
// polar coordinates (r², φ/2π) of the ConcentricDisk case.
TEST(PlanarWarpChi2NegativeControl, DiskSamplesVsLargerDiskPdf) {
  constexpr double kRadius = 1.02;
  const PlanarGrid grid{0, kRadius * kRadius, 0, 1, 21, 21};
  const PlanarPdf wrong = [](const std::array<double, 2>& q) { return q[0] <= kRadius * kRadius ? 1 / (kRadius * kRadius) : 0.0; };
  const PlanarPdf truth = [](const std::array<double, 2>& q) { return kPi * uniform_disk_pdf(from_polar(q)); };
  const PlanarChi2 chi2(wrong, grid);
  const Chi2Result r = chi2.test(
      draw<std::array<double, 2>>(stream_of("DiskControl"),
                                  [](double u1, double u2) { return to_polar(sample_uniform_disk_concentric(u1, u2)); }),
      kFamilyAlpha, family_size());
  report(r);
  const double w = effect_w(PlanarChi2(truth, grid).cell_probabilities(), chi2.cell_probabilities());
  std::cout << "  control effect w = " << w << "\n";
  EXPECT_GT(w, r.detectable_effect);
  EXPECT_FALSE(r.pass) << r.message;
}

// --- two samplers compared without a pdf ------------------------------------

// Malley's and the inversion cosine samplers must agree in distribution;
// kSamples each, 41×20 hemisphere cells, α = the correct cases' per-test level
// (uncounted in their family: a separate claim at the same level).
TEST(TwoSampleChi2, MalleyAndInversionCosineSamplersAgree) {
  const SphericalGrid grid = SphericalGrid::hemisphere(kGridK);
  const double alpha = sidak_alpha(kFamilyAlpha, family_size());
  const DirectionHistogram malley = direction_histogram(draw<Vec3>(stream_of("TwoSampleMalley"), sample_cosine_hemisphere_malley), grid);
  const DirectionHistogram inversion = direction_histogram(draw<Vec3>(stream_of("TwoSampleInversion"), sample_cosine_hemisphere), grid);
  EXPECT_EQ(malley.outside, 0u);
  EXPECT_EQ(inversion.outside, 0u);
  const Chi2Result r = chi2_two_sample(malley.counts, inversion.counts, alpha);
  report(r);
  EXPECT_TRUE(r.pass) << r.message;
  // Negative control: uniform hemisphere samples differ from cosine ones.
  const DirectionHistogram uniform = direction_histogram(draw<Vec3>(stream_of("TwoSampleUniform"), sample_uniform_hemisphere), grid);
  const Chi2Result control = chi2_two_sample(uniform.counts, inversion.counts, alpha);
  report(control);
  EXPECT_FALSE(control.pass) << control.message;
}

}  // namespace
}  // namespace furnace::stats
