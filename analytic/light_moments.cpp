#include "analytic/light_moments.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <variant>

#include <boost/math/quadrature/tanh_sinh.hpp>

#include "analytic/circle_region.h"
#include "analytic/disk_light.h"
#include "analytic/emitter.h"
#include "analytic/error_ledger.h"
#include "analytic/planar_light.h"
#include "analytic/polygon.h"
#include "analytic/polygon_patch.h"
#include "analytic/sin_cos.h"
#include "analytic/sin_cos_power_integral.h"
#include "analytic/small_emitter.h"
#include "core/adaptive_quadrature.h"
#include "core/error.h"

namespace furnace::analytic {

namespace {

// ∫ max(a + b cos ψ, 0)² dψ over ψ ∈ (−π, π].
double ring_cos2(double a, double b) {
  if (b <= std::fabs(a)) return a > 0 ? 2 * kPi * (a * a + 0.5 * b * b) : 0.0;
  const double psi = std::acos(std::clamp(-a / b, -1.0, 1.0));
  return 2 * ((a * a + 0.5 * b * b) * psi + 2 * a * b * std::sin(psi) + 0.25 * b * b * std::sin(2 * psi));
}

// ∫_0^α sin γ·weight(γ)·ring_cos2(cos γ cos β, sin γ sin β) dγ.
template <class Weight>
double cone_integral(const Vec3& center, double R, const Vec3& n, Weight weight) {
  const double D = length(center);
  FURNACE_CHECK(D > R && R > 0);
  const double alpha = std::asin(R / D);
  const double cos_b = dot(n, center) / D, sin_b = length(cross(n, center)) / D;
  if (cos_b <= -std::sin(alpha)) return 0.0;  // wholly below the horizon
  auto f = [&](double gamma) {
    return std::sin(gamma) * weight(gamma) * ring_cos2(std::cos(gamma) * cos_b, std::sin(gamma) * sin_b);
  };
  boost::math::quadrature::tanh_sinh<double> integrator;
  const double gamma_h = std::fabs(kPi / 2 - std::atan2(sin_b, cos_b));
  double sum = 0, error = 0;
  auto piece = [&](double lo, double hi) {
    double piece_error = 0;
    sum += tanh_sinh_integral(integrator, f, lo, hi, 1e-13, &piece_error);
    error += piece_error;
  };
  if (gamma_h > 0 && gamma_h < alpha) {
    piece(0.0, gamma_h);
    piece(gamma_h, alpha);
  } else {
    piece(0.0, alpha);
  }
  ErrorLedger::report(error, sum);
  return sum;
}

// Solid angle of the triangle A B C (vectors from p) by Van Oosterom and
// Strackee, Ω = 2·atan2(a·(b × c), 1 + a·b + b·c + c·a) for the unit vectors,
// with the triple product as A·((B − A) × (C − A))/(|A||B||C|): the edge
// vectors keep it accurate when p is close to the triangle's plane (the
// unit vectors are then nearly coplanar and a·(b × c) computed from them
// has an absolute error ~ ε against a value ~ the plane's distance).
double triangle_solid_angle(const Vec3& A, const Vec3& B, const Vec3& C) {
  const double la = length(A), lb = length(B), lc = length(C);
  const Vec3 a = A / la, b = B / lb, c = C / lc;
  const double triple = dot(A, cross(B - A, C - A)) / (la * lb * lc);
  return 2 * std::atan2(triple, 1 + dot(a, b) + dot(b, c) + dot(c, a));
}

// Solid angle of a convex planar polygon (vertices relative to p) by
// Green's theorem about p's foot point F on its plane (height h):
//   Ω = ∮ (1 − cos T) dφ,  cos T = h/√(h² + ρ²),
// and along an edge at distance d0 from F, in its polar angle ψ
// (ρ = d0/cos ψ), ∫ h/√(h² + ρ²) dφ = asin(k sin ψ), k = h/√(h² + d0²).
// So Ω = 2π·[F inside] − Σ_edges ±[asin(k sin ψ)], the ∮ dφ part exact (2π
// inside, 0 outside, the interior angle on the boundary). Unlike the
// Van Oosterom–Strackee fan, whose denominators 1 + a·b + b·c + c·a cancel
// to ~ h² when p is close to a large polygon (a 1e-11 relative error at
// h = 1e-6 of the polygon's size), nothing here cancels in that regime.
double polygon_solid_angle_green(const std::vector<Vec3>& v) {
  const size_t count = v.size();
  const Vec3 m = polygon_normal(v);
  const double h = std::fabs(dot(m, v[0]));
  if (!(h > 0)) return 0.0;
  const Frame f = Frame::from_normal(m);
  std::vector<double> qx(count), qy(count);
  for (size_t i = 0; i < count; ++i) qx[i] = dot(v[i], f.s), qy[i] = dot(v[i], f.t);
  double orientation = 0, sweep = 0, boundary = 0;
  bool outside = false, on_boundary = false;
  for (size_t i = 0; i < count; ++i) orientation += qx[i] * qy[(i + 1) % count] - qy[i] * qx[(i + 1) % count];
  const double o = orientation > 0 ? 1.0 : -1.0;
  for (size_t i = 0; i < count; ++i) {
    const size_t j = (i + 1) % count;
    const double ax = qx[i], ay = qy[i], bx = qx[j], by = qy[j];
    const double turn = ax * by - ay * bx;
    const double scale = std::hypot(ax, ay) * std::hypot(bx, by);
    if (o * turn < -1e-12 * scale) outside = true;
    // An edge through F (or ending at it) sweeps no angle: φ jumps at F itself.
    if (std::fabs(turn) <= 1e-12 * scale) {
      on_boundary = true;
      continue;
    }
    sweep += o * std::atan2(turn, ax * bx + ay * by);
    const double ex = bx - ax, ey = by - ay, len = std::hypot(ex, ey);
    if (!(len > 0)) continue;
    const double d0 = (ax * ey - ay * ex) / len;
    if (d0 == 0) continue;  // the edge's line passes through F: dφ = 0
    const double dist = std::fabs(d0), tx = ex / len, ty = ey / len;
    const double k = h / std::hypot(h, dist);
    // sin ψ of an end point = (its coordinate along the edge)/ρ.
    const double sa = (ax * tx + ay * ty) / std::hypot(ax, ay), sb = (bx * tx + by * ty) / std::hypot(bx, by);
    // dφ = sign(d0)·dψ; the polygon's own orientation o makes Ω positive.
    boundary += o * (d0 > 0 ? 1 : -1) * (std::asin(k * sb) - std::asin(k * sa));
  }
  const double enclosed = outside ? 0.0 : on_boundary ? sweep : 2 * kPi;
  return std::fmax(enclosed - boundary, 0.0);
}

// Target and caps of the edge integrals of polygon_area_kernel: relative
// tolerance 1e-14 of the first estimate, 30 levels, 2000 bisections per edge
// (a bounded cost; what is not reached is reported to the ledger).
constexpr double kAreaKernelTolerance = 1e-14;
constexpr int kAreaKernelDepth = 30;
constexpr size_t kAreaKernelBisections = 2000;

}  // namespace

double sphere_cos2_solid_angle(const Vec3& center, double R, const Vec3& n) {
  const double value = cone_integral(center, R, n, [](double) { return 1.0; });
  // Round-off of the rings' closed form: each ring's terms are ~ 2π(a² + b²/2)
  // however much of it the horizon cuts off, so a sliver above the horizon
  // keeps an absolute error ~ ε·∫ 2π(a² + b²/2) sin γ dγ (the whole cone's
  // ∫ cos²θ dω, in closed form below), reported relative to the value.
  const double D = length(center), cos_a = std::sqrt((1 - R / D) * (1 + R / D));
  const double cos_b = dot(n, center) / D, sin_b2 = length_squared(cross(n, center)) / (D * D);
  const double cone_scale = 2 * kPi * (cos_b * cos_b * (1 - cos_a * cos_a * cos_a) / 3 +
                                       0.5 * sin_b2 * (2 - 3 * cos_a + cos_a * cos_a * cos_a) / 3);
  if (value > 0) ErrorLedger::report(kRoundoffUlps * std::numeric_limits<double>::epsilon() * cone_scale, value);
  return value;
}

double sphere_area_kernel(const Vec3& center, double R, const Vec3& n) {
  const double D = length(center);
  return cone_integral(center, R, n, [&](double gamma) {
    const double q = std::sqrt(std::fmax(0.0, (R - D * std::sin(gamma)) * (R + D * std::sin(gamma))));
    const double r = (D - R) * (D + R) / (D * std::cos(gamma) + q);
    return (q / R) / (r * r);
  });
}

double polygon_cos2_solid_angle(const std::vector<Vec3>& vertices, const Vec3& n) {
  const std::vector<Vec3> clipped = clip_to_hemisphere(vertices, n);
  const size_t count = clipped.size();
  if (count < 3) return 0.0;
  std::vector<Vec3> u;
  for (const Vec3& v : clipped) u.push_back(normalize(v));
  const double sigma = polygon_solid_angle(clipped);
  double first = 0, edges = 0;
  for (size_t i = 0; i < count; ++i) {
    const Vec3& a = u[i];
    const Vec3& next = u[(i + 1) % count];
    const Vec3 c = cross(a, next);
    const double c_len = length(c);
    if (!(c_len > 0)) continue;
    const double theta = std::atan2(c_len, dot(a, next));
    const Vec3 ni = c / c_len;
    const Vec3 b = cross(ni, a);  // unit, ⟂ a, in the edge's plane, towards `next`
    const double half_sin = std::sin(0.5 * theta);
    first += theta * dot(ni, n);
    edges += dot(ni, n) * (dot(n, a) * std::sin(theta) + dot(n, b) * 2 * half_sin * half_sin);
  }
  const double s = first >= 0 ? 1.0 : -1.0;
  return (std::fabs(sigma) + s * edges) / 3;
}

double polygon_area_kernel(const std::vector<Vec3>& vertices, const Vec3& n) {
  const std::vector<Vec3> clipped = clip_to_hemisphere(vertices, n);
  if (clipped.size() < 3) return 0.0;
  // Small polygons: the edge tails below cancel to ~ (size/distance)² of
  // their terms (a foot point far outside); the product rule keeps every digit.
  if (polygon_angular_size(clipped) <= kSmallAngle) return small_polygon_area_kernel(clipped, n);
  const Vec3 m = polygon_normal(clipped);
  const double signed_h = dot(m, clipped[0]);
  const double h = std::fabs(signed_h);
  if (!(h > 0)) return 0.0;  // p in the polygon's plane: cos θ' = 0
  // Plane coordinates about p's foot point F = signed_h·m (relative to p):
  // x = F + q.x·e1 + q.y·e2, n·x = a + (n·e1)·q.x + (n·e2)·q.y.
  const Frame f = Frame::from_normal(m);
  const double a = signed_h * dot(n, m), n1 = dot(n, f.s), n2 = dot(n, f.t);
  const double h2 = h * h;
  // G(q) = ∫_0^ρ (n·x)²·h²/(h² + s²)⁴·s ds along the ray from F through q
  //      = a²·I1(ρ) + 2a·c·I2(ρ) + c²·I3(ρ),  c = c(φ) = (n·e1) cos φ + (n·e2) sin φ,
  // I_k(ρ) = h²∫_0^ρ s^k/(h² + s²)⁴ ds. Near F (ρ ≲ h) G rises to its limit
  // G∞(φ) = a²/(6h⁴) + 2a·c·(π/32)/h³ + c²/(12h²), which is huge (~ 1/h⁴) when
  // F is outside the polygon and the integral is not. So G is split into
  // G∞ (integrated in closed form, and exactly 0 around a polygon not
  // containing F) and the tail G∞ − G ≥ 0 in each term, integrated
  // numerically without cancellation:
  //   I1∞ − I1 = h²/(6W³),  I3∞ − I3 = h²(h² + 3ρ²)/(12W³),
  //   I2∞ − I2 = J(π/2 − T)/h³ with J the integral of sin⁴t·cos²t over [0, π/2 − T]
  //   (t → π/2 − t in ∫_T^{π/2} sin²t cos⁴t dt), T = atan2(ρ, h), W = h² + ρ².
  auto tail = [&](double qx, double qy) {
    const double rho2 = qx * qx + qy * qy, rho = std::sqrt(rho2);
    const double W = h2 + rho2, W3 = W * W * W;
    const double t1 = h2 / (6 * W3);
    const double t3 = h2 * (h2 + 3 * rho2) / (12 * W3);
    const SinCos angle = sin_cos_of_atan2(h, rho);  // of π/2 − T = atan2(h, ρ)
    const double t2 = sin_cos_power_integral<4, 2>(angle.S, angle.C) / (h2 * h);
    if (rho == 0) return a * a * t1;  // c is undefined at F, but c·t2, c²·t3 are bounded there: measure zero
    const double c = (n1 * qx + n2 * qy) / rho;
    return a * a * t1 + 2 * a * c * t2 + c * c * t3;
  };
  const double A = a * a / (6 * h2 * h2), B = 2 * a * (kPi / 32) / (h2 * h), C = 1 / (12 * h2);
  // ∫ G∞ dφ from φa over a signed sweep Δφ, in closed form.
  auto limit_integral = [&](double phi_a, double sweep) {
    const double phi_b = phi_a + sweep;
    const double int_c = n1 * (std::sin(phi_b) - std::sin(phi_a)) - n2 * (std::cos(phi_b) - std::cos(phi_a));
    const double int_c2 = 0.5 * (n1 * n1 + n2 * n2) * sweep +
                          0.25 * (n1 * n1 - n2 * n2) * (std::sin(2 * phi_b) - std::sin(2 * phi_a)) -
                          0.5 * n1 * n2 * (std::cos(2 * phi_b) - std::cos(2 * phi_a));
    return A * sweep + B * int_c + C * int_c2;
  };
  // Green's theorem in polar coordinates about F: ∫_A f dA = ∮ G dφ
  // (counter-clockwise). Each edge's tail in its own polar angle ψ about the
  // foot of the perpendicular from F to the edge's line (distance d0):
  // ρ = d0/cos ψ, which spreads the near-singular part (an edge passing
  // within ≲ h of F) over ψ instead of concentrating it in the edge's own
  // parameter.
  const size_t count = clipped.size();
  std::vector<double> qx(count), qy(count);
  for (size_t i = 0; i < count; ++i) qx[i] = dot(clipped[i], f.s), qy[i] = dot(clipped[i], f.t);
  // F strictly outside the (convex) polygon: ∮ G∞ dφ = 0 exactly and is
  // skipped (its edge terms would cancel from ~ 1/h⁴ down to nothing).
  const bool outside = foot_point_outside_convex(qx, qy);
  double sum = 0, error = 0;
  for (size_t i = 0; i < count; ++i) {
    const size_t j = (i + 1) % count;
    const double ax = qx[i], ay = qy[i], bx = qx[j], by = qy[j];
    const double ex = bx - ax, ey = by - ay, len = std::hypot(ex, ey);
    if (!(len > 0)) continue;
    const double d0 = (ax * ey - ay * ex) / len;  // signed: > 0 for a counter-clockwise edge about F
    if (d0 == 0) continue;                        // the edge's line passes through F: dφ = 0
    if (!outside) sum += limit_integral(std::atan2(ay, ax), std::atan2(ax * by - ay * bx, ax * bx + ay * by));
    // Unit vectors along the perpendicular (towards the line) and along the edge.
    const double sign = d0 > 0 ? 1 : -1;
    const double px = sign * ey / len, py = -sign * ex / len;
    const double tx = ex / len, ty = ey / len;
    const double dist = std::fabs(d0);
    const double psi_a = std::atan2(ax * tx + ay * ty, dist), psi_b = std::atan2(bx * tx + by * ty, dist);
    auto g = [&](double psi) {
      const double along = dist * std::tan(psi);
      return tail(px * dist + tx * along, py * dist + ty * along);
    };
    const double lo = std::fmin(psi_a, psi_b), hi = std::fmax(psi_a, psi_b);
    double first_error = 0, edge_error = 0;
    const double first = boost::math::quadrature::gauss_kronrod<double, 31>::integrate(g, lo, hi, 0, 0.0, &first_error);
    size_t bisections = kAreaKernelBisections;
    const double value = adaptive_gauss_kronrod<31>(g, lo, hi, kAreaKernelTolerance * std::fabs(first), kAreaKernelDepth,
                                                    &bisections, &edge_error);
    // dφ = sign(d0)·dψ along the edge's direction of travel.
    sum -= (psi_b >= psi_a) == (d0 > 0) ? value : -value;
    error += edge_error;
  }
  const double result = std::fabs(sum);
  ErrorLedger::report(error, result);
  return result;
}

double sphere_solid_angle(double D, double R) {
  FURNACE_CHECK(D > R && R > 0);
  const double s2 = (R / D) * (R / D);  // sin²α
  return 2 * kPi * s2 / (1 + std::sqrt((1 - R / D) * (1 + R / D)));
}

double polygon_solid_angle(const std::vector<Vec3>& vertices) {
  FURNACE_CHECK(vertices.size() >= 3);
  // Large (or near) polygons: Green's form; small ones: the fan, whose
  // triangles then subtend < 1 rad each and whose denominators stay > 2.6.
  if (!(polygon_angular_size(vertices) < 1)) return polygon_solid_angle_green(vertices);
  double sigma = 0;
  for (size_t k = 1; k + 1 < vertices.size(); ++k) sigma += triangle_solid_angle(vertices[0], vertices[k], vertices[k + 1]);
  return std::fabs(sigma);
}

// ---------------------------------------------------------------------------
// Scene-level kernels of one object (light_moments.h, second half).

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

// emitter_cos2_kernel (hemisphere) or emitter_area_kernel: one body, as
// both take the same paths through the geometry.
double emitter_kernel(bool hemisphere, const Scene& scene, size_t i, const Vec3& p, const Vec3& n,
                      std::optional<size_t> receiver) {
  const Object& object = scene.objects[i];
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

}  // namespace

std::vector<Vec3> polygon_vertices_relative(const Rectangle& r, const Vec3& p) {
  return {r.corner - p, r.corner + r.edge_u - p, r.corner + r.edge_u + r.edge_v - p, r.corner + r.edge_v - p};
}
std::vector<Vec3> polygon_vertices_relative(const Triangle& t, const Vec3& p) { return {t.p0 - p, t.p1 - p, t.p2 - p}; }


double emitter_cos2_kernel(const Scene& scene, size_t i, const Vec3& p, const Vec3& n, std::optional<size_t> receiver) {
  return emitter_kernel(true, scene, i, p, n, receiver);
}

double emitter_area_kernel(const Scene& scene, size_t i, const Vec3& p, const Vec3& n, std::optional<size_t> receiver) {
  return emitter_kernel(false, scene, i, p, n, receiver);
}

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


}  // namespace furnace::analytic
