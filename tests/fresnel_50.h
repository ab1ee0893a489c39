// Fresnel reflectances in 50 digits (boost::multiprecision), written from
// the textbook definitions for the Fresnel tests of core/ (core/fresnel.h)
// and analytic/ (analytic/fresnel.h). Neither form below is one of the
// library's: no difference-of-squares rewrites (50 digits spare every
// cancellation the double forms avoid), and the conductor goes through the
// normal wave-vector component instead of cos θt.
//
// Dielectric (Born & Wolf §1.5.2), c = cos θi ∈ [0, 1], η = η_t/η_i:
//   sin θi = √(1 − c²), Snell: sin θt = sin θi/η (total internal reflection
//   when sin θt ≥ 1: F = 1), cos θt = √(1 − sin²θt),
//   r∥ = (η cos θi − cos θt)/(η cos θi + cos θt),
//   r⊥ = (cos θi − η cos θt)/(cos θi + η cos θt),   F = (r∥² + r⊥²)/2.
// Conductor (Born & Wolf §14.2; Heavens), complex index η̃ = n + ik:
//   the normal component of the transmitted wave vector, in units of the
//   vacuum wave number, q = √(η̃² − sin²θi), the root with Im q ≥ 0 (the
//   wave decays into the metal), and
//   r⊥ = (cos θi − q)/(cos θi + q),   r∥ = (η̃² cos θi − q)/(η̃² cos θi + q),
//   F = (|r∥|² + |r⊥|²)/2.
// (q = η̃ cos θt; the r∥ above is the usual (η̃ cos θi − cos θt)/(η̃ cos θi + cos θt)
// multiplied through by η̃.)
//
// Inputs are doubles, converted exactly: the references are the exact
// reflectances of the double inputs, to ~1e-49.
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include <boost/multiprecision/cpp_bin_float.hpp>
#include <boost/multiprecision/cpp_complex.hpp>

