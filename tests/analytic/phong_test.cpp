// The glossy (normalised Phong) references of analytic/phong.h against
// independent methods:
//  - the directional albedo against a 1-D integral in 50 digits whose
//    azimuthal integral is done exactly (n·ω is linear in cos φ on a ring of
//    the lobe), across view angles up to grazing and exponents 1…1000;
//  - the sphere light at e = 0 with the viewer on the normal (f = ρ/π on the
//    whole upper hemisphere) against Snyder's closed form, horizon straddle
//    included; at e = 1 against the closed form r·M·n with M = ∫_cone ωωᵀ dω;
//    at e = 10…1000 against a 1-D integral in the lobe's own frame with the
//    cone's azimuthal arcs solved exactly (tanh-sinh, a different
//    parameterisation from the library's cone-centred one);
//  - every estimator's second moment against the same lobe-frame 2-D
//    quadrature of integrands written here from the estimators' definitions;
//  - refusals of what phong.h does not solve.
// Each sweep prints its worst relative error.
#include "analytic/phong.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <boost/math/quadrature/tanh_sinh.hpp>
#include <boost/multiprecision/cpp_bin_float.hpp>
#include <gtest/gtest.h>

#include "analytic/glossy.h"
#include "analytic/moments.h"
#include "analytic/reference.h"
#include "analytic/sphere.h"
#include "core/adaptive_quadrature.h"
#include "core/error.h"

