// Integrals over the directions to the part of a planar polygon above a
// receiver's horizon, by nested adaptive quadrature in the polygon plane's
// spherical coordinates. Used by the MIS moments (mis_moments.cpp).
#pragma once

#include <algorithm>
#include <cmath>
#include <optional>
#include <tuple>
#include <type_traits>
#include <vector>

#include "analytic/error_ledger.h"
#include "analytic/polygon.h"
#include "analytic/sin_cos.h"
#include "core/adaptive_quadrature.h"
#include "core/error.h"
#include "core/vec3.h"

namespace furnace::analytic {

// An edge from a to b seen from the origin F, in the frame of its line: d0
// the signed distance (> 0: the edge runs counter-clockwise about F), p the
// unit normal away from F, t the unit direction, and ψ the angle from the
// perpendicular's foot, so that the point at ψ is p·dist + t·dist·tan ψ and
// dφ = sign(d0)·dψ along the edge. Empty for an edge of zero length or on a
// line through F (it sweeps no angle).
struct EdgeAboutFoot {
  double d0, dist, px, py, tx, ty, psi_a, psi_b;
  double x(double psi) const { return px * dist + tx * (dist * std::tan(psi)); }
  double y(double psi) const { return py * dist + ty * (dist * std::tan(psi)); }
  // ∫ over the edge in φ from the integral `value` over [min ψ, max ψ].
  double oriented(double value) const { return (psi_b >= psi_a) == (d0 > 0) ? value : -value; }
};

inline std::optional<EdgeAboutFoot> edge_about_foot(double ax, double ay, double bx, double by) {
  const double ex = bx - ax, ey = by - ay, len = std::hypot(ex, ey);
  if (!(len > 0)) return std::nullopt;
  const double d0 = (ax * ey - ay * ex) / len;
  if (d0 == 0) return std::nullopt;
  const double sign = d0 > 0 ? 1 : -1;
  EdgeAboutFoot e;
  e.d0 = d0;
  e.dist = std::fabs(d0);
  e.px = sign * ey / len, e.py = -sign * ex / len, e.tx = ex / len, e.ty = ey / len;
  e.psi_a = std::atan2(ax * e.tx + ay * e.ty, e.dist), e.psi_b = std::atan2(bx * e.tx + by * e.ty, e.dist);
  return e;
}

// Whether the origin F lies strictly outside the convex polygon (qx[i],
// qy[i]) of either orientation: some edge turns the wrong way about F. The
// margin (a turn below 1e-12 of its two radii's product counts as none)
// keeps F on, or within rounding of, the boundary on the inside, where the
// callers' inside forms are correct anyway.
inline bool foot_point_outside_convex(const std::vector<double>& qx, const std::vector<double>& qy) {
  const size_t count = qx.size();
  double orientation = 0;
  for (size_t i = 0; i < count; ++i) orientation += qx[i] * qy[(i + 1) % count] - qy[i] * qx[(i + 1) % count];
  for (size_t i = 0; i < count; ++i) {
    const size_t j = (i + 1) % count;
    const double turn = qx[i] * qy[j] - qy[i] * qx[j];
    if (orientation * turn < 0 && std::fabs(turn) > 1e-12 * std::hypot(qx[i], qy[i]) * std::hypot(qx[j], qy[j]))
      return true;
  }
  return false;
}

// ∫ f(u, cos t) dω over the directions u from p to the part of a convex
// planar polygon (vertices relative to p) above p's horizon, in spherical
// coordinates (t, φ) about the polygon plane's normal through p: t is the
// angle between u and the normal (cos t = cos θ' at the point hit, which lies
// at distance r = h/cos t, h the plane's distance), φ the azimuth about the
// foot point F. No near-singular kernel remains when p is close to the plane:
// dω = sin t dt dφ whatever h is. Green's theorem in polar coordinates about
// F turns the area into a boundary integral ∮ G dφ, G(φ, T) = ∫_0^T f sin t dt
// up to the boundary's T = atan2(ρ, h); when F is outside the polygon, the
// complementary ∮ ∫_T^{π/2} f sin t dt dφ is used instead (with the opposite
// sign: ∮ of the whole ray's integral vanishes around a region not holding F),
// so the result is not a difference of O(1) terms. Each edge is integrated
// in its own polar angle ψ about the foot of the perpendicular from F
// (ρ = d0/cos ψ), the inner t-integral split where the ray crosses the
// horizon. Both levels: adaptive Gauss–Kronrod (core/adaptive_quadrature.h)
// to `rel_tolerance`, at most `depth` levels, `outer_bisections` per edge and
// `inner_bisections` per ray, so at most (2·outer + 1)·31 rays per edge of at
// most (2·inner + 1)·31 evaluations each (nested caps multiply). The error reached (the outer estimate plus the worst inner
// relative estimate times the result) is reported to the open ErrorLedger.
// f returns a std::array<double, N>: N integrands sharing each direction,
// integrated together (adaptive_gauss_kronrod_relative_components), each to
// its own tolerance and each reported to the ledger.
// f is called only with directions above the plane's near side; it must
// handle the receiver's horizon itself (return 0 where n·u ≤ 0).
template <class F, class V = std::invoke_result_t<const F&, const Vec3&, double>>
V polygon_direction_integral(const std::vector<Vec3>& vertices, const Vec3& n, double rel_tolerance, int depth,
                             size_t outer_bisections, size_t inner_bisections, F f) {
  constexpr size_t N = std::tuple_size_v<V>;
  const std::vector<Vec3> v = clip_to_hemisphere(vertices, n);
  const size_t count = v.size();
  if (count < 3) return V{};
  const Vec3 m = polygon_normal(v);
  const double signed_h = dot(m, v[0]);
  const double h = std::fabs(signed_h);
  if (!(h > 0)) return V{};  // p in the plane: the polygon subtends no solid angle
  const Vec3 axis = signed_h > 0 ? m : -m;  // from p towards the plane
  const Frame frame = Frame::from_normal(axis);
  std::vector<double> qx(count), qy(count);
  for (size_t i = 0; i < count; ++i) qx[i] = dot(v[i], frame.s), qy[i] = dot(v[i], frame.t);
  const bool outside = foot_point_outside_convex(qx, qy);
  const double n_axis = dot(n, axis), n1 = dot(n, frame.s), n2 = dot(n, frame.t);
  V worst_inner{}, outer_error{};
  // ∫ f sin t dt over [0, T] (inside) or [T, π/2] (outside) at azimuth (cφ, sφ),
  // split where n·u = cos t·(n·axis) + sin t·c crosses 0. The outside range
  // is integrated in s = π/2 − t ∈ [0, atan2(h, ρ)] (cos t = sin s), since
  // cos t of a t near π/2 carries an absolute error ~ ε that is large
  // relative to the short range's own cos t ~ h/ρ.
  auto ray = [&](double c_phi, double s_phi, double rho) {
    const double c = n1 * c_phi + n2 * s_phi;
    const Vec3 w = frame.s * c_phi + frame.t * s_phi;
    const double hi = outside ? std::atan2(h, rho) : std::atan2(rho, h);
    // n·u = 0 at t = atan2(−n·axis, c), i.e. s = atan2(−c, n·axis) (mod π).
    const double x_h = outside ? std::atan2(-c, n_axis) : std::atan2(-n_axis, c);
    double cuts[3] = {0.0, hi, hi};
    int k = 2;
    for (double x : {x_h, x_h + kPi, x_h - kPi})
      if (x > 0 && x < hi) cuts[1] = x, k = 3;
    V sum{}, error{};
    for (int i = 0; i + 1 < k; ++i)
      if (cuts[i + 1] > cuts[i]) {
        // x: t itself (inside) or s = π/2 − t (outside), in the piece's
        // half-angle variable (HalfAngleArc: no sin or cos at the nodes).
        const HalfAngleArc arc = HalfAngleArc::of(cuts[i], cuts[i + 1]);
        auto g = [&](double tau) {
          double cos_x, sin_x, dx_dtau;
          arc.at(tau, &cos_x, &sin_x, &dx_dtau);
          const double ct = outside ? sin_x : cos_x, st = outside ? cos_x : sin_x;
          V value = f(axis * ct + w * st, ct);
          for (double& component : value) component *= st * dx_dtau;
          return value;
        };
        const V piece = adaptive_gauss_kronrod_relative_components(g, -arc.tau_max, arc.tau_max, rel_tolerance, depth,
                                                                   1, inner_bisections, &error);
        for (size_t j = 0; j < N; ++j) sum[j] += piece[j];
      }
    for (size_t j = 0; j < N; ++j)
      if (sum[j] != 0) worst_inner[j] = std::fmax(worst_inner[j], std::fabs(error[j] / sum[j]));
    return sum;
  };
  V total{};
  for (size_t i = 0; i < count; ++i) {
    const size_t j = (i + 1) % count;
    const double ax = qx[i], ay = qy[i], bx = qx[j], by = qy[j];
    const std::optional<EdgeAboutFoot> e = edge_about_foot(ax, ay, bx, by);
    if (!e) continue;
    auto edge = [&](double psi) {
      const double x = e->x(psi), y = e->y(psi);
      const double rho = std::hypot(x, y);
      return ray(x / rho, y / rho, rho);
    };
    const V value = adaptive_gauss_kronrod_relative_components(edge, std::fmin(e->psi_a, e->psi_b),
                                                               std::fmax(e->psi_a, e->psi_b), rel_tolerance, depth, 1,
                                                               outer_bisections, &outer_error);
    for (size_t c = 0; c < N; ++c) total[c] += e->oriented(value[c]);
  }
  V result;
  for (size_t c = 0; c < N; ++c) {
    result[c] = std::fabs(total[c]);
    ErrorLedger::report(outer_error[c] + worst_inner[c] * result[c], result[c]);
  }
  return result;
}

}  // namespace furnace::analytic