namespace furnace::testing_support {

using Real50 = boost::multiprecision::cpp_bin_float_50;
using Complex50 = boost::multiprecision::cpp_complex_50;

// Unpolarised dielectric reflectance, by Snell's law and the two amplitudes.
inline Real50 fresnel_dielectric_50(const Real50& c, const Real50& n) {
  if (n == 1) return Real50(0);  // no interface; at c = 0 the 0/0 limit along c > 0
  const Real50 sin_i = sqrt(Real50(1) - c * c);
  const Real50 sin_t = sin_i / n;
  if (sin_t >= 1) return Real50(1);
  const Real50 cos_t = sqrt(Real50(1) - sin_t * sin_t);
  const Real50 r_par = (n * c - cos_t) / (n * c + cos_t);
  const Real50 r_perp = (c - n * cos_t) / (c + n * cos_t);
  return (r_par * r_par + r_perp * r_perp) / 2;
}
inline Real50 fresnel_dielectric_50(double cos_i, double eta) { return fresnel_dielectric_50(Real50(cos_i), Real50(eta)); }

// The relative condition number |c·∂F/∂c|/F of the dielectric reflectance
// at c (central difference in 50 digits, step 1e-20·c): a method whose only
// error is one rounding of c (or of c²) errs by about κ·ε/2 at best.
inline double fresnel_dielectric_condition(double cos_i, double eta) {
  const Real50 c(cos_i), n(eta), h = c * Real50(1e-20);
  const Real50 slope = (fresnel_dielectric_50(c + h, n) - fresnel_dielectric_50(c - h, n)) / (2 * h);
  return static_cast<double>(abs(c * slope / fresnel_dielectric_50(c, n)));
}

// The cosine of the refracted direction in 50 digits (Snell); 0 under total
// internal reflection.
inline Real50 refracted_cos_50(double cos_i, double eta) {
  const Real50 c(cos_i), n(eta);
  const Real50 sin_t = sqrt(Real50(1) - c * c) / n;
  if (sin_t >= 1) return Real50(0);
  return sqrt(Real50(1) - sin_t * sin_t);
}

// Unpolarised conductor reflectance, by the wave-vector form.
inline Real50 fresnel_conductor_50(double cos_i, double n, double k) {
  const Real50 c(cos_i);
  const Complex50 eta{Real50(n), Real50(k)};
  const Complex50 eta2 = eta * eta;
  if (eta2 == Complex50(1)) return Real50(0);  // index-matched: no interface (c = 0 by continuity)
  Complex50 q = sqrt(eta2 - Complex50(Real50(1) - c * c));
  if (q.imag() < 0) q = -q;  // the decaying wave
  const Complex50 cc(c);
  const Complex50 r_perp = (cc - q) / (cc + q);
  const Complex50 r_par = (eta2 * cc - q) / (eta2 * cc + q);
  return (norm(r_par) + norm(r_perp)) / 2;
}

// ---------------------------------------------------------------------------
// The grids both Fresnel tests sweep.

// Cosines of incidence: exact 0 and 1, grazing down to 1e-8, 1 − 1e-8 near
// the normal, and 199 interior points k/200 (the nearest to a critical
// cosine √(1 − η²) of the η below is 0.305 at η = 1/1.05, 3e-4 relative
// from it; the neighbourhood of the critical angle has its own grid).
inline std::vector<double> fresnel_cosines() {
  std::vector<double> c{0.0, 1e-8, 1e-6, 1e-4, 1e-3, 1e-2, 0.999, 1 - 1e-6, 1 - 1e-8, 1.0};
  for (int k = 1; k < 200; ++k) c.push_back(k / 200.0);
  std::sort(c.begin(), c.end());
  return c;
}

// Relative indices η = η_t/η_i in [0.25, 4], near 1 on both sides (η = 1
// itself gives F ≡ 0 and is tested apart).
inline const std::vector<double> kFresnelEtas{0.25, 0.3,   0.5,  1 / 1.5, 0.75, 0.9, 1 / 1.05, 0.999, 1 - 1e-6,
                                              1 + 1e-6, 1.001, 1.05, 1.2,  1.33, 1.5, 2.0,      2.4,   3.0,  4.0};

// Complex indices n + ik of conductors: gold- and aluminium-like, the low
// n, k where the approximation of core/fresnel.h fails, silver-like, and
// the two degenerate ones ((1, 0): an index-matched interface, F ≡ 0;
// (0, 1): the ideal conductor, F ≡ 1).
struct ComplexIndex {
  double n, k;
};
inline const std::vector<ComplexIndex> kConductors{{0.2, 3.4}, {1.5, 0.1}, {2, 4}, {0.05, 2}, {1, 0}, {0, 1}};

// The cosine of the critical angle cos θc = √(1 − η²) (η < 1), in 50 digits,
// and the double cosine of the angle θc + dtheta (dtheta < 0: short of it).
inline Real50 critical_cos_50(double eta) {
  const Real50 n(eta);
  return sqrt(Real50(1) - n * n);
}
inline double cos_near_critical(double eta, double dtheta) {
  const Real50 theta_c = asin(Real50(eta));
  return static_cast<double>(cos(theta_c + Real50(dtheta)));
}

// |value − reference|/reference in 50 digits; for reference 0 the absolute
// error (no relative error exists; callers say so).
inline double relative_error(double value, const Real50& reference) {
  const Real50 diff = abs(Real50(value) - reference);
  return static_cast<double>(reference == 0 ? diff : diff / reference);
}

// The worst relative error of a function over a set of points, and where.
struct WorstError {
  double error = 0, cos_i = 0, a = 0, b = 0, value = 0, reference = 0;
  long points = 0;
  void add(double e, double c, double x, double y, double v, const Real50& r) {
    ++points;
    if (e > error || points == 1) *this = WorstError{e, c, x, y, v, static_cast<double>(r), points};
  }
};

}  // namespace furnace::testing_support
