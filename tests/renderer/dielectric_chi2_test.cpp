// Rough dielectric sampling by chi-square goodness of fit (DielectricBsdf,
// renderer/dielectric.h): do the directions sample() draws over the whole
// sphere, both lobes, follow pdf()? Cases: α ∈ kAlphas × views from outside
// (η = 1.5) and from inside (η = 1/1.5), the inside views including θo a
// few degrees short of the critical angle asin(1/1.5) = 41.81° and past it
// (every microfacet near the normal reflects totally).
//
// Cells (the recipe of tests/renderer/ggx_chi2_test.cpp): each lobe maps
// its directions one-to-one onto microfacet normals, so a sample is binned
// by its lobe (wi above or below the horizon) and its normal m: the half
// vector normalize(wo + wi) for a reflection, the generalised half vector
// ±normalize(wo + η wi) (m_z > 0) for a refraction. Per lobe, rows are
// equal steps of v = tan²θm/(α² + tan²θm) (equal mass of D cos θm, so the
// peak of width α is resolved at every α) and kColumns odd equal steps of φ.
// The density claimed for the binned m is pdf(wo, wi(m))·|dωi/dωm|
// (reflection 4 wo·m; refraction (η wi·m + wo·m)²/(η²|wi·m|), Walter 2007
// eq. 17 inverted), wi(m) by Snell at m. Expected counts are N·∫cell by
// nested adaptive Gauss–Kronrod (core/adaptive_quadrature.h, the tolerances
// of stats/chi2.h) in (θ, φ), each ring's φ range cut exactly where its
// lobe's support ends (tests/renderer/dielectric_normal_quadrature.h: the
// thresholds on wo·m of visibility, horizon and total internal reflection)
// and each cell's θ range split where a support's topology changes, so
// every integrand is smooth up to the square root of 1 − F at the critical
// angle. Failed samples form one more bin of expected N·(1 − ∫pdf).
//
// Budget: kSamples per case from a fixed named seed (one stream per case),
// kFamilyAlpha over the cases by Šidák. Negative controls (at the same
// per-test level): defects that change pdf() but not what the sampler draws
// (dielectric_transmission_without_eta2, dielectric_reflection_jacobian)
// must be rejected.
// Measured when written: 28 cases, p from 0.011 to 0.98 at the per-test
// level 3.6e-4 (detectable w 0.012–0.014); the controls give p = 0 (or a
// failure bin the claimed pdf says is empty); ~50 s in all on one core.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <iostream>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/adaptive_quadrature.h"
#include "renderer/dielectric.h"
#include "renderer/microfacet.h"
#include "renderer/rng.h"
#include "stats/chi2.h"
#include "tests/renderer/ggx_normal_grid.h"
#include "stats/statistics.h"
#include "tests/renderer/dielectric_normal_quadrature.h"

