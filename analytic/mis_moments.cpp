// The MIS estimators' second moments at a Lambertian receiver
// (mis_moments.h): quadrature over each unoccluded emitter's directions, the
// point lights and the open sky in closed form.
#include "analytic/mis_moments.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <tuple>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "analytic/emitter.h"
#include "analytic/environment.h"
#include "analytic/error_ledger.h"
#include "analytic/light_moments.h"
#include "analytic/moments.h"
#include "analytic/point_light.h"
#include "analytic/polygon_patch.h"
#include "analytic/sin_cos.h"
#include "analytic/unsupported.h"
#include "core/adaptive_quadrature.h"
#include "core/error.h"

namespace furnace::analytic {

namespace {

// The integrals of one light's (or the sky's) directions: E[Y_b²], E[Y_l²],
// E[Y_b], E[Y_l] of multi-sample MIS, and E[Y²] of one-sample MIS, per unit
// radiance (L², L², L, L, L²).
struct MisTerms {
  double bsdf2 = 0, light2 = 0, bsdf1 = 0, light1 = 0, one_sample2 = 0;
};

// Heuristic weight of density a against b, 0 where a = 0.
double heuristic(double a, double b, int beta) {
  if (!(a > 0)) return 0.0;
  const double x = beta == 2 ? a * a : a, y = beta == 2 ? b * b : b;
  return x / (x + y);
}

// The integrands at a direction with cos θ > 0 and light density p_l
// (selection included); cosine density p_b = cos θ/π. Multi-sample MIS:
// the terms of E[Y_b²], E[Y_l²], E[Y_b], E[Y_l]; one-sample MIS: E[Y²].
using MultiSampleValues = std::array<double, 4>;
using OneSampleValues = std::array<double, 1>;
MultiSampleValues multi_sample_integrands(double cos_theta, double p_light, int beta) {
  const double p_bsdf = cos_theta * kInvPi;
  const double w_b = heuristic(p_bsdf, p_light, beta), w_l = heuristic(p_light, p_bsdf, beta);
  return {w_b * w_b * cos_theta * cos_theta / p_bsdf, w_l * w_l * cos_theta * cos_theta / p_light, w_b * cos_theta,
          w_l * cos_theta};
}
OneSampleValues one_sample_integrand(double cos_theta, double p_light) {
  const double p_bsdf = cos_theta * kInvPi;
  const double q = kOneSampleBsdfProbability * p_bsdf + (1 - kOneSampleBsdfProbability) * p_light;
  return {q > 0 ? cos_theta * cos_theta / q : 0.0};
}

constexpr double kMisQuadratureTolerance = 1e-10;
constexpr int kMisQuadratureDepth = 15;
// A polygon's MIS terms (polygon_direction_integral: smooth integrands in
// the plane's spherical coordinates) to 1e-13, at most 20 bisections per
// edge and 6 per ray: at most 1,271 rays of 403 evaluations per edge, a
// bounded cost, each evaluation serving all the terms integrated together, when every cap is
// reached); the error reached is reported to the ErrorLedger.
constexpr double kMisPolygonTolerance = 1e-13;
constexpr size_t kMisOuterBisections = 20;
constexpr size_t kMisInnerBisections = 6;

// ∫ g(cos θ, p_light) dω over a family of rings: outer u ∈ [u0, u1] (split
// at `kinks`, where the horizon starts to cut the rings), inner φ over the
// arcs where cos θ = A + B cos φ + C sin φ > 0 (ring.coefficients), in the
// half-angle variable of each arc (HalfAngleArcs); ring.row(u) holds what
// depends on u alone, and ring.at(row, cos φ, sin φ) gives cos θ, p_light and
// the measure dω/(du dφ) at (u, φ). Gauss–Kronrod
// (31 points), adaptive (core/adaptive_quadrature.h: Boost's own recursion never
// terminates on the tiny intervals of a far sphere's cone), relative
// tolerance kMisQuadratureTolerance.
// The error reached (the outer estimate plus the worst inner relative
// estimate times the result) is reported to the open ErrorLedger.
template <class Ring, class Integrand, class V = std::invoke_result_t<const Integrand&, double, double>>
V ring_integral(double u0, double u1, const std::vector<double>& kinks, Ring ring, Integrand g) {
  constexpr size_t N = std::tuple_size_v<V>;
  V worst_inner{}, outer_error{};
  auto outer = [&](double u) {
    double A, B, C;
    ring.coefficients(u, &A, &B, &C);
    const auto row = ring.row(u);  // what depends on u alone, once per ring
    V sum{};
    for (const auto& [lo, hi] : positive_arcs(A, B, C)) {
      // φ by the half-angle variable of each piece of the arc (HalfAngleArcs: no sin or cos at the nodes).
      const HalfAngleArcs arcs = HalfAngleArcs::of(lo, hi);
      for (int a = 0; a < arcs.count; ++a) {
        const HalfAngleArc& arc = arcs.piece[a];
        auto inner = [&](double tau) {
          double cos_phi, sin_phi, dphi_dtau;
          arc.at(tau, &cos_phi, &sin_phi, &dphi_dtau);
          double cos_theta, p_light, measure;
          ring.at(row, cos_phi, sin_phi, &cos_theta, &p_light, &measure);
          if (!(cos_theta > 0)) return V{};
          V value = g(cos_theta, p_light);
          for (double& component : value) component *= measure * dphi_dtau;
          return value;
        };
        V error{};
        const V value = adaptive_gauss_kronrod_relative_components(inner, -arc.tau_max, arc.tau_max,
                                                                   kMisQuadratureTolerance, kMisQuadratureDepth, 1,
                                                                   kUnlimitedBisections, &error);
        for (size_t c = 0; c < N; ++c) {
          if (value[c] != 0) worst_inner[c] = std::fmax(worst_inner[c], std::fabs(error[c] / value[c]));
          sum[c] += value[c];
        }
      }
    }
    return sum;
  };
  std::vector<double> cuts{u0, u1};
  for (double k : kinks)
    if (k > u0 && k < u1) cuts.push_back(k);
  std::sort(cuts.begin(), cuts.end());
  V total{};
  for (size_t i = 0; i + 1 < cuts.size(); ++i) {
    const V value = adaptive_gauss_kronrod_relative_components(outer, cuts[i], cuts[i + 1], kMisQuadratureTolerance,
                                                               kMisQuadratureDepth, 1, kUnlimitedBisections,
                                                               &outer_error);
    for (size_t c = 0; c < N; ++c) total[c] += value[c];
  }
  for (size_t c = 0; c < N; ++c) ErrorLedger::report(outer_error[c] + worst_inner[c] * std::fabs(total[c]), total[c]);
  return total;
}

// Sphere seen from outside, sampled uniformly in its cone (p_l = pmf/Ω):
// cone coordinates (γ, ψ) about the centre direction, dω = sin γ dγ dψ,
// cos θ = cos γ (n·ĉ) + sin γ (cos ψ n·s + sin ψ n·t).
struct SphereRings {
  Frame frame;
  Vec3 n;
  double p_light;
  void coefficients(double gamma, double* A, double* B, double* C) const {
    *A = std::cos(gamma) * dot(n, frame.n);
    *B = std::sin(gamma) * dot(n, frame.s);
    *C = std::sin(gamma) * dot(n, frame.t);
  }
  struct Row {
    double cos_gamma, sin_gamma;
  };
  Row row(double gamma) const { return {std::cos(gamma), std::sin(gamma)}; }
  void at(const Row& ring, double cos_psi, double sin_psi, double* cos_theta, double* p, double* measure) const {
    *cos_theta = ring.cos_gamma * dot(n, frame.n) + ring.sin_gamma * (cos_psi * dot(n, frame.s) + sin_psi * dot(n, frame.t));
    *p = p_light;
    *measure = ring.sin_gamma;
  }
};

// A disk light (sampled by area in the renderer: p_l = pmf·r²/(A cos θ'))
// in polar coordinates (ρ, φ) about its centre, dA = ρ dρ dφ.
struct DiskRings {
  Vec3 center, e1, e2, m, n;  // centre relative to p, in-plane axes, unit plane normal, receiver normal
  double pmf, area;
  void coefficients(double rho, double* A, double* B, double* C) const {
    *A = dot(n, center);
    *B = rho * dot(n, e1);
    *C = rho * dot(n, e2);
  }
  double row(double rho) const { return rho; }
  void at(double rho, double cos_phi, double sin_phi, double* cos_theta, double* p, double* measure) const {
    const Vec3 x = center + e1 * (rho * cos_phi) + e2 * (rho * sin_phi);
    const double r2 = length_squared(x), r = std::sqrt(r2);
    const double cos_light = std::fabs(dot(m, x)) / r;
    *cos_theta = dot(n, x) / r;
    *p = pmf * r2 / (area * cos_light);   // area density in solid angle
    *measure = rho * cos_light / r2;       // dω = cos θ'/r² dA, dA = ρ dρ dφ
  }
};

// ∫ g(cos θ, p_light) dω over a polygon light (polygon_patch.h);
// p_light = pmf/Ω for solid-angle sampling (omega > 0), else the area density
// converted to solid angle.
// In the polygon plane's own spherical coordinates (polygon_direction_integral):
// at a direction with cos θ' = cos t the hit point is at r = h/cos t, so the
// area density in solid angle is pmf·r²/(A cos θ') = pmf·h²/(A cos³t).
template <class Integrand, class V = std::invoke_result_t<const Integrand&, double, double>>
V patch_integral_mis(const std::vector<Vec3>& v, const Vec3& n, double pmf, double omega, double area, Integrand g) {
  const Vec3 m = normalize(cross(v[1] - v[0], v[2] - v[0]));
  const double h = std::fabs(dot(m, v[0]));
  return polygon_direction_integral(v, n, kMisPolygonTolerance, kMisQuadratureDepth, kMisOuterBisections,
                                    kMisInnerBisections,
                                    [&](const Vec3& u, double cos_light) {
                                      const double cos_theta = dot(n, u);
                                      if (!(cos_theta > 0) || !(cos_light > 0)) return V{};
                                      const double p_light =
                                          omega > 0 ? pmf / omega
                                                    : pmf * h * h / (area * cos_light * cos_light * cos_light);
                                      return g(cos_theta, p_light);
                                    });
}

// The integrals g returns (per unit radiance) over emitter i's directions (unoccluded).
template <class Integrand, class V = std::invoke_result_t<const Integrand&, double, double>>
V mis_emitter_integrals(const Scene& scene, size_t i, const Vec3& p, const Vec3& n, std::optional<size_t> receiver,
                        double pmf, Integrand g) {
  if (emitter_irradiance(scene, i, p, n, receiver) == 0) return V{};  // nothing of it reaches p
  require_unoccluded(scene, i, p, n, receiver);
  const Object& object = scene.objects[i];
  // Rectangles and triangles: the renderer's choice of method (as for
  // kLightSolidAngle); `perpendicular`: a triangle, or a rectangle whose
  // spherical map the renderer uses.
  auto polygon_integrals = [&](const std::vector<Vec3>& vertices, bool perpendicular) {
    double omega = perpendicular ? polygon_solid_angle(vertices) : 0.0;
    if (!(omega >= kMinSampledSolidAngle)) omega = 0;  // area sampling
    return patch_integral_mis(vertices, n, pmf, omega, shape_area(object.shape), g);
  };
  return std::visit(
      overloaded{
          [&](const Sphere& sphere) {
            const Vec3 center = sphere.center - p;
            const double D = length(center);
            if (!(D > sphere.radius))
              unsupported_configuration(scene, "a receiving point on or inside the sphere light '" + object.name +
                                                   "' (for the MIS second moment)");
            const double alpha = std::asin(sphere.radius / D);
            const SphereRings rings{Frame::from_normal(center / D), n, pmf / sphere_solid_angle(D, sphere.radius)};
            // Kink where the horizon starts to cut the rings: γ = |π/2 − β|.
            const double beta_angle = std::atan2(length(cross(n, center)), dot(n, center));
            return ring_integral(0.0, alpha, {std::fabs(kPi / 2 - beta_angle)}, rings, g);
          },
          [&](const Disk& d) {
            const Frame f = Frame::from_normal(d.normal);
            const DiskRings rings{d.center - p, f.s, f.t, d.normal, n, pmf, d.area()};
            // Kinks in ρ where the horizon starts cutting the rings: |A| = ρ·M.
            const double A = dot(n, d.center - p), M = std::hypot(dot(n, f.s), dot(n, f.t));
            std::vector<double> kinks;
            if (M > 0) kinks.push_back(std::fabs(A) / M);
            return ring_integral(0.0, d.radius, kinks, rings, g);
          },
          [&](const Rectangle& r) {
            const double lu = length(r.edge_u), lv = length(r.edge_v);
            return polygon_integrals(polygon_vertices_relative(r, p),
                                     std::fabs(dot(r.edge_u, r.edge_v)) <= kPerpendicularTolerance * lu * lv);
          },
          [&](const Triangle& t) { return polygon_integrals(polygon_vertices_relative(t, p), true); }},
      object.shape);
}

// The MIS terms of emitter i (unoccluded) per unit radiance: the one of
// one-sample MIS (beta 0), or the four of multi-sample MIS for each of the
// balance (beta 1) and power (beta 2) heuristics, all eight integrated
// together over the same directions (index beta − 1).
MisTerms one_sample_emitter_terms(const Scene& scene, size_t i, const Vec3& p, const Vec3& n,
                                  std::optional<size_t> receiver, double pmf) {
  MisTerms terms;
  terms.one_sample2 = mis_emitter_integrals(scene, i, p, n, receiver, pmf, [](double cos_theta, double p_light) {
                        return one_sample_integrand(cos_theta, p_light);
                      })[0];
  return terms;
}
std::array<MisTerms, 2> multi_sample_emitter_terms(const Scene& scene, size_t i, const Vec3& p, const Vec3& n,
                                                   std::optional<size_t> receiver, double pmf) {
  const std::array<double, 8> v =
      mis_emitter_integrals(scene, i, p, n, receiver, pmf, [](double cos_theta, double p_light) {
        const MultiSampleValues balance = multi_sample_integrands(cos_theta, p_light, 1);
        const MultiSampleValues power = multi_sample_integrands(cos_theta, p_light, 2);
        return std::array<double, 8>{balance[0], balance[1], balance[2], balance[3],
                                     power[0],   power[1],   power[2],   power[3]};
      });
  std::array<MisTerms, 2> terms;
  for (size_t b = 0; b < 2; ++b) {
    terms[b].bsdf2 = v[4 * b], terms[b].light2 = v[4 * b + 1];
    terms[b].bsdf1 = v[4 * b + 2], terms[b].light1 = v[4 * b + 3];
  }
  return terms;
}

}  // namespace

std::array<double, 2> mis_second_moments(const Scene& scene, const Vec3& p, const Vec3& n,
                                         std::optional<size_t> receiver, bool multi_sample,
                                         const std::vector<double>& pmf) {
  if (pmf.empty()) return {0.0, 0.0};
  const double c = kOneSampleBsdfProbability;
  const size_t heuristics = multi_sample ? 2 : 0;
  // Per heuristic (index beta − 1).
  double bsdf2[2] = {}, light2[2] = {}, bsdf1[2] = {}, light1[2] = {};
  double one_sample2 = 0;
  size_t light = 0;
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    const Object& object = scene.objects[i];
    if (!object.is_emitter()) continue;
    const double pmf_i = pmf[light++];
    if (receiver && i == *receiver) continue;
    const double le = object.emitted_radiance;
    if (!multi_sample) {
      one_sample2 += le * le * one_sample_emitter_terms(scene, i, p, n, receiver, pmf_i).one_sample2;
      continue;
    }
    const std::array<MisTerms, 2> t = multi_sample_emitter_terms(scene, i, p, n, receiver, pmf_i);
    for (size_t b = 0; b < heuristics; ++b) {
      bsdf2[b] += le * le * t[b].bsdf2, light2[b] += le * le * t[b].light2;
      bsdf1[b] += le * t[b].bsdf1, light1[b] += le * t[b].light1;
    }
  }
  // Point lights: only the light sample finds them, with weight 1; chosen with
  // pmf P_l it returns E_l/P_l (multi-sample) or E_l/((1 − c)·P_l) (one-sample).
  for (size_t l = 0; l < scene.point_lights.size(); ++l) {
    const double pmf_l = pmf[light++];
    const double e = point_light_irradiance(scene, l, p, n, receiver);
    for (size_t b = 0; b < heuristics; ++b) {
      light2[b] += e * e / pmf_l;
      light1[b] += e;
    }
    one_sample2 += e * e / ((1 - c) * pmf_l);
  }
  // The open sky: p_l = pmf·cos θ/π = pmf·p_b, so w_b = 1/(1 + pmf^β) and
  // w_l = pmf^β/(1 + pmf^β) are constants; with P = E_env/L_env = ∫_sky cos θ dω:
  //   E[Y_b²] = w_b² L² π P,  E[Y_l²] = w_l² L² π P/pmf,  E[Y_b] = w_b L P,  E[Y_l] = w_l L P.
  const double e_env = environment_irradiance(scene, p, n, receiver);
  const double pmf_env = pmf.back();
  // One-sample on the open sky: q = (c + (1 − c)·pmf)·cos θ/π, so
  // E[Y²] = L² π P/(c + (1 − c)·pmf) = L π E_env/(c + (1 − c)·pmf).
  if (!multi_sample)
    return {one_sample2 + (e_env > 0 ? scene.environment.radiance * kPi * e_env / (c + (1 - c) * pmf_env) : 0.0),
            0.0};
  std::array<double, 2> moments{};
  for (size_t b = 0; b < heuristics; ++b) {
    if (e_env > 0) {
      const double l_env = scene.environment.radiance;
      const double q = b == 1 ? pmf_env * pmf_env : pmf_env;
      const double w_b = 1 / (1 + q), w_l = q / (1 + q);
      bsdf2[b] += w_b * w_b * l_env * kPi * e_env;
      light2[b] += w_l * w_l * l_env * kPi * e_env / pmf_env;
      bsdf1[b] += w_b * e_env;
      light1[b] += w_l * e_env;
    }
    moments[b] = bsdf2[b] + light2[b] + 2 * bsdf1[b] * light1[b];
  }
  return moments;
}

std::array<double, 2> multi_sample_mis_second_moments(const Scene& scene, const Vec3& p, const Vec3& n,
                                                      std::optional<size_t> receiver, LightSelection selection) {
  // second_moment's check (the environment map), then the pair it picks from.
  if (scene.environment.map) unsupported_configuration(scene, "MIS under an environment map");
  return mis_second_moments(scene, p, n, receiver, true, light_selection_pmf(scene, selection));
}

}  // namespace furnace::analytic
