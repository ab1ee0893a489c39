#include "analytic/moments.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <tuple>
#include <type_traits>
#include <string>
#include <utility>
#include <vector>

#include <variant>

#include "analytic/circle_region.h"
#include "analytic/disk_light.h"
#include "analytic/emitter.h"
#include "analytic/error_ledger.h"
#include "analytic/light_moments.h"
#include "analytic/phong.h"
#include "analytic/planar_light.h"
#include "analytic/environment.h"
#include "analytic/polygon_patch.h"
#include "analytic/sin_cos.h"
#include "analytic/environment_map.h"
#include "analytic/reference.h"
#include "analytic/unsupported.h"
#include "core/adaptive_quadrature.h"
#include "core/error.h"

namespace furnace::analytic {

namespace {

// ∫_visible h³/(h²+s²)^(5/2) dA: uniform-hemisphere kernel cos²θ·cos θ'/r².
// G(s) = (1 − c³)/3 with c = h/r; G/s² = (1 + c + c²)/(3r(r + h)), from
// 1 − c = s²/(r(r + h)), so nothing cancels for small s.
double hemisphere_kernel(const DiskLightView& v) {
  const double h = v.h;
  return contour_quadrature(visible_boundary(v.light, v.occluder_images), [h](double s2) {
    const double r = std::sqrt(h * h + s2);
    const double c = h / r;
    return (1 + c + c * c) / (3 * r * (r + h));
  });
}

// ∫_visible h⁴/(h²+s²)⁴ dA: light-area kernel (cos θ cos θ'/r²)².
double area_kernel(const DiskLightView& v) {
  const double h2 = v.h * v.h;
  return contour_quadrature(visible_boundary(v.light, v.occluder_images), [h2](double s2) {
    const double r2 = h2 + s2;
    return (3 * h2 * h2 + 3 * h2 * s2 + s2 * s2) / (6 * h2 * r2 * r2 * r2);
  });
}

std::vector<Vec3> polygon_vertices_relative(const Rectangle& r, const Vec3& p) {
  return {r.corner - p, r.corner + r.edge_u - p, r.corner + r.edge_u + r.edge_v - p, r.corner + r.edge_v - p};
}
std::vector<Vec3> polygon_vertices_relative(const Triangle& t, const Vec3& p) { return {t.p0 - p, t.p1 - p, t.p2 - p}; }

// ∫_object max(cos θ, 0)² dω: the cos²-weighted solid angle an environment
// blocker hides from the uniform-hemisphere estimator.
double blocker_cos2_solid_angle(const Scene& scene, size_t j, const Vec3& p, const Vec3& n) {
  const Object& o = scene.objects[j];
  return std::visit(
      overloaded{[&](const Sphere& s) { return sphere_cos2_solid_angle(s.center - p, s.radius, n); },
                 [&](const Disk& d) {
                   if (length(cross(normalize(d.normal), n)) > 1e-12) {
                     // A tilted disk: the general planar path for the disk as a lone
                     // two-sided emitter (as projected_solid_angle does for E).
                     return planar_light_cos2_solid_angle(as_lone_unit_emitter(scene, j), 0, p, n, std::nullopt);
                   }
                   const Vec3 offset = d.center - p;
                   const double h = dot(offset, n);
                   const Frame f = Frame::from_normal(n);
                   DiskLightView view;
                   view.h = h;
                   view.light = {dot(offset, f.s), dot(offset, f.t), d.radius};
                   return hemisphere_kernel(view);
                 },
                 [&](const Rectangle& r) { return polygon_cos2_solid_angle(polygon_vertices_relative(r, p), n); },
                 [&](const Triangle& t) { return polygon_cos2_solid_angle(polygon_vertices_relative(t, p), n); }},
      o.shape);
}

// Per-emitter kernels: K_hemisphere = ∫_visible cos²θ dω, K_area = ∫_visible (cos θ cos θ'/r²)² dA.
double emitter_kernel(Strategy estimator, const Scene& scene, size_t i, const Vec3& p, const Vec3& n,
                      std::optional<size_t> receiver) {
  const Object& object = scene.objects[i];
  const bool hemisphere = estimator == Strategy::kUniformHemisphere;
  // Rectangles and triangles: the exact planar path handles occluders and the
  // horizon for both kernels; an unoccluded light's area kernel has its own
  // closed form (polygon_area_kernel).
  auto polygon_kernel = [&](const auto& polygon) {
    if (hemisphere) return planar_light_cos2_solid_angle(scene, i, p, n, receiver);
    if (emitter_irradiance(scene, i, p, n, receiver) == 0) return 0.0;
    if (possible_blocker(scene, i, p, n, receiver)) return planar_light_area_kernel(scene, i, p, n, receiver);
    return polygon_area_kernel(polygon_vertices_relative(polygon, p), n);
  };
  return std::visit(
      overloaded{[&](const Disk&) {
                   std::string reason;
                   const auto view = disk_light_view(scene, i, p, n, receiver, &reason);
                   // The light-area kernel of an unoccluded disk by the planar path
                   // (small disks by the product rule, the foot point far outside by
                   // the tail form): the circle path's contour terms cancel there.
                   if (view && !hemisphere && view->occluder_images.empty())
                     return planar_light_area_kernel(scene, i, p, n, receiver);
                   if (view) return hemisphere ? hemisphere_kernel(*view) : area_kernel(*view);
                   if (reason.empty()) return 0.0;
                   // The exact planar path (tilted receivers, occluders as planar_light.h allows).
                   return hemisphere ? planar_light_cos2_solid_angle(scene, i, p, n, receiver)
                                     : planar_light_area_kernel(scene, i, p, n, receiver);
                 },
                 [&](const Sphere& sphere) {
                   if (emitter_irradiance(scene, i, p, n, receiver) == 0) return 0.0;  // nothing of it reaches p
                   require_unoccluded(scene, i, p, n, receiver);
                   return hemisphere ? sphere_cos2_solid_angle(sphere.center - p, sphere.radius, n)
                                     : sphere_area_kernel(sphere.center - p, sphere.radius, n);
                 },
                 [&](const Rectangle& r) { return polygon_kernel(r); },
                 [&](const Triangle& t) { return polygon_kernel(t); }},
      object.shape);
}

// Point lights: a light-sampling estimator that picks point light l (pmf P_l)
// returns E_l/P_l exactly, so it adds P_l·(E_l/P_l)² = E_l²/P_l to E[Y²].
// `pmf` is light_selection_pmf (emitters first, then the point lights).
// The hemisphere estimators never see a point light: refused.
double point_lights_second_moment(Strategy estimator, const Scene& scene, const Vec3& p, const Vec3& n,
                                  std::optional<size_t> receiver, const std::vector<double>& pmf) {
  if (scene.point_lights.empty()) return 0.0;
  if (estimator != Strategy::kLightArea && estimator != Strategy::kLightSolidAngle)
    unsupported_configuration(scene, "point lights, which a hemisphere estimator cannot sample,");
  size_t first = 0;
  for (const Object& o : scene.objects) first += o.is_emitter() ? 1 : 0;
  double moment = 0;
  for (size_t l = 0; l < scene.point_lights.size(); ++l) {
    const double e = point_light_irradiance(scene, l, p, n, receiver);
    moment += e * e / pmf[first + l];
  }
  return moment;
}

// ---------------------------------------------------------------------------
// Light solid-angle sampling (Strategy::kLightSolidAngle). The renderer's
// choice of method per emitter is its contract in core/strategy.h: spherical
// maps from kMinSampledSolidAngle up, rectangles within
// kPerpendicularTolerance of perpendicular, area sampling otherwise.

// E[Y²]/(K·L²) of emitter i under light_solid_angle sampling:
//   cone or whole spherical polygon: Ω·∫_visible max(cos θ, 0)² dω,
//   area fallback:                  A·∫_visible (cos θ cos θ'/r²)² dA (kLightArea).
double solid_angle_emitter_kernel(const Scene& scene, size_t i, const Vec3& p, const Vec3& n,
                                  std::optional<size_t> receiver) {
  const Object& object = scene.objects[i];
  auto area_fallback = [&] {
    return shape_area(object.shape) * emitter_kernel(Strategy::kLightArea, scene, i, p, n, receiver);
  };
  // Nothing of it reaches p (behind a one-sided light, edge-on, below the
  // horizon or wholly hidden): every sample is 0, whatever the method.
  auto reaches_p = [&] { return emitter_irradiance(scene, i, p, n, receiver) != 0; };
  // Triangles and rectangles seen from their emitting side (a two-sided light
  // from behind is sampled as its mirror twin: the same Ω).
  auto polygon_kernel = [&](const auto& polygon) {
    if (!reaches_p()) return 0.0;
    const double omega = polygon_solid_angle(polygon_vertices_relative(polygon, p));
    if (!(omega >= kMinSampledSolidAngle)) return area_fallback();
    return omega * planar_light_cos2_solid_angle(scene, i, p, n, receiver);
  };
  return std::visit(
      overloaded{[&](const Disk&) { return area_fallback(); },
                 [&](const Rectangle& r) {
                   const double lu = length(r.edge_u), lv = length(r.edge_v);
                   if (!(std::fabs(dot(r.edge_u, r.edge_v)) <= kPerpendicularTolerance * lu * lv)) return area_fallback();
                   return polygon_kernel(r);
                 },
                 [&](const Triangle& t) { return polygon_kernel(t); },
                 [&](const Sphere& sphere) {
                   if (!reaches_p()) return 0.0;
                   const Vec3 center = sphere.center - p;
                   const double D = length(center);
                   if (!(D > sphere.radius)) return area_fallback();  // on or inside: the renderer has no cone
                   require_unoccluded(scene, i, p, n, receiver);
                   return sphere_solid_angle(D, sphere.radius) * sphere_cos2_solid_angle(center, sphere.radius, n);
                 }},
      object.shape);
}

// ---------------------------------------------------------------------------
// Multi-sample MIS (Strategy::kMisBalance, kMisPower).

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

// The φ-arcs of [0, 2π) on which A + B cos φ + C sin φ > 0.
std::vector<std::pair<double, double>> positive_arcs(double A, double B, double C) {
  const double M = std::hypot(B, C);
  if (M <= std::fabs(A)) return A > 0 ? std::vector<std::pair<double, double>>{{0, 2 * kPi}}
                                      : std::vector<std::pair<double, double>>{};
  const double phi0 = std::atan2(C, B), half = std::acos(-A / M);
  return {{phi0 - half, phi0 + half}};
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

// E[Y²] of MIS: index 0 one-sample MIS, or (multi_sample) index 0 the
// balance and index 1 the power heuristic's multi-sample MIS. `pmf`: the
// selection pmf of every light (light_selection_pmf: emitters in object
// order, then point lights, then the environment).
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

}  // namespace

double second_moment(Strategy strategy, const Scene& scene, const Vec3& p, const Vec3& n,
                     std::optional<size_t> receiver, LightSelection selection) {
  const std::optional<Strategy> model = strategy_info(strategy).variance_model;
  if (!model)
    unsupported_configuration(scene, "the strategy '" + strategy_name(strategy) +
                                         "', which has no variance model,");
  const Strategy estimator = *model;
  if (estimator == Strategy::kMisBalance || estimator == Strategy::kMisPower ||
      estimator == Strategy::kMisOneSample) {
    // mis_second_moments models emitters, point lights and a constant sky.
    if (scene.environment.map) unsupported_configuration(scene, "MIS under an environment map");
    const int beta = strategy_info(estimator).mis_beta;  // 0: one-sample MIS
    const std::array<double, 2> moments =
        mis_second_moments(scene, p, n, receiver, beta != 0, light_selection_pmf(scene, selection));
    return moments[beta == 2 ? 1 : 0];
  }
  // Selection pmf of every light (emitters, point lights, environment), and
  // 1/pmf of the i-th emitter object in object order.
  const std::vector<double> pmf = light_selection_pmf(scene, selection);
  std::vector<double> inverse_pmf_of_object(scene.objects.size(), 0.0);
  size_t light = 0;
  for (size_t i = 0; i < scene.objects.size(); ++i)
    if (scene.objects[i].is_emitter()) inverse_pmf_of_object[i] = 1.0 / pmf[light++];

  double moment = 0;
  ErrorSum errors;
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    const Object& object = scene.objects[i];
    if (!object.is_emitter() || (receiver && i == *receiver)) continue;
    const double le = object.emitted_radiance;
    moment += errors.term([&]() -> double {
      switch (estimator) {
        case Strategy::kUniformHemisphere:
          return 2 * kPi * le * le * emitter_kernel(estimator, scene, i, p, n, receiver);
        case Strategy::kCosineHemisphere:
          return kPi * le * le * emitter_irradiance(scene, i, p, n, receiver);
        case Strategy::kLightArea:
          return inverse_pmf_of_object[i] * shape_area(object.shape) * le * le *
                 emitter_kernel(estimator, scene, i, p, n, receiver);
        case Strategy::kLightSolidAngle:
          return inverse_pmf_of_object[i] * le * le * solid_angle_emitter_kernel(scene, i, p, n, receiver);
        case Strategy::kMisBalance:
        case Strategy::kMisPower:
        case Strategy::kMisOneSample:
          return 0;  // mis_second_moments above
        case Strategy::kBsdf:
        case Strategy::kPathNaive:
        case Strategy::kPathMis:
          break;
      }
      FURNACE_CHECK(false && "mapped to its variance model above");
      return 0;
    });
  }
  moment += errors.term([&] { return point_lights_second_moment(estimator, scene, p, n, receiver, pmf); });
  // E of the environment under its own ledger: its error counts only where
  // a term below is proportional to it.
  double e_env = 0, e_env_relative_error = 0;
  {
    ErrorLedger ledger;
    e_env = environment_irradiance(scene, p, n, receiver);
    e_env_relative_error = ledger.take_relative();
  }
  auto proportional_to_e_env = [&](double value) {
    ErrorLedger::report(e_env_relative_error, 1.0);
    return value;
  };
  if (e_env > 0 && scene.environment.map) {  // unblocked (environment_irradiance refuses blockers)
    switch (estimator) {
      case Strategy::kUniformHemisphere:
        moment += errors.term([&] { return map_uniform_hemisphere_moment(scene.environment, n); });
        break;
      case Strategy::kCosineHemisphere: moment += errors.term([&] { return map_cosine_moment(scene.environment, n); }); break;
      case Strategy::kLightArea:  // the map's texel sampling, chosen with pmf P_env (last)
      case Strategy::kLightSolidAngle:
        moment += errors.term([&] { return map_light_sampling_moment(scene.environment, n, 1) / pmf.back(); });
        break;
      case Strategy::kMisBalance:
      case Strategy::kMisPower:
      case Strategy::kMisOneSample:
        break;  // refused above
      case Strategy::kBsdf:
      case Strategy::kPathNaive:
      case Strategy::kPathMis:
        FURNACE_CHECK(false && "mapped to its variance model above");
    }
  } else if (e_env > 0) {
    const double l_env = scene.environment.radiance;
    switch (estimator) {
      case Strategy::kUniformHemisphere: {
        // ∫ cos²θ dω = 2π/3 over the hemisphere, minus what the blockers hide;
        // the blockers' errors count against what stays visible.
        ErrorSum hidden_errors;
        double hidden = 0;
        for (size_t j : environment_blockers(scene, p, n, receiver))
          hidden += hidden_errors.term([&] { return blocker_cos2_solid_angle(scene, j, p, n); });
        const double visible = std::fmax(2 * kPi / 3 - hidden, 0.0);
        moment += errors.term([&] {
          hidden_errors.report(visible);
          return 2 * kPi * l_env * l_env * visible;
        });
        break;
      }
      case Strategy::kCosineHemisphere:
        moment += errors.term([&] { return proportional_to_e_env(kPi * l_env * e_env); });
        break;
      case Strategy::kLightArea:  // the environment is sampled cosine-weighted, chosen with pmf P_env (last)
      case Strategy::kLightSolidAngle:
        moment += errors.term([&] { return proportional_to_e_env(kPi * l_env * e_env / pmf.back()); });
        break;
      case Strategy::kMisBalance:
      case Strategy::kMisPower:
      case Strategy::kMisOneSample:
        break;  // mis_second_moments above
      case Strategy::kBsdf:
      case Strategy::kPathNaive:
      case Strategy::kPathMis:
        FURNACE_CHECK(false && "mapped to its variance model above");
    }
  }
  errors.report(moment);
  return moment;
}

namespace {

// pixel_center_second_moment's steps for N second moments at once:
// phong(p, n, wo, receiver) gives the N glossy estimators' E[Y²] at a Phong
// hit, lambertian(p, n, receiver) the N irradiance estimators' at a
// Lambertian one.
template <size_t N, class Phong, class Lambertian>
std::array<double, N> pixel_center_moments(const Scene& scene, int px, int py, Phong phong, Lambertian lambertian) {
  std::array<double, N> out;
  const Camera::Ray ray = scene.camera.pixel_center_ray(px, py);
  const std::optional<Hit> hit = intersect(scene, ray.origin, ray.direction);
  if (!hit) {
    out.fill(std::pow(environment_radiance(scene.environment, ray.direction), 2));
    return out;
  }
  const Object& object = scene.objects[hit->object_index];
  const double cos_view = dot(ray.direction, hit->normal);
  const double le = (cos_view < 0 || object.two_sided) ? object.emitted_radiance : 0.0;
  if (object.material.albedo == 0) {
    out.fill(le * le);
    return out;
  }
  const Vec3 n = cos_view < 0 ? hit->normal : -hit->normal;
  if (object.material.type == BsdfType::kPhong) {
    // Y_px = Le + Y with Y the glossy estimator (phong.h), emission constant.
    const double e = phong_reflected_radiance(scene, hit->point, n, -ray.direction, hit->object_index);
    const std::array<double, N> m = phong(hit->point, n, -ray.direction, hit->object_index);
    for (size_t i = 0; i < N; ++i) out[i] = le * le + 2 * le * e + m[i];
    return out;
  }
  if (object.material.type != BsdfType::kLambertian)
    unsupported_configuration(scene, "a camera ray hitting the non-Lambertian, non-black object '" + object.name + "'");
  const double k = object.material.albedo * kInvPi;
  const double e = irradiance(scene, hit->point, n, hit->object_index);
  const std::array<double, N> m = lambertian(hit->point, n, hit->object_index);
  for (size_t i = 0; i < N; ++i) out[i] = le * le + 2 * le * k * e + k * k * m[i];
  return out;
}

}  // namespace

double pixel_center_second_moment(Strategy strategy, const Scene& scene, int px, int py, LightSelection selection) {
  return pixel_center_moments<1>(
      scene, px, py,
      [&](const Vec3& p, const Vec3& n, const Vec3& wo, size_t receiver) {
        return std::array<double, 1>{phong_second_moment(strategy, scene, p, n, wo, receiver, selection)};
      },
      [&](const Vec3& p, const Vec3& n, size_t receiver) {
        return std::array<double, 1>{second_moment(strategy, scene, p, n, receiver, selection)};
      })[0];
}

std::array<double, 2> multi_sample_mis_second_moments(const Scene& scene, const Vec3& p, const Vec3& n,
                                                      std::optional<size_t> receiver, LightSelection selection) {
  // second_moment's check (the environment map), then the pair it picks from.
  if (scene.environment.map) unsupported_configuration(scene, "MIS under an environment map");
  return mis_second_moments(scene, p, n, receiver, true, light_selection_pmf(scene, selection));
}

std::array<double, 2> pixel_center_multi_sample_mis_second_moments(const Scene& scene, int px, int py,
                                                                   LightSelection selection) {
  return pixel_center_moments<2>(
      scene, px, py,
      [&](const Vec3& p, const Vec3& n, const Vec3& wo, size_t receiver) {
        // The glossy estimators have no shared quadrature: one each.
        return std::array<double, 2>{phong_second_moment(Strategy::kMisBalance, scene, p, n, wo, receiver, selection),
                                     phong_second_moment(Strategy::kMisPower, scene, p, n, wo, receiver, selection)};
      },
      [&](const Vec3& p, const Vec3& n, size_t receiver) {
        return multi_sample_mis_second_moments(scene, p, n, receiver, selection);
      });
}

}  // namespace furnace::analytic
