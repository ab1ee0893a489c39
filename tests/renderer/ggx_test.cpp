// GGX (renderer/microfacet.h, GgxBsdf in renderer/bsdf.h) by deterministic
// checks, each with a negative control that must fail it:
//  - the microfacet identities by quadrature (Boost.Math tanh-sinh and
//    exp-sinh in s = tan θm/α, which maps the peak of width α to width 1):
//    ∫ D(m) cos θm dωm = 1 and the weak white furnace ∫ D_ωo(m) dωm = 1
//    (∫ G1(ωo) D(m) max(0, ωo·m) dωm = cos θo), to kIdentityRelTol;
//  - eval against f computed in 50 digits from the textbook forms (the tan²
//    form of D, the plain (√(1 + α²tan²θ) − 1)/2), and at α = 1 against the
//    closed forms albedo/(π(1+μo)(1+μi)) and albedo/(2π(μo+μi)), and the
//    reflected-direction density against 1/(2π(1 + μo));
//  - sample().pdf == pdf(sample().wi), weight == eval·cos θi/pdf, and the
//    visible-normal inverse (sample ∘ invert = identity on normals);
//  - near-specular (α = 1e-3, 2e-3, 1e-2) and grazing (cos θo to 1e-4)
//    robustness: NaN, Inf, and zero pdfs where f > 0, counted and printed.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

#include <boost/math/constants/constants.hpp>
#include <boost/math/quadrature/exp_sinh.hpp>
#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <boost/math/quadrature/tanh_sinh.hpp>
#include <boost/multiprecision/cpp_bin_float.hpp>

#include "renderer/bsdf.h"
#include "renderer/microfacet.h"
#include "renderer/rng.h"

