// The GGX receiver's references (analytic/ggx.h) against independent values
// in 50 digits (boost::multiprecision::cpp_bin_float_50 with Gauss–Kronrod
// quadrature): the radiance and every direct strategy's E[Y²] (uniform and
// cosine hemisphere, bsdf, light_area, light_solid_angle, mis_balance,
// mis_power, mis_one_sample), one light at a time (pmf 1).
//
// The 50-digit integrands are written here from the definitions, at a unit
// direction ω: h = normalize(ωo + ω) and D(h) = α²/(π(α²h_z² + h_x² + h_y²)²),
// Λ = (√(1 + α²tan²θ) − 1)/2 (no stable rewrite: 50 digits spare the
// cancellation), the VNDF reflected density D_ωo(h)/(4 ωo·h) with
// D_ωo(m) = G1(ωo)(ωo·m)D(m)/μo, the sphere's density by area from the ray's
// near intersection. None of the library's two-cosine formulas is used.
//
// Two methods, neither the library's (which integrates over a cap about n or
// the light's axis, in the half-angle variable of the azimuth):
//  - 1-D, where the integrand depends on θ = angle(n, ω) alone: the sky and a
//    sphere centred on the normal at normal view (ωo = n, any α; the two
//    Smith forms coincide, Λ(ωo) = 0), and the sky at α = 1 at any view (D =
//    1/π and f, p_b depend on μi alone). ∫ g dω = 2π ∫ g(θ) sin θ dθ, cut
//    at θ = α·2^k so every piece resolves the lobe (width ~2α at normal view).
//  - 2-D in the lobe frame: polar angle β about the mirror direction r and
//    azimuth φ about r (φ = 0 in the plane of incidence), each ring's arcs
//    inside the horizon and the light's cone solved exactly (both are
//    half-spaces k·ω ≥ b), β cut at α·2^k and where the arcs change topology,
//    φ cut in the plane of incidence (where the lobe, ~2αμo wide across it,
//    peaks on each ring).
//
// Tolerance: the requirement, 1e-13 relative (kPrecisionTarget).
// Each class prints its worst relative error and the time of the values
// under test. Classes with 2-D references are the suite GgxPrecisionSlow
// (label slow: 10.5 min on a shared core, nearly all of it the 50-digit
// references, 8–110 s each); the 1-D ones run by default (~1 s).
// Measured (worst over the radiance and the eight strategies): normal-view
// sky 3.7e-16, sphere on the normal 4.8e-16, α = 1 sky oblique/grazing
// 5.3e-16, oblique/grazing sky at α 0.05/0.3 1.3e-14, oblique sky at α = 1e-3
// 4.8e-14, sphere near the specular direction (α 1e-3…1) 5.2e-14. Negative controls: references
// with a defect (D without 1/π, the other Smith form, p_b without G1(ωo))
// must be missed by far.
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

#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <boost/multiprecision/cpp_bin_float.hpp>
#include <fmt/format.h>
#include <gtest/gtest.h>

#include "analytic/ggx.h"
#include "analytic/moments.h"
#include "core/strategy.h"

