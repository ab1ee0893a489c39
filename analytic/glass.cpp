// Glass scenes' references (glass.h): the directional albedos of a
// dielectric interface and the two kinds of scene.
#include "analytic/glass.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <tuple>
#include <type_traits>

#include <fmt/format.h>

#include "analytic/fresnel.h"
#include "analytic/glass_light.h"
#include "analytic/reference.h"
#include "core/adaptive_quadrature.h"
#include "core/error.h"
#include "core/vec3.h"

namespace furnace::analytic {

namespace {

// Smith Λ of GGX at cos θ = mu > 0 (|cos| for a direction below), cancellation-free.
double lambda_ggx(double alpha, double mu) {
  mu = std::fabs(mu);
  if (!(mu > 0)) return std::numeric_limits<double>::infinity();
  const double a = alpha * alpha * (1 - mu) * (1 + mu) / (mu * mu);
  return a / (2 * (std::sqrt(1 + a) + 1));
}

double g2_over_g1o(MicrofacetShadowing shadowing, double lambda_o, double lambda_i) {
  // G2/G1(ωo): separable G1(ωi); height-correlated (1 + Λo)/(1 + Λo + Λi).
  if (shadowing == MicrofacetShadowing::kSeparable) return 1 / (1 + lambda_i);
  return (1 + lambda_o) / (1 + lambda_o + lambda_i);
}

// One lobe of the sampler at a microfacet normal m: the probability of
// choosing it (F or 1 − F), its weight G2/G1(ωo), the sampled direction's z,
// and the Jacobian dωm/dωi of that direction (0 probability: no sample).
struct LobeSample {
  double probability = 0, weight = 0, z = 0, jacobian = 0;
};
struct LobePair {
  LobeSample reflection, transmission;
};

// The lobes at one microfacet normal m (unit, m_z > 0) for the view
// wo = (sin θo, 0, μ): the reflection where it stays above, the refraction
// where it goes below.
LobePair lobe_samples_at(const Vec3& wo, const Vec3& m, double eta, double alpha, MicrofacetShadowing shadowing,
                         double lambda_o) {
  LobePair out;
  const double c = dot(wo, m);
  if (!(c > 0)) return out;
  const double f = fresnel_dielectric_reference(c, eta);
  // Reflection: ωr = 2(ωo·m)m − ωo; dωm/dωr = 1/(4c).
  const double r_z = 2 * c * m.z - wo.z;
  if (r_z > 0 && f > 0)
    out.reflection = {f, g2_over_g1o(shadowing, lambda_o, lambda_ggx(alpha, r_z)), r_z, 1 / (4 * c)};
  // Refraction (Snell at m): ωt = −ωo/η + (c/η − cos θt)·m, cos θt = √(η² − 1 + c²)/η,
  // so ωt·m = −cos θt; Walter's dωm/dωt = η²·cos θt/(c − η cos θt)².
  const double radicand = (eta - 1) * (eta + 1) + c * c;
  if (radicand > 0 && f < 1) {
    const double ct = std::sqrt(radicand) / eta;
    const double t_z = -wo.z / eta + (c / eta - ct) * m.z;
    if (t_z < 0) {
      // c − η cos θt = −(η² − 1)/(c + η cos θt): no cancellation as η → 1.
      const double d = -(eta - 1) * (eta + 1) / (c + eta * ct);
      out.transmission = {1 - f, g2_over_g1o(shadowing, lambda_o, lambda_ggx(alpha, t_z)), t_z,
                          eta * eta * ct / (d * d)};
    }
  }
  return out;
}

struct Lobes {
  double reflection = 0, transmission = 0;        // the weights' sums, G2/G1 each
  double reflection2 = 0, transmission2 = 0;      // their squares' sums
};

// The lobe terms at m: F·G2/G1 where the reflection stays above, (1 − F)·G2/G1
// where the refraction goes below, and the same with (G2/G1)².
Lobes lobes_at(const Vec3& wo, const Vec3& m, double eta, double alpha, MicrofacetShadowing shadowing,
               double lambda_o) {
  const LobePair p = lobe_samples_at(wo, m, eta, alpha, shadowing, lambda_o);
  Lobes out;
  out.reflection = p.reflection.probability * p.reflection.weight;
  out.reflection2 = p.reflection.probability * p.reflection.weight * p.reflection.weight;
  out.transmission = p.transmission.probability * p.transmission.weight;
  out.transmission2 = p.transmission.probability * p.transmission.weight * p.transmission.weight;
  return out;
}

// The values integrated together, at every node (one set of nodes serves
// all, so the geometry of a normal is computed once): E_R, E_T, E[w²].
using GlassValues = std::array<double, 3>;

// Tolerances of the nested quadrature, relative to each component's whole
// integral: the outer integral's error and the inner integrals' (each
// within kGlassInnerTolerance of the whole, over v ∈ [0, 1]: so the whole's
// too) add, and their sum is kGlassQuadratureTolerance. The inner share is
// the smaller, so that its errors are no noise to the outer rule's estimate.
constexpr double kGlassOuterTolerance = 0.9 * kGlassQuadratureTolerance;
constexpr double kGlassInnerTolerance = 0.1 * kGlassQuadratureTolerance;
// The first pass, which only estimates the whole that the inner integrals'
// tolerance is relative to: loose, and few bisections.
constexpr double kGlassEstimateTolerance = 1e-4;
constexpr int kGlassEstimateDepth = 4;
// A cap on the bisections of one integral (inner or outer): the cuts leave
// nothing for them but round-off, which no bisection resolves; the cap
// bounds the cost where round-off stands above the tolerance (measured:
// a tolerance of 1e-13 took 178 s at the critical view with α = 0.3
// without it). tests/analytic/glass_precision_test.cpp measures the
// accuracy with the cap in place.
constexpr size_t kGlassMaxBisections = 256;
// Bisection levels: every feature is cut first, so these are rarely used.
constexpr int kGlassOuterDepth = 20;
constexpr int kGlassInnerDepth = 16;

// The rule's value on [a, b] bisected until each component's error estimate
// meets its share of the absolute tolerance, or `depth` levels are used up;
// `value` and `error` (absolute) are the rule's on [a, b], already computed;
// each bisection spends one of `bisections_left` (at 0 every remaining piece
// keeps its one-rule value).
template <class F, class V>
V adaptive_pieces(const F& f, double a, double b, const V& value, const V& error, const V& tolerance, int depth,
                  size_t& bisections_left) {
  bool met = true;
  for (size_t c = 0; c < value.size(); ++c) met = met && error[c] <= tolerance[c];
  if (met || depth == 0 || bisections_left == 0) return value;
  --bisections_left;
  const double mid = (a + b) / 2;
  V half = tolerance;
  for (double& t : half) t /= 2;
  V left_error, right_error;
  V left = gauss_kronrod_rule<kDefaultKronrodPoints>(f, a, mid, &left_error);
  V right = gauss_kronrod_rule<kDefaultKronrodPoints>(f, mid, b, &right_error);
  for (size_t c = 0; c < value.size(); ++c) left_error[c] *= (mid - a) / 2, right_error[c] *= (b - mid) / 2;
  left = adaptive_pieces(f, a, mid, left, left_error, half, depth - 1, bisections_left);
  right = adaptive_pieces(f, mid, b, right, right_error, half, depth - 1, bisections_left);
  for (size_t c = 0; c < value.size(); ++c) left[c] += right[c];
  return left;
}

// ∫ f over [cuts.front(), cuts.back()] split at the sorted cuts, each
// component to `rel_tolerance` relative to a first estimate of its whole
// integral (one rule per piece), shared equally by the pieces. Each piece
// [a, b] is taken in t ∈ [0, 1] of x = a + (b − a)(3t² − 2t³), dx =
// 6(b − a)t(1 − t) dt: a square-root end point (1 − F at total internal
// reflection, the inner integral as a cut enters the range), where
// Gauss–Kronrod converges only algebraically, becomes smooth.
// `scale`, when given, replaces the first estimate as the magnitude the
// tolerance is relative to (an inner integral's error is measured against
// the outer integral: relative to itself, a nearly empty ring would ask for
// digits its round-off does not hold, and bisect to full depth).
template <class F, class V = std::invoke_result_t<F, double>>
V integrate_pieces(const F& f, const std::vector<double>& cuts, double rel_tolerance, int depth,
                   const V* scale = nullptr) {
  struct Piece {
    double a, w;
    V value, error;
  };
  // f on the piece [a, a + w] in t.
  const auto mapped = [&f](const Piece& p) {
    return [&f, &p](double t) {
      V v = f(p.a + p.w * t * t * (3 - 2 * t));
      for (double& e : v) e *= 6 * p.w * t * (1 - t);
      return v;
    };
  };
  std::vector<Piece> pieces;
  V first{};
  for (size_t i = 0; i + 1 < cuts.size(); ++i) {
    if (!(cuts[i + 1] > cuts[i])) continue;
    Piece p{cuts[i], cuts[i + 1] - cuts[i], {}, {}};
    p.value = gauss_kronrod_rule<kDefaultKronrodPoints>(mapped(p), 0.0, 1.0, &p.error);
    for (size_t c = 0; c < first.size(); ++c) first[c] += p.value[c], p.error[c] /= 2;
    pieces.push_back(p);
  }
  V tolerance, sum{};
  size_t bisections_left = kGlassMaxBisections;
  for (size_t c = 0; c < first.size(); ++c)
    tolerance[c] = rel_tolerance * std::fabs(scale != nullptr ? (*scale)[c] : first[c]) / double(pieces.size());
  for (const Piece& p : pieces) {
    const V value = adaptive_pieces(mapped(p), 0.0, 1.0, p.value, p.error, tolerance, depth, bisections_left);
    for (size_t c = 0; c < sum.size(); ++c) sum[c] += value[c];
  }
  return sum;
}

// The v ∈ [0, 1] (tan²θm = α²(1 − v²)/v²) where dielectric_interface_albedo's
// inner integral is not smooth, sorted, with 0 and 1: where a φ cut c*
// reaches φ = 0 (c = cos(θm − θo)) or φ = π (c = cos(θm + θo)), and where
// two cuts cross. For view θo and k = 1 − η² (0 for η > 1):
//  - c* = 0 and √k: θm = θo ± acos c*, acos c* − θo;
//  - the reflection's horizon c* = μ/(2 cos θm): cos θm cos(θm ∓ θo) = μ/2,
//    i.e. cos(2θm ∓ θo) = 0: θm = (π/2 ± θo)/2;
//  - the refraction's horizon c* = μ/(2 cos θm) + k cos θm/(2μ): with
//    x = 2θm, (μ² − k/2) cos x ± μ sin θo sin x = k/2;
//  - √k meets the reflection's horizon at cos θm = μ/(2√k) and the
//    refraction's at cos θm = μ/√k (its minimum over q).
std::vector<double> glass_v_cuts(double alpha, double mu, double theta_o, double k) {
  std::vector<double> theta;
  const double sin_o = std::sin(theta_o);
  const auto constant_cut = [&](double c) {
    const double a = std::acos(c);
    for (double t : {theta_o + a, theta_o - a, a - theta_o}) theta.push_back(t);
  };
  constant_cut(0.0);
  theta.push_back((kPi / 2 + theta_o) / 2);
  theta.push_back((kPi / 2 - theta_o) / 2);
  if (k > 0) {
    const double sqrt_k = std::sqrt(k);
    constant_cut(sqrt_k);
    for (double sign : {-1.0, 1.0}) {
      const double p = mu * mu - k / 2, q = sign * mu * sin_o, r = std::hypot(p, q);
      if (k / 2 <= r)
        for (double pm : {-1.0, 1.0}) {
          const double x = std::atan2(q, p) + pm * std::acos(k / (2 * r));
          for (double turn : {-2 * kPi, 0.0, 2 * kPi}) theta.push_back((x + turn) / 2);
        }
    }
    if (mu / (2 * sqrt_k) < 1) theta.push_back(std::acos(mu / (2 * sqrt_k)));
    if (mu / sqrt_k < 1) theta.push_back(std::acos(mu / sqrt_k));
  }
  std::vector<double> cuts{0.0, 1.0};
  for (double t : theta)
    if (t > 0 && t < kPi / 2) {
      const double c = std::cos(t), s = std::sin(t);
      cuts.push_back(alpha * c / std::sqrt(alpha * alpha * c * c + s * s));  // v = 1/√(1 + tan²θm/α²)
    }
  std::sort(cuts.begin(), cuts.end());
  cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
  return cuts;
}

}  // namespace

double transmission_scale(double eta, TransportConvention convention) {
  return convention == TransportConvention::kRadiance ? 1 / (eta * eta) : 1.0;
}

namespace {

// ∫ D_ωo(m)·g(m, ωo·m) dm over the visible normals m of GGX α for the view
// ωo = (sin θo, 0, μ) (D_ωo = G1(ωo)·max(0, ωo·m)·D(m)/μ, the density of the
// visible-normal sampler), for a g returning an array of values integrated
// together, each to kGlassQuadratureTolerance of its whole; `eta` (the far
// side's index relative to the viewer's) places the cuts.
//
// The parametrisation: w = 1 − v² (dw = 2v dv, which cancels the 1/√(1 − w)
// of tan θm at the rim), over φ ∈ [0, π] (twice: every g here is even in
// φ), the measure G1(ωo)·max(0, ωo·m)/(μ cos θm)·2v dv dφ/(2π). Along φ at
// fixed θm, c = ωo·m = A cos φ + B falls monotonically, and every place where
// the integrand jumps or kinks is a value of c: c = 0 (the visible normals'
// rim), c = μ/(2 cos θm) (the reflection reaches the horizon), and for η < 1
// c = √k (total internal reflection; F has a square-root kink there) and
// c = (q² + k)/(2q), q = μ/cos θm (the refraction reaches the horizon:
// (c − √(c² − k))·cos θm = μ). The φ range is split at those, so each piece
// is smooth for the rule (the square root made smooth by integrate_pieces'
// end-point map). The inner integral is not smooth in v where a φ cut
// enters or leaves the range at φ = 0 (c = cos(θm − θo)) or φ = π
// (c = cos(θm + θo)), or two cuts cross; v is cut at each such θm
// (glass_v_cuts).
// The view ωo = (sin θo, 0, μ) of dielectric_interface_albedo.
Vec3 view_at(double mu) { return {std::sqrt((1 - mu) * (1 + mu)), 0, mu}; }

template <class G>
std::invoke_result_t<G, const Vec3&, double> integrate_visible_normals(double alpha, double eta, double mu,
                                                                      const G& g) {
  using V = std::invoke_result_t<G, const Vec3&, double>;
  const Vec3 wo = view_at(mu);
  const double sin_o = wo.x;
  const double theta_o = std::atan2(sin_o, mu);
  const double g1o = 1 / (1 + lambda_ggx(alpha, mu));
  // For η < 1, k = 1 − η²: total internal reflection at ωo·m = c below √k.
  const double k = eta < 1 ? (1 - eta) * (1 + eta) : 0.0;
  const double sqrt_k = std::sqrt(k);
  struct Normal {
    double cos_m, sin_m;
  };
  const auto normal_at = [&](double v) {
    const double w = 1 - v * v;
    const double denom = std::sqrt(v * v + alpha * alpha * w);  // √(1 − w + α²w)
    return Normal{v / denom, alpha * std::sqrt(w) / denom};
  };
  const auto at = [&](const Normal& n, double v, double phi) {
    const Vec3 m{n.sin_m * std::cos(phi), n.sin_m * std::sin(phi), n.cos_m};
    const double c = dot(wo, m);
    if (!(c > 0) || !(n.cos_m > 0)) return V{};
    V out = g(m, c);
    // The 2v of dw over cos θm = v/√(1 − w + α²w): 2√(1 − w + α²w).
    const double weight = g1o * c / mu * 2 * std::sqrt(v * v + alpha * alpha * (1 - v * v)) / kPi;
    for (double& x : out) x = weight * x;
    return out;
  };
  // `scale`: the whole integral's estimate (nullptr: the first pass, each
  // inner integral relative to itself).
  const auto inner = [&](double v, const V* scale) {
    const Normal n = normal_at(v);
    const double a = sin_o * n.sin_m, b = mu * n.cos_m;
    std::vector<double> cuts{0.0, kPi};
    const auto cut_at = [&](double c) {
      if (!(a > 0)) return;
      const double x = (c - b) / a;
      if (x > -1 && x < 1) cuts.push_back(std::acos(x));
    };
    cut_at(0.0);
    cut_at(mu / (2 * n.cos_m));
    if (eta < 1) {
      cut_at(sqrt_k);
      const double q = mu / n.cos_m;
      cut_at((q * q + k) / (2 * q));
    }
    std::sort(cuts.begin(), cuts.end());
    const auto f = [&](double phi) { return at(n, v, phi); };
    if (scale == nullptr) return integrate_pieces(f, cuts, kGlassEstimateTolerance, kGlassEstimateDepth);
    return integrate_pieces(f, cuts, kGlassInnerTolerance, kGlassInnerDepth, scale);
  };
  const std::vector<double> v_cuts = glass_v_cuts(alpha, mu, theta_o, k);
  const V estimate = integrate_pieces([&](double v) { return inner(v, nullptr); }, v_cuts, kGlassEstimateTolerance,
                                      kGlassEstimateDepth);
  return integrate_pieces([&](double v) { return inner(v, &estimate); }, v_cuts, kGlassOuterTolerance,
                          kGlassOuterDepth);
}

}  // namespace

InterfaceAlbedo dielectric_interface_albedo(const Dielectric& d, double eta, double mu,
                                            TransportConvention convention) {
  FURNACE_CHECK(mu > 0 && mu <= 1 && eta > 0 && eta != 1);
  const double s = transmission_scale(eta, convention);
  InterfaceAlbedo out;
  if (d.smooth()) {
    const double r = fresnel_dielectric_reference(mu, eta);
    out.reflection = r;
    out.transmission = 1 - r;
    out.second_moment = r + (1 - r) * s * s;
    return out;
  }
  const double alpha = d.alpha;
  const Vec3 wo = view_at(mu);
  const double lambda_o = lambda_ggx(alpha, mu);
  const GlassValues total = integrate_visible_normals(alpha, eta, mu, [&](const Vec3& m, double) {
    const Lobes l = lobes_at(wo, m, eta, alpha, d.shadowing, lambda_o);
    return GlassValues{l.reflection, l.transmission, l.reflection2 + l.transmission2 * s * s};
  });
  out.reflection = total[0];
  out.transmission = total[1];
  out.second_moment = total[2];
  return out;
}

InterfaceLobeMoments dielectric_interface_lobe_moments(const Dielectric& d, double eta, double mu,
                                                       TransportConvention convention) {
  FURNACE_CHECK(mu > 0 && mu <= 1 && eta > 0 && eta != 1);
  const double s = transmission_scale(eta, convention);
  if (d.smooth()) {
    const double r = fresnel_dielectric_reference(mu, eta);
    return {r, (1 - r) * s * s};
  }
  const double alpha = d.alpha;
  const Vec3 wo = view_at(mu);
  const double lambda_o = lambda_ggx(alpha, mu);
  const std::array<double, 2> total = integrate_visible_normals(alpha, eta, mu, [&](const Vec3& m, double) {
    const Lobes l = lobes_at(wo, m, eta, alpha, d.shadowing, lambda_o);
    return std::array<double, 2>{l.reflection2, l.transmission2 * s * s};
  });
  return {total[0], total[1]};
}

InterfaceMisMoments dielectric_interface_mis_moments(const Dielectric& d, double eta, double mu,
                                                     TransportConvention convention,
                                                     const InterfaceEnvironment& environment) {
  FURNACE_CHECK(mu > 0 && mu <= 1 && eta > 0 && eta != 1);
  FURNACE_CHECK(environment.view >= 0 && environment.far >= 0 && environment.view + environment.far > 0);
  const double s = transmission_scale(eta, convention);
  const double c_b = kOneSampleBsdfProbability;
  const double l_view = environment.view, l_far = environment.far;
  InterfaceMisMoments out;
  if (d.smooth()) {
    // A delta lobe: the light sample's f is 0, the BSDF sample's MIS weight 1.
    const double r = fresnel_dielectric_reference(mu, eta);
    out.balance = out.power = l_view * l_view * r + l_far * l_far * (1 - r) * s * s;
    out.one_sample = out.balance / c_b;
    out.mean = l_view * r + l_far * (1 - r) * s;
    return out;
  }
  if (eta < kMinMisEtaRatio && eta > 1 / kMinMisEtaRatio)
    throw Error(fmt::format("the MIS and light-sampling second moments at a rough interface are modelled for a "
                            "relative index at least {} from 1 (by ratio), not {:.17g}",
                            kMinMisEtaRatio, eta));
  // The light sampler's density toward a lobe's direction (z its cosine on
  // the viewer's side: > 0 reflected, < 0 transmitted).
  const double map_total = 2 * kPi * (l_view + l_far);
  const auto light_density = [&](double z) {
    if (!environment.map) return std::fabs(z) / (2 * kPi);
    return (z > 0 ? l_view : l_far) / map_total;
  };
  const double alpha = d.alpha;
  const Vec3 wo = view_at(mu);
  const double lambda_o = lambda_ggx(alpha, mu);
  const double g1o = 1 / (1 + lambda_o);
  // Per node, E_b[·] of: M = w·s; for β = 1, 2: A = (ws)²·p_b·w_l²/p_l,
  // B = (ws)²·w_b², C = ws·w_l; O = (ws)²·p_b/(c·p_b + (1 − c)·p_l);
  // Lt = (ws)²·p_b/p_l. p_b = D_ωo(m)·P·J, p_l = |z|/(2π).
  using MisValues = std::array<double, 9>;
  const MisValues t = integrate_visible_normals(alpha, eta, mu, [&](const Vec3& m, double c) {
    MisValues v{};
    // GGX D(m) = α²/(π (cos²θm (α² − 1) + 1)²); D_ωo(m) = G1(ωo)·c·D(m)/μ.
    const double q = m.z * m.z * (alpha * alpha - 1) + 1;
    const double visible = g1o * c * alpha * alpha / (kPi * q * q) / mu;
    const LobePair p = lobe_samples_at(wo, m, eta, alpha, d.shadowing, lambda_o);
    const auto add = [&](const LobeSample& l, double scale) {
      if (!(l.probability > 0)) return;
      // A sample toward a black side adds nothing (and the map's light
      // sampler has no density there).
      const double ws = l.weight * scale, ws2 = ws * ws;
      if (ws == 0) return;
      const double pb = visible * l.probability * l.jacobian;
      const double pl = light_density(l.z);
      const double pr = l.probability;
      v[0] += pr * ws;
      for (int beta = 1; beta <= 2; ++beta) {
        const double lb = beta == 1 ? pl : pl * pl, bb = beta == 1 ? pb : pb * pb;
        const double wl = lb / (lb + bb), wb = bb / (lb + bb);
        const size_t at = size_t(3 * (beta - 1));
        v[1 + at] += pr * ws2 * pb * wl * wl / pl;
        v[2 + at] += pr * ws2 * wb * wb;
        v[3 + at] += pr * ws * wl;
      }
      v[7] += pr * ws2 * pb / (c_b * pb + (1 - c_b) * pl);
      v[8] += pr * ws2 * pb / pl;
    };
    add(p.reflection, l_view);
    add(p.transmission, s * l_far);
    return v;
  });
  const double mean = t[0];
  out.balance = t[1] + t[2] + 2 * t[3] * (mean - t[3]);
  out.power = t[4] + t[5] + 2 * t[6] * (mean - t[6]);
  out.one_sample = t[7];
  out.light = t[8];
  out.mean = mean;
  // |δ(A + B + 2C(M − C))| ≤ tol·(A + B + 2C·M + 2C·C) to first order, every term ≥ 0.
  const double tol = kGlassQuadratureTolerance;
  out.balance_bound = tol * (t[1] + t[2] + 2 * t[3] * (mean + t[3]));
  out.power_bound = tol * (t[4] + t[5] + 2 * t[6] * (mean + t[6]));
  out.one_sample_bound = tol * t[7];
  out.light_bound = tol * t[8];
  return out;
}

bool has_dielectric(const Scene& scene) {
  for (const Object& o : scene.objects)
    if (o.material.as<Dielectric>()) return true;
  return false;
}

namespace {

// A lat-long map's two hemisphere values (above and below z = 0), when it is
// constant on each: an even number of rows (the equator a row edge: row
// floor(θ/π·H) of core/environment_map.h), all the upper half's texels
// equal, all the lower half's equal. Empty otherwise.
std::optional<std::array<double, 2>> hemisphere_values(const LatLongMap& map) {
  if (map.height % 2 != 0) return std::nullopt;
  const int half = map.height / 2;
  const double upper = map.texel(0, 0), lower = map.texel(half, 0);
  for (int i = 0; i < map.height; ++i)
    for (int j = 0; j < map.width; ++j)
      if (map.texel(i, j) != (i < half ? upper : lower)) return std::nullopt;
  return std::array<double, 2>{upper, lower};
}

}  // namespace

InterfaceEnvironment interface_environment(const Scene& scene, const Vec3& view_normal) {
  const Environment& env = scene.environment;
  if (!env.map) return {env.radiance, env.radiance, false};
  const std::optional<std::array<double, 2>> values = hemisphere_values(*env.map);
  if (!values || std::fabs(view_normal.x) + std::fabs(view_normal.y) > 1e-12 || view_normal.z == 0)
    throw Error(fmt::format("scene '{}' ({}): the environment map '{}' is not constant on each side of the glass "
                            "plane.",
                            scene.name, scene.source, env.map_file));
  const double above = env.radiance * (*values)[0], below = env.radiance * (*values)[1];
  return view_normal.z > 0 ? InterfaceEnvironment{above, below, true} : InterfaceEnvironment{below, above, true};
}

std::optional<std::string> glass_scene_refusal(const Scene& scene) {
  if (has_glass_light(scene)) return glass_light_scene_refusal(scene);  // kind 3 (glass_light.h)
  if (!scene.point_lights.empty()) return "it has point lights";
  if (scene.closed) return "it is closed";
  if (scene.objects.empty()) return "it has no object";
  for (const Object& o : scene.objects) {
    if (o.is_emitter()) return fmt::format("object '{}' emits", o.name);
    if (!o.material.as<Dielectric>()) return fmt::format("object '{}' is not a dielectric", o.name);
  }
  if (scene.objects.size() == 1 && std::holds_alternative<Sphere>(scene.objects[0].shape)) {
    if (scene.environment.map) return "its environment is a map, not constant";
    if (!scene.objects[0].material.as<Dielectric>()->smooth()) return "its glass sphere is rough";
    return std::nullopt;
  }
  // Planar, all in one plane.
  std::optional<Plane> first;
  for (const Object& o : scene.objects) {
    const std::optional<Plane> plane = plane_of(o.shape);
    if (!plane) return fmt::format("object '{}' is a sphere beside other objects", o.name);
    if (!first) {
      first = plane;
      continue;
    }
    const double scale = std::fmax(1.0, max_abs_component(plane->point));
    if (length(cross(plane->normal, first->normal)) > 1e-13 ||
        std::fabs(dot(plane->point - first->point, first->normal)) > 1e-13 * scale)
      return fmt::format("object '{}' is not in the plane of '{}'", o.name, scene.objects[0].name);
  }
  // A map: a sky on one side, constant on each hemisphere of a plane z = const.
  if (scene.environment.map) {
    if (!hemisphere_values(*scene.environment.map))
      return fmt::format("its environment map '{}' is not constant on each hemisphere (an even number of rows, the "
                         "upper half's texels all equal and the lower half's)",
                         scene.environment.map_file);
    if (std::fabs(first->normal.x) + std::fabs(first->normal.y) > 1e-12)
      return "its environment is a map and its glass plane is not z = const, so the sky is not on one side";
  }
  return std::nullopt;
}

namespace {

[[noreturn]] void refuse(const Scene& scene, const std::string& reason) {
  throw Error(fmt::format("scene '{}' ({}) has no exact glass reference: {}.", scene.name, scene.source, reason));
}

// The interface albedos met so far, by (object, side, μ): an orthographic
// camera meets a plane at one angle, so a planar scene needs one quadrature
// per object and side.
using AlbedoMemo = std::map<std::tuple<size_t, bool, double>, InterfaceAlbedo>;
using MisMemo = std::map<std::tuple<size_t, bool, double>, InterfaceMisMoments>;
using LobeMemo = std::map<std::tuple<size_t, bool, double>, InterfaceLobeMoments>;

// E[Y²]/a² of `strategy` at an interface under `env` (a constant
// environment, view = far = L, or a sky on one side): bsdf's from the
// albedo's E[Y²] times L², or under a sky from the lobes' shares; the others
// from dielectric_interface_mis_moments under `env`. Memoised per (object,
// side, μ).
double interface_second_moment(const Scene& scene, Strategy strategy, const Dielectric& d, double eta, double mu,
                               TransportConvention convention, const InterfaceAlbedo& albedo,
                               const InterfaceEnvironment& env, const std::tuple<size_t, bool, double>& key,
                               MisMemo& memo, LobeMemo& lobe_memo) {
  if (strategy == Strategy::kBsdf) {
    if (!env.map) return env.view * env.view * albedo.second_moment;
    auto it = lobe_memo.find(key);
    if (it == lobe_memo.end())
      it = lobe_memo.emplace(key, dielectric_interface_lobe_moments(d, eta, mu, convention)).first;
    return env.view * env.view * it->second.reflection + env.far * env.far * it->second.transmission;
  }
  const bool light = strategy == Strategy::kLightArea || strategy == Strategy::kLightSolidAngle;
  if (light && d.smooth()) refuse(scene, "light sampling alone cannot find a smooth interface's delta lobe");
  auto it = memo.find(key);
  if (it == memo.end())
    it = memo.emplace(key, dielectric_interface_mis_moments(d, eta, mu, convention, env)).first;
  const InterfaceMisMoments& m = it->second;
  switch (strategy) {
    case Strategy::kMisBalance: return m.balance;
    case Strategy::kMisPower: return m.power;
    case Strategy::kMisOneSample: return m.one_sample;
    default: return m.light;
  }
}

// The value of one pixel centre's ray: its radiance, or with `second_moment`
// that strategy's E[Y²] (direct lighting).
double glass_pixel(const Scene& scene, const Vec3& origin, const Vec3& direction, int max_segments,
                   TransportConvention convention, bool direct_only, std::optional<Strategy> second_moment,
                   AlbedoMemo& memo, MisMemo& mis_memo, LobeMemo& lobe_memo) {
  const std::optional<Hit> hit = intersect(scene, origin, direction);
  if (!hit) {
    const double l_miss = environment_radiance(scene.environment, normalize(direction));
    return second_moment ? l_miss * l_miss : l_miss;
  }
  const double l_env = scene.environment.radiance;
  if (max_segments < 2) return 0.0;
  const Object& o = scene.objects[hit->object_index];
  const Dielectric& d = *o.material.as<Dielectric>();
  const double a = o.material.albedo;
  const double cos_view = dot(direction, hit->normal);
  const bool in_front = cos_view < 0;
  const double eta = in_front ? d.eta : 1 / d.eta;
  const double mu = std::fabs(cos_view) / length(direction);
  if (std::holds_alternative<Sphere>(o.shape)) {
    if (!in_front) refuse(scene, "a camera ray starts inside the glass sphere");
    const double r = fresnel_dielectric_reference(mu, eta);
    const double t = 1 - r;
    // Direct lighting: a reflection (weight a) sees L, a refraction sees the
    // non-emitting inside. A delta lobe: MIS weighs the BSDF sample 1 (the
    // light sample's f is 0); one-sample MIS draws it with probability c.
    if (second_moment) {
      if (*second_moment == Strategy::kLightArea || *second_moment == Strategy::kLightSolidAngle)
        refuse(scene, "light sampling alone cannot find the smooth sphere's delta lobe");
      const double m2 = a * a * l_env * l_env * r;
      return *second_moment == Strategy::kMisOneSample ? m2 / kOneSampleBsdfProbability : m2;
    }
    if (direct_only) return a * r * l_env;
    const double ar = a * r;
    // Σ_{k=0}^{K} (aR)^k = (1 − (aR)^{K+1})/(1 − aR), K = S − 3 (−1 for S = 2: an empty sum).
    double sum = 0;
    if (max_segments == kUnlimitedDepth) {
      sum = 1 / (1 - ar);
    } else {
      const int k_plus_1 = max_segments - 2;
      sum = ar == 0 ? (k_plus_1 > 0 ? 1.0 : 0.0) : -std::expm1(double(k_plus_1) * std::log(ar)) / (1 - ar);
    }
    return l_env * (ar + a * a * t * t * sum);
  }
  const auto key = std::make_tuple(hit->object_index, in_front, mu);
  auto it = memo.find(key);
  if (it == memo.end()) it = memo.emplace(key, dielectric_interface_albedo(d, eta, mu, convention)).first;
  const InterfaceAlbedo& e = it->second;
  const double s = transmission_scale(eta, convention);
  // A constant environment, or a sky on one side: each lobe sees its own side's radiance.
  const InterfaceEnvironment env = interface_environment(scene, in_front ? hit->normal : -hit->normal);
  if (second_moment) {
    return a * a *
           interface_second_moment(scene, *second_moment, d, eta, mu, convention, e, env, key, mis_memo, lobe_memo);
  }
  return a * (env.view * e.reflection + s * env.far * e.transmission);
}

}  // namespace

namespace {

// glass_pixel at every pixel centre (row-major), one albedo memo for the image.
std::vector<double> glass_image(const Scene& scene, int max_segments, TransportConvention convention,
                                bool direct_only, std::optional<Strategy> second_moment) {
  const Camera& camera = scene.camera;
  std::vector<double> image(size_t(camera.width_px) * size_t(camera.height_px));
  AlbedoMemo memo;
  MisMemo mis_memo;
  LobeMemo lobe_memo;
  for (int py = 0; py < camera.height_px; ++py)
    for (int px = 0; px < camera.width_px; ++px) {
      const Camera::Ray ray = camera.pixel_center_ray(px, py);
      image[size_t(py) * camera.width_px + px] =
          glass_pixel(scene, ray.origin, ray.direction, max_segments, convention, direct_only, second_moment, memo,
                      mis_memo, lobe_memo);
    }
  return image;
}

}  // namespace

std::vector<double> glass_reference_image(const Scene& scene, int max_segments, TransportConvention convention,
                                          bool direct_only) {
  if (auto reason = glass_scene_refusal(scene)) refuse(scene, *reason);
  if (max_segments < 1) throw Error(fmt::format("max_segments must be at least 1, got {}.", max_segments));
  if (has_glass_light(scene)) return glass_light_reference_image(scene, direct_only ? 2 : max_segments, convention);
  return glass_image(scene, direct_only ? 2 : max_segments, convention, direct_only, std::nullopt);
}

std::vector<double> glass_second_moment_image(const Scene& scene, Strategy strategy, TransportConvention convention,
                                              LightSelection selection) {
  if (auto reason = glass_scene_refusal(scene)) refuse(scene, *reason);
  if (has_glass_light(scene)) return glass_light_second_moment_image(scene, strategy, convention, selection);
  const bool modelled = strategy == Strategy::kBsdf || strategy == Strategy::kMisBalance ||
                        strategy == Strategy::kMisPower || strategy == Strategy::kMisOneSample ||
                        strategy == Strategy::kLightArea || strategy == Strategy::kLightSolidAngle;
  if (!modelled)
    refuse(scene, fmt::format("the second moment of strategy '{}' at a dielectric is not modelled",
                              strategy_name(strategy)));
  return glass_image(scene, 2, convention, true, strategy);
}

}  // namespace furnace::analytic
