// ∫_0^T sin^m t·cos^n t dt from sin T and cos T, without any trigonometric
// call: the radial integrals of the light-area kernels (contour_area_kernel,
// polygon_area_kernel) need it at every quadrature node, where the callers
// know S = sin T and C = cos T algebraically (T = atan2(ρ, h) gives
// S = ρ/√(ρ² + h²), C = h/√(ρ² + h²)).
#pragma once

#include <array>
#include <cmath>
#include <cstddef>

namespace furnace::analytic {

namespace sin_cos_power_detail {

// ν = (n − 1)/2, the exponent of (1 − s²) in the integrand in s = sin t.
constexpr long double nu(int n) { return (n - 1) / 2.0L; }

// a_k = (−1)^k·C(ν, k)/(m + 2k + 1): the series' coefficients, from the
// binomial recurrence b_{k+1} = b_k·(k − ν)/(k + 1) in long double (each
// coefficient within an ulp of double once rounded; the terms where the
// recurrence's rounding accumulates are below 1e-17 of the sum).
template <int M, int N, size_t K>
constexpr std::array<double, K> coefficients() {
  std::array<double, K> a{};
  long double b = 1;
  for (size_t k = 0; k < K; ++k) {
    a[k] = static_cast<double>(b / (M + 2 * static_cast<long double>(k) + 1));
    b = b * (static_cast<long double>(k) - nu(N)) / (static_cast<long double>(k) + 1);
  }
  return a;
}

constexpr long double abs_ld(long double x) { return x < 0 ? -x : x; }

// The largest x = s² the series is used for: s ≤ c with s² + c² = 1 within
// a few ulps, so x ≤ 1/2·(1 + a few ε); 2^-20 of margin covers that.
constexpr long double kMaxX = 0.5L + 0x1p-20L;

// A lower bound of the series' sum Σ a_k x^k = ∫_0^1 u^m (1 − x u²)^ν du on
// [0, kMaxX]: ≥ (1 − kMaxX)^ν/(m + 1) for ν ≥ 0, ≥ 1/(m + 1) for ν < 0.
template <int M, int N>
constexpr long double sum_lower_bound() {
  long double factor = 1;
  for (int i = 0; i < N - 1; ++i) factor *= (1 - kMaxX);  // (1 − x)^(2ν) = (1 − x)^(n − 1)
  // (1 − x)^ν = √((1 − x)^(2ν)) ≥ (1 − x)^(2ν) since 0 < 1 − x < 1 and 2ν ≥ ν.
  return N >= 1 ? factor / (M + 1) : 1.0L / (M + 1);
}

// The number of terms K for which the truncated tail Σ_{k≥K} a_k x^k is
// below 2^-60 of the sum for every x ≤ x_max: past k > ν the |a_k| do not
// increase (|b_{k+1}/b_k| = |k − ν|/(k + 1) ≤ 1 and the denominators grow),
// so the tail is at most |a_K|·x_max^K/(1 − x_max). When n is odd ν is an
// integer and the series is a polynomial of ν + 1 terms: exact.
template <int M, int N>
constexpr size_t terms_needed(long double x_max) {
  if (N % 2 == 1) return static_cast<size_t>((N - 1) / 2 + 1);
  const long double target = 0x1p-60L * sum_lower_bound<M, N>();
  long double b = 1, power = 1;
  for (size_t k = 0; k < 400; ++k) {
    const long double a = abs_ld(b) / (M + 2 * static_cast<long double>(k) + 1);
    if (static_cast<long double>(k) > nu(N) && a * power / (1 - x_max) <= target) return k;
    b = b * (static_cast<long double>(k) - nu(N)) / (static_cast<long double>(k) + 1);
    power *= x_max;
  }
  return 0;  // not reached for m, n ≥ 0 (static_assert below)
}

// ∫_0^{π/2} sin^m t cos^n t dt = (m − 1)!!(n − 1)!!/(m + n)!!, times π/2
// when m and n are both even (Wallis).
template <int M, int N>
constexpr double full_integral() {
  long double value = 1;
  for (int i = M - 1; i > 0; i -= 2) value *= i;
  for (int i = N - 1; i > 0; i -= 2) value *= i;
  for (int i = M + N; i > 0; i -= 2) value /= i;
  if (M % 2 == 0 && N % 2 == 0) value *= 1.5707963267948966192313216916397514L;  // π/2
  return static_cast<double>(value);
}

// ∫_0^S s^m (1 − s²)^ν ds = S^(m+1)·Σ_k a_k (S²)^k, for 0 ≤ S ≤ 1/√2.
// Horner from the last term the tail needs at this x (fewer for small x).
template <int M, int N>
double series(double S) {
  constexpr size_t kTerms = terms_needed<M, N>(kMaxX);
  static_assert(kTerms > 0, "the series converges on [0, 1/2] for m, n >= 0");
  static constexpr std::array<double, kTerms> a = coefficients<M, N, kTerms>();
  // Fewer terms for smaller x, each count with its own tail bound (for
  // (2, 4): 45 terms up to x = 1/2, 24 up to 1/4, 17 up to 1/8, 11 up to 1/32).
  constexpr size_t kTermsQuarter = terms_needed<M, N>(1.0L / 4), kTermsEighth = terms_needed<M, N>(1.0L / 8),
                   kTermsThirtySecond = terms_needed<M, N>(1.0L / 32);
  const double x = S * S;
  const size_t terms = x <= 1.0 / 32 ? kTermsThirtySecond
                       : x <= 1.0 / 8 ? kTermsEighth
                       : x <= 1.0 / 4 ? kTermsQuarter
                                      : kTerms;
  // Plain multiply-adds: the build targets no FMA instruction, and std::fma
  // would be a library call per term.
  double sum = a[terms - 1];
  for (size_t k = terms - 1; k-- > 0;) sum = sum * x + a[k];
  double power = S;  // S^(m+1)
  for (int i = 0; i < M; ++i) power *= S;
  return power * sum;
}

}  // namespace sin_cos_power_detail

// J_{m,n}(T) = ∫_0^T sin^m t·cos^n t dt for T ∈ [0, π/2], given S = sin T ≥ 0
// and C = cos T ≥ 0 (S² + C² = 1 within a few ulps), integers m, n ≥ 0.
// Dimensionless. T is taken as asin S when S ≤ C and as acos C otherwise
// (the one of the two that determines T best).
//
// Method. s = sin t turns it into ∫_0^S s^m (1 − s²)^((n−1)/2) ds, and the
// binomial series of (1 − s²)^ν, ν = (n − 1)/2, integrated term by term:
//   J_{m,n}(T) = S^(m+1)·Σ_k (−1)^k·C(ν, k)·S^(2k)/(m + 2k + 1).
// For S ≤ C (T ≤ π/4, S² ≤ 1/2) its terms fall at least as 2^-k; it is
// truncated where the tail is below 2^-60 of the sum (about 40 terms at
// S² = 1/2, fewer for smaller S, exact for odd n). For S > C the complement
// t → π/2 − t is used:
//   J_{m,n}(T) = J_{m,n}(π/2) − J_{n,m}(π/2 − T),
// with the same series in C (sin(π/2 − T) = C ≤ 1/√2) and J_{m,n}(π/2) =
// (m − 1)!!(n − 1)!!/(m + n)!!·(π/2 if m, n both even) (π/32 for (2, 4) and
// (4, 2)). Nothing cancels for small T (the first term is S^(m+1)/(m + 1),
// the closed forms in T lose T² of their digits), and the complement takes at
// most J_{n,m}(π/4)/J_{m,n}(π/4) of the full integral (2.5 for (4, 2), 0.4
// for (2, 4)), so no catastrophic cancellation anywhere on [0, π/2].
//
// Accuracy: a few ulps for (2, 4) and (4, 2) over the whole range against
// 50-digit references (tests/analytic/sin_cos_power_integral_test.cpp), as
// much as the inputs' own rounding (J moves by (m + 1)·δ for a relative
// change δ of a small S). Cost: one polynomial of ≤ 40 terms in S², no
// libm call (it replaces a 20-point Gauss–Legendre rule: 40 sin/cos).
template <int M, int N>
double sin_cos_power_integral(double S, double C) {
  static_assert(M >= 0 && N >= 0, "powers are non-negative integers");
  if (S <= C) return sin_cos_power_detail::series<M, N>(S);
  return sin_cos_power_detail::full_integral<M, N>() - sin_cos_power_detail::series<N, M>(C);
}

}  // namespace furnace::analytic