namespace furnace::analytic {
namespace {

using Real = boost::multiprecision::cpp_bin_float_50;

// The claimed accuracy of phong.h's quadrature: its relative tolerance per
// nested integral (smooth pieces converge much further, as the printed worst
// errors show).
constexpr double kReferenceTolerance = kPhongQuadratureTolerance;

PhongReceiver receiver_viewed_at(double theta, double albedo, double exponent) {
  return PhongReceiver{{0, 0, 1}, {-std::sin(theta), 0, std::cos(theta)}, albedo, exponent};
}

// ρ·∫₀^{π/2} (e+2)/(2π) cos^e α sin α ∫_{n·ω>0} (n·ω) dφ dα in the lobe frame,
// n·ω = A + B cos φ with A = cos α cos θr, B = sin α sin θr; the inner
// integral exactly: 2πA if B ≤ A, else 2(Aφ₀ + B sin φ₀), cos φ₀ = −A/B.
Real albedo_50_digits(double theta_r, double albedo, double exponent) {
  const Real ct = cos(Real(theta_r)), st = sin(Real(theta_r));
  const Real pi = boost::math::constants::pi<Real>();
  auto f = [&](Real alpha) -> Real {
    const Real A = cos(alpha) * ct, B = sin(alpha) * st;
    Real inner;
    if (B <= A) inner = 2 * pi * A;
    else {
      const Real phi0 = acos(-A / B);
      inner = 2 * (A * phi0 + B * sin(phi0));
    }
    return (exponent + 2) / (2 * pi) * pow(cos(alpha), Real(exponent)) * sin(alpha) * inner;
  };
  boost::math::quadrature::tanh_sinh<Real> ts;
  const Real kink = pi / 2 - Real(theta_r);  // the horizon starts to cut the rings
  const Real tol = 1e-25;
  Real total = kink > 0 ? ts.integrate(f, Real(0), kink, tol) : Real(0);
  total += ts.integrate(f, std::max(kink, Real(0)), pi / 2, tol);
  return albedo * total;
}

TEST(PhongAlbedo, NormalIncidenceIsTheAlbedo) {
  for (double e : {0.0, 1.0, 10.0, 100.0, 1000.0}) {
    const double a = directional_albedo(receiver_viewed_at(0, 0.8, e));
    EXPECT_NEAR(a / 0.8 - 1, 0, kReferenceTolerance) << "e = " << e;
  }
}

TEST(PhongAlbedo, MatchesExactAzimuthIntegralUpToGrazing) {
  double worst = 0;
  for (double e : {1.0, 10.0, 100.0, 1000.0})
    for (double deg : {0.0, 45.0, 70.0, 85.0, 89.0, 89.9}) {
      const double theta = deg * kPi / 180;
      const double got = directional_albedo(receiver_viewed_at(theta, 0.8, e));
      const double want = static_cast<double>(albedo_50_digits(theta, 0.8, e));
      const double rel = std::fabs(got / want - 1);
      worst = std::max(worst, rel);
      EXPECT_LT(rel, kReferenceTolerance) << "e = " << e << ", view " << deg << " deg: " << got << " vs " << want;
    }
  std::printf("directional albedo vs 50-digit exact-azimuth integral: worst relative error %.3g\n", worst);
}

TEST(PhongAlbedo, DecreasesTowardGrazing) {
  // The horizon cuts more of the lobe as the view tilts: a monotone limit check.
  for (double e : {10.0, 100.0}) {
    double previous = 1;
    for (double deg : {0.0, 30.0, 60.0, 80.0, 89.0}) {
      const double a = directional_albedo(receiver_viewed_at(deg * kPi / 180, 1, e));
      EXPECT_LE(a, previous * (1 + 1e-14)) << "e = " << e << ", " << deg << " deg";
      previous = a;
    }
  }
}

// Sphere centre at distance D in the direction at polar angle beta from n = z, azimuth phi.
Vec3 sphere_center(double D, double beta, double phi) {
  return {D * std::sin(beta) * std::cos(phi), D * std::sin(beta) * std::sin(phi), D * std::cos(beta)};
}

TEST(PhongSphere, ExponentZeroSeenAlongTheNormalIsLambertian) {
  // Viewer on the normal: r = n, so cos α = cos θ and f = ρ/π exactly on the
  // upper hemisphere; the reflected radiance is ρ/π·E (Snyder).
  double worst = 0;
  for (double ratio : {1.5, 10.0, 1000.0})
    for (double beta_deg : {0.0, 30.0, 80.0, 90.0, 100.0, 120.0}) {
      const double R = 1, D = ratio * R, beta = beta_deg * kPi / 180;
      if (D * std::cos(beta) <= -R) continue;  // wholly below the horizon: both 0
      const Vec3 c = sphere_center(D, beta, 0.4);
      const double got = sphere_reflectance(receiver_viewed_at(0, 0.7, 0), c, R);
      const double want = 0.7 * kInvPi * sphere_irradiance(c, R, {0, 0, 1});
      const double rel = std::fabs(got / want - 1);
      worst = std::max(worst, rel);
      EXPECT_LT(rel, kReferenceTolerance) << "D/R " << ratio << ", beta " << beta_deg << ": " << got << " vs " << want;
    }
  std::printf("sphere, e = 0 vs Snyder: worst relative error %.3g\n", worst);
}

TEST(PhongSphere, ExponentOneMatchesTheConeMomentClosedForm) {
  // e = 1, cone wholly where r·ω > 0 and n·ω > 0: ρ·3/(2π)·rᵀMn with
  // M = a ĉĉᵀ + b (I − ĉĉᵀ), a = 2π(1 − cos³γ)/3, b = π(2/3 − cos γ + cos³γ/3).
  double worst = 0;
  for (double view_deg : {0.0, 30.0, 60.0})
    for (double ratio : {2.0, 5.0, 100.0})
      for (double beta_deg : {0.0, 20.0, 40.0}) {
        const PhongReceiver rx = receiver_viewed_at(view_deg * kPi / 180, 0.9, 1);
        const double R = 0.5, D = ratio * R;
        const Vec3 c = sphere_center(D, beta_deg * kPi / 180, 0.0);
        const Vec3 axis = c / D, r = rx.mirror(), n = rx.n;
        const double cg = std::sqrt(1 - (R / D) * (R / D));
        const double a = 2 * kPi * (1 - cg * cg * cg) / 3, b = kPi * (2.0 / 3 - cg + cg * cg * cg / 3);
        const double rMn = a * dot(r, axis) * dot(n, axis) + b * (dot(r, n) - dot(r, axis) * dot(n, axis));
        const double want = 0.9 * 3 / (2 * kPi) * rMn;
        const double got = sphere_reflectance(rx, c, R);
        const double rel = std::fabs(got / want - 1);
        worst = std::max(worst, rel);
        EXPECT_LT(rel, kReferenceTolerance) << "view " << view_deg << ", D/R " << ratio << ", beta " << beta_deg;
      }
  std::printf("sphere, e = 1 vs cone-moment closed form: worst relative error %.3g\n", worst);
}

// The lobe frame (axis r) and the arc of azimuths φ on the ring at polar angle α
// where ω lies in the cone (ω·ĉ ≥ cos γm): A + B cos φ + C sin φ ≥ 0.
struct LobeFrameCone {
  Vec3 r, s, t, axis;
  double cos_gamma_max;
  LobeFrameCone(const PhongReceiver& rx, const Vec3& c, double R) {
    r = rx.mirror();
    const Frame f = Frame::from_normal(r);
    s = f.s, t = f.t;
    axis = normalize(c);
    cos_gamma_max = std::sqrt(1 - (R / length(c)) * (R / length(c)));
  }
  Vec3 direction(double alpha, double phi) const {
    return r * std::cos(alpha) + (s * std::cos(phi) + t * std::sin(phi)) * std::sin(alpha);
  }
  // [lo, hi], empty when lo > hi.
  std::pair<double, double> arc(double alpha) const {
    const double A = std::cos(alpha) * dot(r, axis) - cos_gamma_max;
    const double B = std::sin(alpha) * dot(s, axis), C = std::sin(alpha) * dot(t, axis);
    const double M = std::hypot(B, C);
    if (M <= std::fabs(A)) return A > 0 ? std::pair{0.0, 2 * kPi} : std::pair{1.0, 0.0};
    const double centre = std::atan2(C, B), half = std::acos(-A / M);
    return {centre - half, centre + half};
  }
  // Polar angles (from r) where the arc's topology changes.
  std::vector<double> kinks() const {
    const double gc = std::acos(std::clamp(dot(r, axis), -1.0, 1.0)), gm = std::acos(cos_gamma_max);
    return {std::fabs(gc - gm), gc + gm};
  }
};

// ∫ over the cone (wholly above the horizon) of ρ(e+2)/(2π) cos^e α (n·ω) dω,
// the azimuthal integral of n·ω = An + Bn cos φ + Cn sin φ done exactly.
double sphere_lobe_frame(const PhongReceiver& rx, const Vec3& c, double R) {
  const LobeFrameCone cone(rx, c, R);
  const double An = dot(rx.n, cone.r), Bn = dot(rx.n, cone.s), Cn = dot(rx.n, cone.t);
  auto f = [&](double alpha) {
    const auto [lo, hi] = cone.arc(alpha);
    if (!(hi > lo)) return 0.0;
    const double inner = std::cos(alpha) * An * (hi - lo) +
                         std::sin(alpha) * (Bn * (std::sin(hi) - std::sin(lo)) - Cn * (std::cos(hi) - std::cos(lo)));
    return rx.albedo * (rx.exponent + 2) / (2 * kPi) * std::pow(std::cos(alpha), rx.exponent) * inner * std::sin(alpha);
  };
  std::vector<double> cuts{0, kPi / 2};
  for (double k : cone.kinks())
    if (k > 0 && k < kPi / 2) cuts.push_back(k);
  std::sort(cuts.begin(), cuts.end());
  boost::math::quadrature::tanh_sinh<double> ts;
  double total = 0;
  for (size_t i = 0; i + 1 < cuts.size(); ++i) total += ts.integrate(f, cuts[i], cuts[i + 1], 1e-14);
  return total;
}

TEST(PhongSphere, HighExponentsMatchTheLobeFrameIntegral) {
  double worst = 0;
  for (double e : {10.0, 100.0, 1000.0})
    for (double view_deg : {20.0, 45.0, 70.0})
      for (double offset_deg : {0.0, 3.0, 10.0, 25.0})
        for (double ratio : {1.2, 3.0, 30.0}) {
          // The sphere near the mirror direction, wholly above the horizon.
          const double view = view_deg * kPi / 180, R = 1, D = ratio * R;
          const double beta = view - offset_deg * kPi / 180;
          if (D * std::cos(beta) <= R * 1.0001) continue;
          const PhongReceiver rx = receiver_viewed_at(view, 0.8, e);
          const Vec3 c = sphere_center(D, beta, 0.05);  // near r = (sin θ, 0, cos θ)
          const double got = sphere_reflectance(rx, c, R);
          const double want = sphere_lobe_frame(rx, c, R);
          if (want < 1e-30) continue;  // nothing of the lobe reaches the sphere (e = 1000 far off the mirror ray)
          const double rel = std::fabs(got / want - 1);
          worst = std::max(worst, rel);
          EXPECT_LT(rel, kReferenceTolerance) << "e " << e << ", view " << view_deg << ", offset " << offset_deg
                                              << ", D/R " << ratio << ": " << got << " vs " << want;
        }
  std::printf("sphere, e = 10..1000 vs lobe-frame integral: worst relative error %.3g\n", worst);
}

// ---------------------------------------------------------------------------
// Second moments: a Phong floor at the origin (n = z) under one light, each
// estimator's E[Y²] by 2-D quadrature in the lobe frame (α, φ) of an
// integrand written from the estimator's definition.

// Both sides at relative tolerance ≤ 1e-9 per nested integral (61-point rule
// here, 31-point in receiver.cpp); variance tests resolve ≥ 0.5 %.
constexpr double kMomentTolerance = 1e-8;

struct GlossyCase {
  double view_deg, exponent;
  bool environment;  // else a sphere light of radius 0.5 at `center`
  Vec3 center;
};

Scene glossy_scene(const GlossyCase& g) {
  Scene scene;
  scene.name = "glossy_test";
  scene.source = "phong_test";
  scene.objects.push_back({"floor", Rectangle{{-3, -3, 0}, {6, 0, 0}, {0, 6, 0}}, {0.8, Phong{g.exponent}}, 0});
  if (g.environment) scene.environment.radiance = 1.5;
  else scene.objects.push_back({"light", Sphere{g.center, 0.5}, {}, 4.0});
  return scene;
}

// E[Y²] of `strategy` by the lobe-frame quadrature (single light, pmf 1).
double independent_moment(Strategy strategy, const GlossyCase& g) {
  const PhongReceiver rx = receiver_viewed_at(g.view_deg * kPi / 180, 0.8, g.exponent);
  const Vec3 n = rx.n, r = rx.mirror();
  const Frame lobe = Frame::from_normal(r);
  const double e = g.exponent, L = g.environment ? 1.5 : 4.0, R = 0.5;
  const double D = length(g.center), cos_gm = std::sqrt(1 - (R / D) * (R / D));
  const double omega = 2 * kPi * (1 - cos_gm), area = 4 * kPi * R * R;
  const Vec3 axis = g.center / D;
  const int beta = strategy_info(strategy).mis_beta;
  // Densities in solid angle of the light strategies at ω.
  auto p_light = [&](const Vec3& w, bool by_area) {
    if (g.environment) return std::fmax(dot(n, w), 0.0) / kPi;
    if (!by_area) return 1 / omega;
    const double b = dot(w, g.center), t = b - std::sqrt(b * b - D * D + R * R);
    const Vec3 x = w * t - g.center;  // hit point relative to the centre
    return t * t / (area * dot(x / R, -w));
  };
  // Arc of φ on the ring α: above the horizon (environment) or in the cone (sphere above the horizon).
  auto arc = [&](double alpha) -> std::pair<double, double> {
    const Vec3 a = g.environment ? n : axis;
    const double A = std::cos(alpha) * dot(r, a) - (g.environment ? 0.0 : cos_gm);
    const double B = std::sin(alpha) * dot(lobe.s, a), C = std::sin(alpha) * dot(lobe.t, a);
    const double M = std::hypot(B, C);
    if (M <= std::fabs(A)) return A > 0 ? std::pair{0.0, 2 * kPi} : std::pair{1.0, 0.0};
    const double centre = std::atan2(C, B), half = std::acos(-A / M);
    return {centre - half, centre + half};
  };
  auto cos_alpha_of = [](double alpha) { return std::cos(alpha); };
  auto integrate = [&](auto value) {
    auto outer = [&](double alpha) {
      const auto [lo, hi] = arc(alpha);
      if (!(hi > lo)) return 0.0;
      auto inner = [&](double phi) {
        const Vec3 w = r * std::cos(alpha) + (lobe.s * std::cos(phi) + lobe.t * std::sin(phi)) * std::sin(alpha);
        const double cos_theta = dot(n, w), cos_alpha = std::cos(alpha);
        if (!(cos_theta > 0)) return 0.0;
        if (!(std::pow(cos_alpha_of(alpha), e) > 0)) return 0.0;  // f = p_b = 0 (underflow of cos^e α)
        const double f = 0.8 * (e + 2) / (2 * kPi) * std::pow(cos_alpha, e);
        const double p_b = (e + 1) / (2 * kPi) * std::pow(cos_alpha, e);
        return value(w, f * cos_theta * L, p_b, cos_theta) * std::sin(alpha);
      };
      return adaptive_gauss_kronrod_relative<61>(inner, lo, hi, 1e-11, 15);
    };
    std::vector<double> cuts{0, kPi / 2};
    const Vec3 a = g.environment ? n : axis;
    const double gc = std::acos(std::clamp(dot(r, a), -1.0, 1.0));
    for (double k : g.environment ? std::vector<double>{kPi / 2 - gc} : std::vector<double>{std::fabs(gc - std::acos(cos_gm)), gc + std::acos(cos_gm)})
      if (k > 0 && k < kPi / 2) cuts.push_back(k);
    std::sort(cuts.begin(), cuts.end());
    double total = 0;
    for (size_t i = 0; i + 1 < cuts.size(); ++i)
      total += adaptive_gauss_kronrod_relative<61>(outer, cuts[i], cuts[i + 1], 1e-11, 15);
    return total;
  };
  const bool by_area = strategy == Strategy::kLightArea;
  auto w_b = [&](const Vec3& w, double p_b) {
    const double pl = p_light(w, false);
    return std::pow(p_b, beta) / (std::pow(p_b, beta) + std::pow(pl, beta));
  };
  switch (strategy) {
    case Strategy::kUniformHemisphere:
      return integrate([&](const Vec3&, double h, double, double) { return h * h * 2 * kPi; });
    case Strategy::kCosineHemisphere:
      return integrate([&](const Vec3&, double h, double, double c) { return h * h * kPi / c; });
    case Strategy::kBsdf:
      return integrate([&](const Vec3&, double h, double p_b, double) { return h * h / p_b; });
    case Strategy::kLightArea:
    case Strategy::kLightSolidAngle:
      return integrate([&](const Vec3& w, double h, double, double) { return h * h / p_light(w, by_area); });
    case Strategy::kMisBalance:
    case Strategy::kMisPower: {
      const double b2 = integrate([&](const Vec3& w, double h, double p_b, double) { return std::pow(w_b(w, p_b), 2) * h * h / p_b; });
      const double l2 = integrate([&](const Vec3& w, double h, double p_b, double) {
        return std::pow(1 - w_b(w, p_b), 2) * h * h / p_light(w, false);
      });
      const double b1 = integrate([&](const Vec3& w, double h, double p_b, double) { return w_b(w, p_b) * h; });
      const double l1 = integrate([&](const Vec3& w, double h, double p_b, double) { return (1 - w_b(w, p_b)) * h; });
      return b2 + l2 + 2 * b1 * l1;
    }
    case Strategy::kMisOneSample:
      return integrate([&](const Vec3& w, double h, double p_b, double) {
        return h * h / (kOneSampleBsdfProbability * p_b + (1 - kOneSampleBsdfProbability) * p_light(w, false));
      });
    case Strategy::kPathNaive:
    case Strategy::kPathMis:
      break;  // not a direct strategy: no single-sample estimator
  }
  return NAN;
}

TEST(PhongMoments, EveryEstimatorMatchesTheLobeFrameQuadrature) {
  const std::vector<GlossyCase> cases = {
      {70, 10, true, {}},  {70, 100, true, {}},  {85, 10, true, {}},
      {45, 10, false, {0.6, 0.05, 0.7}}, {45, 100, false, {0.6, 0.05, 0.65}}, {30, 100, false, {1.5, 0.3, 2.0}},
  };
  double worst = 0;
  for (const GlossyCase& g : cases) {
    const Scene scene = glossy_scene(g);
    const PhongReceiver rx = receiver_viewed_at(g.view_deg * kPi / 180, 0.8, g.exponent);
    for (Strategy s : direct_strategies()) {
      const double got = glossy_second_moment(s, scene, {0, 0, 0}, rx.n, rx.wo, 0);
      const double want = independent_moment(s, g);
      const double rel = std::fabs(got / want - 1);
      worst = std::max(worst, rel);
      EXPECT_LT(rel, kMomentTolerance) << strategy_name(s) << ", view " << g.view_deg << ", e " << g.exponent
                                       << (g.environment ? ", sky" : ", sphere") << ": " << got << " vs " << want;
    }
  }
  std::printf("second moments vs lobe-frame quadrature: worst relative error %.3g\n", worst);
}

TEST(PhongMoments, ExceedTheSquaredMean) {
  // Var Y ≥ 0 for every estimator (Jensen), strictly for these sampled ones.
  const GlossyCase g{45, 10, false, {0.6, 0.05, 0.7}};
  const Scene scene = glossy_scene(g);
  const PhongReceiver rx = receiver_viewed_at(g.view_deg * kPi / 180, 0.8, g.exponent);
  const double mean = glossy_reflected_radiance(scene, {0, 0, 0}, rx.n, rx.wo, 0);
  for (Strategy s : direct_strategies())
    EXPECT_GT(glossy_second_moment(s, scene, {0, 0, 0}, rx.n, rx.wo, 0), mean * mean) << strategy_name(s);
}

TEST(PhongReference, RefusesWhatItDoesNotSolve) {
  const GlossyCase g{45, 10, false, {0.6, 0.05, 0.7}};
  const PhongReceiver rx = receiver_viewed_at(g.view_deg * kPi / 180, 0.8, g.exponent);
  Scene point = glossy_scene(g);
  point.point_lights.push_back({"p", {0, 0, 1}, 1.0});
  EXPECT_THROW(glossy_reflected_radiance(point, {0, 0, 0}, rx.n, rx.wo, 0), Error);
  Scene disk = glossy_scene(g);  // a disk light behind a sphere (planar lights are solved past parallel disks only)
  disk.objects[1].shape = Disk{{0, 0, 1}, {0, 0, -1}, 0.3};
  disk.objects.push_back({"sphere blocker", Sphere{{0, 0, 0.5}, 0.1}, {}, 0});
  EXPECT_THROW(glossy_reflected_radiance(disk, {0, 0, 0}, rx.n, rx.wo, 0), Error);
  Scene blocked = glossy_scene({70, 10, true, {}});
  blocked.objects.push_back({"blocker", Sphere{{0, 0, 2}, 0.5}, {}, 0});
  EXPECT_THROW(glossy_reflected_radiance(blocked, {0, 0, 0}, rx.n, rx.wo, 0), Error);
  EXPECT_THROW(glossy_second_moment(Strategy::kPathMis, glossy_scene(g), {0, 0, 0}, rx.n, rx.wo, 0), Error);
}

TEST(PhongReference, SceneImageUsesTheLobe) {
  // A camera pixel of the built-in glossy sky scene: the reference equals the
  // sky radiance times the directional albedo at the camera's view angle.
  const Scene scene = load_scene(std::string(FURNACE_SCENE_DIR) + "/glossy_environment.json");
  const Camera::Ray ray = scene.camera.pixel_center_ray(12, 8);  // the e = 100 half
  const PhongReceiver rx{{0, 0, 1}, -ray.direction, 0.8, 100};
  EXPECT_NEAR(pixel_center_radiance(scene, 12, 8) / (1.5 * directional_albedo(rx)) - 1, 0, 1e-14);
}

}  // namespace
}  // namespace furnace::analytic