namespace furnace::stats {
namespace {

constexpr uint64_t kSeed = 0xd1e1c2;
constexpr size_t kSamples = 1000000;
constexpr double kFamilyAlpha = 0.01;
constexpr int kRows = kGgxGridRows;
constexpr int kColumns = kGgxGridColumns;
constexpr double kAlbedo = 0.8;

// The sum of 2·420 cell integrals, each to kQuadratureRelTolerance by its
// error estimate; 1e-7 bounds it as in ggx_chi2_test.cpp.
constexpr double kPdfIntegralTol = 1e-7;

const std::vector<double> kAlphas{0.01, 0.1, 0.5, 1.0};
struct View {
  double eta, theta_deg;
  const char* name;
};
// Critical angle from inside at η = 1/1.5: asin(2/3) = 41.81°.
const std::vector<View> kViews{{1.5, 0, "Out0"},           {1.5, 45, "Out45"},          {1.5, 80, "Out80"},
                               {1 / 1.5, 20, "In20"},      {1 / 1.5, 38.8, "In38p8"},   {1 / 1.5, 40.8, "In40p8"},
                               {1 / 1.5, 43.8, "In43p8"}};
size_t family_size() { return kAlphas.size() * kViews.size(); }

Vec3 wo_at(double theta_deg) {
  const double t = theta_deg * kPi / 180;
  return {std::sin(t), 0, std::cos(t)};
}

enum Lobe { kReflect = 0, kTransmit = 1 };


// The normal of a sampled direction in its lobe.
std::optional<Vec3> binned_normal(const Vec3& wo, const Vec3& wi, double eta) {
  Vec3 h = wi.z > 0 ? wo + wi : wo + eta * wi;
  const double len = length(h);
  if (!(len > 0)) return std::nullopt;
  h = h / len;
  if (h.z < 0) h = -h;
  return h;
}

// Snell at m (wo·m > 0), η below over above; nullopt under TIR.
std::optional<Vec3> snell_refract(const Vec3& wo, const Vec3& m, double eta) {
  const double c = dot(wo, m);
  const double sin2_t = (1 - c * c) / (eta * eta);
  if (sin2_t >= 1) return std::nullopt;
  return -wo / eta + (c / eta - std::sqrt(1 - sin2_t)) * m;
}

// The claimed density of the binned normal of a lobe.
double normal_density(const DielectricBsdf& b, const Vec3& wo, const Vec3& m, Lobe lobe) {
  const double c = dot(wo, m);
  if (!(c > 0)) return 0.0;
  if (lobe == kReflect) {
    const Vec3 wi = 2 * c * m - wo;
    return wi.z > 0 ? b.pdf(wo, wi) * 4 * c : 0.0;
  }
  const std::optional<Vec3> wi = snell_refract(wo, m, b.eta);
  if (!wi || !(wi->z < 0)) return 0.0;
  const double wi_m = dot(*wi, m), denom = b.eta * wi_m + c;
  return b.pdf(wo, *wi) * denom * denom / (b.eta * b.eta * std::fabs(wi_m));
}

// The lobe's support on the ring θ: cos φ > K (wo in the xz-plane).
double support_cut(const Vec3& wo, double eta, double theta, Lobe lobe) {
  const std::array<double, 4> t = testing_support::ring_thresholds(wo, eta, theta);
  const double c_min = lobe == kReflect ? std::max(t[0], t[1]) : std::max({t[0], t[2], t[3]});
  const double a = wo.x * std::sin(theta), b = wo.z * std::cos(theta);
  if (a > 0) return (c_min - b) / a;
  return b > c_min ? -2.0 : 2.0;  // every φ, or none
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

// ∫_a^b f with x = a + (b − a)(1 − cos πt)/2: a square root at either end
// (1 − F at the critical angle, a ring's support entering or leaving a
// cell) becomes linear in t, so Gauss–Kronrod converges at the rule's rate
// instead of bisecting down to kQuadratureMaxDepth at every such end.
template <class F>
double integrate_smoothed(const F& f, double a, double b, double rel_tolerance, int initial_pieces) {
  const double half = (b - a) / 2;
  return adaptive_gauss_kronrod_relative<kQuadraturePoints>(
      [&](double t) { return f(a + half * (1 - std::cos(kPi * t))) * half * kPi * std::sin(kPi * t); }, 0.0, 1.0,
      rel_tolerance, kQuadratureMaxDepth, initial_pieces, kQuadratureMaxBisections);
}

double cell_probability(const DielectricBsdf& b, const Vec3& wo, Lobe lobe, const std::vector<double>& breaks,
                        double t0, double t1, double p0, double p1) {
  const double c_crit = b.eta < 1 ? std::sqrt((1 - b.eta) * (1 + b.eta)) : 0.0;
  const auto ring = [&](double theta) {
    const double st = std::sin(theta), ct = std::cos(theta);
    // The reflection lobe's F has a square-root kink at the critical angle
    // (from inside): each piece is cut there too.
    const double a = wo.x * st, bb = wo.z * ct;
    double sum = 0;
    for (const auto& [lo, hi] : phi_pieces(support_cut(wo, b.eta, theta, lobe), p0, p1)) {
      std::vector<double> cuts{lo, hi};
      if (c_crit > 0 && a > 0) {
        const double k = (c_crit - bb) / a;
        if (k > -1 && k < 1)
          for (double phi : {std::acos(k), 2 * kPi - std::acos(k)})
            if (phi > lo && phi < hi) cuts.push_back(phi);
      }
      std::sort(cuts.begin(), cuts.end());
      for (size_t i = 0; i + 1 < cuts.size(); ++i)
        sum += integrate_smoothed(
            [&](double phi) { return normal_density(b, wo, {st * std::cos(phi), st * std::sin(phi), ct}, lobe); },
            cuts[i], cuts[i + 1], kQuadratureInnerRelTolerance, 1);
    }
    return st * sum;
  };
  std::vector<double> edges{t0, t1};
  for (double x : breaks)
    if (x > t0 && x < t1) edges.push_back(x);
  std::sort(edges.begin(), edges.end());
  double sum = 0;
  for (size_t i = 0; i + 1 < edges.size(); ++i)
    sum += integrate_smoothed(ring, edges[i], edges[i + 1], kQuadratureRelTolerance, kQuadratureInitialPieces);
  return sum;
}

struct Outcome {
  Chi2Result chi2;
  double pdf_integral = 0, failures = 0, transmitted = 0;
};

// Draws kSamples with `sampler` and tests them against the pdf of `claimed`
// (the same BSDF, or one whose defect changes only the pdf).
Outcome run(const DielectricBsdf& sampler, const DielectricBsdf& claimed, double theta_deg, const std::string& name,
            double alpha_each) {
  const Vec3 wo = wo_at(theta_deg);
  const GgxNormalGrid grid{sampler.alpha};
  const size_t cells = size_t(kRows) * kColumns;
  std::vector<double> observed(2 * cells + 1, 0), expected(2 * cells + 1, 0);  // two lobes + failed samples
  uint64_t stream = 0xcbf29ce484222325ULL;
  for (unsigned char ch : name) stream = (stream ^ ch) * 0x100000001b3ULL;  // FNV-1a: per-case stream
  Rng rng(kSeed, stream, 0);
  double transmitted = 0;
  for (size_t i = 0; i < kSamples; ++i) {
    const double u1 = rng.next_double(), u2 = rng.next_double(), ul = rng.next_double();
    const auto s = sampler.sample(wo, u1, u2, ul);
    const std::optional<Vec3> m = s ? binned_normal(wo, s->wi_local, sampler.eta) : std::nullopt;
    const long cell = m ? grid.cell_of(*m) : -1;
    if (cell < 0) {
      observed[2 * cells] += 1;
      continue;
    }
    const size_t lobe = s->wi_local.z > 0 ? kReflect : kTransmit;
    transmitted += lobe == kTransmit ? 1 : 0;
    observed[lobe * cells + size_t(cell)] += 1;
  }
  const std::vector<double> breaks = testing_support::support_theta_breaks(wo, claimed.eta);
  double total = 0;
  for (Lobe lobe : {kReflect, kTransmit})
    for (int r = 0; r < kRows; ++r)
      for (int c = 0; c < kColumns; ++c) {
        const double p = cell_probability(claimed, wo, lobe, breaks, grid.theta_edge(r), grid.theta_edge(r + 1),
                                          2 * kPi * c / kColumns, 2 * kPi * (c + 1) / kColumns);
        expected[size_t(lobe) * cells + size_t(r) * kColumns + c] = double(kSamples) * p;
        total += p;
      }
  expected[2 * cells] = double(kSamples) * std::fmax(0.0, 1 - total);
  Outcome o{chi2_from_counts(observed, expected, alpha_each), total, observed[2 * cells], transmitted};
  std::cout << "  " << name << ": N = " << o.chi2.samples << ", chi2 " << o.chi2.statistic << " dof " << o.chi2.dof
            << " p " << o.chi2.p_value << " (alpha " << o.chi2.alpha << "), pooled " << o.chi2.pooled_cells << "/"
            << o.chi2.cells << ", int pdf " << total << ", failed " << o.failures << ", transmitted " << transmitted
            << ", detectable w " << o.chi2.detectable_effect << "\n";
  if (!o.chi2.pass) std::cout << "    " << o.chi2.message << "\n";
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
  double alpha;
  View view;
  std::string name;
};
void PrintTo(const Chi2Case& c, std::ostream* os) { *os << c.name; }
std::vector<Chi2Case> cases() {
  std::vector<Chi2Case> out;
  for (double a : kAlphas)
    for (const View& v : kViews) out.push_back({a, v, "Alpha" + number_name(a) + v.name});
  return out;
}

class DielectricChi2 : public testing::TestWithParam<Chi2Case> {};

TEST_P(DielectricChi2, DirectionsFollowPdf) {
  const Chi2Case& c = GetParam();
  const DielectricBsdf b{kAlbedo, c.view.eta, c.alpha};
  const Outcome o = run(b, b, c.view.theta_deg, c.name, sidak_alpha(kFamilyAlpha, family_size()));
  EXPECT_TRUE(o.chi2.pass) << o.chi2.message;
  EXPECT_LE(o.pdf_integral, 1 + kPdfIntegralTol);
}

INSTANTIATE_TEST_SUITE_P(Grid, DielectricChi2, testing::ValuesIn(cases()),
                         [](const auto& info) { return info.param.name; });

// Negative controls: a wrong transmission Jacobian changes pdf() but not
// what sample() draws (its m and lobe choice do not depend on the Jacobian;
// a draw fails only where pdf() is 0, which the defects do not change), so
// the BSDF's own samples are tested against its own, wrong, pdf().
TEST(DielectricChi2Control, PdfDefectsAreRejected) {
  struct Control {
    Defect defect;
    double eta, alpha, theta_deg;
  };
  const std::vector<Control> controls{
      {Defect::kDielectricTransmissionWithoutEta2, 1.5, 0.5, 45},
      {Defect::kDielectricTransmissionWithoutEta2, 1 / 1.5, 0.1, 38.8},
      {Defect::kDielectricReflectionJacobian, 1.5, 0.5, 45},
  };
  for (const Control& k : controls) {
    const DielectricBsdf b{kAlbedo, k.eta, k.alpha, MicrofacetShadowing::kHeightCorrelated,
                           TransportConvention::kRadiance, k.defect};
    const std::string name = defect_name(k.defect) + " eta " + number_name(k.eta) + " (control)";
    const Outcome o = run(b, b, k.theta_deg, name, sidak_alpha(kFamilyAlpha, family_size()));
    EXPECT_FALSE(o.chi2.pass) << name << ": not rejected";
  }
}

}  // namespace
}  // namespace furnace::stats
