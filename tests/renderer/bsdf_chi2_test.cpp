// BSDF sampling through the renderer's Bsdf interface (renderer/bsdf.h:
// sample/pdf/eval), not the raw warps: chi-square goodness of fit of
// sample() against pdf(), ∫pdf = P(sample() succeeds), sample().pdf ==
// pdf(sample().wi), and weight == eval·cos θ/pdf; the mirror's delta
// convention. Negative controls: a sampler tested against a wrong pdf fails.
//
// Cells (equal probability for the lobe, not equal area): about the lobe's
// axis a (the normal for Lambertian, the mirror direction of wo for Phong,
// exponent m = 1 resp. n), rows of equal v = 1 − cos^(m+1) α on α ∈ [0, π/2],
// an odd number of equal φ columns, one cell for α > π/2 (zero expectation:
// a sample there fails at once) and one bin for failed samples (expected
// N·(1 − ∫pdf)). Expected counts N·∫cell pdf() dω by nested adaptive
// Gauss–Kronrod in (α, φ), the φ range of each ring cut exactly at p's
// horizon wi.z = 0 (pdf() is 0 below it by contract; the separate
// quadrature over the whole sphere checks that).
//
// Budget: kSamples samples per case from a fixed named seed (one stream per
// case), kFamilyAlpha over the correct cases by Šidák; each negative control
// runs at that same per-test level.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <ostream>
#include <string>

#include <boost/math/quadrature/gauss_kronrod.hpp>

#include "renderer/bsdf.h"
#include "renderer/rng.h"
#include "stats/chi2.h"

