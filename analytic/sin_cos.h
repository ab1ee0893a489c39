// sin and cos without a trigonometric call at quadrature nodes: of an angle
// given by its legs (the light-area kernels' radial integrals,
// sin_cos_power_integral.h, need sin T and cos T of T = atan2(ρ, h) at every
// node), and along an arc by its half-angle variable (HalfAngleArc: the MIS
// and Phong integrals over azimuths and polar angles).
#pragma once

#include <cmath>
#include <utility>
#include <vector>

#include "core/vec3.h"

namespace furnace::analytic {

namespace sin_cos_detail {

// a·b = p + e exactly (Dekker's product with Veltkamp's split at 2^27 + 1:
// each factor splits into two 26-bit halves whose products are exact),
// for |a|, |b| below 2^995 and |a·b| well inside the normal range.
inline void two_product(double a, double b, double* p, double* e) {
  constexpr double kSplit = 134217729.0;  // 2^27 + 1
  const double ca = kSplit * a, a_hi = ca - (ca - a), a_lo = a - a_hi;
  const double cb = kSplit * b, b_hi = cb - (cb - b), b_lo = b - b_hi;
  *p = a * b;
  *e = ((a_hi * b_hi - *p) + a_hi * b_lo + a_lo * b_hi) + a_lo * b_lo;
}

}  // namespace sin_cos_detail

struct SinCos {
  double S, C;  // sin T, cos T
};

// sin and cos of T = atan2(y, x) for x, y ≥ 0 (not both 0), without a
// trigonometric call: S = y/r, C = x/r, r = √(x² + y²), each within about
// half an ulp (the plain y/sqrt(x*x + y*y) is off by up to 1.25 ulps, which
// sin_cos_power_integral's J_{m,n} multiplies by m + 1 for small T). Method:
// x² + y² as a double-double (exact products), r = r0 + δr with r0 = √(its
// high part) and δr its Newton correction, then S = s0 + (y − s0·r)/r0 from
// the rounded quotient s0 = y/r0 and its exact residual (likewise C).
// Valid while x², y² stay normal (|x|, |y| in about 1e-146 … 1e146); beyond,
// the error terms underflow and it degrades to the plain formula's ulp.
inline SinCos sin_cos_of_atan2(double y, double x) {
  using sin_cos_detail::two_product;
  double yy, y_err, xx, x_err;
  two_product(y, y, &yy, &y_err);
  two_product(x, x, &xx, &x_err);
  const double w = yy + xx, w_part = w - yy;
  const double w_err = (yy - (w - w_part)) + (xx - w_part) + y_err + x_err;  // x² + y² = w + w_err
  const double r0 = std::sqrt(w);
  double rr, rr_err;
  two_product(r0, r0, &rr, &rr_err);
  const double dr = ((w - rr) - rr_err + w_err) / (2 * r0);  // r = r0 + dr
  const double s0 = y / r0, c0 = x / r0;
  double p, e;
  two_product(s0, r0, &p, &e);
  const double S = s0 + (((y - p) - e) - s0 * dr) / r0;
  two_product(c0, r0, &p, &e);
  const double C = c0 + (((x - p) - e) - c0 * dr) / r0;
  return {S, C};
}

// An arc of angles [lo, hi], 0 < hi − lo ≤ π, in the half-angle variable τ
// of φ = c + 2·atan τ about its midpoint c: τ ∈ [−τ_max, τ_max] with
// τ_max = tan((hi − lo)/4) ≤ 1, and cos φ, sin φ rational in τ, so a
// quadrature over the arc makes no trigonometric call at its nodes (one
// sincos and one tan per arc instead): with q = 1/(1 + τ²),
//   cos(φ − c) = (1 − τ)(1 + τ)·q,  sin(φ − c) = 2τ·q,  dφ/dτ = 2q.
// The map is smooth with dφ/dτ between 1 and 2 on the arc, so an integrand
// smooth in φ stays smooth in τ. (1 − τ)(1 + τ) keeps cos(φ − c) accurate
// relative to itself where τ is near 1.
struct HalfAngleArc {
  double cos_c = 1, sin_c = 0, tau_max = 0;
  static HalfAngleArc of(double lo, double hi) {
    HalfAngleArc arc;
    const double c = 0.5 * (lo + hi);
    arc.cos_c = std::cos(c);
    arc.sin_c = std::sin(c);
    arc.tau_max = std::tan(0.25 * (hi - lo));
    return arc;
  }
  // cos φ, sin φ and dφ/dτ at τ.
  void at(double tau, double* cos_phi, double* sin_phi, double* dphi_dtau) const {
    const double q = 1 / (1 + tau * tau);
    const double cos_d = (1 - tau) * (1 + tau) * q, sin_d = 2 * tau * q;
    *cos_phi = cos_c * cos_d - sin_c * sin_d;
    *sin_phi = sin_c * cos_d + cos_c * sin_d;
    *dphi_dtau = 2 * q;
  }
};

// [lo, hi] (0 ≤ hi − lo ≤ 2π) as at most two HalfAngleArcs of equal width
// (two where it is wider than π); count 0 for an empty arc.
struct HalfAngleArcs {
  HalfAngleArc piece[2];
  int count = 0;
  static HalfAngleArcs of(double lo, double hi) {
    HalfAngleArcs arcs;
    if (!(hi > lo)) return arcs;
    if (hi - lo <= kHalfAngleArcMaxWidth) {
      arcs.piece[0] = HalfAngleArc::of(lo, hi);
      arcs.count = 1;
    } else {
      const double mid = 0.5 * (lo + hi);
      arcs.piece[0] = HalfAngleArc::of(lo, mid);
      arcs.piece[1] = HalfAngleArc::of(mid, hi);
      arcs.count = 2;
    }
    return arcs;
  }
  static constexpr double kHalfAngleArcMaxWidth = kPi;  // τ_max ≤ 1
};

// The arc of azimuths ψ (length ≤ 2π, none when empty) on which
// A + B cos ψ + C sin ψ > 0: with M = √(B² + C²) the sum is A + M cos(ψ − ψ₀),
// ψ₀ = atan2(C, B), positive on ψ₀ ± acos(−A/M) (everywhere if A ≥ M,
// nowhere if A ≤ −M). The horizon n·ω > 0 on a ring of directions.
inline std::vector<std::pair<double, double>> positive_arcs(double A, double B, double C) {
  const double M = std::hypot(B, C);
  if (M <= std::fabs(A))
    return A > 0 ? std::vector<std::pair<double, double>>{{0, 2 * kPi}} : std::vector<std::pair<double, double>>{};
  const double centre = std::atan2(C, B), half = std::acos(-A / M);
  return {{centre - half, centre + half}};
}

}  // namespace furnace::analytic