namespace furnace::analytic {
namespace {

using Big = boost::multiprecision::cpp_bin_float_50;

// The requirement on every reference value (radiance and E[Y²]).
constexpr double kPrecisionTarget = 1e-13;
// The 50-digit quadratures' relative tolerance per nested integral: far
// below the target (Gauss–Kronrod's error estimate is pessimistic: at 1e-16,
// 1e-18 and 1e-19 with other cuts the values agreed to 20 digits, sky at
// μo 0.5 with α 0.3 and 1e-3).
constexpr double kReferenceTolerance = 1e-16;
// A defective reference must be missed by more than this (a control that
// passes within a few times the target would prove nothing).
constexpr double kControlMiss = 1e-6;

Big pi_big() { return boost::math::constants::pi<Big>(); }

// The values integrated together, at every node (one set of nodes serves
// all: the geometry of a direction is computed once).
enum Component {
  kMean,        // h = L·f·μi
  kUniform,     // 2π h²
  kCosine,      // π h²/μi
  kBsdf,        // h²/p_b
  kSolidAngle,  // h²/p_l (light_solid_angle)
  kArea,        // h²/p_l (light_area)
  kBalanceB2, kBalanceL2, kBalanceB1, kBalanceL1,  // w_b² h²/p_b, w_l² h²/p_l, w_b h, w_l h
  kPowerB2, kPowerL2, kPowerB1, kPowerL1,
  kOneSample,  // h²/(c p_b + (1 − c) p_l)
  kComponentCount
};
using Values = std::array<Big, kComponentCount>;

enum class Defect { kNone, kDWithoutInvPi, kOtherSmithForm, kPdfWithoutG1 };

// One configuration: a GGX floor (n = z) seen from ωo = (−sin θo, 0, μo),
// under the sky or one sphere light.
struct Case {
  std::string name;
  double cos_theta_o;
  double alpha;
  MicrofacetShadowing shadowing;
  bool environment;
  Vec3 center;  // sphere light's centre relative to the receiving point
  double radius;
};

constexpr double kAlbedo = 0.8;
constexpr double kSkyRadiance = 1.5;
constexpr double kSphereRadiance = 4.0;

Vec3 view_of(const Case& c) { return {-std::sqrt((1 - c.cos_theta_o) * (1 + c.cos_theta_o)), 0, c.cos_theta_o}; }

// The geometry of a case in 50 digits, from the doubles the library sees.
struct Geometry {
  Big wo[3], mu_o, alpha, albedo, radiance;
  bool environment;
  Big c[3], D2, R, cone_solid_angle, area;
  MicrofacetShadowing shadowing;
  explicit Geometry(const Case& k) {
    const Vec3 w = view_of(k);
    wo[0] = w.x, wo[1] = w.y, wo[2] = w.z;
    mu_o = wo[2];
    alpha = k.alpha;
    albedo = kAlbedo;
    environment = k.environment;
    radiance = environment ? kSkyRadiance : kSphereRadiance;
    shadowing = k.shadowing;
    c[0] = k.center.x, c[1] = k.center.y, c[2] = k.center.z;
    D2 = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
    R = k.radius;
    if (!environment) {
      const Big cos_cone = sqrt(1 - R * R / D2);
      cone_solid_angle = 2 * pi_big() * (1 - cos_cone);
      area = 4 * pi_big() * R * R;
    }
  }
  Big lambda(const Big& mu) const {
    const Big tan2 = (1 - mu * mu) / (mu * mu);
    return (sqrt(1 + alpha * alpha * tan2) - 1) / 2;
  }
};

// Every component at the unit direction (x, y, z), z = μi > 0, ω inside the
// light's directions (the caller's domain).
Values components(const Geometry& g, const Big& x, const Big& y, const Big& z, Defect defect) {
  Values v;
  const Big& mu_i = z;
  // The half vector, normalised.
  Big hx = g.wo[0] + x, hy = g.wo[1] + y, hz = g.wo[2] + z;
  const Big hl = sqrt(hx * hx + hy * hy + hz * hz);
  hx /= hl, hy /= hl, hz /= hl;
  const Big a2 = g.alpha * g.alpha;
  const Big q = a2 * hz * hz + hx * hx + hy * hy;
  const Big d = a2 / ((defect == Defect::kDWithoutInvPi ? Big(1) : pi_big()) * q * q);
  const Big lo = g.lambda(g.mu_o), li = g.lambda(mu_i);
  const Big g1o = 1 / (1 + lo), g1i = 1 / (1 + li);
  const bool separable = (g.shadowing == MicrofacetShadowing::kSeparable) != (defect == Defect::kOtherSmithForm);
  const Big g2 = separable ? g1o * g1i : 1 / (1 + lo + li);
  const Big f = g.albedo * d * g2 / (4 * g.mu_o * mu_i);
  const Big h = g.radiance * f * mu_i;
  // VNDF: D_ωo(m) = G1(ωo)·(ωo·m)·D(m)/μo, reflected: /(4 ωo·m).
  const Big wo_m = g.wo[0] * hx + g.wo[1] * hy + g.wo[2] * hz;
  const Big vndf = (defect == Defect::kPdfWithoutG1 ? Big(1) : g1o) * wo_m * d / g.mu_o;
  const Big p_b = vndf / (4 * wo_m);
  Big p_sa, p_area;
  if (g.environment) {
    p_sa = p_area = mu_i / pi_big();
  } else {
    p_sa = 1 / g.cone_solid_angle;
    const Big b = x * g.c[0] + y * g.c[1] + z * g.c[2];
    const Big t = b - sqrt(b * b - g.D2 + g.R * g.R);  // near intersection
    const Big px = x * t - g.c[0], py = y * t - g.c[1], pz = z * t - g.c[2];
    const Big cos_emission = -(x * px + y * py + z * pz) / g.R;
    p_area = t * t / (g.area * cos_emission);
  }
  const Big h2 = h * h;
  v[kMean] = h;
  v[kUniform] = 2 * pi_big() * h2;
  v[kCosine] = pi_big() * h2 / mu_i;
  v[kBsdf] = h2 / p_b;
  v[kSolidAngle] = h2 / p_sa;
  v[kArea] = h2 / p_area;
  const Big wb1 = p_b / (p_b + p_sa), wb2 = p_b * p_b / (p_b * p_b + p_sa * p_sa);
  v[kBalanceB2] = wb1 * wb1 * h2 / p_b;
  v[kBalanceL2] = (1 - wb1) * (1 - wb1) * h2 / p_sa;
  v[kBalanceB1] = wb1 * h;
  v[kBalanceL1] = (1 - wb1) * h;
  v[kPowerB2] = wb2 * wb2 * h2 / p_b;
  v[kPowerL2] = (1 - wb2) * (1 - wb2) * h2 / p_sa;
  v[kPowerB1] = wb2 * h;
  v[kPowerL1] = (1 - wb2) * h;
  const Big cb = kOneSampleBsdfProbability;
  v[kOneSample] = h2 / (cb * p_b + (1 - cb) * p_sa);
  return v;
}

// The expected value of `strategy` (E[Y²]), or the radiance for none.
Big expected(const Values& v, const Strategy* strategy) {
  if (strategy == nullptr) return v[kMean];
  switch (*strategy) {
    case Strategy::kUniformHemisphere: return v[kUniform];
    case Strategy::kCosineHemisphere: return v[kCosine];
    case Strategy::kBsdf: return v[kBsdf];
    case Strategy::kLightSolidAngle: return v[kSolidAngle];
    case Strategy::kLightArea: return v[kArea];
    case Strategy::kMisBalance: return v[kBalanceB2] + v[kBalanceL2] + 2 * v[kBalanceB1] * v[kBalanceL1];
    case Strategy::kMisPower: return v[kPowerB2] + v[kPowerL2] + 2 * v[kPowerB1] * v[kPowerL1];
    case Strategy::kMisOneSample: return v[kOneSample];
    case Strategy::kPathNaive:
    case Strategy::kPathMis:
      break;
  }
  return Big(-1);
}

// ---------------------------------------------------------------------------
// Adaptive Gauss–Kronrod (61 points) in 50 digits for Values: one rule per
// piece, bisected until every component's error estimate meets its share of
// its absolute tolerance.
using Rule = boost::math::quadrature::gauss_kronrod<Big, 61>;
using Gauss = boost::math::quadrature::gauss<Big, 30>;
constexpr int kReferenceDepth = 30;  // bisection levels: the cuts and the end-point map resolve every feature first

Values rule(const std::function<Values(const Big&)>& f, const Big& a, const Big& b, Values* error) {
  static const auto& x = Rule::abscissa();
  static const auto& wk = Rule::weights();
  static const auto& wg = Gauss::weights();
  const Big mean = (a + b) / 2, scale = (b - a) / 2;
  Values kronrod{}, gauss{};
  const Values f0 = f(mean);
  for (int c = 0; c < kComponentCount; ++c) kronrod[c] = f0[c] * wk[0];  // 0 is no Gauss node (30 points)
  for (size_t i = 1; i < x.size(); ++i) {
    const Values fp = f(mean + scale * x[i]), fm = f(mean - scale * x[i]);
    for (int c = 0; c < kComponentCount; ++c) {
      kronrod[c] += (fp[c] + fm[c]) * wk[i];
      if (i % 2 == 1) gauss[c] += (fp[c] + fm[c]) * wg[i / 2];
    }
  }
  Values value;
  for (int c = 0; c < kComponentCount; ++c) {
    (*error)[c] = abs(kronrod[c] - gauss[c]) * scale;
    value[c] = kronrod[c] * scale;
  }
  return value;
}

// `value` and `error`: the rule's on [a, b], already computed.
Values adaptive(const std::function<Values(const Big&)>& f, const Big& a, const Big& b, const Values& tolerance,
                int depth, const Values& value, const Values& error) {
  bool met = true;
  for (int c = 0; c < kComponentCount; ++c) met = met && error[c] <= tolerance[c];
  if (met || depth == 0) return value;
  Values half = tolerance;
  for (Big& t : half) t /= 2;
  const Big mid = (a + b) / 2;
  Values left_error, right_error;
  const Values left_value = rule(f, a, mid, &left_error), right_value = rule(f, mid, b, &right_error);
  Values sum = adaptive(f, a, mid, half, depth - 1, left_value, left_error);
  const Values right = adaptive(f, mid, b, half, depth - 1, right_value, right_error);
  for (int c = 0; c < kComponentCount; ++c) sum[c] += right[c];
  return sum;
}

// ∫ f over [cuts[0], cuts.back()] split at the cuts, each component to
// kReferenceTolerance relative to a first estimate (one rule per piece).
// Each piece [a, b] in the variable t ∈ [0, 1] of x = a + (b − a)(3t² − 2t³),
// dx = 6(b − a)t(1 − t) dt: a square-root end point (an arc's end as the
// ring passes a kink, a sphere's rim in the area density) becomes smooth.
Values integrate(const std::function<Values(const Big&)>& f, std::vector<Big> cuts) {
  std::sort(cuts.begin(), cuts.end());
  cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
  std::vector<std::function<Values(const Big&)>> pieces;
  for (size_t i = 0; i + 1 < cuts.size(); ++i) {
    const Big a = cuts[i], w = cuts[i + 1] - cuts[i];
    pieces.push_back([&f, a, w](const Big& t) {
      Values v = f(a + w * t * t * (3 - 2 * t));
      const Big jacobian = 6 * w * t * (1 - t);
      for (Big& e : v) e *= jacobian;
      return v;
    });
  }
  Values first{};
  std::vector<Values> values(pieces.size()), errors(pieces.size());
  for (size_t i = 0; i < pieces.size(); ++i) {
    values[i] = rule(pieces[i], Big(0), Big(1), &errors[i]);
    for (int c = 0; c < kComponentCount; ++c) first[c] += values[i][c];
  }
  Values tolerance;
  const double count = double(std::max<size_t>(pieces.size(), 1));
  for (int c = 0; c < kComponentCount; ++c) tolerance[c] = Big(kReferenceTolerance) * abs(first[c]) / count;
  Values sum{};
  for (size_t i = 0; i < pieces.size(); ++i) {
    const Values piece = adaptive(pieces[i], Big(0), Big(1), tolerance, kReferenceDepth, values[i], errors[i]);
    for (int c = 0; c < kComponentCount; ++c) sum[c] += piece[c];
  }
  return sum;
}

// Cuts at `first`·ratio^k below `end`, and 0 and `end`: pieces that resolve a
// lobe of width ~α at 0 and its tail (first ~ α).
std::vector<Big> graded_cuts(const Big& first, const Big& end, int ratio) {
  std::vector<Big> cuts{Big(0), end};
  for (Big t = first; t < end; t *= ratio) cuts.push_back(t);
  return cuts;
}

// ---------------------------------------------------------------------------
// 1-D: the integrand depends on θ alone (normal view, or α = 1): over
// θ ∈ [0, θmax] (π/2 for the sky, the cone's half-angle for a sphere on the
// normal), ω = (sin θ, 0, cos θ), dω = 2π sin θ dθ.
Values reference_1d(const Case& k, Defect defect) {
  const Geometry g(k);
  const Big theta_max = g.environment ? boost::math::constants::half_pi<Big>() : asin(g.R / sqrt(g.D2));
  auto f = [&](const Big& theta) {
    const Big s = sin(theta), c = cos(theta);
    Values v = c > 0 ? components(g, s, Big(0), c, defect) : Values{};
    for (Big& x : v) x *= 2 * pi_big() * s;
    return v;
  };
  return integrate(f, graded_cuts(g.alpha / 8, theta_max, 2));
}

// ---------------------------------------------------------------------------
// 2-D in the lobe frame about r = (sin θo, 0, μo): ω = cos β r +
// sin β (cos φ s + sin φ t), s = (μo, 0, −sin θo) in the plane of incidence,
// t = (0, 1, 0).

// The azimuths φ ∈ [−π, π] of a ring where A + B cos φ + C sin φ ≥ 0, as
// intervals.
using Intervals = std::vector<std::pair<Big, Big>>;
Intervals arcs(const Big& A, const Big& B, const Big& C) {
  const Big pi = pi_big();
  const Big M = sqrt(B * B + C * C);
  if (M <= abs(A)) return A > 0 ? Intervals{{-pi, pi}} : Intervals{};
  const Big centre = atan2(C, B), half = acos(-A / M);
  const Big lo = centre - half, hi = centre + half;
  if (lo < -pi) return {{-pi, hi}, {lo + 2 * pi, pi}};
  if (hi > pi) return {{-pi, hi - 2 * pi}, {lo, pi}};
  return {{lo, hi}};
}
Intervals intersect(const Intervals& a, const Intervals& b) {
  Intervals out;
  for (const auto& [a0, a1] : a)
    for (const auto& [b0, b1] : b) {
      const Big lo = a0 > b0 ? a0 : b0, hi = a1 < b1 ? a1 : b1;
      if (hi > lo) out.push_back({lo, hi});
    }
  return out;
}

// A half-space k·ω ≥ b (the horizon: k = n, b = 0; the cone: k = ĉ, b = cos γm).
struct HalfSpace {
  Big k[3], b;
};

Values reference_2d(const Case& k, Defect defect) {
  const Geometry g(k);
  const Big pi = pi_big();
  const Big r[3] = {-g.wo[0], -g.wo[1], g.wo[2]};  // 2μo n − ωo, unit to 50 digits as ωo is
  const Big rl = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
  const Big ru[3] = {r[0] / rl, r[1] / rl, r[2] / rl};
  const Big sin_r = sqrt(ru[0] * ru[0] + ru[1] * ru[1]);
  const Big s[3] = {ru[2], Big(0), -sin_r}, t[3] = {Big(0), Big(1), Big(0)};
  std::vector<HalfSpace> constraints{{{Big(0), Big(0), Big(1)}, Big(0)}};
  if (!g.environment) {
    const Big D = sqrt(g.D2);
    constraints.push_back({{g.c[0] / D, g.c[1] / D, g.c[2] / D}, sqrt(1 - g.R * g.R / g.D2)});
  }
  auto dot3 = [](const Big* a, const Big* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
  // The outer range ends where a constraint excludes every ring; kinks where a
  // constraint starts or stops cutting the rings.
  Big beta_max = pi;
  std::vector<Big> kinks;
  for (const HalfSpace& h : constraints) {
    const Big kappa = acos(dot3(h.k, ru)), tau = acos(h.b);
    if (kappa + tau < beta_max) beta_max = kappa + tau;
    kinks.push_back(abs(kappa - tau));
  }
  std::vector<Big> cuts = graded_cuts(g.alpha / 2, beta_max, 4);
  for (const Big& kink : kinks)
    if (kink > 0 && kink < beta_max) cuts.push_back(kink);
  auto ring = [&](const Big& beta) {
    const Big cb = cos(beta), sb = sin(beta);
    Intervals allowed{{-pi, pi}};
    for (const HalfSpace& h : constraints)
      allowed = intersect(allowed, arcs(cb * dot3(h.k, ru) - h.b, sb * dot3(h.k, s), sb * dot3(h.k, t)));
    Values sum{};
    for (const auto& [lo, hi] : allowed) {
      std::vector<Big> phi_cuts{lo, hi};
      if (lo < 0 && hi > 0) phi_cuts.push_back(Big(0));  // the plane of incidence (φ = ±π are ends)
      auto inner = [&](const Big& phi) {
        const Big cp = cos(phi), sp = sin(phi);
        const Big x = cb * ru[0] + sb * (cp * s[0] + sp * t[0]);
        const Big y = cb * ru[1] + sb * (cp * s[1] + sp * t[1]);
        const Big z = cb * ru[2] + sb * (cp * s[2] + sp * t[2]);
        Values v = z > 0 ? components(g, x, y, z, defect) : Values{};
        for (Big& e : v) e *= sb;
        return v;
      };
      const Values piece = integrate(inner, phi_cuts);
      for (int c = 0; c < kComponentCount; ++c) sum[c] += piece[c];
    }
    return sum;
  };
  return integrate(ring, cuts);
}

// ---------------------------------------------------------------------------
// The library's values for a case: radiance and each direct strategy's E[Y²].

Scene scene_of(const Case& k) {
  Scene scene;
  scene.name = "ggx_precision";
  scene.source = "ggx_precision_test";
  Material m{BsdfType::kGgx, kAlbedo, 0};
  m.ggx_alpha = k.alpha;
  m.shadowing = k.shadowing;
  scene.objects.push_back({"floor", Rectangle{{-3, -3, 0}, {6, 0, 0}, {0, 6, 0}}, m, 0});
  if (k.environment) scene.environment.radiance = kSkyRadiance;
  else scene.objects.push_back({"light", Sphere{k.center, k.radius}, {}, kSphereRadiance});
  return scene;
}

double relative_error(double value, const Big& want) {
  return static_cast<double>(abs((Big(value) - want) / want));
}

struct Worst {
  double error = 0, seconds = 0, slowest = 0;
  std::string where = "nowhere";
  int count = 0;
};

// Compares the library with `reference` on every quantity of the case.
void check_case(const Case& k, const Values& reference, Worst& worst) {
  const Scene scene = scene_of(k);
  const Vec3 n{0, 0, 1}, wo = view_of(k), p{0, 0, 0};
  std::vector<Strategy> strategies = direct_strategies();
  for (size_t i = 0; i <= strategies.size(); ++i) {
    const Strategy* s = i == 0 ? nullptr : &strategies[i - 1];
    const auto start = std::chrono::steady_clock::now();
    const double got = s == nullptr ? ggx_reflected_radiance(scene, p, n, wo, 0) : ggx_second_moment(*s, scene, p, n, wo, 0);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    worst.seconds += seconds;
    worst.slowest = std::max(worst.slowest, seconds);
    const Big want = expected(reference, s);
    const double err = relative_error(got, want);
    const std::string what = s == nullptr ? "radiance" : strategy_name(*s);
    EXPECT_LE(err, kPrecisionTarget) << k.name << ", " << what << ": " << got << " vs " << static_cast<double>(want);
    if (err > worst.error) worst.error = err, worst.where = k.name + ", " + what;
    ++worst.count;
  }
}

void print(const char* what, const Worst& w) {
  std::printf("[ ggx ] %-44s %3d values: worst relative error %.3g (%.1f eps) at %s; %.3g s for the values under test "
              "(slowest %.3g s)\n",
              what, w.count, w.error, w.error / std::numeric_limits<double>::epsilon(), w.where.c_str(), w.seconds,
              w.slowest);
}

// Cases and their reference method.
void sweep(const char* what, const std::vector<Case>& cases, bool one_dimensional) {
  Worst worst;
  for (const Case& k : cases) {
    const auto start = std::chrono::steady_clock::now();
    const Values reference = one_dimensional ? reference_1d(k, Defect::kNone) : reference_2d(k, Defect::kNone);
    std::printf("  %s: reference %.3g s\n", k.name.c_str(),
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    std::fflush(stdout);  // progress of a slow sweep, also when piped
    check_case(k, reference, worst);
  }
  print(what, worst);
}

constexpr MicrofacetShadowing kSeparable = MicrofacetShadowing::kSeparable;
constexpr MicrofacetShadowing kHeightCorrelated = MicrofacetShadowing::kHeightCorrelated;

// Normal view: the sky for α from kMinGgxAlpha to 1 (1-D).
TEST(GgxPrecision, NormalViewSky) {
  std::vector<Case> cases;
  for (double alpha : {scene_limits::kMinGgxAlpha, 0.01, 0.05, 0.2, 0.5, 1.0})
    cases.push_back({fmt::format("sky, normal view, alpha {:g}", alpha), 1.0, alpha, kHeightCorrelated, true, {}, 0});
  sweep("sky, normal view, alpha 1e-3..1", cases, true);
}

// Normal view: a sphere centred on the normal (the specular direction), its
// cone wide and narrow against the lobe (1-D).
TEST(GgxPrecision, NormalViewSphereOnTheSpecularDirection) {
  std::vector<Case> cases;
  for (double alpha : {scene_limits::kMinGgxAlpha, 0.05, 0.5, 1.0})
    for (double ratio : {0.01, 0.5}) {
      cases.push_back({fmt::format("sphere on the normal, R/D {:g}, alpha {:g}", ratio, alpha), 1.0, alpha,
                       kSeparable, false, {0, 0, 2.0}, 2.0 * ratio});
    }
  sweep("sphere on the normal, normal view", cases, true);
}

// α = 1: f and p_b depend on μi alone, the sky 1-D at any view; oblique and
// grazing views, both Smith forms.
TEST(GgxPrecision, AlphaOneSkyObliqueAndGrazing) {
  std::vector<Case> cases;
  for (double mu : {0.5, 0.2, 0.05})
    for (MicrofacetShadowing form : {kSeparable, kHeightCorrelated})
      cases.push_back({fmt::format("sky, alpha 1, mu_o {:g}, {}", mu, microfacet_shadowing_name(form)), mu, 1.0, form,
                       true, {}, 0});
  sweep("sky, alpha 1, mu_o 0.5/0.2/0.05", cases, true);
}

// Negative controls: references with a defect are missed by far.
TEST(GgxPrecision, DefectiveReferencesAreMissed) {
  const Case oblique{"sky, alpha 1, mu_o 0.5", 0.5, 1.0, kHeightCorrelated, true, {}, 0};
  const Case normal{"sky, normal view, alpha 0.05", 1.0, 0.05, kHeightCorrelated, true, {}, 0};
  struct Control {
    const Case& k;
    Defect defect;
    const char* name;
    Strategy strategy;
  };
  const Control controls[] = {{normal, Defect::kDWithoutInvPi, "D without 1/pi", Strategy::kCosineHemisphere},
                              {oblique, Defect::kOtherSmithForm, "separable values for height-correlated",
                               Strategy::kUniformHemisphere},
                              {oblique, Defect::kPdfWithoutG1, "p_b without G1(wo)", Strategy::kBsdf}};
  for (const Control& c : controls) {
    const Values wrong = reference_1d(c.k, c.defect);
    const Scene scene = scene_of(c.k);
    const double got = ggx_second_moment(c.strategy, scene, {0, 0, 0}, {0, 0, 1}, view_of(c.k), 0);
    const double miss = relative_error(got, expected(wrong, &c.strategy));
    std::printf("[ ggx ] control %-40s (%s): relative difference %.3g\n", c.name, strategy_name(c.strategy).c_str(),
                miss);
    EXPECT_GT(miss, kControlMiss) << c.name;
  }
}

// ---------------------------------------------------------------------------
// 2-D references (label slow).
// Oblique and grazing views of the sky for α < 1 (both Smith forms at two of them).
TEST(GgxPrecisionSlow, ObliqueSky) {
  std::vector<Case> cases;
  auto add = [&](double mu, double alpha, MicrofacetShadowing form) {
    cases.push_back({fmt::format("sky, mu_o {:g}, alpha {:g}, {}", mu, alpha, microfacet_shadowing_name(form)), mu,
                     alpha, form, true, {}, 0});
  };
  for (double mu : {0.5, 0.2, 0.05})
    for (double alpha : {0.05, 0.3}) add(mu, alpha, kHeightCorrelated);
  add(0.2, 0.3, kSeparable);
  add(0.05, 0.05, kSeparable);
  sweep("sky, oblique/grazing, alpha 0.05/0.3", cases, false);
}

// The sky at the smallest α, oblique.
TEST(GgxPrecisionSlow, ObliqueSkySmallestAlpha) {
  std::vector<Case> cases;
  for (double mu : {0.5, 0.2})
    cases.push_back({fmt::format("sky, mu_o {:g}, alpha 1e-3", mu), mu, scene_limits::kMinGgxAlpha, kHeightCorrelated,
                     true, {}, 0});
  sweep("sky, oblique, alpha 1e-3", cases, false);
}

// A sphere light near the specular direction, oblique view, α from 1e-3 to 1:
// centre 0.05 rad off the mirror direction (sin θo, 0, μo), distance 2,
// radius 0.2 (half-angle 0.1 rad: the mirror direction inside the cone).
TEST(GgxPrecisionSlow, SphereNearTheSpecularDirection) {
  std::vector<Case> cases;
  auto add = [&](double mu, double alpha, MicrofacetShadowing form) {
    const Vec3 r{std::sqrt(1 - mu * mu), 0, mu};
    cases.push_back({fmt::format("sphere near specular, mu_o {:g}, alpha {:g}, {}", mu, alpha,
                                 microfacet_shadowing_name(form)),
                     mu, alpha, form, false, normalize(r + Vec3{0, 0.05, 0}) * 2.0, 0.2});
  };
  for (double alpha : {scene_limits::kMinGgxAlpha, 0.05, 0.3, 1.0}) add(0.5, alpha, kHeightCorrelated);
  add(0.5, 0.05, kSeparable);
  add(0.5, 1.0, kSeparable);
  for (double alpha : {scene_limits::kMinGgxAlpha, 0.05}) add(0.2, alpha, kHeightCorrelated);
  sweep("sphere near the specular direction", cases, false);
}

}  // namespace
}  // namespace furnace::analytic
