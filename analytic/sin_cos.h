// sin and cos of an angle given by its legs, without a trigonometric call:
// the light-area kernels' radial integrals (sin_cos_power_integral.h) need
// sin T and cos T of T = atan2(ρ, h) at every quadrature node.
#pragma once

#include <cmath>

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

}  // namespace furnace::analytic
