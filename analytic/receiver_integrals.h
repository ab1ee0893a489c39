// The receiver model's light-integral machinery (receiver.h), as templates
// over the concrete receiver type R so that every quadrature node calls R::at
// directly, not through the vtable (and the compiler may inline it). A BSDF
// derives from ReceiverModel<R>
// (receiver.h), includes this header in its own .cpp and instantiates the
// machinery there once (template class ReceiverModel<R>;).
// Internal to analytic/ (not installed).
#pragma once

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include <boost/math/quadrature/gauss_kronrod.hpp>

#include "analytic/error_ledger.h"
#include "analytic/receiver.h"
#include "analytic/receiver_planar.h"
#include "analytic/sin_cos.h"
#include "core/adaptive_quadrature.h"
#include "core/error.h"

namespace furnace::analytic {

namespace receiver_detail {

// Bisection levels of each nested quadrature: the lobe peak of a Phong
// e = 100 has a width ~0.1 rad, resolved after a few levels; the cap edges
// are smooth in the chosen variables.
inline constexpr int kReceiverQuadratureDepth = 18;

// Bisections allowed to one ray's integral on a planar light: a peak of
// width w at the ray's start costs about 2·log2(length/w) of them (24 for
// w = 2⁻¹² of the ray), so 48 resolve lobes far narrower than GGX's
// α = 1e-3; the cap stops a ray chasing the lobe's own rounding noise (a
// lobe cos^e α read from a rounded cos α is noisy to ~e·ε relative, 1e-9 at
// e = 4e6, as large as the tolerance), which at e = 4e6 cost 5–8 times the
// time for the same result (tests/analytic/receiver_planar_test.cpp,
// DISABLED_GgxWidthLobesAtTheShadowEdge).
inline constexpr size_t kPlaneInnerBisections = 48;

// One ring of a cap: polar angle γ about the axis and what depends on it only.
struct Ring {
  double cos_gamma = 1, sin_gamma = 0;
  double measure = 0;       // dω = measure · du dψ
  double cos_emission = 1;  // sphere: cos θ' at the near intersection
  double distance = 0;      // sphere: distance to the near intersection
};

// A sphere's cone seen from outside, outer variable v ∈ [0, π/2] with
// sin γ = k sin v, k = R/D: cos θ' = cos v, d = D cos γ − R cos v.
struct SphereCap {
  double D, R;
  double k() const { return R / D; }
  double u_max() const { return kPi / 2; }
  Ring at(double v) const {
    Ring ring;
    const double s = k() * std::sin(v);
    ring.sin_gamma = s;
    ring.cos_gamma = std::sqrt((1 - s) * (1 + s));
    ring.measure = s * k() * std::cos(v) / ring.cos_gamma;  // sin γ dγ/dv
    ring.cos_emission = std::cos(v);
    ring.distance = D * ring.cos_gamma - R * ring.cos_emission;
    return ring;
  }
  // The outer variable of the ring at polar angle γ (π/2 beyond the cone).
  double u_of_gamma(double gamma) const {
    const double s = std::sin(gamma) / k();
    return gamma >= kPi / 2 || s >= 1 ? kPi : std::asin(s);
  }
};

// The hemisphere about the cap's axis (a lobe's own cap cos α ≥ 0 about r,
// or the sky above n), outer variable α ∈ [0, π/2].
struct LobeCap {
  double u_max() const { return kPi / 2; }
  Ring at(double alpha) const {
    Ring ring;
    ring.cos_gamma = std::cos(alpha);
    ring.sin_gamma = std::sin(alpha);
    ring.measure = ring.sin_gamma;
    return ring;
  }
  double u_of_gamma(double gamma) const { return gamma; }
};

// What an integrand sees of a direction ω toward a light.
struct Direction {
  double cos_theta;  // n·ω > 0
  double cos_alpha;  // r·ω
  BsdfValue bsdf;    // receiver.at(cos_theta, cos_alpha): evaluated once per direction, however many terms use it
  double distance;      // to the light point it meets (sphere: the near intersection); 0 for the environment
  double cos_emission;  // cos θ' there (the light-area density's emission cosine); 1 for the environment
};

// The error a nested quadrature reached, for the ErrorLedger: the outer
// rule's error estimates plus the worst relative error estimate of an inner
// integral (one ring's, or one ray's on a planar light, over all its pieces)
// times the whole. Every node the outer quadrature evaluated counts, also
// those of pieces it bisected further.
struct NestedError {
  double outer = 0;        // Σ of the accepted outer pieces' absolute error estimates
  double worst_inner = 0;  // max over inner integrals of Σ|error|/|Σ value|
  void inner(double value, double error) {
    if (error > 0) worst_inner = std::fmax(worst_inner, value != 0 ? std::fabs(error / value) : INFINITY);
  }
  void report(double total) const { ErrorLedger::report(outer + worst_inner * std::fabs(total), total); }
};

// ∫ g(Direction) dω over the part of the cap (axis `axis`) above the
// receiver's horizon, the receiver's BSDF evaluated once per direction.
// The error reached goes to the open ErrorLedger (NestedError).
template <class R, class Cap, class G>
double cap_integral(const Cap& cap, const Vec3& axis, const R& receiver, G g) {
  NestedError reached;
  const Vec3& n = receiver.n;
  const Vec3 r = receiver.mirror();
  // Azimuths ψ from r's (ψ_mirror = 0 unless r is within kAxialMirror of the
  // axis, where its azimuth is round-off): the nodes near a lobe's peak are
  // then small angles, rounded to ε·|ψ|, not to ε·2π.
  constexpr double kAxialMirror = 1e-6;
  Frame frame = Frame::from_normal(axis);
  const Vec3 r_across = receiver.mirror() - axis * dot(receiver.mirror(), axis);
  if (length(r_across) > kAxialMirror) frame.s = normalize(r_across), frame.t = cross(axis, frame.s);
  const double na = dot(n, axis), ns = dot(n, frame.s), nt = dot(n, frame.t);
  const double ra = dot(r, axis), rs = dot(r, frame.s), rt = dot(r, frame.t);
  const double psi_mirror = std::atan2(rt, rs);
  const double gamma_mirror = std::atan2(length(cross(r, axis)), ra);
  const double width = receiver.R::lobe_width();
  auto outer = [&](double u) {
    const Ring ring = cap.at(u);
    double sum = 0, ring_error = 0;
    for (auto [lo, hi] : positive_arcs(ring.cos_gamma * na, ring.sin_gamma * ns, ring.sin_gamma * nt)) {
      if (hi - lo >= 2 * kPi) lo = psi_mirror - kPi, hi = psi_mirror + kPi;  // a whole ring: about the peak
      // ψ over [a, b] by the half-angle variable of each of its pieces (HalfAngleArcs: no sin or cos at the nodes).
      auto arc_integral = [&](double a, double b) {
        const HalfAngleArcs arcs = HalfAngleArcs::of(a, b);
        double value = 0;
        for (int k = 0; k < arcs.count; ++k) {
          const HalfAngleArc& arc = arcs.piece[k];
          auto inner = [&](double tau) {
            double c, s, dpsi_dtau;
            arc.at(tau, &c, &s, &dpsi_dtau);
            const double cos_theta = ring.cos_gamma * na + ring.sin_gamma * (c * ns + s * nt);
            if (!(cos_theta > 0)) return 0.0;
            const double cos_alpha = ring.cos_gamma * ra + ring.sin_gamma * (c * rs + s * rt);
            // 1 − cos α = |ω − r|²/2 from component differences: relative error ~ε/|ω − r|, not ε/|ω − r|².
            const double da = ring.cos_gamma - ra, ds = ring.sin_gamma * c - rs, dt = ring.sin_gamma * s - rt;
            const double one_minus_cos_alpha = 0.5 * (da * da + ds * ds + dt * dt);
            return g(Direction{cos_theta, cos_alpha,
                               receiver.R::at_direction(cos_theta, cos_alpha, one_minus_cos_alpha), ring.distance,
                               ring.cos_emission}) *
                   ring.measure * dpsi_dtau;
          };
          value += adaptive_gauss_kronrod_relative(inner, -arc.tau_max, arc.tau_max, kReceiverQuadratureTolerance,
                                                   kReceiverQuadratureDepth, 1, kUnlimitedBisections, &ring_error);
        }
        return value;
      };
      // Cut the arc at the lobe's peak azimuth, and for a narrow lobe at
      // azimuths graded by 2 from it, from the ring's distance to r (≥ w).
      double peak = psi_mirror;
      while (peak < lo) peak += 2 * kPi;
      while (peak >= lo + 2 * kPi) peak -= 2 * kPi;
      std::vector<double> at{lo, hi, peak};
      const double gap = std::max(width, std::fabs(std::atan2(ring.sin_gamma, ring.cos_gamma) - gamma_mirror));
      for (double d = gap / ring.sin_gamma; width > 0 && d < kPi; d *= 2)
        for (double x : {peak - d, peak + d, peak - 2 * kPi + d, peak + 2 * kPi - d}) at.push_back(x);
      std::sort(at.begin(), at.end());
      for (size_t i = 0; i + 1 < at.size(); ++i)
        if (at[i] >= lo && at[i + 1] <= hi && at[i + 1] > at[i]) sum += arc_integral(at[i], at[i + 1]);
    }
    reached.inner(sum, ring_error);
    return sum;
  };
  // Cuts: where the horizon starts to cut the rings (γ = |π/2 − β|, β the
  // axis' angle from n) and the ring through the mirror direction.
  const double beta = std::atan2(length(cross(n, axis)), na);
  std::vector<double> cuts{0.0, cap.u_max(), cap.u_of_gamma(std::fabs(kPi / 2 - beta)), cap.u_of_gamma(gamma_mirror)};
  // A lobe of width w ≪ the cap (R::lobe_width()): rings graded by 2 from the
  // mirror ring, so that no piece's first estimate spans the peak and its tail.
  for (double d = width; d > 0 && d < kPi; d *= 2)
    for (double gamma : {gamma_mirror - d, gamma_mirror + d})
      if (gamma > 0) cuts.push_back(cap.u_of_gamma(gamma));
  std::sort(cuts.begin(), cuts.end());
  double total = 0;
  for (size_t i = 0; i + 1 < cuts.size(); ++i) {
    const double a = cuts[i], b = std::min(cuts[i + 1], cap.u_max());
    if (b > a)
      total += adaptive_gauss_kronrod_relative(outer, a, b, kReceiverQuadratureTolerance, kReceiverQuadratureDepth, 1,
                                               kUnlimitedBisections, &reached.outer);
  }
  reached.report(total);
  return total;
}

// A support edge (receiver.h) as a planar light's rays meet it: the cone
// a·ω = k with ω ∝ v = x·s + y·t − h·toward_receiver (receiver_planar.h),
// a·v = as·x + at·y + ah, crossed where (a·v)² = k²|v|².
struct EdgeInPlane {
  double as, at, ah, k, k2;
  EdgeInPlane(const SupportEdge& e, const PlanarEmitter& light)
      : as(dot(e.axis, light.s)),
        at(dot(e.axis, light.t)),
        ah(-light.height * dot(e.axis, light.toward_receiver)),
        k(e.cos_angle),
        k2(e.cos_angle * e.cos_angle) {}
};

// The real roots of qa·x² + qb·x + qc = 0 (qa may be 0), in the cancellation-free form.
inline void quadratic_roots(double qa, double qb, double qc, std::vector<double>& out) {
  if (qa == 0) {
    if (qb != 0) out.push_back(-qc / qb);
    return;
  }
  const double disc = qb * qb - 4 * qa * qc;
  if (!(disc >= 0)) return;
  const double q = -0.5 * (qb + std::copysign(std::sqrt(disc), qb));
  if (q != 0) out.push_back(qc / q);
  out.push_back(q / qa);
}

// The ρ in (lo, hi) where the ray (cx, cy) + ρ(c, s) crosses the edge's cone
// (either nappe: a spurious cut costs one more piece, nothing else).
inline void edge_crossings(const EdgeInPlane& e, double cx, double cy, double h, double c, double s, double lo,
                           double hi, std::vector<double>& out) {
  const double a0 = e.as * cx + e.at * cy + e.ah, a1 = e.as * c + e.at * s;
  const double v0 = cx * cx + cy * cy + h * h, v1 = cx * c + cy * s;
  std::vector<double> roots;
  quadratic_roots(a1 * a1 - e.k2, 2 * (a0 * a1 - e.k2 * v1), a0 * a0 - e.k2 * v0, roots);
  for (double rho : roots)
    if (rho > lo && rho < hi) out.push_back(rho);
}

// The angles φ of the rays from (cx, cy) tangent to the edge's conic in the
// light's plane: where the crossings' discriminant, a quadratic form
// q11·c² + 2·q12·c·s + q22·s² in (c, s) = (cos φ, sin φ), vanishes (each
// line through the centre gives φ and φ + π).
inline void edge_tangent_angles(const EdgeInPlane& e, double cx, double cy, double h, std::vector<double>& out) {
  const size_t first = out.size();  // `out` may hold other angles already: turn only this edge's lines
  const double a0 = e.as * cx + e.at * cy + e.ah;
  const double p = a0 * e.as - e.k2 * cx, q = a0 * e.at - e.k2 * cy;
  const double big_e = a0 * a0 - e.k2 * (cx * cx + cy * cy + h * h);
  const double q11 = p * p - big_e * (e.as * e.as - e.k2), q12 = p * q - big_e * e.as * e.at,
               q22 = q * q - big_e * (e.at * e.at - e.k2);
  std::vector<double> roots;
  if (std::fabs(q22) >= std::fabs(q11)) {
    quadratic_roots(q22, 2 * q12, q11, roots);  // tan φ
    for (double t : roots) out.push_back(std::atan(t));
  } else {
    quadratic_roots(q11, 2 * q12, q22, roots);  // cot φ
    for (double u : roots) out.push_back(std::atan2(1.0, u));
  }
  const size_t last = out.size();
  for (size_t i = first; i < last; ++i) out.push_back(out[i] + kPi);
}

// Steps of a boundary curve's parameter scanned for an edge's crossings: an
// arc spans at most π (exact_region.h) and a circle meets a cone's conic at
// most four times, so steps of 1/64 of a curve separate its crossings unless
// the edge nearly grazes the boundary (two crossings within one step are
// missed: the outer quadrature then bisects at that kink, as without a cut).
inline constexpr int kBoundaryScanSteps = 64;

// The angles φ of the rays from (cx, cy) through the points where the edge
// meets a curve of the region's boundary: there a ray's interval inside the
// support turns from ending at the edge to ending at the boundary, a kink in
// the outer integrand (its derivative jumps where f jumps at the edge). The
// points are the sign changes of a·v − k|v| (zero on the edge's own nappe
// only) along the curve's parameter, each bisected to the last bit.
inline void edge_boundary_angles(const EdgeInPlane& e, const Curve2& curve, double cx, double cy, double h,
                                 std::vector<double>& out) {
  auto point = [&](double u) {
    if (!curve.is_arc)
      return Point2{curve.start.x + u * (curve.end.x - curve.start.x),
                    curve.start.y + u * (curve.end.y - curve.start.y)};
    const double t = curve.t0 + u * curve.sweep;
    return Point2{curve.circle.cx + curve.circle.radius * std::cos(t),
                  curve.circle.cy + curve.circle.radius * std::sin(t)};
  };
  auto off = [&](double u) {
    const Point2 x = point(u);
    return e.as * x.x + e.at * x.y + e.ah - e.k * std::sqrt(x.x * x.x + x.y * x.y + h * h);
  };
  double lo = 0, before = off(0);
  for (int i = 1; i <= kBoundaryScanSteps; ++i) {
    const double hi = double(i) / kBoundaryScanSteps, after = off(hi);
    if ((before < 0) != (after < 0)) {
      const bool rising = before < 0;
      double a = lo, b = hi;
      for (double mid = 0.5 * (a + b); mid > a && mid < b; mid = 0.5 * (a + b))
        ((off(mid) < 0) == rising ? a : b) = mid;
      const Point2 x = point(0.5 * (a + b));
      out.push_back(std::atan2(x.y - cy, x.x - cx));
    }
    lo = hi, before = after;
  }
}

// The points where two edges meet on the light's plane (in its (x, y)):
// two cones about the receiving point meet along at most two directions,
// ω = α·a1 + β·a2 ± γ·(a1 × a2) with a1·ω = k1, a2·ω = k2 (α + β·c = k1,
// α·c + β = k2, c = a1·a2) and |ω| = 1 (γ²|a1 × a2|² = 1 − |α·a1 + β·a2|²);
// each meets the plane at (x, y) = h·(ω·s, ω·t)/(−ω·u), u =
// toward_receiver, if it points at it.
inline void edge_corners(const SupportEdge& e1, const SupportEdge& e2, const PlanarEmitter& light,
                         std::vector<Point2>& out) {
  const Vec3 normal = cross(e1.axis, e2.axis);
  const double c = dot(e1.axis, e2.axis), sin2 = dot(normal, normal);
  if (!(sin2 > 0)) return;  // coaxial cones share no isolated direction
  const double alpha = (e1.cos_angle - c * e2.cos_angle) / sin2, beta = (e2.cos_angle - c * e1.cos_angle) / sin2;
  const Vec3 in_plane = e1.axis * alpha + e2.axis * beta;
  const double gamma2 = (1 - dot(in_plane, in_plane)) / sin2;
  if (!(gamma2 >= 0)) return;  // the cones do not meet
  for (const double sign : {-1.0, 1.0}) {
    const Vec3 w = in_plane + normal * (sign * std::sqrt(gamma2));
    const double toward_plane = -dot(w, light.toward_receiver);
    if (toward_plane > 0)
      out.push_back({light.height * dot(w, light.s) / toward_plane, light.height * dot(w, light.t) / toward_plane});
  }
}

// The polar angles φ about the region's centre where the outer integrand of
// plane_integral is not smooth because of the support edges: the rays
// tangent to an edge (a square root in φ), through the points where an edge
// meets the region's boundary, and through the points inside the region
// where two edges meet (there a ray's interval inside the support turns
// from ending at one to ending at the other: kinks in φ). Unreduced: any
// turn.
inline std::vector<double> support_edge_angles(const std::vector<SupportEdge>& support_edges,
                                               const PlanarEmitter& light, const PolarRegion& region) {
  const double cx = region.centre().x, cy = region.centre().y, h = light.height;
  std::vector<double> angles;
  for (const SupportEdge& edge : support_edges) {
    const EdgeInPlane e(edge, light);
    edge_tangent_angles(e, cx, cy, h, angles);
    for (const Curve2& curve : light.boundary) edge_boundary_angles(e, curve, cx, cy, h, angles);
  }
  std::vector<Point2> corners;
  for (size_t i = 0; i < support_edges.size(); ++i)
    for (size_t j = i + 1; j < support_edges.size(); ++j) edge_corners(support_edges[i], support_edges[j], light, corners);
  std::vector<std::pair<double, double>> spans;
  for (const Point2& x : corners) {
    const double dx = x.x - cx, dy = x.y - cy, rho = std::hypot(dx, dy);
    if (!(rho > 0)) continue;
    region.intervals(dx / rho, dy / rho, spans);
    for (const auto& [lo, hi] : spans)
      if (rho > lo && rho < hi) angles.push_back(std::atan2(dy, dx));
  }
  return angles;
}

// ∫ g(Direction) dω over a planar light's visible region (receiver_planar.h),
// in polar coordinates (ρ, φ) about the lobe's peak direction's hit point C
// on the light's plane (R::lobe_centre(), the mirror direction unless R says
// otherwise): dω = (h/d³)·ρ dρ dφ. The inner ρ runs over the exact
// intervals of each ray inside the region, starting at the lobe's peak when
// C is inside it; the outer φ is cut at every critical angle (the boundary's
// vertices and tangents, PolarRegion), and each piece [a, b] is integrated
// in halves by φ = a + σ², φ = b − σ², which removes the square-root
// behaviour of a chord at a tangent angle. The outer pieces share an
// absolute tolerance, kReceiverQuadratureTolerance times a first estimate of
// the whole (one rule per piece), so that a piece holding little of the
// integral is not asked for digits below its round-off. Where the
// receiver's f has support edges (R::support_edges()), each ray is also cut
// where it crosses one, so that no piece spans the edge's kink or jump, and
// φ where a ray touches one (a square root in φ) or passes where one meets
// the region's boundary or another edge (a kink in φ). The error reached
// goes to the open ErrorLedger (NestedError).
template <class R, class G>
double plane_integral(const PlanarEmitter& light, const R& receiver, G g) {
  NestedError reached;
  const Vec3& n = receiver.n;
  const Vec3 r = receiver.mirror();
  const PolarRegion region(light.boundary, polar_centre(light, receiver.R::lobe_centre()));
  const double h = light.height;
  const std::vector<SupportEdge> support_edges = receiver.R::support_edges();
  std::vector<EdgeInPlane> edges;
  for (const SupportEdge& e : support_edges) edges.emplace_back(e, light);
  // n·v and r·v for v = x·s + y·t − h·toward_receiver (receiver_planar.h).
  const double ns = dot(n, light.s), nt = dot(n, light.t), nh = -h * dot(n, light.toward_receiver);
  const double r_toward = dot(r, light.toward_receiver);
  const double rs = dot(r, light.s), rt = dot(r, light.t), rh = -h * r_toward;
  const double cx = region.centre().x, cy = region.centre().y;
  auto outer = [&](double phi) {
    const double c = std::cos(phi), s = std::sin(phi);
    std::vector<std::pair<double, double>> spans;
    region.intervals(c, s, spans);
    double sum = 0, ray_error = 0;
    std::vector<double> pieces;
    for (const auto& [lo, hi] : spans) {
      pieces.assign({lo, hi});
      for (const EdgeInPlane& e : edges) edge_crossings(e, cx, cy, h, c, s, lo, hi, pieces);
      std::sort(pieces.begin(), pieces.end());
      auto inner = [&](double rho) {
        const double x = cx + rho * c, y = cy + rho * s;
        const double d2 = x * x + y * y + h * h, d = std::sqrt(d2);
        const double cos_theta = (ns * x + nt * y + nh) / d;
        if (!(cos_theta > 0)) return 0.0;  // on the horizon's boundary line, by rounding
        const double cos_alpha = (rs * x + rt * y + rh) / d;
        const double cos_emission = h / d;
        // 1 − cos α = |ω − r|²/2 from component differences in the light's frame (as cap_integral).
        const double ds = x / d - rs, dt = y / d - rt, du = -cos_emission - r_toward;
        const double one_minus_cos_alpha = 0.5 * (ds * ds + dt * dt + du * du);
        return g(Direction{cos_theta, cos_alpha, receiver.R::at_direction(cos_theta, cos_alpha, one_minus_cos_alpha),
                           d, cos_emission}) *
               rho * cos_emission / d2;
      };
      for (size_t i = 0; i + 1 < pieces.size(); ++i)
        if (pieces[i + 1] > pieces[i])
          sum += adaptive_gauss_kronrod_relative(inner, pieces[i], pieces[i + 1], kReceiverQuadratureTolerance,
                                                 kReceiverQuadratureDepth, 1, kPlaneInnerBisections, &ray_error);
    }
    reached.inner(sum, ray_error);
    return sum;
  };
  // The region's critical angles, and within their turn the support edges' (support_edge_angles).
  std::vector<double> angles = region.angles();
  if (!support_edges.empty()) {
    const double base = angles.front();
    for (double a : support_edge_angles(support_edges, light, region)) {
      a = base + std::remainder(a - base - kPi, 2 * kPi) + kPi;  // into [base, base + 2π]
      if (a > base && a < base + 2 * kPi) angles.push_back(a);
    }
    std::sort(angles.begin(), angles.end());
  }
  // Each piece's two halves in σ ∈ [0, √((b − a)/2)].
  auto from_low = [&](double a) { return [&outer, a](double sigma) { return 2 * sigma * outer(a + sigma * sigma); }; };
  auto from_high = [&](double b) { return [&outer, b](double sigma) { return 2 * sigma * outer(b - sigma * sigma); }; };
  double first = 0;
  for (size_t i = 0; i + 1 < angles.size(); ++i) {
    const double a = angles[i], b = angles[i + 1], half = std::sqrt(0.5 * (b - a));
    double error = 0;
    first += std::fabs(boost::math::quadrature::gauss_kronrod<double, kDefaultKronrodPoints>::integrate(
        from_low(a), 0, half, 0, 0.0, &error));
    first += std::fabs(boost::math::quadrature::gauss_kronrod<double, kDefaultKronrodPoints>::integrate(
        from_high(b), 0, half, 0, 0.0, &error));
  }
  const double tolerance = kReceiverQuadratureTolerance * first / double(2 * (angles.size() - 1));
  double total = 0;
  for (size_t i = 0; i + 1 < angles.size(); ++i) {
    const double a = angles[i], b = angles[i + 1], half = std::sqrt(0.5 * (b - a));
    total += adaptive_gauss_kronrod(from_low(a), 0, half, tolerance, kReceiverQuadratureDepth, nullptr, &reached.outer);
    total += adaptive_gauss_kronrod(from_high(b), 0, half, tolerance, kReceiverQuadratureDepth, nullptr, &reached.outer);
  }
  reached.report(total);
  return total;
}

// ∫ g(Direction) dω over the light's directions above the horizon: a
// sphere's cone, a planar light's visible region, or the sky's hemisphere
// where f can be non-zero.
template <class R, class G>
double light_integral(const ReceiverLight& light, const R& receiver, G g) {
  if (light.planar) return plane_integral(*light.planar, receiver, g);
  if (light.environment)
    return cap_integral(LobeCap{}, receiver.vanishes_below_mirror_plane() ? receiver.mirror() : receiver.n, receiver, g);
  const double D = length(light.center);
  return cap_integral(SphereCap{D, light.radius}, light.center / D, receiver, g);
}

// Solid angle of a sphere's cone: 2π(1 − cos γ) = 2π sin²γ/(1 + cos γ).
inline double cone_solid_angle(double D, double R) {
  const double s2 = (R / D) * (R / D);
  return 2 * kPi * s2 / (1 + std::sqrt((1 - R / D) * (1 + R / D)));
}

// Density in solid angle of the light strategy that samples `light` (pmf
// included), as the renderer samples it (renderer/light_strategy.cpp, whose
// choice core/strategy.h states): light_solid_angle draws uniformly in a
// sphere's cone or in a planar light's whole spherical triangle or rectangle
// (PlanarEmitter::solid_angle, unclipped and unoccluded: p = P/Ω), a disk or
// any other planar light by area; light_area draws a point uniformly on the
// whole surface, p = P·d²/(A cos θ'); the environment is cosine-weighted.
// What depends on the light alone is computed once per light (LightDensity's
// constructor), not per direction.
struct LightDensity {
  const ReceiverLight& light;
  bool by_area;
  double solid_angle = 0;  // Ω sampled uniformly (light_solid_angle), 0: by area
  double area = 0;         // the emitter's whole area (by area)
  LightDensity(const ReceiverLight& l, bool area_sampling) : light(l), by_area(area_sampling) {
    if (light.environment) return;
    if (light.planar) {
      area = light.planar->area;
      if (!by_area) solid_angle = light.planar->solid_angle;
    } else {
      area = 4 * kPi * light.radius * light.radius;
      if (!by_area) solid_angle = cone_solid_angle(length(light.center), light.radius);
    }
    by_area = !(solid_angle > 0);
  }
  double operator()(const Direction& d) const {
    if (light.environment) return light.pmf * d.cos_theta / kPi;
    if (!by_area) return light.pmf / solid_angle;
    return light.pmf * d.distance * d.distance / (area * d.cos_emission);
  }
};

// E[Y²] of the strategy's estimator for receiver type R (receiver.h).
template <class R>
double second_moment_of(Strategy strategy, const R& receiver, const std::vector<ReceiverLight>& lights) {
  const double c = kOneSampleBsdfProbability;
  const int beta = strategy_info(strategy).mis_beta;
  double moment = 0, bsdf2 = 0, light2 = 0, bsdf1 = 0, light1 = 0;
  for (const ReceiverLight& light : lights) {
    const double L = light.radiance;
    auto h = [&](const Direction& d) { return d.bsdf.f_cos * L; };
    auto h2_over_bsdf = [&](const Direction& d) { return d.bsdf.f_cos2_over_pdf * L * L; };
    const LightDensity p_light(light, strategy == Strategy::kLightArea);
    auto weight_bsdf = [&](const Direction& d) {
      const double pb = d.bsdf.pdf_solid_angle, pl = p_light(d);
      if (!(pb > 0)) return 0.0;
      return beta == 2 ? pb * pb / (pb * pb + pl * pl) : pb / (pb + pl);
    };
    // 1 − w_b as its own quotient: where w_b ≈ 1 (a lobe's peak) 1 − w_b would keep only ε/(1 − w_b) of it.
    auto weight_light = [&](const Direction& d) {
      const double pb = d.bsdf.pdf_solid_angle, pl = p_light(d);
      if (!(pb > 0)) return 1.0;
      return beta == 2 ? pl * pl / (pb * pb + pl * pl) : pl / (pb + pl);
    };
    switch (strategy) {
      case Strategy::kUniformHemisphere:
        moment += light_integral(light, receiver, [&](const Direction& d) { return 2 * kPi * h(d) * h(d); });
        break;
      case Strategy::kCosineHemisphere:
        moment += light_integral(light, receiver, [&](const Direction& d) { return kPi * h(d) * h(d) / d.cos_theta; });
        break;
      case Strategy::kBsdf:
        moment += light_integral(light, receiver, h2_over_bsdf);
        break;
      case Strategy::kLightArea:
      case Strategy::kLightSolidAngle:
        moment += light_integral(light, receiver, [&](const Direction& d) { return h(d) * h(d) / p_light(d); });
        break;
      case Strategy::kMisBalance:
      case Strategy::kMisPower: {
        bsdf2 += light_integral(light, receiver, [&](const Direction& d) {
          const double w = weight_bsdf(d);
          return w * w * h2_over_bsdf(d);
        });
        light2 += light_integral(light, receiver, [&](const Direction& d) {
          const double w = weight_light(d);
          return w * w * h(d) * h(d) / p_light(d);
        });
        bsdf1 += light_integral(light, receiver, [&](const Direction& d) { return weight_bsdf(d) * h(d); });
        light1 += light_integral(light, receiver, [&](const Direction& d) { return weight_light(d) * h(d); });
        break;
      }
      case Strategy::kMisOneSample:
        moment += light_integral(light, receiver, [&](const Direction& d) {
          const double q = c * d.bsdf.pdf_solid_angle + (1 - c) * p_light(d);
          return q > 0 ? h(d) * h(d) / q : 0.0;
        });
        break;
      case Strategy::kPathNaive:
      case Strategy::kPathMis:
        throw Error("the path tracer '" + strategy_name(strategy) + "' has no single-sample estimator over " +
                    receiver.name());
    }
  }
  if (is_multi_sample_mis(strategy)) return bsdf2 + light2 + 2 * bsdf1 * light1;
  return moment;
}

}  // namespace receiver_detail

template <class R>
double ReceiverModel<R>::light_reflectance(const ReceiverLight& light) const {
  return receiver_detail::light_integral(light, static_cast<const R&>(*this),
                                         [](const receiver_detail::Direction& d) { return d.bsdf.f_cos; });
}

template <class R>
double ReceiverModel<R>::second_moment(Strategy strategy, const std::vector<ReceiverLight>& lights) const {
  return receiver_detail::second_moment_of(strategy, static_cast<const R&>(*this), lights);
}

}  // namespace furnace::analytic
