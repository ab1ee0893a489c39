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
// Lights: the sky, a sphere, and planar lights (disk, rectangle, triangle;
// density by area d²/(A cos θ'), light_solid_angle 1/Ω of a rectangle's or a
// triangle's whole spherical polygon, Ω by Van Oosterom–Strackee in 50
// digits) with disk_occluder's occluder (a black disk parallel to the light,
// between: its visible region the disk minus the occluder's central image).
//
// Three methods, none the library's (which integrates over a cap about n or
// the light's axis in the half-angle variable of the azimuth, and a planar
// light's region in polar coordinates about the mirror direction's hit):
//  - 1-D, where the integrand depends on θ = angle(n, ω) alone: the sky, a
//    sphere centred on the normal, and a disk (occluded or not) centred on
//    the normal and parallel to the receiver at normal view (ωo = n, any α;
//    the two Smith forms coincide, Λ(ωo) = 0), and the sky and such disks at
//    α = 1 at any view (D = 1/π and f, p_b depend on μi alone; the disk's
//    densities on θ alone). ∫ g dω = 2π ∫ g(θ) sin θ dθ, cut
//    at θ = α·2^k so every piece resolves the lobe (width ~2α at normal view).
//  - 2-D in the lobe frame: polar angle β about the mirror direction r and
//    azimuth φ about r (φ = 0 in the plane of incidence), each ring's arcs
//    inside the horizon and the light's cone solved exactly (both are
//    half-spaces k·ω ≥ b), β cut at α·2^k and where the arcs change topology,
//    φ cut in the plane of incidence (where the lobe, ~2αμo wide across it,
//    peaks on each ring).
//  - 2-D over a planar light's surface in Cartesian (affine) coordinates of
//    its plane, cut at the mirror hit and graded by 2 from it, and at the
//    occluder image's chords' changes (reference_plane).
//
// Tolerance: the requirement, 1e-13 relative (kPrecisionTarget).
// Each class prints its worst relative error and the time of the values
// under test. Classes with 2-D references are the suite GgxPrecisionSlow
// (label slow: 28 min on a shared core, nearly all of it the 50-digit
// references, 8–110 s each; the planar classes 3.5 to 4 min each, a
// reference 1–160 s); the 1-D ones run by default (~1 s each).
// Every value is also computed under an ErrorLedger (error_ledger.h): its
// error must lie within the ledger's bound, and the ledger must have
// received the quadratures' reports (no report: only the round-off allowance).
// Measured (worst over the radiance and the eight strategies): normal-view
// sky 3.7e-16, sphere on the normal 4.8e-16, α = 1 sky oblique/grazing
// 5.3e-16, oblique/grazing sky at α 0.05/0.3 1.3e-14, oblique sky at α = 1e-3
// 4.8e-14, sphere near the specular direction (α 1e-3…1) 5.2e-14; planar:
// disk on the normal at normal view (α 1e-3…1, R/H 0.375 and 0.01) 7.7e-16,
// occluded disk at normal view 6.1e-16, disk, small disk and occluded disk at
// α = 1, μo 0.5/0.2/0.05, both forms 6.0e-16 (2.9e-13 before the polar
// centre was kept within 2 region sizes: receiver_planar.cpp, kFarCentre);
// slow: rectangle and triangle near the specular direction (α 1e-3…1)
// 7.1e-15, a vertical rectangle at grazing μo 0.2/0.05 9.7e-15 (round-off of
// cos θ near the horizon, ~ε·extent/height), occluded disk with the mirror
// direction at the shadow edge, normal and μo 0.5, 4.8e-16. The ledger's
// bound: at most 3.9e-9 relative, error/bound at most 0.046. Negative
// controls: references with a defect (D without 1/π, the other Smith form,
// p_b without G1(ωo), the occluded disk wholly visible, light_area's density
// without 1/cos θ') must be missed by far, and outside the ledger's bound.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include <boost/multiprecision/cpp_bin_float.hpp>
#include <fmt/format.h>
#include <gtest/gtest.h>

#include "analytic/error_ledger.h"
#include "tests/analytic/big_quadrature.h"
#include "analytic/ggx.h"
#include "analytic/glossy.h"
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

