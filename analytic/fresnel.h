// Fresnel reflectances for the references, written in other forms than the
// renderer's (core/fresnel.h), so that one slip cannot make a BSDF and its
// reference agree: the dielectric by Walter et al. 2007's eq. 22, the
// conductor in real arithmetic (Moeller's form, as Mitsuba 3's
// fresnel_conductor). tests/core/fresnel_test.cpp checks both forms against
// 50-digit values.
//
// Dielectric (c = cos θi ∈ [0, 1], η = η_t/η_i):
//   g = √(η² − 1 + c²)  (total internal reflection when the radicand ≤ 0: F = 1),
//   F = ½·((g − c)/(g + c))²·[1 + ((c(g + c) − 1)/(c(g − c) + 1))²],
// with g − c = (η² − 1)/(g + c) and c(g + c) − 1 = cg − (1 − c²), which keep
// the digits as η → 1.
// Conductor (η̃ = n + ik, s² = 1 − c²): t = n² − k² − s²,
//   a² + b² = √(t² + 4n²k²),  a = √((a² + b² + t)/2),
//   R⊥ = (a² + b² + c² − 2ac)/(a² + b² + c² + 2ac),
//   R∥ = R⊥·((a² + b²)c² + s⁴ − 2ac s²)/((a² + b²)c² + s⁴ + 2ac s²),
//   F = (R⊥ + R∥)/2.
#pragma once

#include <algorithm>
#include <cmath>

namespace furnace::analytic {

inline double fresnel_dielectric_reference(double c, double eta) {
  if (eta == 1) return 0.0;  // no interface
  c = std::clamp(c, 0.0, 1.0);
  const double eta2_minus_1 = (eta - 1) * (eta + 1);
  // g² = η² − 1 + c², which vanishes at the critical angle: η² and c² split
  // exactly (fma), the 1 taken from the head in [0.5, 2] (exact, Sterbenz).
  const double e2 = eta * eta, c2 = c * c;
  const double tails = std::fma(eta, eta, -e2) + std::fma(c, c, -c2);
  const double g2 = (c2 >= 0.5 ? (c2 - 1) + e2 : (e2 - 1) + c2) + tails;
  if (!(g2 > 0)) return 1.0;
  const double g = std::sqrt(g2);
  const double g_plus_c = g + c;
  const double ratio = eta2_minus_1 / (g_plus_c * g_plus_c);  // (g − c)/(g + c)
  const double s2 = (1 - c) * (1 + c);
  const double g_minus_c = eta2_minus_1 / g_plus_c;
  const double q = (c * g - s2) / (c * g_minus_c + 1);
  return 0.5 * ratio * ratio * (1 + q * q);
}

inline double fresnel_conductor_reference(double c, double n, double k) {
  if (n == 1 && k == 0) return 0.0;  // no interface (at grazing the terms are 0/0)
  c = std::clamp(c, 0.0, 1.0);
  const double s2 = (1 - c) * (1 + c);
  const double t = (n - 1) * (n + 1) - k * k + c * c;  // n² − k² − s², without 1 − (1 − c²)
  const double a2b2 = std::sqrt(t * t + 4 * n * n * k * k);
  const double a = std::sqrt(std::max(0.0, (a2b2 + t) / 2));
  const double r_perp = (a2b2 + c * c - 2 * a * c) / (a2b2 + c * c + 2 * a * c);
  const double r_par = r_perp * (a2b2 * c * c + s2 * s2 - 2 * a * c * s2) / (a2b2 * c * c + s2 * s2 + 2 * a * c * s2);
  return 0.5 * (r_perp + r_par);
}

}  // namespace furnace::analytic
