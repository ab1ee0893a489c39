// The reference for lights behind rough glass (analytic/glass_light.h)
// against an independent computation: the radiance and every direct
// strategy's E[Y²] as 2-D integrals over the disk light's area, in polar
// coordinates about the disk's centre (not the receiver model's mirror map
// and polar coordinates about the lobe's peak in the mirrored plane), with
// the BTDF evaluated from 3-D vectors by Walter et al. 2007's definitions
// (m = ±normalize(ωo + η ωi), D from tan²θm, Λ from tan²θ, J = η²|ωi·m|/(η
// ωi·m + ωo·m)²) and the renderer-side Fresnel form of core/fresnel.h (the
// reference uses analytic/fresnel.h's Walter form). Nested adaptive
// Gauss–Kronrod in double to 1e-11 of each component's whole, graded cuts at the
// lobe's peak (Snell's direction) on the disk.
//
// Tolerance: the reference claims kReceiverQuadratureTolerance = 1e-9
// relative per nested integral; each value is held to kAgreement = 1e-8
// relative (the claim, summed over a handful of nested integrals and the
// four terms of multi-sample MIS, with margin), fixed before the first run.
// Measured: at most 5.2e-14 over 8 geometries × 2 conventions (α 0.1, 0.3,
// 1, both Smith forms, views 10°–70° from outside and 20°–30° from inside, a
// disk off the lobe's peak), about 1 s; the 3 disks the support's edges
// cross × 2 conventions at most 7.9e-12 (the independent integral's outer
// angle is not cut where its rays touch an edge: its own error), 0.7 s (the
// library without its edge cuts had not finished them after 3 CPU-minutes).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "analytic/error_ledger.h"
#include "analytic/glass.h"
#include "analytic/glass_light.h"
#include "core/adaptive_quadrature.h"
#include "core/fresnel.h"
#include "core/scene.h"
#include "core/strategy.h"
#include "tests/analytic/glass_light_cases.h"
#include "tests/analytic/nested_components.h"