enum class Defect {
  kNone, kDWithoutInvPi, kOtherSmithForm, kPdfWithoutG1,
  kNoOccluder,                // the occluded disk's whole light counted as visible
  kAreaWithoutEmissionCosine  // light_area's density d²/A, without 1/cos θ'
};

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
  // A planar light (environment false; center and radius unused): a disk,
  // rectangle or triangle facing the receiving point, and a disk occluder
  // parallel to it, strictly between (disk_occluder's configuration).
  std::optional<Shape> planar{};
  std::optional<Disk> occluder{};
};

constexpr double kAlbedo = 0.8;
constexpr double kSkyRadiance = 1.5;
constexpr double kSphereRadiance = 4.0;
constexpr double kPlanarRadiance = 4.0;  // disk_occluder's emission

Vec3 view_of(const Case& c) { return {-std::sqrt((1 - c.cos_theta_o) * (1 + c.cos_theta_o)), 0, c.cos_theta_o}; }

// The geometry of a case in 50 digits, from the doubles the library sees.
struct Geometry {
  Big wo[3], mu_o, alpha, albedo, radiance;
  bool environment;
  Big c[3], D2, R, cone_solid_angle, area;
  MicrofacetShadowing shadowing;
  // A planar light: its plane's unit normal N toward the receiving point (the
  // origin) and N·P0 < 0 for a point P0 of it; its whole area (light_area)
  // and the Ω light_solid_angle samples uniformly (a triangle's or a
  // rectangle's whole spherical polygon; 0 for a disk: by area).
  bool planar = false;
  Big N[3], NP0, plane_area, plane_omega;
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
    if (k.planar) {
      planar = true;
      radiance = kPlanarRadiance;
      plane_of_light(*k.planar);
    } else if (!environment) {
      const Big cos_cone = sqrt(1 - R * R / D2);
      cone_solid_angle = 2 * pi_big() * (1 - cos_cone);
      area = 4 * pi_big() * R * R;
    }
  }
  void plane_of_light(const Shape& shape) {
    auto big = [](const Vec3& v, Big* out) { out[0] = v.x, out[1] = v.y, out[2] = v.z; };
    Big P0[3], normal[3];
    if (const auto* d = std::get_if<Disk>(&shape)) {
      big(d->center, P0), big(d->normal, normal);
      plane_area = pi_big() * Big(d->radius) * Big(d->radius);
      plane_omega = 0;
    } else {
      std::vector<Vec3> corners;
      if (const auto* r = std::get_if<Rectangle>(&shape)) {
        const auto c = r->corners();
        corners.assign(c.begin(), c.end());
      } else {
        const auto& t = std::get<Triangle>(shape);
        corners = {t.p0, t.p1, t.p2};
      }
      std::vector<std::array<Big, 3>> v(corners.size());
      for (size_t i = 0; i < corners.size(); ++i) big(corners[i], v[i].data());
      big(corners[0], P0);
      // Area and Ω as fans of triangles (v0, vi, vi+1) from the corners in
      // 50 digits; Ω by Van Oosterom and Strackee: tan(Ω/2) =
      // |a·(b×c)|/(|a||b||c| + (a·b)|c| + (a·c)|b| + (b·c)|a|).
      Big area2 = 0, omega = 0, nx = 0, ny = 0, nz = 0;
      auto dot3 = [](const std::array<Big, 3>& a, const std::array<Big, 3>& b) {
        return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
      };
      auto cross3 = [](const std::array<Big, 3>& a, const std::array<Big, 3>& b) {
        return std::array<Big, 3>{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
      };
      for (size_t i = 1; i + 1 < v.size(); ++i) {
        const std::array<Big, 3> e1{v[i][0] - v[0][0], v[i][1] - v[0][1], v[i][2] - v[0][2]};
        const std::array<Big, 3> e2{v[i + 1][0] - v[0][0], v[i + 1][1] - v[0][1], v[i + 1][2] - v[0][2]};
        const auto x = cross3(e1, e2);
        area2 += sqrt(dot3(x, x));
        nx += x[0], ny += x[1], nz += x[2];
        const auto &a = v[0], &b = v[i], &c = v[i + 1];
        const Big la = sqrt(dot3(a, a)), lb = sqrt(dot3(b, b)), lc = sqrt(dot3(c, c));
        omega += 2 * atan2(abs(dot3(a, cross3(b, c))),
                           la * lb * lc + dot3(a, b) * lc + dot3(a, c) * lb + dot3(b, c) * la);
      }
      plane_area = area2 / 2;
      normal[0] = nx, normal[1] = ny, normal[2] = nz;
      plane_omega = omega >= Big(kMinSampledSolidAngle) ? omega : Big(0);
    }
    const Big nl = sqrt(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]);
    for (int i = 0; i < 3; ++i) N[i] = normal[i] / nl;
    NP0 = N[0] * P0[0] + N[1] * P0[1] + N[2] * P0[2];
    if (!(NP0 < 0)) throw std::logic_error("the planar light faces away from the receiving point");
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
  } else if (g.planar) {
    // The ray t·ω meets the plane N·(x − P0) = 0 at t = N·P0/(N·ω), cos θ' = −N·ω.
    const Big nw = g.N[0] * x + g.N[1] * y + g.N[2] * z;
    const Big t = g.NP0 / nw;
    const Big cos_emission = defect == Defect::kAreaWithoutEmissionCosine ? Big(1) : Big(-nw);
    p_area = t * t / (g.plane_area * cos_emission);
    p_sa = g.plane_omega > 0 ? 1 / g.plane_omega : p_area;
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
constexpr int kReferenceDepth = 30;  // bisection levels: the cuts and the end-point map resolve every feature first

// ∫ f over the cuts' span, each component to kReferenceTolerance of itself
// (big_quadrature.h: the pieces' end points smoothed, square-root ends
// included).
Values integrate(const big_quadrature::Integrand<Values>& f, std::vector<Big> cuts) {
  return big_quadrature::integrate(f, std::move(cuts), kReferenceTolerance, kReferenceDepth);
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
// θ ∈ [θmin, θmax] (π/2 for the sky, the cone's half-angle for a sphere on the
// normal, atan(R/H) for a disk of radius R facing the receiver at height H on
// the normal; θmin = atan(r/h) behind a disk occluder of radius r at height h
// on the normal, else 0), ω = (sin θ, 0, cos θ), dω = 2π sin θ dθ.
Values reference_1d(const Case& k, Defect defect) {
  const Geometry g(k);
  Big theta_max, theta_min = 0;
  if (g.environment) {
    theta_max = boost::math::constants::half_pi<Big>();
  } else if (k.planar) {
    const Disk& light = std::get<Disk>(*k.planar);  // coaxial: centre on the normal, parallel to the receiver
    theta_max = atan(Big(light.radius) / Big(light.center.z));
    if (k.occluder && defect != Defect::kNoOccluder) theta_min = atan(Big(k.occluder->radius) / Big(k.occluder->center.z));
  } else {
    theta_max = asin(g.R / sqrt(g.D2));
  }
  auto f = [&](const Big& theta) {
    const Big s = sin(theta), c = cos(theta);
    Values v = c > 0 ? components(g, s, Big(0), c, defect) : Values{};
    for (Big& x : v) x *= 2 * pi_big() * s;
    return v;
  };
  std::vector<Big> cuts{theta_min};
  for (const Big& t : graded_cuts(g.alpha / 8, theta_max, 2))
    if (t > theta_min) cuts.push_back(t);
  return integrate(f, cuts);
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
// 2-D over a planar light's own surface, in affine coordinates (u, v) of its
// plane: X = O + u·E1 + v·E2 (the receiving point at the origin), dω =
// cos θ'·dA/|X|² = (−N·X)·|E1 × E2|/|X|³ du dv. A rectangle: O its corner,
// E1, E2 its edges, (u, v) ∈ [0, 1]²; a triangle: O = p0, E1 = p1 − p0,
// E2 = p2 − p0, v ∈ [0, 1 − u]; a disk: O its centre, E1, E2 an orthonormal
// pair of its plane times R, v ∈ ±√(1 − u²), minus the chord of an
// occluder's image (the occluder disk, parallel, projected from the origin:
// a circle of radius r·H/h about the projection of its centre). Not the
// library's polar coordinates about the mirror hit: Cartesian, with cuts in
// u and in v graded by 2 from the mirror direction's hit point (u0, v0),
// the first ~α|X0|/8 from it, and at the occluder image's extreme u (where
// the chords change) — the lights lie wholly above the horizon.
Values reference_plane(const Case& k, Defect defect) {
  const Geometry g(k);
  using B3 = std::array<Big, 3>;
  auto big = [](const Vec3& v) { return B3{Big(v.x), Big(v.y), Big(v.z)}; };
  auto dot3 = [](const B3& a, const B3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
  auto cross3 = [](const B3& a, const B3& b) {
    return B3{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  };
  auto sub = [](const B3& a, const B3& b) { return B3{a[0] - b[0], a[1] - b[1], a[2] - b[2]}; };
  B3 O, E1, E2;
  enum { kRectangle, kTriangle, kDisk } kind;
  Big oc_u = 0, oc_v = 0, oc_r = -1;  // the occluder's image in (u, v); radius < 0: none
  if (const auto* r = std::get_if<Rectangle>(&*k.planar)) {
    kind = kRectangle, O = big(r->corner), E1 = big(r->edge_u), E2 = big(r->edge_v);
  } else if (const auto* t = std::get_if<Triangle>(&*k.planar)) {
    kind = kTriangle, O = big(t->p0), E1 = sub(big(t->p1), O), E2 = sub(big(t->p2), O);
  } else {
    const Disk& d = std::get<Disk>(*k.planar);
    kind = kDisk, O = big(d.center);
    const B3 N{g.N[0], g.N[1], g.N[2]};
    // a ⟂ N from the axis least aligned with N, b = N × a.
    B3 axis{Big(0), Big(0), Big(0)};
    int least = 0;
    for (int i = 1; i < 3; ++i)
      if (abs(N[i]) < abs(N[least])) least = i;
    axis[least] = 1;
    B3 a = cross3(N, axis);
    const Big la = sqrt(dot3(a, a));
    for (Big& e : a) e /= la;
    const B3 b = cross3(N, a);
    const Big R = d.radius;
    for (int i = 0; i < 3; ++i) E1[i] = a[i] * R, E2[i] = b[i] * R;
    if (k.occluder && defect != Defect::kNoOccluder) {
      const B3 c = big(k.occluder->center);
      const Big scale = g.NP0 / dot3(N, c);  // heights along N: the light's over the occluder's
      const B3 image = sub(B3{c[0] * scale, c[1] * scale, c[2] * scale}, O);
      oc_u = dot3(image, a) / R, oc_v = dot3(image, b) / R, oc_r = Big(k.occluder->radius) * scale / R;
    }
  }
  const B3 cross12 = cross3(E1, E2);
  const Big jacobian = sqrt(dot3(cross12, cross12));
  const B3 N{g.N[0], g.N[1], g.N[2]};
  // The mirror direction's hit (u0, v0), and the grading's first step in u and v.
  const B3 r{-g.wo[0], -g.wo[1], g.wo[2]};
  const Big nr = dot3(N, r);
  Big u0 = 0, v0 = 0, step_u = g.alpha / 8, step_v = g.alpha / 8;
  if (nr < 0) {
    const Big t = g.NP0 / nr;
    const B3 rel = sub(B3{r[0] * t, r[1] * t, r[2] * t}, O);
    const Big a11 = dot3(E1, E1), a12 = dot3(E1, E2), a22 = dot3(E2, E2);
    const Big b1 = dot3(rel, E1), b2 = dot3(rel, E2), det = a11 * a22 - a12 * a12;
    u0 = (b1 * a22 - b2 * a12) / det, v0 = (a11 * b2 - a12 * b1) / det;
    step_u = g.alpha * t / (8 * sqrt(a11)), step_v = g.alpha * t / (8 * sqrt(a22));
  }
  // Cuts graded by 2 on both sides of `centre` inside [lo, hi].
  auto graded = [](const Big& lo, const Big& hi, const Big& centre, const Big& step) {
    std::vector<Big> cuts{lo, hi};
    if (centre > lo && centre < hi) cuts.push_back(centre);
    for (Big d = step; d < hi - lo; d *= 2)
      for (const Big& x : {centre - d, centre + d})
        if (x > lo && x < hi) cuts.push_back(x);
    return cuts;
  };
  auto inner_at = [&](const Big& u) {
    std::vector<std::pair<Big, Big>> spans;
    if (kind == kRectangle) spans = {{Big(0), Big(1)}};
    else if (kind == kTriangle) spans = {{Big(0), 1 - u}};
    else {
      const Big half = sqrt(1 - u * u);
      const Big du = u - oc_u;
      if (oc_r > 0 && abs(du) < oc_r) {
        const Big chord = sqrt(oc_r * oc_r - du * du);
        const Big lo = oc_v - chord, hi = oc_v + chord;
        spans = {{-half, lo < half ? lo : half}, {hi > -half ? hi : -half, half}};
      } else {
        spans = {{-half, half}};
      }
    }
    Values sum{};
    for (const auto& [lo, hi] : spans) {
      if (!(hi > lo)) continue;
      auto f = [&](const Big& v) {
        B3 X;
        for (int i = 0; i < 3; ++i) X[i] = O[i] + u * E1[i] + v * E2[i];
        const Big d2 = dot3(X, X), d = sqrt(d2);
        Values val = components(g, X[0] / d, X[1] / d, X[2] / d, defect);
        const Big measure = -dot3(N, X) * jacobian / (d2 * d);
        for (Big& e : val) e *= measure;
        return val;
      };
      const Values piece = integrate(f, graded(lo, hi, v0, step_v));
      for (int c = 0; c < kComponentCount; ++c) sum[c] += piece[c];
    }
    return sum;
  };
  const Big u_lo = kind == kDisk ? Big(-1) : Big(0);
  std::vector<Big> cuts = graded(u_lo, Big(1), u0, step_u);
  if (oc_r > 0) {
    std::vector<Big> kinks{oc_u - oc_r, oc_u + oc_r};
    // Where the image's circle crosses the disk's (the chords' ends change curve).
    const Big d = sqrt(oc_u * oc_u + oc_v * oc_v);
    if (d > 0) {
      const Big a = (1 - oc_r * oc_r + d * d) / (2 * d), h2 = 1 - a * a;
      if (h2 > 0)
        for (const Big& x : {(a * oc_u - sqrt(h2) * oc_v) / d, (a * oc_u + sqrt(h2) * oc_v) / d}) kinks.push_back(x);
    }
    for (const Big& x : kinks)
      if (x > u_lo && x < 1) cuts.push_back(x);
  }
  return integrate(inner_at, cuts);
}

// ---------------------------------------------------------------------------
// The library's values for a case: radiance and each direct strategy's E[Y²].

Scene scene_of(const Case& k) {
  Scene scene;
  scene.name = "ggx_precision";
  scene.source = "ggx_precision_test";
  const Material m{kAlbedo, Ggx{k.alpha, k.shadowing, std::nullopt}};
  scene.objects.push_back({"floor", Rectangle{{-3, -3, 0}, {6, 0, 0}, {0, 6, 0}}, m, 0});
  if (k.environment) scene.environment.radiance = kSkyRadiance;
  else if (k.planar) scene.objects.push_back({"light", *k.planar, {}, kPlanarRadiance});
  else scene.objects.push_back({"light", Sphere{k.center, k.radius}, {}, kSphereRadiance});
  // disk_occluder's occluder: black (albedo 0), parallel to the light.
  if (k.occluder) scene.objects.push_back({"occluder", *k.occluder, Material{0.0, Lambertian{}}, 0});
  return scene;
}

double relative_error(double value, const Big& want) {
  return static_cast<double>(abs((Big(value) - want) / want));
}

struct Worst {
  double error = 0, seconds = 0, slowest = 0;
  std::string where = "nowhere";
  int count = 0;
  // The ErrorLedger's bound (error_ledger.h) on each value: the largest
  // error/bound (≤ 1: covered), the largest bound relative to the value, and
  // whether every value's quadratures reported to the ledger.
  double worst_coverage = 0, widest_bound = 0;
  std::string widest_where = "nowhere";
  bool all_reported = true;
};

// Compares the library with `reference` on every quantity of the case.
void check_case(const Case& k, const Values& reference, Worst& worst) {
  const Scene scene = scene_of(k);
  const Vec3 n{0, 0, 1}, wo = view_of(k), p{0, 0, 0};
  std::vector<Strategy> strategies = direct_strategies();
  for (size_t i = 0; i <= strategies.size(); ++i) {
    const Strategy* s = i == 0 ? nullptr : &strategies[i - 1];
    const auto start = std::chrono::steady_clock::now();
    double got = 0, bound = 0, reported = 0;
    {
      const ErrorLedger ledger;
      got = s == nullptr ? glossy_reflected_radiance(scene, p, n, wo, 0) : glossy_second_moment(*s, scene, p, n, wo, 0);
      bound = ledger.bound(got);
      reported = ledger.relative_quadrature_error();
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    worst.seconds += seconds;
    worst.slowest = std::max(worst.slowest, seconds);
    const Big want = expected(reference, s);
    const double err = relative_error(got, want);
    const std::string what = s == nullptr ? "radiance" : strategy_name(*s);
    EXPECT_LE(err, kPrecisionTarget) << k.name << ", " << what << ": " << got << " vs " << static_cast<double>(want);
    if (err > worst.error) worst.error = err, worst.where = k.name + ", " + what;
    // The bound `furnace analytic` can state must cover the error, and must
    // come from the quadratures' own reports (none: only the round-off allowance).
    const double actual = static_cast<double>(abs(Big(got) - want));
    EXPECT_LE(actual, bound) << k.name << ", " << what << ": error " << actual << " outside the ledger's bound " << bound;
    EXPECT_GT(reported, 0) << k.name << ", " << what << ": no quadrature reported to the ErrorLedger";
    worst.all_reported = worst.all_reported && reported > 0;
    worst.worst_coverage = std::max(worst.worst_coverage, actual / bound);
    if (bound / std::fabs(got) > worst.widest_bound) worst.widest_bound = bound / std::fabs(got), worst.widest_where = k.name + ", " + what;
    ++worst.count;
  }
}

void print(const char* what, const Worst& w) {
  std::printf("[ ggx ] %-44s %3d values: worst relative error %.3g (%.1f eps) at %s; %.3g s for the values under test "
              "(slowest %.3g s)\n",
              what, w.count, w.error, w.error / std::numeric_limits<double>::epsilon(), w.where.c_str(), w.seconds,
              w.slowest);
  std::printf("[ ggx ] %-44s ErrorLedger bound: widest %.3g relative (at %s), error/bound at most %.3g%s\n", "",
              w.widest_bound, w.widest_where.c_str(), w.worst_coverage, w.all_reported ? "" : ", SOME UNREPORTED");
}

// Cases and their reference method.
void sweep(const char* what, const std::vector<Case>& cases, bool one_dimensional) {
  Worst worst;
  for (const Case& k : cases) {
    const auto start = std::chrono::steady_clock::now();
    const Values reference = one_dimensional ? reference_1d(k, Defect::kNone)
                             : k.planar      ? reference_plane(k, Defect::kNone)
                                             : reference_2d(k, Defect::kNone);
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

// Planar lights. disk_occluder's light and occluder (scenes/disk_occluder.json):
// a disk of radius 0.75 at height 2 facing down, a black disk of radius 0.35
// at height 1 between, both centred on the receiving point's normal.
const Disk kSceneLight{{0, 0, 2}, {0, 0, -1}, 0.75};
const Disk kSceneOccluder{{0, 0, 1}, {0, 0, 1}, 0.35};

Case planar_case(const std::string& name, double mu, double alpha, MicrofacetShadowing form, const Shape& light,
                 std::optional<Disk> occluder = std::nullopt) {
  Case k{name, mu, alpha, form, false, {}, 0};
  k.planar = light;
  k.occluder = occluder;
  return k;
}

// Normal view: a disk light centred on the normal (the specular direction),
// wide (disk_occluder's) and narrow (R/H = 0.01) against the lobe (1-D).
TEST(GgxPrecision, NormalViewCoaxialDisk) {
  std::vector<Case> cases;
  for (double alpha : {scene_limits::kMinGgxAlpha, 0.01, 0.05, 0.2, 0.5, 1.0}) {
    cases.push_back(planar_case(fmt::format("disk on the normal, alpha {:g}", alpha), 1.0, alpha, kHeightCorrelated,
                                kSceneLight));
    cases.push_back(planar_case(fmt::format("small disk on the normal, alpha {:g}", alpha), 1.0, alpha, kSeparable,
                                Disk{{0, 0, 2}, {0, 0, -1}, 0.02}));
  }
  sweep("disk on the normal, normal view", cases, true);
}

// Normal view: disk_occluder's occluded disk at the receiver's centre (the
// visible region an annulus about the hidden specular direction), α from
// kMinGgxAlpha to 1 (1-D).
TEST(GgxPrecision, NormalViewOccludedDisk) {
  std::vector<Case> cases;
  for (double alpha : {scene_limits::kMinGgxAlpha, 0.01, 0.05, 0.2, 0.5, 1.0})
    cases.push_back(planar_case(fmt::format("occluded disk, normal view, alpha {:g}", alpha), 1.0, alpha,
                                kHeightCorrelated, kSceneLight, kSceneOccluder));
  sweep("occluded disk, normal view, alpha 1e-3..1", cases, true);
}

// α = 1: f and p_b depend on μi alone, so the coaxial disk and the occluded
// disk are 1-D at any view; oblique and grazing views, both Smith forms.
TEST(GgxPrecision, AlphaOnePlanarObliqueAndGrazing) {
  std::vector<Case> cases;
  for (double mu : {0.5, 0.2, 0.05})
    for (MicrofacetShadowing form : {kSeparable, kHeightCorrelated}) {
      cases.push_back(planar_case(fmt::format("disk, alpha 1, mu_o {:g}, {}", mu, microfacet_shadowing_name(form)), mu,
                                  1.0, form, kSceneLight));
      cases.push_back(planar_case(
          fmt::format("occluded disk, alpha 1, mu_o {:g}, {}", mu, microfacet_shadowing_name(form)), mu, 1.0, form,
          kSceneLight, kSceneOccluder));
      // A small disk (R/H = 0.01): at mu_o 0.05 the mirror direction meets its
      // plane ~950 radii from it.
      cases.push_back(planar_case(fmt::format("small disk, alpha 1, mu_o {:g}, {}", mu, microfacet_shadowing_name(form)),
                                  mu, 1.0, form, Disk{{0, 0, 2}, {0, 0, -1}, 0.02}));
    }
  sweep("disk and occluded disk, alpha 1, mu_o 0.5/0.2/0.05", cases, true);
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
  const Case occluded =
      planar_case("occluded disk, alpha 1, mu_o 0.5", 0.5, 1.0, kHeightCorrelated, kSceneLight, kSceneOccluder);
  const Control controls[] = {{normal, Defect::kDWithoutInvPi, "D without 1/pi", Strategy::kCosineHemisphere},
                              {occluded, Defect::kNoOccluder, "the occluded disk wholly visible",
                               Strategy::kCosineHemisphere},
                              {occluded, Defect::kAreaWithoutEmissionCosine, "light_area's density without cos",
                               Strategy::kLightArea},
                              {oblique, Defect::kOtherSmithForm, "separable values for height-correlated",
                               Strategy::kUniformHemisphere},
                              {oblique, Defect::kPdfWithoutG1, "p_b without G1(wo)", Strategy::kBsdf}};
  for (const Control& c : controls) {
    const Values wrong = reference_1d(c.k, c.defect);
    const Scene scene = scene_of(c.k);
    double got = 0, bound = 0;
    {
      const ErrorLedger ledger;
      got = glossy_second_moment(c.strategy, scene, {0, 0, 0}, {0, 0, 1}, view_of(c.k), 0);
      bound = ledger.bound(got);
    }
    const double miss = relative_error(got, expected(wrong, &c.strategy));
    std::printf("[ ggx ] control %-40s (%s): relative difference %.3g, %.3g times the ledger's bound\n", c.name,
                strategy_name(c.strategy).c_str(), miss, miss * std::fabs(got) / bound);
    EXPECT_GT(miss, kControlMiss) << c.name;
    // The coverage check (check_case) fails on a wrong reference: the bound is no blanket.
    EXPECT_GT(static_cast<double>(abs(Big(got) - expected(wrong, &c.strategy))), bound) << c.name;
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

// Planar lights off the normal (2-D over the light's surface, label slow).
// A rectangle (perpendicular edges 0.4 × 0.3: light_solid_angle samples its
// spherical rectangle) and a triangle facing the receiver at distance 2,
// centred 0.05 rad off the mirror direction (the mirror direction hits them).
Frame facing_frame(double mu) {
  const Vec3 r{std::sqrt((1 - mu) * (1 + mu)), 0, mu};
  return Frame::from_normal(-normalize(r + Vec3{0, 0.05, 0}));
}
Vec3 facing_centre(double mu) {
  const Vec3 r{std::sqrt((1 - mu) * (1 + mu)), 0, mu};
  return normalize(r + Vec3{0, 0.05, 0}) * 2.0;
}
Shape facing_rectangle(double mu) {
  const Frame f = facing_frame(mu);
  const Vec3 eu = f.s * 0.4, ev = f.t * 0.3;
  return Rectangle{facing_centre(mu) - eu * 0.5 - ev * 0.5, eu, ev};
}
Shape facing_triangle(double mu) {
  const Frame f = facing_frame(mu);
  const Vec3 c = facing_centre(mu);
  return Triangle{c - f.s * 0.2 - f.t * 0.15, c + f.s * 0.25 - f.t * 0.1, c + f.t * 0.2};
}

TEST(GgxPrecisionSlow, RectangleAndTriangleNearTheSpecularDirection) {
  std::vector<Case> cases;
  for (double alpha : {scene_limits::kMinGgxAlpha, 0.05, 0.3, 1.0})
    cases.push_back(planar_case(fmt::format("rectangle near specular, mu_o 0.5, alpha {:g}", alpha), 0.5, alpha,
                                kHeightCorrelated, facing_rectangle(0.5)));
  cases.push_back(planar_case("rectangle near specular, mu_o 0.5, alpha 0.3, separable", 0.5, 0.3, kSeparable,
                              facing_rectangle(0.5)));
  for (double alpha : {0.05, 1.0})
    cases.push_back(planar_case(fmt::format("triangle near specular, mu_o 0.5, alpha {:g}", alpha), 0.5, alpha,
                                kHeightCorrelated, facing_triangle(0.5)));
  cases.push_back(planar_case("triangle near specular, mu_o 0.5, alpha 1, separable", 0.5, 1.0, kSeparable,
                              facing_triangle(0.5)));
  sweep("rectangle and triangle near the specular direction", cases, false);
}

// Grazing views: a vertical rectangle 3 away (x = 3, y in [-0.5, 0.5], z in
// [0.02, 0.6]) that the low mirror direction hits, μo 0.2 and 0.05.
TEST(GgxPrecisionSlow, GrazingRectangle) {
  const Shape wall = Rectangle{{3, 0.5, 0.02}, {0, -1, 0}, {0, 0, 0.58}};
  std::vector<Case> cases;
  for (double mu : {0.2, 0.05}) {
    cases.push_back(planar_case(fmt::format("wall, mu_o {:g}, alpha 0.05", mu), mu, 0.05, kHeightCorrelated, wall));
    cases.push_back(planar_case(fmt::format("wall, mu_o {:g}, alpha 1, separable", mu), mu, 1.0, kSeparable, wall));
  }
  cases.push_back(planar_case("wall, mu_o 0.05, alpha 0.3, separable", 0.05, 0.3, kSeparable, wall));
  sweep("vertical rectangle, grazing mu_o 0.2/0.05", cases, false);
}

// The occluded disk with the mirror direction just outside the occluder's
// shadow, inside the light: at normal view the light and occluder moved by
// −0.36 in x (the image's circle 0.02 from the hit point), at μo 0.5 the
// light at x = 3 and the occluder at x = 1.37 (the hit 0.46 from the light's
// centre and 0.02 outside the image, which sticks out of the disk).
TEST(GgxPrecisionSlow, OccludedDiskAtTheShadowEdge) {
  std::vector<Case> cases;
  const Disk light0{{-0.36, 0, 2}, {0, 0, -1}, 0.75}, occluder0{{-0.36, 0, 1}, {0, 0, 1}, 0.35};
  for (double alpha : {scene_limits::kMinGgxAlpha, 0.05, 0.3})
    cases.push_back(planar_case(fmt::format("occluded disk at the shadow edge, normal view, alpha {:g}", alpha), 1.0,
                                alpha, kHeightCorrelated, light0, occluder0));
  const Disk light1{{3, 0, 2}, {0, 0, -1}, 0.75}, occluder1{{1.37, 0, 1}, {0, 0, 1}, 0.35};
  cases.push_back(planar_case("occluded disk at the shadow edge, mu_o 0.5, alpha 0.05", 0.5, 0.05, kHeightCorrelated,
                              light1, occluder1));
  for (MicrofacetShadowing form : {kSeparable, kHeightCorrelated})
    cases.push_back(planar_case(fmt::format("occluded disk at the shadow edge, mu_o 0.5, alpha 1, {}",
                                            microfacet_shadowing_name(form)),
                                0.5, 1.0, form, light1, occluder1));
  sweep("occluded disk at the shadow edge", cases, false);
}

}  // namespace
}  // namespace furnace::analytic
