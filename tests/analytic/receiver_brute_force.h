// The receiver tests' brute force (receiver_planar_test.cpp): the radiance
// and every direct strategy's E[Y²] at a receiver-model BSDF under planar
// lights, by quadrature in each light's own coordinates (polar about a
// disk's centre, (u, v) on a parallelogram or triangle), the horizon and a
// parallel occluder's shadow circle cut exactly per ring or row, the light
// strategy's Ω integrated as ∫ cos θ'/d² dA, every estimator's integrand
// written out from its definition (analytic/receiver.h's file comment), none
// of the model's code (receiver_integrals.h, receiver_planar.*) used.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>
#include <variant>
#include <vector>

#include "analytic/disk.h"
#include "analytic/phong.h"
#include "analytic/point_light.h"
#include "analytic/receiver.h"
#include "core/adaptive_quadrature.h"
#include "core/error.h"
#include "core/scene.h"
#include "core/strategy.h"

namespace furnace::analytic::receiver_testing {

// The brute force's tolerances: the outer one a tenth of the model's, the
// inner one 100 times tighter still, so that the inner results' own error
// is no noise the outer quadrature has to chase; each integral's bisections
// capped (kBruteBisections), which bounds the cost where round-off is
// reached first.
constexpr double kBruteOuterTolerance = 1e-10;
constexpr double kBruteInnerTolerance = 1e-12;
constexpr int kBruteDepth = 24;
// A lobe cos^e α evaluated from a rounded cos α carries a relative noise of
// about e·ε (e ~ 1/width²): the brute force asks no more than kNoiseUlps
// times that of its inner integrals (and ten times more of the outer).
constexpr double kNoiseUlps = 10;
constexpr size_t kBruteBisections = 600;

// ---------------------------------------------------------------------------
// The brute force: every estimator's integrand over the light's own
// coordinates, written from the definitions (receiver.h's file comment).

enum Term {
  kRadiance, kUniform, kCosine, kBsdfTerm, kArea, kSolidAngle, kOneSample,
  kBalanceB2, kBalanceL2, kBalanceB1, kBalanceL1, kPowerB2, kPowerL2, kPowerB1, kPowerL1, kTermCount
};
using Terms = std::array<double, kTermCount>;

// One planar light as the brute force sees it (world space).
struct BruteLight {
  const Object* object = nullptr;
  Vec3 front;  // unit normal on p's side
  double pmf = 1;
  double omega = 0;  // Ω sampled uniformly by light_solid_angle, 0: by area
  std::optional<Circle2> shadow;  // the occluder's central projection, in the disk's (e1, e2) coordinates about its centre
  double lobe_width = 0;  // a narrow lobe's angular width, rad: the brute force cuts around its peak; 0: none
  double inner_tolerance = kBruteInnerTolerance, outer_tolerance = kBruteOuterTolerance;
};

// The integrand terms at light point x (world), times dω/dA = cos θ'/d².
inline Terms terms_at(const Receiver& receiver, const BruteLight& light, const Vec3& p, const Vec3& x) {
  Terms t{};
  const Vec3 v = x - p;
  const double d2 = length_squared(v), d = std::sqrt(d2);
  const Vec3 w = v / d;
  const double cos_theta = dot(receiver.n, w), cos_emission = -dot(light.front, w);
  if (!(cos_theta > 0) || !(cos_emission > 0)) return t;
  const BsdfValue b = receiver.at(cos_theta, dot(receiver.mirror(), w));
  const double L = light.object->emitted_radiance, area = shape_area(light.object->shape);
  const double h = b.f_cos * L, pb = b.pdf_solid_angle;
  const double pa = light.pmf * d2 / (area * cos_emission);
  const double ps = light.omega > 0 ? light.pmf / light.omega : pa;
  const double c = kOneSampleBsdfProbability;
  t[kRadiance] = h;
  t[kUniform] = 2 * kPi * h * h;
  t[kCosine] = kPi * h * h / cos_theta;
  t[kBsdfTerm] = b.f_cos2_over_pdf * L * L;
  t[kArea] = h * h / pa;
  t[kSolidAngle] = h * h / ps;
  t[kOneSample] = h * h / (c * pb + (1 - c) * ps);
  for (int beta = 1; beta <= 2; ++beta) {
    const double xb = beta == 2 ? pb * pb : pb, xl = beta == 2 ? ps * ps : ps;
    const double wb = xb / (xb + xl), wl = xl / (xb + xl);
    const int o = beta == 1 ? kBalanceB2 : kPowerB2;
    t[o] = wb * wb * b.f_cos2_over_pdf * L * L;
    t[o + 1] = wl * wl * h * h / ps;
    t[o + 2] = wb * h;
    t[o + 3] = wl * h;
  }
  for (double& value : t) value *= cos_emission / d2;
  return t;
}

// Pieces of [lo, hi] between sorted cuts inside it.
inline std::vector<double> with_cuts(double lo, double hi, std::vector<double> cuts) {
  std::vector<double> out{lo, hi};
  for (double c : cuts)
    if (c > lo && c < hi) out.push_back(c);
  std::sort(out.begin(), out.end());
  return out;
}

template <class F>
inline Terms integrate_pieces(const F& f, const std::vector<double>& edges, double tolerance) {
  Terms sum{};
  for (size_t i = 0; i + 1 < edges.size(); ++i) {
    if (!(edges[i + 1] > edges[i])) continue;
    const Terms v = adaptive_gauss_kronrod_relative_components(f, edges[i], edges[i + 1], tolerance, kBruteDepth, 1,
                                                               kBruteBisections);
    for (int k = 0; k < kTermCount; ++k) sum[k] += v[k];
  }
  return sum;
}

// Where the receiver's mirror direction meets the light's plane (or the centre
// of the light when it does not).
inline Vec3 mirror_hit(const Receiver& receiver, const Vec3& p, const Vec3& on_plane, const Vec3& front) {
  const Vec3 r = receiver.mirror();
  const double toward = -dot(r, front);
  if (!(toward > 0)) return on_plane;
  return p + r * (dot(p - on_plane, front) / toward);
}

// Terms over a disk light: polar (ρ, φ) about its centre, the horizon and the
// shadow circle cut exactly on every ring, cuts at the mirror hit's ring and azimuth.
// The integrand at a light point (terms_at, or one of the reduced ones below).
using TermsAt = Terms (*)(const Receiver&, const BruteLight&, const Vec3&, const Vec3&);

inline Terms disk_terms(const Receiver& receiver, const BruteLight& light, const Disk& disk, const Vec3& p, TermsAt at) {
  const Frame f = Frame::from_normal(disk.normal);
  const double A = dot(receiver.n, disk.center - p), B = dot(receiver.n, f.s), C = dot(receiver.n, f.t);
  const double M = std::hypot(B, C), phi_n = std::atan2(C, B);
  const Vec3 hit = mirror_hit(receiver, p, disk.center, light.front) - disk.center;
  const double hx = dot(hit, f.s), hy = dot(hit, f.t);
  // A narrow lobe's footprint on the plane, about its width times the distance to the peak.
  const double footprint = light.lobe_width * length(hit + disk.center - p);
  const double rho_hit = std::hypot(hx, hy);
  std::vector<double> rho_cuts{rho_hit};
  for (double k : {1.0, 4.0, 16.0})
    if (footprint > 0) rho_cuts.push_back(rho_hit - k * footprint), rho_cuts.push_back(rho_hit + k * footprint);
  if (M > 0) rho_cuts.push_back(std::fabs(A) / M);
  if (light.shadow) {
    const double D = std::hypot(light.shadow->cx, light.shadow->cy);
    rho_cuts.push_back(std::fabs(D - light.shadow->radius));
    rho_cuts.push_back(D + light.shadow->radius);
  }
  auto ring = [&](double rho) {
    auto lit = [&](double phi) {
      const double x = rho * std::cos(phi), y = rho * std::sin(phi);
      if (!(A + B * x + C * y > 0)) return false;
      return !light.shadow || std::hypot(x - light.shadow->cx, y - light.shadow->cy) >= light.shadow->radius;
    };
    std::vector<double> cuts{std::atan2(hy, hx)};
    for (double k : {1.0, 4.0, 16.0})
      if (footprint > 0 && k * footprint < 0.5 * rho)
        cuts.push_back(std::atan2(hy, hx) + k * footprint / rho), cuts.push_back(std::atan2(hy, hx) - k * footprint / rho);
    if (rho * M > std::fabs(A)) {
      const double half = std::acos(-A / (rho * M));
      cuts.push_back(phi_n + half), cuts.push_back(phi_n - half);
    }
    if (light.shadow && rho > 0) {
      const double D = std::hypot(light.shadow->cx, light.shadow->cy), rs = light.shadow->radius;
      const double k = (rho * rho + D * D - rs * rs) / (2 * rho * D);
      if (std::fabs(k) < 1) {
        const double centre = std::atan2(light.shadow->cy, light.shadow->cx), half = std::acos(k);
        cuts.push_back(centre + half), cuts.push_back(centre - half);
      }
    }
    for (double& c : cuts) c -= 2 * kPi * std::floor(c / (2 * kPi));
    std::vector<double> edges = with_cuts(0, 2 * kPi, cuts);
    auto g = [&](double phi) {
      const Vec3 x = disk.center + f.s * (rho * std::cos(phi)) + f.t * (rho * std::sin(phi));
      Terms t = at(receiver, light, p, x);
      for (double& value : t) value *= rho;
      return t;
    };
    Terms sum{};
    for (size_t i = 0; i + 1 < edges.size(); ++i) {
      if (!lit(0.5 * (edges[i] + edges[i + 1]))) continue;
      const Terms v = integrate_pieces(g, {edges[i], edges[i + 1]}, light.inner_tolerance);
      for (int k = 0; k < kTermCount; ++k) sum[k] += v[k];
    }
    return sum;
  };
  return integrate_pieces(ring, with_cuts(0, disk.radius, rho_cuts), light.outer_tolerance);
}

// Terms over a parallelogram (triangle: v ≤ 1 − u) x = o + u·e1 + v·e2, the
// horizon cut exactly on every row, cuts at the mirror hit.
inline Terms patch_terms(const Receiver& receiver, const BruteLight& light, const Vec3& o, const Vec3& e1, const Vec3& e2,
                        bool triangle, const Vec3& p, TermsAt at) {
  const Vec3 m = cross(e1, e2);
  const double jacobian = length(m);
  const Vec3 hit = mirror_hit(receiver, p, o, light.front) - o;
  const double uh = dot(hit, cross(e2, m)) / dot(e1, cross(e2, m)), vh = dot(hit, cross(m, e1)) / dot(e2, cross(m, e1));
  const double a = dot(receiver.n, o - p), b = dot(receiver.n, e1), c = dot(receiver.n, e2);
  auto v_max = [&](double u) { return triangle ? 1 - u : 1.0; };
  std::vector<double> u_cuts{uh};
  if (b != 0) u_cuts.push_back(-a / b);
  if (triangle && b != c) u_cuts.push_back(-(a + c) / (b - c));
  if (!triangle && b != 0) u_cuts.push_back(-(a + c) / b);
  auto row = [&](double u) {
    double lo = 0, hi = v_max(u);
    // a + b·u + c·v > 0.
    const double base = a + b * u;
    if (c > 0) lo = std::fmax(lo, -base / c);
    else if (c < 0) hi = std::fmin(hi, -base / c);
    else if (!(base > 0)) hi = lo;
    if (!(hi > lo)) return Terms{};
    auto g = [&](double v) {
      Terms t = at(receiver, light, p, o + e1 * u + e2 * v);
      for (double& value : t) value *= jacobian;
      return t;
    };
    return integrate_pieces(g, with_cuts(lo, hi, {vh}), light.inner_tolerance);
  };
  return integrate_pieces(row, with_cuts(0, 1, u_cuts), light.outer_tolerance);
}

inline Terms shape_terms(const Receiver& receiver, const BruteLight& light, const Vec3& p, TermsAt at) {
  return std::visit(
      overloaded{[&](const Disk& d) { return disk_terms(receiver, light, d, p, at); },
                 [&](const Rectangle& r) { return patch_terms(receiver, light, r.corner, r.edge_u, r.edge_v, false, p, at); },
                 [&](const Triangle& t) { return patch_terms(receiver, light, t.p0, t.p1 - t.p0, t.p2 - t.p0, true, p, at); },
                 [&](const Sphere&) -> Terms { throw Error("the brute force takes planar lights only"); }},
      light.object->shape);
}

// Ω = ∫ cos θ'/d² dA over the whole light (no horizon): a "receiver" that is
// the light's own front seen from p, through terms_at's radiance slot.
inline Terms solid_angle_at(const Receiver&, const BruteLight& light, const Vec3& p, const Vec3& x) {
  Terms t{};
  const Vec3 v = x - p;
  const double d2 = length_squared(v);
  t[kRadiance] = std::fmax(-dot(light.front, v) / std::sqrt(d2), 0.0) / d2;
  return t;
}

// The moments of every direct strategy and the radiance, by brute force, for
// the scene's planar lights at p (object 0 the receiver; a parallel disk
// occluder, if any, cast as a shadow circle on a disk light).
struct BruteResult {
  double radiance = 0;
  std::vector<std::pair<Strategy, double>> moments;
};
inline BruteResult brute_force(const Scene& scene, const Vec3& p, const Receiver& receiver, LightSelection selection,
                        double lobe_width = 0) {
  const std::vector<double> pmf = light_selection_pmf(scene, selection);
  Terms sum{};
  size_t index = 0;
  for (size_t i = 1; i < scene.objects.size(); ++i) {
    const Object& object = scene.objects[i];
    if (!object.is_emitter()) continue;
    BruteLight light;
    light.object = &object;
    light.pmf = pmf[index++];
    light.lobe_width = lobe_width;
    if (lobe_width > 0) {
      const double noise = kNoiseUlps * std::numeric_limits<double>::epsilon() / (lobe_width * lobe_width);
      light.inner_tolerance = std::max(kBruteInnerTolerance, noise);
      light.outer_tolerance = std::max(kBruteOuterTolerance, 10 * light.inner_tolerance);
    }
    const Plane plane = *plane_of(object.shape);
    light.front = normalize(plane.normal);
    if (dot(p - plane.point, light.front) < 0) {
      if (!object.two_sided) continue;
      light.front = -light.front;
    }
    // A parallel disk occluder: its central projection from p onto the light's plane.
    for (const Object& other : scene.objects) {
      const auto* o = std::get_if<Disk>(&other.shape);
      const auto* d = std::get_if<Disk>(&object.shape);
      if (&other == &object || other.is_emitter() || !o || !d) continue;
      const double h = dot(p - d->center, light.front), h_o = dot(p - o->center, light.front);
      const Vec3 image = p + (o->center - p) * (h / h_o) - d->center;
      const Frame f = Frame::from_normal(d->normal);
      light.shadow = Circle2{dot(image, f.s), dot(image, f.t), o->radius * h / h_o};
    }
    const bool spherical_map = std::visit(
        overloaded{[](const Rectangle& r) { return std::fabs(dot(r.edge_u, r.edge_v)) <= 1e-12 * length(r.edge_u) * length(r.edge_v); },
                   [](const Triangle&) { return true; }, [](const Disk&) { return false; },
                   [](const Sphere&) { return false; }},
        object.shape);
    if (spherical_map) {
      // The whole light, unclipped and unoccluded: a normal facing it has all of it above the horizon.
      const PhongReceiver everywhere(-light.front, -light.front, 0, 0);
      BruteLight whole = light;
      whole.shadow.reset();
      const double omega = shape_terms(everywhere, whole, p, solid_angle_at)[kRadiance];
      if (omega >= kMinSampledSolidAngle) light.omega = omega;
    }
    const Terms t = shape_terms(receiver, light, p, terms_at);
    for (int k = 0; k < kTermCount; ++k) sum[k] += t[k];
  }
  BruteResult out;
  out.radiance = sum[kRadiance];
  for (Strategy s : direct_strategies()) {
    double m = 0;
    switch (s) {
      case Strategy::kUniformHemisphere: m = sum[kUniform]; break;
      case Strategy::kCosineHemisphere: m = sum[kCosine]; break;
      case Strategy::kBsdf: m = sum[kBsdfTerm]; break;
      case Strategy::kLightArea: m = sum[kArea]; break;
      case Strategy::kLightSolidAngle: m = sum[kSolidAngle]; break;
      case Strategy::kMisOneSample: m = sum[kOneSample]; break;
      case Strategy::kMisBalance: m = sum[kBalanceB2] + sum[kBalanceL2] + 2 * sum[kBalanceB1] * sum[kBalanceL1]; break;
      case Strategy::kMisPower: m = sum[kPowerB2] + sum[kPowerL2] + 2 * sum[kPowerB1] * sum[kPowerL1]; break;
      case Strategy::kPathNaive:
      case Strategy::kPathMis: continue;
    }
    out.moments.emplace_back(s, m);
  }
  return out;
}

// The radiance term alone (the brute force's other terms 0): for lobes so
// narrow that every term to full precision would cost minutes.
inline Terms radiance_at(const Receiver& receiver, const BruteLight& light, const Vec3& p, const Vec3& x) {
  Terms t = terms_at(receiver, light, p, x);
  for (int k = kRadiance + 1; k < kTermCount; ++k) t[k] = 0;
  return t;
}

}  // namespace furnace::analytic::receiver_testing
