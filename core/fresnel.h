// Fresnel reflectance of a smooth interface for unpolarised light, exact
// (no Schlick): a dielectric interface and a conductor of complex index.
// Shared by renderer/ (the BSDFs) and analytic/ (the references) because
// both need the same physics; the 50-digit tests
// (tests/core/fresnel_test.cpp) check it against independent forms (Walter
// et al. 2007 eq. 22 for the dielectric, the real-arithmetic form of the
// conductor) in Boost.Multiprecision.
//
// Formulas (Born & Wolf §1.5; pbrt 4th ed. §9.3), with c = cos θi ≥ 0 the
// cosine of incidence on the incident side, s² = 1 − c², η the index of the
// transmitting side relative to the incident side, ct = cos θt:
//   sin²θt = s²/η², ct = √(1 − sin²θt)   (total internal reflection when sin²θt ≥ 1);
//   r∥ = (ηc − ct)/(ηc + ct),  r⊥ = (c − η ct)/(c + η ct),  F = (r∥² + r⊥²)/2.
// Written without the cancellations that lose the digits as η → 1 (F ~ (η−1)²):
//   r⊥ = (1 − η²)/(c + η ct)²,   r∥ = (η² − 1)(c² − s²/η²)/(ηc + ct)²
// (from (ηc)² − ct² = (η² − 1)(c² − s²/η²) and c² − η²ct² = 1 − η²), with
// η² − 1 = (η − 1)(η + 1) and 1 − sin²θt = (η² − s²)/η² = ((η−1)(η+1) + c²)/η².
// η² − 1 + c², which vanishes at the critical angle, is formed without
// rounding its parts first (eta2_minus_sin2). tests/core/fresnel_test.cpp
// prints the worst relative error against 50-digit values per class (η in
// [0.25, 4], η within 1e-6 of 1, grazing, within 1e-10 rad of the critical
// angle) and holds it to 1e-13.
//
// Conductor (complex index η̃ = n + ik of the metal relative to the outside):
// the same two amplitudes with complex η̃ and the principal root of
// 1 − s²/η̃² (Re ≥ 0: the transmitted wave decays into the metal), F = (|r∥|² + |r⊥|²)/2.
// n = 0, k = 1 gives F ≡ 1 (an ideal conductor).
// DEFECT(conductor_fresnel_approximate) is the classic approximation that
// Cycles used until 5.0 (R∥ = ((n²+k²)c² − 2nc + 1)/((n²+k²)c² + 2nc + 1),
// R⊥ = (n²+k² − 2nc + c²)/(n²+k² + 2nc + c²)): off by up to 0.096 at low n, k.
#pragma once

#include <algorithm>
#include <cmath>
#include <complex>

namespace furnace {

// η² − sin²θi = η² − 1 + c² = η²·cos²θt, accurate relative to itself near
// the critical angle, where it vanishes: η² and c² are split exactly into
// head and tail (fma), and the head that lies in [0.5, 2] takes the 1 away
// exactly (Sterbenz), so the only rounding is of the result (relative
// error ~ε, where rounding c² and η² − 1 first would leave ~ε/(η² − 1 + c²)).
inline double eta2_minus_sin2(double c, double eta) {
  const double e2 = eta * eta, e2_tail = std::fma(eta, eta, -e2);
  const double c2 = c * c, c2_tail = std::fma(c, c, -c2);
  const double head = c2 >= 0.5 ? (c2 - 1.0) + e2 : (e2 - 1.0) + c2;
  return head + (e2_tail + c2_tail);
}

// The cosine of the transmitted direction, ≥ 0, for incidence cos θi = c on
// the incident side and relative index η; 0 at and past the critical angle
// (where fresnel_dielectric is 1). Computed as √(η² − 1 + c²)/η without
// forming 1 − c².
inline double refracted_cos(double c, double eta) {
  c = std::clamp(c, 0.0, 1.0);
  const double radicand = eta2_minus_sin2(c, eta);  // η²·cos²θt
  return radicand > 0 ? std::sqrt(radicand) / eta : 0.0;
}

// Whether light incident at cos θi = c (≥ 0) on the side of index 1 relative
// to the other side's η is totally reflected (η < 1 and sin θi ≥ η).
inline bool total_internal_reflection(double c, double eta) {
  c = std::clamp(c, 0.0, 1.0);
  return !(eta2_minus_sin2(c, eta) > 0);
}

// Unpolarised Fresnel reflectance of a dielectric interface for incidence
// cos θi = c ∈ [0, 1] (clamped) on the incident side, η = η_transmitted/η_incident > 0.
// 1 under total internal reflection; 0 at η = 1.
inline double fresnel_dielectric(double c, double eta) {
  if (eta == 1) return 0.0;  // no interface: at grazing too (where the limit for η → 1 is 1, from both sides)
  c = std::clamp(c, 0.0, 1.0);
  const double eta2_minus_1 = (eta - 1.0) * (eta + 1.0);
  const double radicand = eta2_minus_sin2(c, eta);  // η²cos²θt
  if (!(radicand > 0)) return 1.0;
  const double eta_ct = std::sqrt(radicand);  // η·cos θt
  const double ct = eta_ct / eta;
  const double s2 = (1.0 - c) * (1.0 + c);
  const double a = eta * c + ct, b = c + eta_ct;
  const double r_par = eta2_minus_1 * (c * c - s2 / (eta * eta)) / (a * a);
  const double r_perp = -eta2_minus_1 / (b * b);
  return 0.5 * (r_par * r_par + r_perp * r_perp);
}

// Unpolarised Fresnel reflectance of a conductor of complex relative index
// n + ik (n > 0 or k > 0, both ≥ 0) at cos θi = c ∈ [0, 1] (clamped).
inline double fresnel_conductor(double c, double n, double k) {
  using C = std::complex<double>;
  if (n == 1 && k == 0) return 0.0;  // no interface (at grazing the amplitudes are 0/0)
  c = std::clamp(c, 0.0, 1.0);
  const C eta(n, k);
  // cos²θt = 1 − s²/η̃² = (η̃² − 1 + c²)/η̃², with Re(η̃² − 1) = (n − 1)(n + 1) − k²:
  // no 1 − (1 − c²) where η̃² is near 1.
  const C eta2_minus_1((n - 1.0) * (n + 1.0) - k * k, 2.0 * n * k);
  const C ct = std::sqrt((eta2_minus_1 + c * c) / (eta * eta));  // principal root: Re ≥ 0
  const C r_par = (eta * c - ct) / (eta * c + ct);
  const C r_perp = (C(c) - eta * ct) / (C(c) + eta * ct);
  return 0.5 * (std::norm(r_par) + std::norm(r_perp));
}

// The approximation above (a negative control only).
inline double fresnel_conductor_approximate(double c, double n, double k) {
  c = std::clamp(c, 0.0, 1.0);
  const double nk2 = n * n + k * k;
  const double r_par = (nk2 * c * c - 2 * n * c + 1) / (nk2 * c * c + 2 * n * c + 1);
  const double r_perp = (nk2 - 2 * n * c + c * c) / (nk2 + 2 * n * c + c * c);
  return 0.5 * (r_par + r_perp);
}

}  // namespace furnace