namespace furnace::stats {
namespace {

constexpr uint64_t kSeed = 0xb5df0c41;
constexpr size_t kSamples = 1000000;
constexpr double kFamilyAlpha = 0.01;
constexpr int kRows = 20;
constexpr int kColumns = 21;  // odd: no cell edge on the lobe's symmetry plane
constexpr double kEps = 2.220446049250313e-16;

struct BsdfCase {
  std::string name;
  Material material;
  double incidence_deg;  // angle of wo from the normal
};

Vec3 wo_at(double incidence_deg) {
  const double t = incidence_deg * kPi / 180;
  return {std::sin(t), 0, std::cos(t)};
}

std::vector<BsdfCase> correct_cases() {
  std::vector<BsdfCase> cases;
  const std::vector<std::pair<std::string, double>> angles{
      {"Normal", 0}, {"Deg45", 45}, {"Deg80", 80}, {"Grazing89p9", 89.9}};
  for (const auto& [an, a] : angles) cases.push_back({"Lambertian" + an, {0.8, Lambertian{}}, a});
  for (double n : {1.0, 10.0, 100.0, 1000.0})
    for (const auto& [an, a] : angles)
      cases.push_back({"PhongN" + std::to_string(int(n)) + an, {0.7, Phong{n}}, a});
  return cases;
}

// The lobe the cells are shaped for: axis and exponent.
struct Lobe {
  Frame frame;
  double exponent;
};
Lobe lobe_of(const Material& m, const Vec3& wo) {
  if (const Phong* p = m.as<Phong>()) return {Frame::from_normal(normalize(reflect_about_normal(wo))), p->exponent};
  return {Frame::from_normal({0, 0, 1}), 1.0};
}

// α at the row boundary v (v = 1 − cos^(m+1) α).
double alpha_of_v(double v, double m) { return std::acos(std::pow(1 - v, 1 / (m + 1))); }

// The φ interval(s) of the ring at α where wi.z > 0: wi.z = A + M cos(φ − φ0).
// Returns the pieces of [φ_lo, φ_hi] on which wi.z > 0.
std::vector<std::pair<double, double>> above_horizon(const Lobe& lobe, double alpha, double lo, double hi) {
  const double A = std::cos(alpha) * lobe.frame.n.z;
  const double B = std::sin(alpha) * lobe.frame.s.z, C = std::sin(alpha) * lobe.frame.t.z;
  const double M = std::hypot(B, C);
  if (M <= std::fabs(A)) {
    if (A > 0) return {{lo, hi}};
    return {};
  }
  const double phi0 = std::atan2(C, B), half = std::acos(-A / M);
  std::vector<std::pair<double, double>> out;
  // The arc (φ0 − half, φ0 + half) modulo 2π, intersected with [lo, hi].
  for (double shift : {-2 * kPi, 0.0, 2 * kPi}) {
    const double a = std::max(lo, phi0 - half + shift), b = std::min(hi, phi0 + half + shift);
    if (b > a) out.push_back({a, b});
  }
  return out;
}

using PdfFn = std::function<double(const Vec3& wi)>;

double cell_integral(const PdfFn& pdf, const Lobe& lobe, double a0, double a1, double p0, double p1) {
  using boost::math::quadrature::gauss_kronrod;
  auto ring = [&](double alpha) {
    double sum = 0;
    for (const auto& [lo, hi] : above_horizon(lobe, alpha, p0, p1)) {
      auto f = [&](double phi) {
        const Vec3 local{std::sin(alpha) * std::cos(phi), std::sin(alpha) * std::sin(phi), std::cos(alpha)};
        return pdf(lobe.frame.world_from_local(local));
      };
      sum += gauss_kronrod<double, 15>::integrate(f, lo, hi, 10, 1e-11);
    }
    return std::sin(alpha) * sum;
  };
  return gauss_kronrod<double, 15>::integrate(ring, a0, a1, 12, 1e-9);
}

struct Histogram {
  std::vector<double> observed, expected;
  double pdf_integral = 0;
};

// Bins N samples of `sample` and the expectation of `pdf` over the cells.
Histogram histogram(const std::string& name, const Bsdf& bsdf, const Vec3& wo, const Lobe& lobe, const PdfFn& pdf) {
  const size_t cells = size_t(kRows) * kColumns;
  Histogram h;
  h.observed.assign(cells + 2, 0);  // + back cell (α > π/2) + failures
  h.expected.assign(cells + 2, 0);
  uint64_t stream = 0xcbf29ce484222325ULL;
  for (unsigned char ch : name) stream = (stream ^ ch) * 0x100000001b3ULL;  // FNV-1a: per-case stream
  Rng rng(kSeed, stream, 0);
  for (size_t i = 0; i < kSamples; ++i) {
    const double u1 = rng.next_double(), u2 = rng.next_double();
    const auto s = bsdf.sample(wo, u1, u2);
    if (!s) {
      h.observed[cells + 1] += 1;
      continue;
    }
    const Vec3 w = lobe.frame.local_from_world(s->wi_local);
    if (!(w.z > 0)) {
      h.observed[cells] += 1;
      continue;
    }
    const double v = 1 - std::pow(std::fmin(w.z, 1.0), lobe.exponent + 1);
    double phi = std::atan2(w.y, w.x);
    if (phi < 0) phi += 2 * kPi;
    const int row = std::min(kRows - 1, int(v * kRows));
    const int col = std::min(kColumns - 1, int(phi / (2 * kPi) * kColumns));
    h.observed[size_t(row) * kColumns + col] += 1;
  }
  double total = 0;
  for (int r = 0; r < kRows; ++r) {
    const double a0 = alpha_of_v(double(r) / kRows, lobe.exponent);
    const double a1 = r + 1 == kRows ? kPi / 2 : alpha_of_v(double(r + 1) / kRows, lobe.exponent);
    for (int c = 0; c < kColumns; ++c) {
      const double p = cell_integral(pdf, lobe, a0, a1, 2 * kPi * c / kColumns, 2 * kPi * (c + 1) / kColumns);
      h.expected[size_t(r) * kColumns + c] = double(kSamples) * p;
      total += p;
    }
  }
  const double back = cell_integral(pdf, lobe, kPi / 2, kPi, 0, 2 * kPi);
  h.expected[cells] = double(kSamples) * back;
  total += back;
  h.pdf_integral = total;
  h.expected[cells + 1] = double(kSamples) * std::fmax(0.0, 1 - total);
  return h;
}

void report(const std::string& name, const Chi2Result& r, double pdf_integral, double failures) {
  std::cout << "  " << name << ": N = " << r.samples << ", chi2 " << r.statistic << " dof " << r.dof << " p "
            << r.p_value << " (alpha " << r.alpha << "), pooled " << r.pooled_cells << "/" << r.cells
            << ", int pdf " << pdf_integral << ", failed samples " << failures << ", detectable w "
            << r.detectable_effect << "\n";
}

void PrintTo(const BsdfCase& c, std::ostream* os) { *os << c.name; }

class BsdfChi2 : public testing::TestWithParam<BsdfCase> {};

TEST_P(BsdfChi2, SamplesFollowPdf) {
  const BsdfCase& c = GetParam();
  const Bsdf bsdf(c.material);
  const Vec3 wo = wo_at(c.incidence_deg);
  const Lobe lobe = lobe_of(c.material, wo);
  const Histogram h = histogram(c.name, bsdf, wo, lobe, [&](const Vec3& wi) { return bsdf.pdf(wo, wi); });
  const Chi2Result r = chi2_from_counts(h.observed, h.expected, sidak_alpha(kFamilyAlpha, correct_cases().size()));
  report(c.name, r, h.pdf_integral, h.observed.back());
  EXPECT_TRUE(r.pass) << r.message;
  EXPECT_LE(h.pdf_integral, 1 + 1e-8);
}

INSTANTIATE_TEST_SUITE_P(Bsdfs, BsdfChi2, testing::ValuesIn(correct_cases()),
                         [](const auto& info) { return info.param.name; });

// Negative controls: Phong exponent n sampled, pdf of n + 1 tested; the
// Lambertian sampled, the normalised cos^1.1 lobe about the normal tested.
TEST(BsdfChi2Control, WrongPdfFails) {
  const size_t family = correct_cases().size();
  struct Control {
    std::string name;
    Material material;
    double incidence;
    PdfFn (*claimed)(const Vec3& wo);
  };
  const std::vector<Control> controls{
      {"PhongN10SampledPdfN11", {0.7, Phong{10}}, 45,
       [](const Vec3& wo) -> PdfFn {
         static const Material wrong{0.7, Phong{11}};
         return [wo](const Vec3& wi) { return Bsdf(wrong).pdf(wo, wi); };
       }},
      {"PhongN100SampledPdfN101Grazing", {0.7, Phong{100}}, 80,
       [](const Vec3& wo) -> PdfFn {
         static const Material wrong{0.7, Phong{101}};
         return [wo](const Vec3& wi) { return Bsdf(wrong).pdf(wo, wi); };
       }},
      {"LambertianSampledCos1p1Pdf", {0.8, Lambertian{}}, 30,
       [](const Vec3&) -> PdfFn {
         return [](const Vec3& wi) { return wi.z > 0 ? 2.1 / (2 * kPi) * std::pow(wi.z, 1.1) : 0.0; };
       }},
  };
  for (const Control& k : controls) {
    const Bsdf bsdf(k.material);
    const Vec3 wo = wo_at(k.incidence);
    const Histogram h = histogram(k.name, bsdf, wo, lobe_of(k.material, wo), k.claimed(wo));
    const Chi2Result r = chi2_from_counts(h.observed, h.expected, sidak_alpha(kFamilyAlpha, family));
    report(k.name + " (control)", r, h.pdf_integral, h.observed.back());
    EXPECT_FALSE(r.pass) << k.name << ": the wrong pdf was not rejected";
  }
}

// ∫_sphere pdf() dω = P(sample() succeeds): quadrature over the whole sphere
// in the normal frame (cos θ ∈ [−1, 1] split at 0, φ split at the lobe's
// plane), against 1 where the lobe lies wholly above the horizon (Lambertian;
// Phong at normal incidence) and against the failure rate of sample() by a
// binomial z-test elsewhere (N = kSamples, Šidák over the cases).
TEST(BsdfPdf, IntegratesToSuccessProbability) {
  using boost::math::quadrature::gauss_kronrod;
  const std::vector<BsdfCase> cases = correct_cases();
  const double alpha_each = sidak_alpha(kFamilyAlpha, cases.size());
  const double z_crit = normal_upper_quantile(alpha_each / 2);
  for (const BsdfCase& c : cases) {
    const Bsdf bsdf(c.material);
    const Vec3 wo = wo_at(c.incidence_deg);
    auto over = [&](double z0, double z1) {
      auto ring = [&](double z) {
        const double s = std::sqrt(std::fmax(0.0, (1 - z) * (1 + z)));
        auto f = [&](double phi) { return bsdf.pdf(wo, {s * std::cos(phi), s * std::sin(phi), z}); };
        // The lobe is symmetric about φ = 0 (wo in the xz plane): split there and at π.
        return gauss_kronrod<double, 31>::integrate(f, 0, kPi, 15, 1e-12) +
               gauss_kronrod<double, 31>::integrate(f, kPi, 2 * kPi, 15, 1e-12);
      };
      return gauss_kronrod<double, 31>::integrate(ring, z0, z1, 15, 1e-10);
    };
    EXPECT_EQ(over(-1, 0), 0.0) << c.name << ": pdf() is positive below the horizon";
    const double integral = over(0, 1);
    Rng rng(kSeed, 7, 0);
    double successes = 0;
    for (size_t i = 0; i < kSamples; ++i) {
      const double u1 = rng.next_double(), u2 = rng.next_double();
      successes += bsdf.sample(wo, u1, u2) ? 1 : 0;
    }
    const double rate = successes / double(kSamples);
    const bool whole_lobe = c.material.as<Lambertian>() || c.incidence_deg == 0;
    const double se = std::sqrt(std::fmax(integral * (1 - integral), 0.0) / double(kSamples));
    std::cout << "  " << c.name << ": int pdf " << integral << ", success rate " << rate << ", z "
              << (se > 0 ? (rate - integral) / se : 0.0) << "\n";
    if (whole_lobe) {
      // The high exponents' lobe is a spike: 1e-7 is what adaptive GK reaches on it.
      EXPECT_NEAR(integral, 1.0, 1e-7) << c.name;
      EXPECT_EQ(rate, 1.0) << c.name;
    } else {
      EXPECT_LE(std::fabs(rate - integral), z_crit * se) << c.name;
    }
  }
}

// sample().pdf == pdf(sample().wi) and weight == eval·cos θ/pdf recomputed.
TEST(BsdfSample, PdfAndWeightAgreeWithPdfAndEval) {
  for (const BsdfCase& c : correct_cases()) {
    const Bsdf bsdf(c.material);
    const Vec3 wo = wo_at(c.incidence_deg);
    Rng rng(kSeed, 11, 0);
    int checked = 0;
    for (int i = 0; i < 20000; ++i) {
      const double u1 = rng.next_double(), u2 = rng.next_double();
      const auto s = bsdf.sample(wo, u1, u2);
      if (!s) continue;
      ++checked;
      ASSERT_FALSE(s->delta);
      const double pdf = bsdf.pdf(wo, s->wi_local);
      ASSERT_GT(pdf, 0);
      EXPECT_LE(std::fabs(s->pdf_solid_angle - pdf), 4 * kEps * pdf) << c.name;
      const double weight = bsdf.eval(wo, s->wi_local) * s->wi_local.z / pdf;
      EXPECT_LE(std::fabs(s->weight - weight), 8 * kEps * weight) << c.name;
    }
    EXPECT_GT(checked, 1000) << c.name;
  }
}

// The mirror: a delta sample along reflect(wo), pdf 0, eval 0, weight = reflectance.
TEST(BsdfSample, MirrorIsDelta) {
  const Material mirror{0.9, Mirror{}};
  const Bsdf bsdf(mirror);
  EXPECT_TRUE(bsdf.is_delta());
  for (double a : {0.0, 45.0, 80.0, 89.9}) {
    const Vec3 wo = wo_at(a);
    const auto s = bsdf.sample(wo, 0.3, 0.7);
    ASSERT_TRUE(s);
    EXPECT_TRUE(s->delta);
    EXPECT_EQ(s->pdf_solid_angle, 0.0);
    EXPECT_EQ(s->weight, 0.9);
    EXPECT_EQ(s->wi_local, reflect_about_normal(wo));
    EXPECT_EQ(bsdf.pdf(wo, s->wi_local), 0.0);
    EXPECT_EQ(bsdf.eval(wo, s->wi_local), 0.0);
  }
}

}  // namespace
}  // namespace furnace::stats