namespace furnace::analytic {
namespace {

constexpr double kAgreement = 1e-8;
constexpr double kIndependentTolerance = 1e-8;
constexpr double kEmission = 3.0;

using glass_light_cases::Case;

// The independent BTDF: f·|cos θi| and the sampling density, from vectors.
struct Btdf {
  double f_cos = 0, pdf = 0;
};
double lambda_of(double alpha, double mu) {
  const double tan2 = (1 - mu * mu) / (mu * mu);
  return (std::sqrt(1 + alpha * alpha * tan2) - 1) / 2;
}
// without_eta2: the negative control, J without its η² (f and pdf alike, the
// pbrt-v4 2021 class).
Btdf btdf(const Vec3& n, const Vec3& wo, const Vec3& wi, double eta, double alpha, MicrofacetShadowing shadowing,
          double s, bool without_eta2 = false) {
  const double mu_o = dot(n, wo), mu_i = -dot(n, wi);
  if (!(mu_i > 0)) return {};
  Vec3 m = normalize(wo + wi * eta);
  if (dot(m, n) < 0) m = -m;
  const double o_m = dot(wo, m), i_m = dot(wi, m);
  if (!(o_m > 0) || !(i_m < 0)) return {};
  const double t = 1 - fresnel_dielectric(o_m, eta);
  const double cos_m = dot(m, n);
  const Vec3 m_across = m - n * cos_m;
  const double tan2_m = dot(m_across, m_across) / (cos_m * cos_m);
  const double a2 = alpha * alpha;
  const double d = a2 / (kPi * std::pow(cos_m, 4) * (a2 + tan2_m) * (a2 + tan2_m));
  const double lo = lambda_of(alpha, mu_o), li = lambda_of(alpha, mu_i);
  const double g1o = 1 / (1 + lo);
  const double g2 = shadowing == MicrofacetShadowing::kSeparable ? g1o / (1 + li) : 1 / (1 + lo + li);
  const double jacobian = (without_eta2 ? 1 : eta * eta) * std::fabs(i_m) / ((eta * i_m + o_m) * (eta * i_m + o_m));
  Btdf b;
  b.f_cos = s * t * d * g2 * o_m * jacobian / mu_o;  // f = s(1−F)D G2 |ωo·m| J/(μo μi), times μi
  b.pdf = t * g1o * o_m * d / mu_o * jacobian;
  return b;
}

// The case's scene (glass in z = 0, front normal +z, η 1.5; a one-sided
// disk light facing the glass), the point p and the view ωo.
struct CaseGeometry {
  Scene scene;
  Vec3 p, wo, n;
  double eta;
  Disk disk;
};
CaseGeometry setup_of(const Case& c) {
  CaseGeometry u;
  const double th = c.view_degrees * kPi / 180;
  const double side = c.from_inside ? -1 : 1;  // the viewer's side of z = 0
  u.n = {0, 0, side};
  u.p = {0.1, -0.05, 0};
  u.wo = {0, -std::sin(th), side * std::cos(th)};
  u.eta = c.from_inside ? 1 / 1.5 : 1.5;
  u.disk = Disk{{0.02, c.offset, -side * c.depth}, {0, 0, side}, c.radius};
  u.scene.name = "glass_light_test";
  u.scene.source = c.name;
  u.scene.camera.center = u.p + u.wo * 10;
  u.scene.objects.push_back(
      {"glass", Rectangle{{-3, -3, 0}, {6, 0, 0}, {0, 6, 0}}, Material{1.0, Dielectric{1.5, c.alpha, c.shadowing}}, 0});
  u.scene.objects.push_back({"light", u.disk, Material{}, kEmission});
  return u;
}

// The components integrated over the disk, per unit area ρ dρ dψ.
constexpr size_t kComponents = 12;
using Values = std::array<double, kComponents>;
enum : size_t { kMean, kBsdf, kLight, kBal2B, kBal2L, kBal1B, kBal1L, kPow2B, kPow2L, kPow1B, kPow1L, kOne };

Values independent(const Case& c, TransportConvention convention, bool without_eta2 = false) {
  const CaseGeometry u = setup_of(c);
  const double s = convention == TransportConvention::kRadiance ? 1 / (u.eta * u.eta) : 1.0;
  const Vec3 e1{1, 0, 0}, e2{0, 1, 0};
  const double area = kPi * c.radius * c.radius;
  const double cb = kOneSampleBsdfProbability;
  auto at = [&](double rho, double cs, double sn) {
    Values v{};
    const Vec3 x = u.disk.center + e1 * (rho * cs) + e2 * (rho * sn);
    const Vec3 to = x - u.p;
    const double d2 = dot(to, to), d = std::sqrt(d2);
    const Vec3 wi = to / d;
    const double cos_emission = -dot(u.disk.normal, wi);
    if (!(cos_emission > 0)) return v;
    const Btdf b = btdf(u.n, u.wo, wi, u.eta, c.alpha, c.shadowing, s, without_eta2);
    const double h = b.f_cos * kEmission;
    const double pl = d2 / (area * cos_emission), pb = b.pdf;
    const double jac = cos_emission / d2 * rho;  // dω = cos θ'/d² dA
    v[kMean] = h * jac;
    if (pb > 0) v[kBsdf] = h * h / pb * jac;
    v[kLight] = h * h / pl * jac;
    for (int beta : {1, 2}) {
      const double a = beta == 2 ? pb * pb : pb, l = beta == 2 ? pl * pl : pl;
      const double wb = a / (a + l), wl = l / (a + l);
      const size_t k = beta == 1 ? kBal2B : kPow2B;
      if (pb > 0) v[k] = wb * wb * h * h / pb * jac;
      v[k + 1] = wl * wl * h * h / pl * jac;
      v[k + 2] = wb * h * jac;
      v[k + 3] = wl * h * jac;
    }
    v[kOne] = h * h / (cb * pb + (1 - cb) * pl) * jac;
    return v;
  };
  // Snell's direction from p and where it meets the disk's plane: the lobe's peak.
  const double mu_o = dot(u.n, u.wo);
  const double cos_t2 = 1 - (1 - mu_o * mu_o) / (u.eta * u.eta);
  // Past the critical angle (from inside) the macro interface reflects ωo totally: no peak, no graded cuts.
  const Vec3 t = -u.wo / u.eta + u.n * (mu_o / u.eta - std::sqrt(std::fmax(cos_t2, 0.0)));
  const Vec3 peak = cos_t2 > 0 ? u.p + t * (dot(u.disk.center - u.p, u.disk.normal) / dot(t, u.disk.normal))
                               : u.disk.center;
  const double px = peak.x - u.disk.center.x, py = peak.y - u.disk.center.y;
  const double rho_peak = std::hypot(px, py), psi_peak = std::atan2(py, px);
  const double width = c.alpha * c.depth / 4;  // the lobe's footprint scale on the disk (a guess for cuts)
  std::vector<double> rho_cuts{0.0, c.radius};
  for (double w = width; w < c.radius; w *= 2)
    for (double r : {rho_peak - w, rho_peak, rho_peak + w})
      if (r > 0 && r < c.radius) rho_cuts.push_back(r);
  std::sort(rho_cuts.begin(), rho_cuts.end());
  std::vector<double> psi_cuts{psi_peak - kPi, psi_peak + kPi, psi_peak};
  for (double w = width / std::fmax(rho_peak, width); w < kPi; w *= 2)
    psi_cuts.push_back(psi_peak - w), psi_cuts.push_back(psi_peak + w);
  std::sort(psi_cuts.begin(), psi_cuts.end());
  // Two passes (NestedPass): a coarse one for each component's whole, then
  // absolute tolerances kIndependentTolerance × that whole, shared out over
  // the pieces by length.
  auto integrate = [&](const NestedPass<Values>& pass) {
    auto inner = [&](double psi) {
      const double cs = std::cos(psi), sn = std::sin(psi);
      // Along this ray, also cut where the BTDF's support ends: −ωo·ωi =
      // min(η, 1/η) (ωo·m = 0 for η > 1, total internal reflection of ωi for
      // η < 1: a kink) and n·m = 0 (η|n·ωi| = μo, a jump): the roots of
      // quadratics in ρ for x − p = c0 + ρe.
      std::vector<double> cuts = rho_cuts;
      const Vec3 c0 = u.disk.center - u.p, e = e1 * cs + e2 * sn;
      const auto roots = [&](double qa, double qb, double qc) {
        const double disc = qb * qb - 4 * qa * qc;
        if (!(disc > 0) || qa == 0) return;
        for (double r : {(-qb - std::sqrt(disc)) / (2 * qa), (-qb + std::sqrt(disc)) / (2 * qa)})
          if (r > 0 && r < c.radius) cuts.push_back(r);
      };
      const double k = std::fmin(u.eta, 1 / u.eta), k2 = k * k, a = -dot(u.wo, e), b = -dot(u.wo, c0);
      roots(a * a - k2, 2 * (a * b - dot(c0, e) * k2), b * b - dot(c0, c0) * k2);
      const double far = u.eta * std::fabs(dot(c0, u.n)) / dot(u.n, u.wo);  // |x − p| where η|n·ωi| = μo
      roots(1, 2 * dot(c0, e), dot(c0, c0) - far * far);
      std::sort(cuts.begin(), cuts.end());
      Values sum{};
      for (size_t i = 0; i + 1 < cuts.size(); ++i)
        if (cuts[i + 1] > cuts[i])
          add_scaled(sum, pass.inner([&](double rho) { return at(rho, cs, sn); }, cuts[i], cuts[i + 1]));
      return sum;
    };
    Values total{};
    for (size_t i = 0; i + 1 < psi_cuts.size(); ++i) add_scaled(total, pass.outer(inner, psi_cuts[i], psi_cuts[i + 1]));
    return total;
  };
  const double outer = double(psi_cuts.size()), inner = 2 * kPi * double(rho_cuts.size());
  const Values coarse = integrate(NestedPass<Values>(1e-4, nullptr, outer, inner));
  const Values total = integrate(NestedPass<Values>(kIndependentTolerance, &coarse, outer, inner));
  return total;
}

// The disks wholly inside the BTDF's support for their point and view
// (ωo·m > 0, ωi·m < 0, n·m > 0 at every disk point: checked by
// DisksLieInsideTheSupport below), and the disks its edges cross
// (glass_light_cases.h; the library cuts at the edges).
const std::vector<Case>& cases() { return glass_light_cases::inside_support(); }
const std::vector<Case>& crossing_cases() { return glass_light_cases::crossing_support(); }

// The smallest and the largest of min(ωo·m, −ωi·m, n·m) over the disk (its
// centre and 2000 points on each of two circles): the support's edge crosses
// the disk where they straddle 0.
std::pair<double, double> support_margin_range(const Case& c) {
  const CaseGeometry u = setup_of(c);
  double lo = INFINITY, hi = -INFINITY;
  for (int k = 0; k < 2000; ++k) {
    const double a = 2 * kPi * k / 2000;
    for (double r : {c.radius, c.radius / 2, 0.0}) {
      const Vec3 wi = normalize(u.disk.center + Vec3{r * std::cos(a), r * std::sin(a), 0} - u.p);
      Vec3 m = normalize(u.wo + wi * u.eta);
      if (dot(m, u.n) < 0) m = -m;
      const double margin = std::fmin(dot(u.wo, m), std::fmin(-dot(wi, m), dot(u.n, m)));
      lo = std::fmin(lo, margin), hi = std::fmax(hi, margin);
    }
  }
  return {lo, hi};
}

// The cases' precondition: the smallest margin is positive.
TEST(GlassLightReference, DisksLieInsideTheSupport) {
  for (const Case& c : cases()) EXPECT_GT(support_margin_range(c).first, 0.05) << c.name;
}

TEST(GlassLightReference, CrossingDisksStraddleTheSupportsEdge) {
  for (const Case& c : crossing_cases()) {
    const auto [lo, hi] = support_margin_range(c);
    EXPECT_LT(lo, -0.05) << c.name;
    EXPECT_GT(hi, 0.05) << c.name;
  }
}

// The reference against the independent integral for case c: every value within kAgreement.
void expect_matches_independent(const Case& c, TransportConvention convention) {
  const CaseGeometry u = setup_of(c);
  const Values v = independent(c, convention);
  ASSERT_GT(v[kMean], 0) << c.name;
  struct Check {
    const char* what;
    double reference, expected;
  };
  std::vector<Check> checks;
  double bound = 0;
  {
    ErrorLedger ledger;
    const double radiance = glass_light_radiance(u.scene, u.p, u.wo, 0, convention);
    bound = ledger.bound(radiance) / radiance;
    checks.push_back({"radiance", radiance, v[kMean]});
  }
  auto moment = [&](Strategy s) {
    return glass_light_second_moment(s, u.scene, u.p, u.wo, 0, convention, LightSelection::kUniform);
  };
  checks.push_back({"bsdf", moment(Strategy::kBsdf), v[kBsdf]});
  checks.push_back({"light_area", moment(Strategy::kLightArea), v[kLight]});
  checks.push_back({"light_solid_angle", moment(Strategy::kLightSolidAngle), v[kLight]});  // a disk: by area
  checks.push_back({"mis_balance", moment(Strategy::kMisBalance), v[kBal2B] + v[kBal2L] + 2 * v[kBal1B] * v[kBal1L]});
  checks.push_back({"mis_power", moment(Strategy::kMisPower), v[kPow2B] + v[kPow2L] + 2 * v[kPow1B] * v[kPow1L]});
  checks.push_back({"mis_one_sample", moment(Strategy::kMisOneSample), v[kOne]});
  double worst = 0;
  for (const Check& k : checks) {
    const double relative = std::fabs(k.reference - k.expected) / std::fabs(k.expected);
    worst = std::fmax(worst, relative);
    EXPECT_LE(relative, kAgreement) << c.name << " " << k.what << ": reference " << k.reference << ", independent "
                                    << k.expected;
  }
  std::printf("%s %s: radiance %.12g, worst relative difference %.2e over radiance and 6 E[Y^2] (radiance's ledger "
              "bound %.1e)\n",
              c.name.c_str(), transport_convention_name(convention).c_str(), v[kMean], worst, bound);
}

using CaseParam = std::tuple<size_t, TransportConvention>;

// Every case of a list in both conventions, and the test's name: the case's and the convention's.
auto params_of(const std::vector<Case>& list) {
  return testing::Combine(testing::Range(size_t(0), list.size()),
                          testing::Values(TransportConvention::kRadiance, TransportConvention::kNone));
}
template <const std::vector<Case>& (*List)()>
std::string param_name(const testing::TestParamInfo<CaseParam>& info) {
  return List()[std::get<0>(info.param)].name +
         (std::get<1>(info.param) == TransportConvention::kRadiance ? "Radiance" : "None");
}

class GlassLightReference : public testing::TestWithParam<CaseParam> {};

TEST_P(GlassLightReference, MatchesAnIntegralOverTheDisk) {
  expect_matches_independent(cases()[std::get<0>(GetParam())], std::get<1>(GetParam()));
}

INSTANTIATE_TEST_SUITE_P(Cases, GlassLightReference, params_of(cases()), param_name<cases>);

class GlassLightAcrossTheSupport : public testing::TestWithParam<CaseParam> {};

TEST_P(GlassLightAcrossTheSupport, MatchesAnIntegralOverTheDisk) {
  expect_matches_independent(crossing_cases()[std::get<0>(GetParam())], std::get<1>(GetParam()));
}

INSTANTIATE_TEST_SUITE_P(Cases, GlassLightAcrossTheSupport, params_of(crossing_cases()),
                         param_name<crossing_cases>);

// Negative control: the independent integral with f and pdf both without η²
// misses the reference's radiance and its light_area E[Y²] by far more than
// kAgreement (the bsdf E[Y²] ratio h²/p keeps one factor of the error).
TEST(GlassLightReference, JacobianWithoutEta2IsFarFromTheReference) {
  for (size_t i : {size_t(1), size_t(6)}) {  // from outside and from inside
    const Case& c = cases()[i];
    const CaseGeometry u = setup_of(c);
    const Values wrong = independent(c, TransportConvention::kRadiance, true);
    const double radiance = glass_light_radiance(u.scene, u.p, u.wo, 0, TransportConvention::kRadiance);
    const double light = glass_light_second_moment(Strategy::kLightArea, u.scene, u.p, u.wo, 0,
                                                   TransportConvention::kRadiance, LightSelection::kUniform);
    EXPECT_GT(std::fabs(wrong[kMean] / radiance - 1), 0.1) << c.name;
    EXPECT_GT(std::fabs(wrong[kLight] / light - 1), 0.1) << c.name;
  }
}

// The two conventions differ by s² = 1/η′⁴ in E[Y²] and s in the mean, exactly.
TEST(GlassLightReference, ConventionsDifferByTheScale) {
  const CaseGeometry u = setup_of(cases()[1]);
  const double r = glass_light_radiance(u.scene, u.p, u.wo, 0, TransportConvention::kRadiance);
  const double none = glass_light_radiance(u.scene, u.p, u.wo, 0, TransportConvention::kNone);
  EXPECT_NEAR(r * 1.5 * 1.5 / none, 1.0, 1e-14);
}

// Outside the kind: a reflecting light, a smooth glass, a lit environment are refused in one sentence.
TEST(GlassLightReference, RefusesWhatItDoesNotSolve) {
  CaseGeometry u = setup_of(cases()[1]);
  EXPECT_FALSE(glass_light_scene_refusal(u.scene).has_value());
  Scene reflecting = u.scene;
  reflecting.objects[1].material.albedo = 0.5;
  EXPECT_TRUE(glass_light_scene_refusal(reflecting).has_value());
  Scene smooth = u.scene;
  smooth.objects[0].material = Material{1.0, Dielectric{1.5, 0.0, MicrofacetShadowing::kHeightCorrelated}};
  EXPECT_TRUE(glass_light_scene_refusal(smooth).has_value());
  Scene sky = u.scene;
  sky.environment.radiance = 1;
  EXPECT_TRUE(glass_light_scene_refusal(sky).has_value());
  EXPECT_THROW(glass_light_second_moment(Strategy::kCosineHemisphere, u.scene, u.p, u.wo, 0,
                                         TransportConvention::kRadiance, LightSelection::kUniform),
               Error);
  EXPECT_THROW(glass_light_second_moment(Strategy::kPathMis, u.scene, u.p, u.wo, 0, TransportConvention::kRadiance,
                                         LightSelection::kUniform),
               Error);
}

}  // namespace
}  // namespace furnace::analytic
