// The rough dielectric interface's references (analytic/glass.h:
// dielectric_interface_albedo) against independent values in 50 digits
// (boost::multiprecision::cpp_bin_float_50 with Gauss–Kronrod quadrature):
// the directional albedos E_R and E_T, R + s·T in both transport conventions
// (s = 1/η′² or 1, transmission_scale) and the bsdf strategy's E[Y²].
//
// The 50-digit integrands are written here from the definitions (Walter et
// al. 2007), at a unit direction ω on the sphere: above the interface the
// half vector h = normalize(ωo + ω), f_r·μi = F(ωo·h) D(h) G2/(4μo); below
// it the generalised half vector m = ±normalize(ωo + η ω) (m_z > 0),
// f_t·|μi| = (ωo·m)|ω·m| η² (1 − F) D G2/(μo (ωo·m + η ω·m)²); D(m) =
// α²/(π(α² m_z² + m_x² + m_y²)²), Λ = (√(1 + α²tan²θ) − 1)/2, F from the
// s and p amplitudes via Snell's law; bsdf's density (the visible normals,
// then a lobe with probability F) p_r = F·D_ωo(h)/(4 ωo·h), p_t = (1 − F)·
// D_ωo(m)·η²|ω·m|/(ωo·m + η ω·m)², D_ωo(m) = G1(ωo)(ωo·m)D(m)/μo, and
// E[Y²] = ∫ (f|cos|)²/p (transmission times s²). None of the library's
// formulas (its Fresnel form, its Λ, its G2/G1 weights) is used.
//
// The method, not the library's (which integrates over the visible normals
// in (w, φ), tan²θm = α²w/(1 − w)): over ω on the sphere, in polar
// coordinates (β, φ) about each lobe's peak (the mirror direction; the
// refraction of ωo at the macro normal, or the horizon in the plane of
// incidence when the view is totally reflected), φ = 0 in the plane of
// incidence, φ ∈ [0, π] twice (the integrand is even in y). Every place
// where the integrand is not smooth is a circle k·ω = b on the sphere, so
// each ring's arcs are solved exactly: the horizon; for transmission the
// microfacets' rim m_z = 0 (ω_z = −μo/η), and the cone −ωo·ω ≥ min(η, 1/η)
// of the directions refraction reaches (its edge is ωo·m = 0 for η > 1 and
// total internal reflection for η < 1); for reflection from inside, F's
// square-root kink at total internal reflection (ωo·ω = 1 − 2η²). β is cut
// where a circle starts or stops cutting the rings, where two circles cross,
// and graded by 2 from a quarter of the lobe's width (α, times |η − 1|/η
// for refraction: the lobe of η = 1.0001 is 1e-4 α wide).
//
// Tolerance: the requirement, 1e-13 relative (kPrecisionTarget).
// The library states the bound kGlassQuadratureTolerance + kRoundoffUlps·ε
// relative (verify/analytic_query.cpp prints it); it must cover every error.
// Each class prints its worst relative error. GlassPrecision.* run by
// default (two cases a class; ~35 s on a shared core, nearly all of it the
// references), GlassPrecisionSlow.* (the wide grid, 2 to 140 s a reference,
// about 24 min) are labelled slow.
// Measured (worst over E_R, E_T, R + sT and E[Y²] in both conventions):
// default: η 1.5 outside 2.9e-16, 1/1.5 inside at and beyond the critical
// angle 2.0e-16, η 1.0001 and 1/1.0001 5.0e-16; slow: η 1.5 outside, α 0.01
// to 1, μ 1 to 0.05, both forms 4.8e-16; 1/1.5 inside, μ 1 to 0.05 and
// within 0.1 % of the critical angle 2.0e-14 (E_T ~ 1e-4 at μ 0.05, α 0.01;
// the same error against a reference computed to a tolerance of 1e-18: the
// library's), else at most 1.9e-15; η 1.0001 and 1/1.0001, α 0.01 to 1, μ 1
// to 0.05 and the critical view 1.8e-14 (E_R ~ 4e-4 at μ 0.05, α 0.01), else
// at most 7.3e-15.
// The two methods agreeing to a few ε in nearly every case is the evidence
// that both are right. Before the library's quadrature was made relative
// per value and cut in v: 1.7e-4 at η 1.0001 (E_R ~ 2e-8 against an
// absolute tolerance of 1e-11) and 1.6e-10 inside at normal view.
// Negative controls: the refraction Jacobian without η² (E_T off by 1.25
// relative) and Fresnel at the macro normal (E_R 0.43, E_T 6e-3).
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <boost/multiprecision/cpp_bin_float.hpp>
#include <fmt/format.h>
#include <gtest/gtest.h>

