// GGX sampling by hypothesis tests (GgxBsdf, renderer/bsdf.h):
//  - chi-square goodness of fit of the visible-normal sampler against
//    visible_normal_pdf(), and of sample()'s reflected directions against
//    pdf(), on α ∈ {0.01, 0.05, 0.2, 0.5, 1} × θo ∈ {0°, 30°, 60°, 80°, 85°};
//  - at α = 1 the fraction of sample()s that succeed (reflected above the
//    horizon) is exactly 1/(1 + cos θo): a binomial z-test.
// Negative controls: the defects that change what is sampled or claimed
// (ggx_sample_alpha_squared, ggx_vndf_pdf_without_g1, ggx_lambda_other_alpha,
// ggx_d_without_inv_pi) must be rejected at the same per-test level; a
// sampler of roughness 0.9 must fail the α = 1 binomial test.
//
// Cells: both tests bin a normal, the drawn m or the half vector
// h = normalize(wo + wi) of a reflected direction (a bijection between wi
// above the horizon and h with wo·h > 0, dωi = 4(wo·h) dωh). Rows are equal
// steps of v = tan²θ/(α² + tan²θ), the marginal of D(m) cos θm (equal mass
// for the normal distribution, so the peak of width α is resolved at every
// α); kColumns odd equal steps of φ. Expected counts are N·∫cell pdf dω by
// nested adaptive Gauss–Kronrod (core/adaptive_quadrature.h, to the
// tolerances of stats/chi2.h and for the reasons given there) in (θ, φ), the
// φ range of each ring cut exactly where the density's support ends
// (wo·m = 0; for reflection also wi_z = 0), so every integrand is smooth.
// Failed samples form one more bin of expected N·(1 − ∫pdf).
//
// Budget: kSamples per case from a fixed named seed (one stream per case),
// kFamilyAlpha over the 2 × 25 correct tests by Šidák; the controls run at
// that per-test level.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <string>
#include <utility>
#include <vector>

#include "core/adaptive_quadrature.h"
#include "renderer/bsdf.h"
#include "renderer/rng.h"
#include "stats/chi2.h"
#include "tests/renderer/ggx_normal_grid.h"
#include "stats/statistics.h"