namespace furnace {
namespace {

constexpr uint64_t kSeed = 0x66c7;  // "ggx"
constexpr double kEps = 2.220446049250313e-16;
constexpr double kInf = std::numeric_limits<double>::infinity();

// Quadrature of the identities: Boost's double-exponential rules stop at
// relative error ~1e-15 on these smooth (after the substitution) integrands;
// the issue asks for 1e-12, a thousand times the rule's error.
constexpr double kIdentityRelTol = 1e-12;
constexpr double kQuadratureTol = 1e-15;

// The roughnesses and views of the deterministic checks: the scene minimum
// α = 1e-3 up to 1, views from the normal to cos θo = 1e-4.
const std::vector<double> kAlphas{1e-3, 2e-3, 1e-2, 0.05, 0.2, 0.5, 1.0};
const std::vector<double> kCosThetaO{1.0, 0.8660254037844387, 0.5, 0.17364817766693041, 0.08715574274765817,
                                     1e-2, 1e-4};  // 0°, 30°, 60°, 80°, 85°, and grazing

Vec3 wo_from_cos(double mu) { return {std::sqrt((1 - mu) * (1 + mu)), 0, mu}; }

GgxBsdf ggx(double alpha, MicrofacetShadowing shadowing = MicrofacetShadowing::kHeightCorrelated,
            Defect defect = Defect::kNone, double albedo = 0.8) {
  return GgxBsdf{albedo, alpha, shadowing, defect};
}

// ---------------------------------------------------------------------------
// The identities by quadrature.

// m at s = tan θm/α and azimuth φ, and dωm/(ds dφ) = sin θ·dθ/ds = (αs·r)·(α r²), r = cos θm = 1/√(1 + α²s²).
struct SubstitutedNormal {
  Vec3 m;
  double jacobian;
};
SubstitutedNormal normal_at(double s, double phi, double alpha) {
  const double q = alpha * s, r = 1 / std::sqrt(1 + q * q);
  return {{q * r * std::cos(phi), q * r * std::sin(phi), r}, alpha * q * r * r * r};
}

// ∫0^∞ g(s) ds: tanh-sinh on [0, s_split], exp-sinh beyond (s_split = ∞: exp-sinh alone).
template <class G>
double integrate_s(const G& g, double s_split) {
  boost::math::quadrature::exp_sinh<double> tail;
  if (!(s_split < kInf)) return tail.integrate(g, 0.0, kInf, kQuadratureTol);
  boost::math::quadrature::tanh_sinh<double> head;
  return head.integrate(g, 0.0, s_split, kQuadratureTol) + tail.integrate(g, s_split, kInf, kQuadratureTol);
}
template <class F>
double integrate_phi(const F& f, double a, double b) {
  return boost::math::quadrature::gauss_kronrod<double, 61>::integrate(f, a, b, 15, kQuadratureTol);
}

// ∫ D(m) cos θm dωm, D of `bsdf` (defects included).
double d_normalisation(const GgxBsdf& bsdf) {
  return integrate_s(
      [&](double s) {
        return integrate_phi(
            [&](double phi) {
              const SubstitutedNormal n = normal_at(s, phi, bsdf.alpha);
              return bsdf.distribution(n.m) * n.m.z * n.jacobian;
            },
            0, 2 * kPi);
      },
      kInf);
}

// ∫ D_ωo(m) dωm for wo = (sin θo, 0, cos θo). ωo·m > 0 ⟺ cos φ > −cos θo/(αs sin θo):
// every φ below s* = cos θo/(α sin θo), |φ| < acos(…) above; the integral is split there.
double visible_normal_integral(const GgxBsdf& bsdf, double mu) {
  const Vec3 wo = wo_from_cos(mu);
  const double s_star = wo.x > 0 ? mu / (bsdf.alpha * wo.x) : kInf;
  return integrate_s(
      [&](double s) {
        const auto f = [&](double phi) {
          const SubstitutedNormal n = normal_at(s, phi, bsdf.alpha);
          return bsdf.visible_normal_pdf(wo, n.m) * n.jacobian;
        };
        if (s <= s_star) return integrate_phi(f, 0, 2 * kPi);
        const double phi_max = std::acos(std::fmax(-1.0, -mu / (bsdf.alpha * s * wo.x)));
        return integrate_phi(f, -phi_max, phi_max);
      },
      s_star);
}

TEST(GgxIdentities, NormalDensityAndVisibleNormalsIntegrateToOne) {
  double worst_d = 0, worst_vndf = 0;
  for (double alpha : kAlphas) {
    const GgxBsdf b = ggx(alpha);
    const double d = d_normalisation(b);
    worst_d = std::fmax(worst_d, std::fabs(d - 1));
    EXPECT_LE(std::fabs(d - 1), kIdentityRelTol) << "alpha " << alpha << ": int D cos = " << d;
    for (double mu : kCosThetaO) {
      const double v = visible_normal_integral(b, mu);
      worst_vndf = std::fmax(worst_vndf, std::fabs(v - 1));
      EXPECT_LE(std::fabs(v - 1), kIdentityRelTol) << "alpha " << alpha << " cos " << mu << ": int D_wo = " << v;
    }
  }
  std::cout << "  " << kAlphas.size() << " alphas x " << kCosThetaO.size()
            << " views: worst |int D cos - 1| = " << worst_d << ", worst |int D_wo - 1| = " << worst_vndf
            << " (tolerance " << kIdentityRelTol << ")\n";
}

// Negative controls: D without 1/π fails ∫D cos = 1; Λ of α² and the density
// without G1(ωo) fail ∫D_ωo = 1 at an oblique view (at the normal Λ = 0 and G1 = 1).
TEST(GgxIdentities, DefectsBreakThem) {
  const double d = d_normalisation(ggx(0.2, MicrofacetShadowing::kHeightCorrelated, Defect::kGgxDWithoutInvPi));
  std::cout << "  ggx_d_without_inv_pi: int D cos = " << d << "\n";
  EXPECT_GT(std::fabs(d - 1), kIdentityRelTol);
  for (Defect defect : {Defect::kGgxLambdaOtherAlpha, Defect::kGgxVndfPdfWithoutG1}) {
    const double v = visible_normal_integral(ggx(0.2, MicrofacetShadowing::kHeightCorrelated, defect), 0.5);
    std::cout << "  " << defect_name(defect) << ": int D_wo at 60 deg = " << v << "\n";
    EXPECT_GT(std::fabs(v - 1), kIdentityRelTol) << defect_name(defect);
  }
}

// ---------------------------------------------------------------------------
// eval against 50 digits.

using Big = boost::multiprecision::cpp_bin_float_50;

struct BigDir {
  Big x, y, z;
};
BigDir big_unit(const Vec3& w) {
  const Big x = w.x, y = w.y, z = w.z;
  const Big l = sqrt(x * x + y * y + z * z);
  return {x / l, y / l, z / l};
}
// The textbook forms, with the cancellations they have (harmless in 50 digits).
Big big_tan2(const Big& cos_theta) { return (1 - cos_theta * cos_theta) / (cos_theta * cos_theta); }
Big big_lambda(const Big& cos_theta, const Big& alpha) {
  return (sqrt(1 + alpha * alpha * big_tan2(cos_theta)) - 1) / 2;
}
double reference_f(const Vec3& wo, const Vec3& wi, double alpha_d, double albedo, MicrofacetShadowing shadowing) {
  const BigDir o = big_unit(wo), i = big_unit(wi);
  // h = normalize(wo + wi) of the vectors as given, as the formula reads.
  // Normalising wo and wi first would move h's tangent part by ~ε, where at
  // a grazing view near the mirror direction it is itself only ~α·cos θo:
  // f's conditioning on inputs that are unit to an ulp (6e-11 relative at
  // α = 1e-3, cos θo = 1e-4), not an error of eval.
  const Big hx = Big(wo.x) + Big(wi.x), hy = Big(wo.y) + Big(wi.y), hz = Big(wo.z) + Big(wi.z);
  const Big cos_h = hz / sqrt(hx * hx + hy * hy + hz * hz);
  const Big alpha = alpha_d, a2 = alpha * alpha, t2 = big_tan2(cos_h);
  const Big d = a2 / (boost::math::constants::pi<Big>() * pow(cos_h, 4) * (a2 + t2) * (a2 + t2));
  const Big lo = big_lambda(o.z, alpha), li = big_lambda(i.z, alpha);
  const Big g2 = shadowing == MicrofacetShadowing::kSeparable ? 1 / ((1 + lo) * (1 + li)) : 1 / (1 + lo + li);
  return static_cast<double>(Big(albedo) * d * g2 / (4 * o.z * i.z));
}

// Query pairs: wi uniform on the hemisphere and wi reflected about a visible
// normal (the lobe), for each α and view.
struct Query {
  double alpha;
  Vec3 wo, wi;
};
std::vector<Query> queries(const std::vector<double>& alphas, int per_case) {
  std::vector<Query> out;
  uint64_t stream = 0;
  for (double alpha : alphas)
    for (double mu : kCosThetaO) {
      const Vec3 wo = wo_from_cos(mu);
      Rng rng(kSeed, ++stream, 0);
      for (int k = 0; k < per_case; ++k) {
        const double u1 = rng.next_double(), u2 = rng.next_double();
        const Vec3 wi = k % 2 ? sample_uniform_hemisphere(u1, u2)
                              : reflect_about(wo, sample_ggx_visible_normal(wo, alpha, u1, u2));
        if (wi.z > 0) out.push_back({alpha, wo, wi});
      }
    }
  return out;
}

// eval is a product of a dozen roundings, D's squared denominator doubling
// the relative error of its sum: a few ulps to a few tens (7 ulps measured,
// 1.5e-15). 32 ε (7.1e-15) is that with margin, and ten billion times below
// the smallest defect effect measured (ggx_separable_as_height_correlated at
// an oblique view, > 1e-4).
constexpr double kEvalRelTol = 32 * kEps;

struct EvalErrors {
  double worst = 0;
  int mismatches = 0, checked = 0;
};
EvalErrors eval_errors(MicrofacetShadowing shadowing, Defect defect, const std::vector<double>& alphas) {
  EvalErrors e;
  for (const Query& q : queries(alphas, 200)) {
    const double f = ggx(q.alpha, shadowing, defect).eval(q.wo, q.wi);
    const double ref = reference_f(q.wo, q.wi, q.alpha, 0.8, shadowing);
    const double rel = std::fabs(f - ref) / ref;
    e.worst = std::fmax(e.worst, rel);
    e.mismatches += rel <= kEvalRelTol ? 0 : 1;
    ++e.checked;
  }
  return e;
}

TEST(GgxEval, AgreesWithFiftyDigitReference) {
  for (MicrofacetShadowing s : {MicrofacetShadowing::kSeparable, MicrofacetShadowing::kHeightCorrelated}) {
    const EvalErrors e = eval_errors(s, Defect::kNone, kAlphas);
    std::cout << "  " << microfacet_shadowing_name(s) << ": " << e.checked << " queries, worst relative error "
              << e.worst << " (tolerance " << kEvalRelTol << ")\n";
    EXPECT_EQ(e.mismatches, 0) << microfacet_shadowing_name(s);
    EXPECT_GT(e.checked, 1000);
  }
}

TEST(GgxEval, DefectsDisagreeWithReference) {
  const std::vector<double> alphas{0.2, 0.5};
  struct Control {
    Defect defect;
    MicrofacetShadowing shadowing;
  };
  for (const Control& c : {Control{Defect::kGgxSeparableAsHeightCorrelated, MicrofacetShadowing::kHeightCorrelated},
                           Control{Defect::kGgxDWithoutInvPi, MicrofacetShadowing::kSeparable},
                           Control{Defect::kGgxLambdaOtherAlpha, MicrofacetShadowing::kHeightCorrelated}}) {
    const EvalErrors e = eval_errors(c.shadowing, c.defect, alphas);
    std::cout << "  " << defect_name(c.defect) << ": " << e.mismatches << "/" << e.checked
              << " queries disagree, worst relative error " << e.worst << "\n";
    EXPECT_GT(e.mismatches, e.checked / 2) << defect_name(c.defect);
  }
}

// α = 1: D = 1/π and G1 = 2μ/(1 + μ), so f has closed forms, and the
// reflected-direction density is the constant 1/(2π(1 + μo)).
TEST(GgxEval, ClosedFormsAtAlphaOne) {
  double worst = 0;
  for (const Query& q : queries({1.0}, 400)) {
    const double mo = q.wo.z, mi = q.wi.z;
    const double sep = ggx(1, MicrofacetShadowing::kSeparable, Defect::kNone, 1).eval(q.wo, q.wi);
    const double hc = ggx(1, MicrofacetShadowing::kHeightCorrelated, Defect::kNone, 1).eval(q.wo, q.wi);
    const double pdf = ggx(1).pdf(q.wo, q.wi);
    for (const auto& [value, form] : {std::pair{sep, 1 / (kPi * (1 + mo) * (1 + mi))},
                                      std::pair{hc, 1 / (2 * kPi * (mo + mi))}, std::pair{pdf, 1 / (2 * kPi * (1 + mo))}}) {
      const double rel = std::fabs(value - form) / form;
      worst = std::fmax(worst, rel);
      EXPECT_LE(rel, kEvalRelTol) << "wo.z " << mo << " wi.z " << mi;
    }
  }
  std::cout << "  alpha = 1: worst relative error against the closed forms " << worst << "\n";
}

// ---------------------------------------------------------------------------
// sample() against pdf() and eval(); the visible-normal inverse.

TEST(GgxSample, PdfAndWeightAgreeWithPdfAndEval) {
  int checked = 0;
  uint64_t stream = 0;
  for (double alpha : kAlphas)
    for (double mu : kCosThetaO)
      for (MicrofacetShadowing sh : {MicrofacetShadowing::kSeparable, MicrofacetShadowing::kHeightCorrelated}) {
        const GgxBsdf b = ggx(alpha, sh);
        const Vec3 wo = wo_from_cos(mu);
        Rng rng(kSeed, 1000 + ++stream, 0);
        for (int i = 0; i < 4000; ++i) {
          const double u1 = rng.next_double(), u2 = rng.next_double();
          const auto s = b.sample(wo, u1, u2);
          if (!s) continue;
          ++checked;
          ASSERT_FALSE(s->delta);
          const double pdf = b.pdf(wo, s->wi_local);
          ASSERT_GT(pdf, 0);
          EXPECT_LE(std::fabs(s->pdf_solid_angle - pdf), 4 * kEps * pdf);
          const double weight = b.eval(wo, s->wi_local) * s->wi_local.z / pdf;
          EXPECT_LE(std::fabs(s->weight - weight), 8 * kEps * weight);
        }
      }
  std::cout << "  " << checked << " samples checked\n";
  EXPECT_GT(checked, 100000);
}

// Round trip m → (u1, u2) → m'. The angle between m and m' is round-off
// amplified by the stretch (1/α on the tangent components, undone by α
// again) and by the cap's azimuth near its pole (c ≈ +z, u1 → 0): 1e-9 rad
// is far above both and far below a wrong inverse (an α² stretch moves m by
// ~α).
constexpr double kRoundTripAngleTol = 1e-9;

TEST(GgxVisibleNormal, InverseRoundTrip) {
  double worst = 0;
  int checked = 0, failed = 0;
  uint64_t stream = 0;
  for (double alpha : kAlphas)
    for (double mu : kCosThetaO) {
      const Vec3 wo = wo_from_cos(mu);
      Rng rng(kSeed, 2000 + ++stream, 0);
      for (int i = 0; i < 2000; ++i) {
        const double u1 = rng.next_double(), u2 = rng.next_double();
        const Vec3 m = sample_ggx_visible_normal(wo, alpha, u1, u2);
        const auto u = invert_ggx_visible_normal(wo, m, alpha);
        ++checked;
        if (!u) {
          ++failed;
          continue;
        }
        const double angle = angle_between(m, sample_ggx_visible_normal(wo, alpha, (*u)[0], (*u)[1]));
        worst = std::fmax(worst, angle);
        EXPECT_LE(angle, kRoundTripAngleTol) << "alpha " << alpha << " cos " << mu << " u " << u1 << " " << u2;
      }
    }
  std::cout << "  " << checked << " normals, " << failed << " not invertible (pdf 0), worst round-trip angle "
            << worst << " rad\n";
  EXPECT_EQ(failed, 0);
}

// ---------------------------------------------------------------------------
// Near-specular and grazing: no NaN, no Inf, no zero pdf where f > 0.

TEST(GgxRobustness, NearSpecularAndGrazing) {
  constexpr int kSamplesPerCase = 100000;
  const std::vector<double> alphas{1e-3, 2e-3, 1e-2};
  const std::vector<double> mus{1.0, 0.5, 1e-1, 1e-2, 1e-3, 1e-4};
  long samples = 0, failed = 0, nonfinite = 0, zero_pdf_with_f = 0, queries = 0, normal_pdf_zero = 0;
  uint64_t stream = 0;
  for (double alpha : alphas)
    for (double mu : mus)
      for (MicrofacetShadowing sh : {MicrofacetShadowing::kSeparable, MicrofacetShadowing::kHeightCorrelated}) {
        const GgxBsdf b = ggx(alpha, sh);
        const Vec3 wo = wo_from_cos(mu);
        Rng rng(kSeed, 3000 + ++stream, 0);
        for (int i = 0; i < kSamplesPerCase; ++i) {
          const double u1 = rng.next_double(), u2 = rng.next_double();
          const Vec3 m = sample_ggx_visible_normal(wo, alpha, u1, u2);
          const double pm = ggx_visible_normal_pdf(wo, m, alpha);
          nonfinite += is_finite(m) && std::isfinite(pm) ? 0 : 1;
          normal_pdf_zero += pm > 0 ? 0 : 1;
          ++samples;
          const auto s = b.sample(wo, u1, u2);
          if (!s) {
            ++failed;
            continue;
          }
          nonfinite += std::isfinite(s->weight) && std::isfinite(s->pdf_solid_angle) && is_finite(s->wi_local) ? 0 : 1;
          // Queries: the sampled direction, a uniform one, and one just above the horizon.
          const double u3 = rng.next_double(), u4 = rng.next_double();
          const Vec3 grazing = normalize(Vec3{std::cos(2 * kPi * u3), std::sin(2 * kPi * u3), 1e-4 * (u4 + 1e-3)});
          for (const Vec3& wi : {s->wi_local, sample_uniform_hemisphere(u3, u4), grazing}) {
            const double f = b.eval(wo, wi), pdf = b.pdf(wo, wi);
            ++queries;
            nonfinite += std::isfinite(f) && std::isfinite(pdf) ? 0 : 1;
            zero_pdf_with_f += f > 0 && !(pdf > 0) ? 1 : 0;
          }
        }
      }
  std::cout << "  " << samples << " samples (" << failed << " failed: reflected below the horizon), " << queries
            << " queries: " << nonfinite << " NaN/Inf, " << zero_pdf_with_f << " zero pdf with f > 0, "
            << normal_pdf_zero << " drawn normals of pdf 0\n";
  EXPECT_EQ(nonfinite, 0);
  EXPECT_EQ(zero_pdf_with_f, 0);
  EXPECT_EQ(normal_pdf_zero, 0);
}

}  // namespace
}  // namespace furnace