#include "analytic/error_ledger.h"
#include "tests/analytic/big_quadrature.h"
#include "analytic/glass.h"
#include "core/material.h"
#include "core/strategy.h"

namespace furnace::analytic {
namespace {

using Big = boost::multiprecision::cpp_bin_float_50;

// The requirement on every value.
constexpr double kPrecisionTarget = 1e-13;
// The 50-digit quadratures' relative tolerance per nested integral, on
// Gauss–Kronrod's |K − G| estimate (pessimistic by many orders for a smooth
// piece): far below the target.
constexpr double kReferenceTolerance = 1e-15;
// Bisection levels of a 50-digit integral: the cuts resolve every feature first.
constexpr int kReferenceDepth = 30;
// A defective reference must be missed by more than this.
constexpr double kControlMiss = 1e-6;

Big pi_big() { return boost::math::constants::pi<Big>(); }

// Per lobe, integrated together: the mean (f·|cos|) and (f·|cos|)²/p
// (unscaled by s² for transmission).
using Values = std::array<Big, 2>;

enum class Defect {
  kNone,
  kJacobianWithoutEta2,  // the refraction Jacobian |ω·m|/(ωo·m + η ω·m)², without η²
  kMacroFresnel          // F at the macro normal, F(μo), instead of F(ωo·m)
};

struct Case {
  std::string name;
  double eta;  // the far side's index relative to the viewer's, as the library receives it
  double mu;   // cos θo
  double alpha;
  MicrofacetShadowing shadowing;
};

// A case in 50 digits, from the doubles the library sees; ωo = (sin θo, 0, μo).
struct Geometry {
  Big eta, mu_o, wo[3], alpha, lambda_o, g1o;
  MicrofacetShadowing shadowing;
  Defect defect;
  Geometry(const Case& k, Defect d) : eta(k.eta), mu_o(k.mu), alpha(k.alpha), shadowing(k.shadowing), defect(d) {
    wo[0] = sqrt(1 - mu_o * mu_o), wo[1] = 0, wo[2] = mu_o;
    lambda_o = lambda(mu_o);
    g1o = 1 / (1 + lambda_o);
  }
  Big lambda(const Big& cos_theta) const {
    const Big mu = abs(cos_theta);
    return (sqrt(1 + alpha * alpha * (1 - mu * mu) / (mu * mu)) - 1) / 2;
  }
  Big g2(const Big& cos_i) const {
    const Big li = lambda(cos_i);
    return shadowing == MicrofacetShadowing::kSeparable ? g1o / (1 + li) : 1 / (1 + lambda_o + li);
  }
  Big d(const Big* m) const {
    const Big q = alpha * alpha * m[2] * m[2] + m[0] * m[0] + m[1] * m[1];
    return alpha * alpha / (pi_big() * q * q);
  }
  // Fresnel at cos θ = c from the s and p amplitudes, θt by Snell's law.
  Big fresnel(const Big& c) const {
    const Big sin_t2 = (1 - c * c) / (eta * eta);
    if (sin_t2 >= 1) return Big(1);
    const Big ct = sqrt(1 - sin_t2);
    const Big rs = (c - eta * ct) / (c + eta * ct), rp = (eta * c - ct) / (eta * c + ct);
    return (rs * rs + rp * rp) / 2;
  }
};

Big dot3(const Big* a, const Big* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// Reflection at the unit direction w above the interface.
Values reflection_at(const Geometry& g, const Big* w) {
  if (!(w[2] > 0)) return Values{};
  Big h[3] = {g.wo[0] + w[0], g.wo[1] + w[1], g.wo[2] + w[2]};
  const Big hl = sqrt(dot3(h, h));
  for (Big& e : h) e /= hl;
  const Big c = dot3(g.wo, h);
  const Big f = g.fresnel(g.defect == Defect::kMacroFresnel ? g.mu_o : c);
  const Big d = g.d(h);
  const Big f_cos = f * d * g.g2(w[2]) / (4 * g.mu_o);  // f_r·μi
  const Big p = f * (g.g1o * c * d / g.mu_o) / (4 * c);
  return {f_cos, p > 0 ? f_cos * f_cos / p : Big(0)};
}

// Transmission at the unit direction w below the interface.
Values transmission_at(const Geometry& g, const Big* w) {
  if (!(w[2] < 0)) return Values{};
  Big m[3] = {g.wo[0] + g.eta * w[0], g.wo[1] + g.eta * w[1], g.wo[2] + g.eta * w[2]};
  Big ml = sqrt(dot3(m, m));
  if (m[2] < 0) ml = -ml;
  for (Big& e : m) e /= ml;
  const Big c = dot3(g.wo, m), ci = dot3(w, m);
  if (!(m[2] > 0) || !(c > 0) || !(ci < 0)) return Values{};
  const Big f = g.fresnel(g.defect == Defect::kMacroFresnel ? g.mu_o : c);
  if (!(f < 1)) return Values{};
  const Big denom = (c + g.eta * ci) * (c + g.eta * ci);
  const Big jacobian = (g.defect == Defect::kJacobianWithoutEta2 ? Big(1) : g.eta * g.eta) * abs(ci) / denom;
  const Big d = g.d(m);
  const Big f_cos = c * (1 - f) * d * g.g2(w[2]) / g.mu_o * jacobian;  // f_t·|μi|
  const Big p = (1 - f) * (g.g1o * c * d / g.mu_o) * jacobian;
  return {f_cos, f_cos * f_cos / p};
}

// ---------------------------------------------------------------------------
// Adaptive Gauss–Kronrod (61 points) in 50 digits for Values.
using Integrand = big_quadrature::Integrand<Values>;

// ∫ f over the cuts' span, each component to kReferenceTolerance of itself
// (big_quadrature.h: the pieces' end points smoothed, square-root ends
// included, such as 1 − F at total internal reflection).
Values integrate(const Integrand& f, std::vector<Big> cuts) {
  return big_quadrature::integrate(f, std::move(cuts), kReferenceTolerance, kReferenceDepth);
}

// ---------------------------------------------------------------------------
// One lobe over the sphere: ω = cos β p + sin β (cos φ s + sin φ y), p and
// every circle's axis in the plane of incidence (xz).

// A circle k·ω = b (k unit, in the xz plane): a constraint keeps k·ω ≥ b, a
// split only cuts the rings there.
struct Circle {
  Big k[3], b;
};

struct Lobe {
  Big p[3];                       // the polar axis (unit, y = 0)
  std::vector<Circle> constraints;
  std::vector<Circle> splits;
  Big first_width;                // the finest β cut
};

Values integrate_lobe(const Lobe& lobe, const std::function<Values(const Big*)>& at) {
  const Big pi = pi_big();
  const Big* p = lobe.p;
  const Big s[3] = {p[2], Big(0), -p[0]};
  std::vector<Circle> circles = lobe.constraints;
  circles.insert(circles.end(), lobe.splits.begin(), lobe.splits.end());
  // β range, and the kinks: where a circle starts or stops cutting the rings.
  Big beta_max = pi;
  std::vector<Big> kinks;
  for (size_t i = 0; i < circles.size(); ++i) {
    const Big kappa = acos(dot3(circles[i].k, p)), tau = acos(circles[i].b);
    if (i < lobe.constraints.size() && kappa + tau < beta_max) beta_max = kappa + tau;
    kinks.push_back(abs(kappa - tau));
    kinks.push_back(kappa + tau);
  }
  // Where two circles cross: ω = (u, ±y, w) with k1·ω = b1, k2·ω = b2.
  for (size_t i = 0; i < circles.size(); ++i)
    for (size_t j = i + 1; j < circles.size(); ++j) {
      const Big* k1 = circles[i].k;
      const Big* k2 = circles[j].k;
      const Big det = k1[0] * k2[2] - k1[2] * k2[0];
      if (abs(det) < Big(1e-30)) continue;
      const Big u = (circles[i].b * k2[2] - circles[j].b * k1[2]) / det;
      const Big w = (k1[0] * circles[j].b - k2[0] * circles[i].b) / det;
      if (u * u + w * w <= 1) kinks.push_back(acos(p[0] * u + p[2] * w));
    }
  std::vector<Big> cuts{Big(0), beta_max};
  for (Big t = lobe.first_width; t < beta_max; t *= 2) cuts.push_back(t);
  for (const Big& kink : kinks)
    if (kink > 0 && kink < beta_max) cuts.push_back(kink);
  // Each ring: A + B cos φ ≥ 0 per circle, A = cos β k·p − b, B = sin β k·s.
  const auto ring = [&](const Big& beta) {
    const Big cb = cos(beta), sb = sin(beta);
    Big lo = 0, hi = pi;
    for (const Circle& c : lobe.constraints) {
      const Big A = cb * dot3(c.k, p) - c.b, B = sb * dot3(c.k, s);
      if (abs(B) <= abs(A)) {
        if (A < 0) return Values{};
        continue;
      }
      const Big edge = acos(-A / B);
      if (B > 0) hi = std::min(hi, edge);
      else lo = std::max(lo, edge);
    }
    if (!(hi > lo)) return Values{};
    std::vector<Big> phi_cuts{lo, hi};
    for (const Circle& c : lobe.splits) {
      const Big A = cb * dot3(c.k, p) - c.b, B = sb * dot3(c.k, s);
      if (abs(B) > abs(A)) {
        const Big edge = acos(-A / B);
        if (edge > lo && edge < hi) phi_cuts.push_back(edge);
      }
    }
    const auto inner = [&](const Big& phi) {
      const Big cp = cos(phi), sp = sin(phi);
      const Big w[3] = {cb * p[0] + sb * cp * s[0], sb * sp, cb * p[2] + sb * cp * s[2]};
      Values v = at(w);
      for (Big& e : v) e *= 2 * sb;  // φ and −φ; dω = sin β dβ dφ
      return v;
    };
    return integrate(inner, phi_cuts);
  };
  return integrate(ring, cuts);
}

struct Reference {
  Values reflection, transmission;  // {E, ∫(f|cos|)²/p} of each lobe (transmission's unscaled by s²)
};

Reference reference(const Case& k, Defect defect) {
  const Geometry g(k, defect);
  const Big eta = g.eta, mu = g.mu_o, sin_o = g.wo[0];
  const Circle above{{Big(0), Big(0), Big(1)}, Big(0)}, below{{Big(0), Big(0), Big(-1)}, Big(0)};
  Reference out;
  // Reflection: about the mirror direction, above the horizon; from inside,
  // F's kink at total internal reflection (c² = (1 + ωo·ω)/2 = 1 − η²).
  Lobe r;
  r.p[0] = -sin_o, r.p[1] = 0, r.p[2] = mu;
  r.constraints = {above};
  if (eta < 1) r.splits.push_back({{g.wo[0], g.wo[1], g.wo[2]}, 1 - 2 * eta * eta});
  r.first_width = g.alpha / 4;
  out.reflection = integrate_lobe(r, [&](const Big* w) { return reflection_at(g, w); });
  // Transmission: about the refraction at the macro normal (the horizon in
  // the plane of incidence under total internal reflection).
  Lobe t;
  const Big sin_t2 = sin_o * sin_o / (eta * eta);
  if (sin_t2 < 1) t.p[0] = -sin_o / eta, t.p[1] = 0, t.p[2] = -sqrt(1 - sin_t2);
  else t.p[0] = -1, t.p[1] = 0, t.p[2] = 0;
  // The refracted directions: −ωo·ω ≥ min(η, 1/η) (ωo·m ≥ 0 for η > 1, c ≥ √k
  // for η < 1), and m_z > 0 with m ∝ ±(ωo + ηω): ω_z < −μo/η for η > 1,
  // ω_z > −μo/η for η < 1.
  const Circle cone{{-g.wo[0], -g.wo[1], -g.wo[2]}, eta < 1 ? eta : 1 / eta};
  const Circle rim =
      eta > 1 ? Circle{{Big(0), Big(0), Big(-1)}, mu / eta} : Circle{{Big(0), Big(0), Big(1)}, -mu / eta};
  t.constraints = {below, rim, cone};
  // The lobe's width: a microfacet tilt δ turns the refraction by ~δ|η − 1|/η.
  Big spread = abs(eta - 1) / (eta > 1 ? eta : Big(1));
  if (spread > 1) spread = 1;
  t.first_width = g.alpha * spread / 4;
  out.transmission = integrate_lobe(t, [&](const Big* w) { return transmission_at(g, w); });
  return out;
}

// ---------------------------------------------------------------------------
// The library's values against the reference.

double relative_error(double value, const Big& want) { return static_cast<double>(abs((Big(value) - want) / want)); }

// The relative bound `furnace analytic` states for a rough interface's values.
double stated_bound() {
  return kGlassQuadratureTolerance + kRoundoffUlps * std::numeric_limits<double>::epsilon();
}

struct Worst {
  double error = 0, seconds = 0, reference_seconds = 0;
  std::string where = "nowhere";
  int count = 0;
};

void check_case(const Case& k, const Reference& ref, Worst& worst) {
  const Dielectric d{k.eta > 1 ? k.eta : 1 / k.eta, k.alpha, k.shadowing};
  for (TransportConvention convention : {TransportConvention::kRadiance, TransportConvention::kNone}) {
    const auto start = std::chrono::steady_clock::now();
    const InterfaceAlbedo e = dielectric_interface_albedo(d, k.eta, k.mu, convention);
    worst.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const Big s = Big(transmission_scale(k.eta, convention));
    const std::string conv = transport_convention_name(convention);
    const std::pair<const char*, std::pair<double, Big>> values[] = {
        {"E_R", {e.reflection, ref.reflection[0]}},
        {"E_T", {e.transmission, ref.transmission[0]}},
        {"R + sT", {e.reflection + transmission_scale(k.eta, convention) * e.transmission,
                    ref.reflection[0] + s * ref.transmission[0]}},
        {"E[Y^2]", {e.second_moment, ref.reflection[1] + s * s * ref.transmission[1]}}};
    for (const auto& [what, pair] : values) {
      const auto& [got, want] = pair;
      const double err = relative_error(got, want);
      EXPECT_LE(err, kPrecisionTarget) << k.name << ", " << conv << ", " << what << ": " << got << " vs "
                                       << static_cast<double>(want);
      EXPECT_LE(err, stated_bound()) << k.name << ", " << conv << ", " << what << ": outside the stated bound";
      if (err > worst.error) worst.error = err, worst.where = k.name + ", " + conv + ", " + what;
      ++worst.count;
    }
  }
}

void sweep(const char* what, const std::vector<Case>& cases) {
  Worst worst;
  for (const Case& k : cases) {
    const auto start = std::chrono::steady_clock::now();
    const Reference ref = reference(k, Defect::kNone);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    worst.reference_seconds += seconds;
    Worst one;
    check_case(k, ref, one);
    std::printf("  %-58s reference %6.2f s, worst %.3g (%s)\n", k.name.c_str(), seconds, one.error, one.where.c_str());
    std::fflush(stdout);  // progress of a slow sweep, also when piped
    worst.seconds += one.seconds;
    worst.count += one.count;
    if (one.error > worst.error) worst.error = one.error, worst.where = one.where;
  }
  std::printf("[ glass ] %-46s %3d values: worst relative error %.3g (%.1f eps) at %s; %.3g s for the values under "
              "test, %.3g s for the references; stated bound %.3g\n",
              what, worst.count, worst.error, worst.error / std::numeric_limits<double>::epsilon(), worst.where.c_str(),
              worst.seconds, worst.reference_seconds, stated_bound());
}

constexpr MicrofacetShadowing kSeparable = MicrofacetShadowing::kSeparable;
constexpr MicrofacetShadowing kHeightCorrelated = MicrofacetShadowing::kHeightCorrelated;

// The views of a grid: normal, oblique and grazing.
Case make(double eta, double mu, double alpha, MicrofacetShadowing form) {
  const char* side = eta > 1 ? "outside" : "inside";
  return {fmt::format("eta {:.6g} ({}), mu {:.6g}, alpha {:g}, {}", eta, side, mu, alpha,
                      microfacet_shadowing_name(form)),
          eta, mu, alpha, form};
}

// The critical view from inside at η = 1/1.5: cos θc = √(1 − η²).
double critical_mu(double eta) { return std::sqrt((1 - eta) * (1 + eta)); }

// ---------------------------------------------------------------------------
// Default run.

TEST(GlassPrecision, Outside15) {
  sweep("eta 1.5 outside, oblique and grazing",
        {make(1.5, 0.5, 0.3, kHeightCorrelated), make(1.5, 0.05, 1.0, kSeparable)});
}

TEST(GlassPrecision, Inside15NearTheCriticalAngle) {
  const double eta = 1 / 1.5, mc = critical_mu(eta);
  sweep("eta 1/1.5 inside, at and beyond the critical angle",
        {make(eta, mc, 0.3, kHeightCorrelated), make(eta, mc * 0.99, 1.0, kSeparable)});
}

TEST(GlassPrecision, EtaNearOne) {
  sweep("eta 1.0001 and 1/1.0001", {make(1.0001, 0.5, 1.0, kHeightCorrelated), make(1 / 1.0001, 0.2, 1.0, kSeparable)});
}

// Negative controls: a reference with a defect misses the library and the
// right reference by far (and outside the library's stated bound).
TEST(GlassPrecision, DefectiveReferencesAreMissed) {
  const Case k = make(1.5, 0.5, 1.0, kSeparable);
  const Dielectric d{1.5, k.alpha, k.shadowing};
  const Reference right = reference(k, Defect::kNone);
  const InterfaceAlbedo e = dielectric_interface_albedo(d, k.eta, k.mu, TransportConvention::kRadiance);
  struct Control {
    Defect defect;
    const char* name;
    bool reflection, transmission;  // the values the defect changes
  };
  const Control controls[] = {{Defect::kJacobianWithoutEta2, "Jacobian without eta^2", false, true},
                              {Defect::kMacroFresnel, "Fresnel at the macro normal", true, true}};
  for (const Control& c : controls) {
    const Reference wrong = reference(k, c.defect);
    for (const bool transmission : {false, true}) {
      if (!(transmission ? c.transmission : c.reflection)) continue;
      const double got = transmission ? e.transmission : e.reflection;
      const Big& want_wrong = transmission ? wrong.transmission[0] : wrong.reflection[0];
      const Big& want_right = transmission ? right.transmission[0] : right.reflection[0];
      const double miss = relative_error(got, want_wrong);
      const double miss_reference = relative_error(static_cast<double>(want_right), want_wrong);
      const std::string what = fmt::format("{}, {}", c.name, transmission ? "E_T" : "E_R");
      std::printf("[ glass ] control %-36s relative difference %.3g from the library, %.3g from the right reference\n",
                  what.c_str(), miss, miss_reference);
      EXPECT_GT(miss, kControlMiss) << what;
      EXPECT_GT(miss, stated_bound()) << what;
      EXPECT_GT(miss_reference, kControlMiss) << what;
      EXPECT_LE(relative_error(got, want_right), kPrecisionTarget) << what;
    }
  }
}

// ---------------------------------------------------------------------------
// The wide grid (label slow).

TEST(GlassPrecisionSlow, Outside15) {
  std::vector<Case> cases;
  for (double alpha : {0.01, 0.1, 0.3, 1.0})
    for (double mu : {1.0, 0.5, 0.2, 0.05}) cases.push_back(make(1.5, mu, alpha, kHeightCorrelated));
  for (double mu : {1.0, 0.2, 0.05}) cases.push_back(make(1.5, mu, 0.1, kSeparable));
  sweep("eta 1.5 outside, alpha 0.01..1", cases);
}

TEST(GlassPrecisionSlow, Inside15) {
  const double eta = 1 / 1.5, mc = critical_mu(eta);
  std::vector<Case> cases;
  for (double alpha : {0.01, 0.1, 0.3, 1.0})
    for (double mu : {1.0, 0.9, mc * 1.001, mc, mc * 0.999, 0.5, 0.05})
      cases.push_back(make(eta, mu, alpha, kHeightCorrelated));
  for (double mu : {0.9, mc, 0.2}) cases.push_back(make(eta, mu, 0.1, kSeparable));
  sweep("eta 1/1.5 inside, alpha 0.01..1, near critical", cases);
}

TEST(GlassPrecisionSlow, EtaNearOne) {
  std::vector<Case> cases;
  for (double eta : {1.0001, 1 / 1.0001})
    for (double alpha : {0.01, 0.3, 1.0})
      for (double mu : {1.0, 0.5, 0.05}) cases.push_back(make(eta, mu, alpha, kHeightCorrelated));
  cases.push_back(make(1.0001, 0.5, 0.3, kSeparable));
  cases.push_back(make(1 / 1.0001, critical_mu(1 / 1.0001), 0.3, kSeparable));
  sweep("eta 1.0001 and 1/1.0001, alpha 0.01..1", cases);
}

}  // namespace
}  // namespace furnace::analytic