namespace furnace::stats {
namespace {

constexpr uint64_t kSeed = 0x66c7c412;
constexpr size_t kSamples = 1000000;
constexpr double kFamilyAlpha = 0.01;
constexpr int kRows = kGgxGridRows;
constexpr int kColumns = kGgxGridColumns;

// The sum of 421 cell integrals, each to kQuadratureRelTolerance (1e-8) by
// its error estimate: 1.5e-8 measured at α = 0.01, θo = 85°; 1e-7 bounds it.
constexpr double kPdfIntegralTol = 1e-7;

const std::vector<double> kAlphas{0.01, 0.05, 0.2, 0.5, 1.0};
const std::vector<double> kViewsDeg{0, 30, 60, 80, 85};
constexpr size_t kTestsPerCase = 2;  // normals and reflected directions
size_t family_size() { return kTestsPerCase * kAlphas.size() * kViewsDeg.size(); }

Vec3 wo_at(double theta_deg) {
  const double t = theta_deg * kPi / 180;
  return {std::sin(t), 0, std::cos(t)};
}

// What is binned: a drawn visible normal, or the half vector of a reflected direction.
enum class Binned { kNormal, kReflected };


// The density is positive only where cos φ > K(θ) on the ring of normals at
// θ (wo = (sin θo, 0, cos θo)):
//  - wo·m > 0:  sin θo sin θ cos φ > −cos θo cos θ;
//  - wi_z > 0 with wi = 2(wo·h)h − wo:  sin θo sin 2θ cos φ > −cos θo cos 2θ.
double cut(double a, double b) {  // cos φ > K where a·cos φ > b
  if (a > 0) return b / a;
  return b < 0 ? -2.0 : 2.0;  // every φ, or none
}
double support_cut(Binned binned, const Vec3& wo, double theta) {
  const double visible = cut(wo.x * std::sin(theta), -wo.z * std::cos(theta));
  if (binned == Binned::kNormal) return visible;
  return std::max(visible, cut(wo.x * std::sin(2 * theta), -wo.z * std::cos(2 * theta)));
}
// The θ where a cut reaches cos φ = ±1 (a ring's support starts or ends):
// θ = π/2 − θo for visibility; (π/2 ∓ θo)/2 for the horizon of wi. The
// cells' θ integrals are split there, or a sliver of support inside a cell
// (at α = 0.01 and θo = 85°, 6e-5 rad of a 1.5 rad row) could fall between
// every quadrature node and read as a zero-expectation cell.
std::vector<double> support_breaks(Binned binned, const Vec3& wo) {
  const double theta_o = std::atan2(wo.x, wo.z);
  std::vector<double> breaks{kPi / 2 - theta_o};
  if (binned == Binned::kReflected) {
    breaks.push_back((kPi / 2 - theta_o) / 2);
    breaks.push_back((kPi / 2 + theta_o) / 2);
  }
  return breaks;
}
// Pieces of [lo, hi] ⊂ [0, 2π] on which cos φ > K.
std::vector<std::pair<double, double>> phi_pieces(double k, double lo, double hi) {
  if (k < -1) return {{lo, hi}};
  if (k >= 1) return {};
  const double a = std::acos(k);  // allowed: [0, a) ∪ (2π − a, 2π]
  std::vector<std::pair<double, double>> out;
  if (std::min(hi, a) > lo) out.push_back({lo, std::min(hi, a)});
  if (hi > std::max(lo, 2 * kPi - a)) out.push_back({std::max(lo, 2 * kPi - a), hi});
  return out;
}

using NormalPdf = std::function<double(const Vec3& m)>;  // density in solid angle of the binned normal

double cell_probability(const NormalPdf& pdf, Binned binned, const Vec3& wo, double t0, double t1, double p0,
                        double p1) {
  const auto ring = [&](double theta) {
    const double st = std::sin(theta), ct = std::cos(theta);
    double sum = 0;
    for (const auto& [lo, hi] : phi_pieces(support_cut(binned, wo, theta), p0, p1))
      sum += adaptive_gauss_kronrod_relative<kQuadraturePoints>(
          [&](double phi) { return pdf({st * std::cos(phi), st * std::sin(phi), ct}); }, lo, hi,
          kQuadratureInnerRelTolerance, kQuadratureMaxDepth, 1, kQuadratureMaxBisections);
    return st * sum;
  };
  std::vector<double> edges{t0, t1};
  for (double b : support_breaks(binned, wo))
    if (b > t0 && b < t1) edges.push_back(b);
  std::sort(edges.begin(), edges.end());
  double sum = 0;
  for (size_t i = 0; i + 1 < edges.size(); ++i)
    sum += adaptive_gauss_kronrod_relative<kQuadraturePoints>(ring, edges[i], edges[i + 1], kQuadratureRelTolerance,
                                                              kQuadratureMaxDepth, kQuadratureInitialPieces,
                                                              kQuadratureMaxBisections);
  return sum;
}

struct Outcome {
  Chi2Result chi2;
  double pdf_integral = 0;
  double failures = 0;
};

// Draws kSamples with `bsdf` (its defect included) and tests them against
// its own pdf: visible_normal_pdf for normals, pdf() (mapped to h) for
// reflected directions.
Outcome run(const GgxBsdf& bsdf, double theta_deg, Binned binned, const std::string& name, double alpha_each) {
  const Vec3 wo = wo_at(theta_deg);
  const GgxNormalGrid grid{bsdf.alpha};
  const size_t cells = size_t(kRows) * kColumns;
  std::vector<double> observed(cells + 1, 0), expected(cells + 1, 0);  // + failed samples
  uint64_t stream = 0xcbf29ce484222325ULL;
  for (unsigned char ch : name) stream = (stream ^ ch) * 0x100000001b3ULL;  // FNV-1a: per-case stream
  Rng rng(kSeed, stream, 0);
  for (size_t i = 0; i < kSamples; ++i) {
    const double u1 = rng.next_double(), u2 = rng.next_double();
    Vec3 m;
    if (binned == Binned::kNormal) {
      m = bsdf.sample_visible_normal(wo, u1, u2);
    } else {
      const auto s = bsdf.sample(wo, u1, u2);
      if (!s) {
        observed[cells] += 1;
        continue;
      }
      m = normalize(wo + s->wi_local);
    }
    const long cell = grid.cell_of(m);
    if (cell < 0) {
      observed[cells] += 1;  // a normal below the horizon: in the failure bin, whose expectation is the rest
      continue;
    }
    observed[size_t(cell)] += 1;
  }
  const NormalPdf pdf = binned == Binned::kNormal ? NormalPdf([&](const Vec3& m) { return bsdf.visible_normal_pdf(wo, m); })
                                                  : NormalPdf([&](const Vec3& h) {
                                                      const double wo_dot_h = dot(wo, h);
                                                      if (!(wo_dot_h > 0)) return 0.0;
                                                      return bsdf.pdf(wo, reflect_about(wo, h)) * 4 * wo_dot_h;
                                                    });
  double total = 0;
  for (int r = 0; r < kRows; ++r)
    for (int c = 0; c < kColumns; ++c) {
      const double p = cell_probability(pdf, binned, wo, grid.theta_edge(r), grid.theta_edge(r + 1),
                                        2 * kPi * c / kColumns, 2 * kPi * (c + 1) / kColumns);
      expected[size_t(r) * kColumns + c] = double(kSamples) * p;
      total += p;
    }
  expected[cells] = double(kSamples) * std::fmax(0.0, 1 - total);
  Outcome o{chi2_from_counts(observed, expected, alpha_each), total, observed[cells]};
  std::cout << "  " << name << ": N = " << o.chi2.samples << ", chi2 " << o.chi2.statistic << " dof " << o.chi2.dof
            << " p " << o.chi2.p_value << " (alpha " << o.chi2.alpha << "), pooled " << o.chi2.pooled_cells << "/"
            << o.chi2.cells << ", int pdf " << total << ", failed " << o.failures << ", detectable w "
            << o.chi2.detectable_effect << "\n";
  return o;
}

std::string number_name(double x) {
  std::string s = std::to_string(x);
  s.erase(s.find_last_not_of('0') + 1);
  if (s.back() == '.') s.pop_back();
  std::replace(s.begin(), s.end(), '.', 'p');
  return s;
}

struct Chi2Case {
  double alpha, theta_deg;
  std::string name;
};
void PrintTo(const Chi2Case& c, std::ostream* os) { *os << c.name; }
std::vector<Chi2Case> cases() {
  std::vector<Chi2Case> out;
  for (double a : kAlphas)
    for (double t : kViewsDeg) out.push_back({a, t, "Alpha" + number_name(a) + "Deg" + number_name(t)});
  return out;
}

class GgxChi2 : public testing::TestWithParam<Chi2Case> {};

TEST_P(GgxChi2, VisibleNormalsFollowPdf) {
  const Chi2Case& c = GetParam();
  const Outcome o = run(GgxBsdf{0.8, c.alpha}, c.theta_deg, Binned::kNormal, c.name + "Normals",
                        sidak_alpha(kFamilyAlpha, family_size()));
  EXPECT_TRUE(o.chi2.pass) << o.chi2.message;
  // ∫D_wo = 1 over the grid (the identity itself is tested to 1e-12 in
  // ggx_test.cpp): the cells' quadrature reaches it to their tolerance only.
  EXPECT_NEAR(o.pdf_integral, 1.0, kPdfIntegralTol);
  EXPECT_EQ(o.failures, 0);
}

TEST_P(GgxChi2, ReflectedDirectionsFollowPdf) {
  const Chi2Case& c = GetParam();
  const Outcome o = run(GgxBsdf{0.8, c.alpha}, c.theta_deg, Binned::kReflected, c.name + "Reflected",
                        sidak_alpha(kFamilyAlpha, family_size()));
  EXPECT_TRUE(o.chi2.pass) << o.chi2.message;
  EXPECT_LE(o.pdf_integral, 1 + kPdfIntegralTol);
}

INSTANTIATE_TEST_SUITE_P(Grid, GgxChi2, testing::ValuesIn(cases()), [](const auto& info) { return info.param.name; });

// Negative controls: each defect that changes the sampler or the claimed
// density is rejected at the per-test level of the family above.
TEST(GgxChi2Control, DefectsAreRejected) {
  struct Control {
    Defect defect;
    double alpha, theta_deg;
    Binned binned;
  };
  const std::vector<Control> controls{
      {Defect::kGgxSampleAlphaSquared, 0.5, 30, Binned::kNormal},
      {Defect::kGgxSampleAlphaSquared, 0.5, 30, Binned::kReflected},
      {Defect::kGgxVndfPdfWithoutG1, 0.5, 60, Binned::kNormal},
      {Defect::kGgxVndfPdfWithoutG1, 0.5, 60, Binned::kReflected},
      {Defect::kGgxLambdaOtherAlpha, 0.5, 60, Binned::kReflected},
      {Defect::kGgxDWithoutInvPi, 0.5, 0, Binned::kReflected},
  };
  for (const Control& k : controls) {
    const std::string name = defect_name(k.defect) + (k.binned == Binned::kNormal ? " normals" : " reflected");
    const Outcome o = run(GgxBsdf{0.8, k.alpha, MicrofacetShadowing::kHeightCorrelated, k.defect}, k.theta_deg,
                          k.binned, name + " (control)", sidak_alpha(kFamilyAlpha, family_size()));
    EXPECT_FALSE(o.chi2.pass) << name << ": not rejected";
  }
}

// ---------------------------------------------------------------------------
// α = 1: the reflected direction is uniform on the cap of area 2π(1 + cos θo)
// (density 1/(2π(1 + cos θo)) over every wi whose h is visible), so
// P(wi_z > 0) = 2π/(2π(1 + cos θo)) = 1/(1 + cos θo) exactly.

const std::vector<double> kHorizonViewsDeg{0, 30, 60, 80, 85, 89.99};
constexpr size_t kHorizonSamples = 4000000;

struct Binomial {
  double rate, expected, z, threshold, detectable;
};
Binomial horizon_fraction(const GgxBsdf& bsdf, double theta_deg, uint64_t stream) {
  const Vec3 wo = wo_at(theta_deg);
  Rng rng(kSeed, stream, 0);
  double successes = 0;
  for (size_t i = 0; i < kHorizonSamples; ++i) {
    const double u1 = rng.next_double(), u2 = rng.next_double();
    successes += bsdf.sample(wo, u1, u2) ? 1 : 0;
  }
  const double p = 1 / (1 + wo.z), n = double(kHorizonSamples);
  const double se = std::sqrt(p * (1 - p) / n);
  const double alpha_each = sidak_alpha(kFamilyAlpha, kHorizonViewsDeg.size());
  const double threshold = normal_upper_quantile(alpha_each / 2);
  return {successes / n, p, (successes / n - p) / se, threshold,
          (threshold + normal_upper_quantile(1 - kDefaultPower)) * se};
}

TEST(GgxHorizon, FractionAboveHorizonAtAlphaOne) {
  for (size_t k = 0; k < kHorizonViewsDeg.size(); ++k) {
    const Binomial b = horizon_fraction(GgxBsdf{0.8, 1.0}, kHorizonViewsDeg[k], 100 + k);
    std::cout << "  theta_o " << kHorizonViewsDeg[k] << ": N = " << kHorizonSamples << ", rate " << b.rate
              << ", 1/(1+cos) " << b.expected << ", z " << b.z << " (|z| < " << b.threshold
              << "), detects |bias| >= " << b.detectable << " with power " << kDefaultPower << "\n";
    EXPECT_LT(std::fabs(b.z), b.threshold) << kHorizonViewsDeg[k];
  }
}

TEST(GgxHorizon, RoughnessPointNineIsRejected) {
  const Binomial b = horizon_fraction(GgxBsdf{0.8, 0.9}, 60, 200);
  std::cout << "  alpha 0.9 at 60 deg (control): rate " << b.rate << ", 1/(1+cos) " << b.expected << ", z " << b.z
            << "\n";
  EXPECT_GT(std::fabs(b.z), b.threshold);
}

}  // namespace
}  // namespace furnace::stats
