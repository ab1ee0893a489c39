// Adaptive Gauss–Kronrod quadrature that terminates on tiny intervals.
//
// Boost 1.74's own recursive mode of gauss_kronrod::integrate compares the
// error estimate of a piece rescaled to [−1, 1] with a tolerance on the
// unscaled integral, so on a short interval (a sphere light subtending 1e-12 sr
// is a cone of half-angle 1e-6) it can never meet the tolerance and bisects
// everything to full depth, nested integrals multiplying the cost (minutes per
// pixel). Here Boost's rule is applied once per piece (its own error estimate,
// rescaled by the half-width) and pieces are bisected until their error meets
// an absolute tolerance shared out by halving, or `depth` levels are used up.
//
// The depth bounds the cost of a jump: the piece holding it fails at every
// level (its error and its share of the tolerance both halve), so each jump
// costs 2·depth rule applications and its error ends at about
// jump·width·2^−depth. It does not bound the cost where every piece fails:
// a tolerance below round-off (keep it above ~100 ε·|∫f|), a relative
// tolerance whose first estimate missed the integrand's mass, or an
// integrand that is noise at the scale of the pieces (a support test
// flickering along a rim). There the recursion costs 2^depth unless the
// bisections are capped.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <tuple>
#include <type_traits>

#include <boost/math/quadrature/gauss.hpp>
#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <boost/math/quadrature/tanh_sinh.hpp>

namespace furnace {

// Points of the Kronrod rule unless a caller asks for another: 31 points
// integrate polynomials of degree 46 exactly, so smooth pieces stop at once.
inline constexpr unsigned kDefaultKronrodPoints = 31;

// ∫_a^b f to an absolute tolerance, at most `depth` bisection levels.
// `bisections_left`, when given, caps the bisections of the whole integral:
// each one decrements it, and at 0 every remaining piece keeps its one-rule
// value. A cap bounds the cost where the integrand is round-off noise at
// the scale of the pieces (a support test flickering along a rim), which no
// depth cap does: there every piece fails and the cost is 2^depth.
// `error_sum`, when given, receives the sum of the accepted pieces' error
// estimates (the error the integral reached, whether or not it met the
// tolerance).
template <unsigned Points = kDefaultKronrodPoints, class F>
double adaptive_gauss_kronrod(const F& f, double a, double b, double abs_tolerance, int depth,
                              size_t* bisections_left = nullptr, double* error_sum = nullptr) {
  double error = 0;
  const double value = boost::math::quadrature::gauss_kronrod<double, Points>::integrate(f, a, b, 0, 0.0, &error);
  const bool stop = error * (b - a) / 2 <= abs_tolerance || depth == 0 ||
                    (bisections_left != nullptr && *bisections_left == 0);
  if (stop) {
    if (error_sum != nullptr) *error_sum += error * (b - a) / 2;
    return value;
  }
  if (bisections_left != nullptr) --*bisections_left;
  const double mid = (a + b) / 2;
  return adaptive_gauss_kronrod<Points>(f, a, mid, abs_tolerance / 2, depth - 1, bisections_left, error_sum) +
         adaptive_gauss_kronrod<Points>(f, mid, b, abs_tolerance / 2, depth - 1, bisections_left, error_sum);
}

// No cap on the bisections of an integral (the depth alone bounds them).
inline constexpr size_t kUnlimitedBisections = SIZE_MAX;

// The same to a tolerance relative to a first estimate of |∫f|: one rule
// application on each of `initial_pieces` equal pieces of [a, b], which then
// share the absolute tolerance equally. More than one piece puts the first
// nodes closer together, so that a narrow feature is less likely to fall
// between all of them (no error estimate sees what no node samples).
// `max_bisections` caps the bisections of the whole integral (see above);
// `error_sum` receives the error estimate reached (see above).
template <unsigned Points = kDefaultKronrodPoints, class F>
double adaptive_gauss_kronrod_relative(const F& f, double a, double b, double rel_tolerance, int depth,
                                       int initial_pieces = 1, size_t max_bisections = kUnlimitedBisections,
                                       double* error_sum = nullptr) {
  const auto edge = [&](int i) { return i == initial_pieces ? b : a + (b - a) * i / initial_pieces; };
  double first = 0;
  for (int i = 0; i < initial_pieces; ++i) {
    double error = 0;
    first += boost::math::quadrature::gauss_kronrod<double, Points>::integrate(f, edge(i), edge(i + 1), 0, 0.0, &error);
  }
  const double abs_tolerance = rel_tolerance * std::fabs(first) / initial_pieces;
  size_t bisections_left = max_bisections;
  size_t* cap = max_bisections == kUnlimitedBisections ? nullptr : &bisections_left;
  double sum = 0;
  for (int i = 0; i < initial_pieces; ++i)
    sum += adaptive_gauss_kronrod<Points>(f, edge(i), edge(i + 1), abs_tolerance, depth, cap, error_sum);
  return sum;
}

// The same for an integrand of N components (f returns std::array<double, N>),
// integrated together: one set of nodes serves every component (an integrand
// whose components share their costly part, such as the geometry of a
// direction, pays for it once), and a piece is bisected until every component
// meets its own share of the tolerance, so each gets at least the pieces it
// would have asked for alone unless the bisection cap runs out first. Each
// component's rule is Boost's gauss_kronrod<double, Points> on it alone, to
// the bit, error estimate included (tests/core/adaptive_quadrature_test.cpp).
template <unsigned Points, class F, class V = std::invoke_result_t<const F&, double>>
V gauss_kronrod_rule(const F& f, double a, double b, V* error) {
  using Kronrod = boost::math::quadrature::gauss_kronrod<double, Points>;
  using Gauss = boost::math::quadrature::gauss<double, (Points - 1) / 2>;
  static_assert(((Points - 1) / 2) % 2 == 1, "the Gauss rule's order is odd, so 0 is one of its nodes");
  constexpr size_t N = std::tuple_size_v<V>;
  if (a == b) {  // as Boost: nothing, no error
    error->fill(0.0);
    return V{};
  }
  if (b < a) {
    V value = gauss_kronrod_rule<Points>(f, b, a, error);
    for (double& v : value) v = -v;
    return value;
  }
  const auto& x = Kronrod::abscissa();
  const auto& wk = Kronrod::weights();
  const auto& wg = Gauss::weights();
  // As Boost's integrate(f, a, b, 0): f(scale·x + mean) on [−1, 1], scaled.
  const double mean = (b + a) / 2, scale = (b - a) / 2;
  V kronrod{}, gauss{};
  const V f0 = f(scale * 0.0 + mean);
  for (size_t c = 0; c < N; ++c) kronrod[c] = f0[c] * wk[0], gauss[c] += f0[c] * wg[0];
  for (size_t i = 2; i < x.size(); i += 2) {
    const V fp = f(scale * x[i] + mean), fm = f(scale * -x[i] + mean);
    for (size_t c = 0; c < N; ++c) kronrod[c] += (fp[c] + fm[c]) * wk[i], gauss[c] += (fp[c] + fm[c]) * wg[i / 2];
  }
  for (size_t i = 1; i < x.size(); i += 2) {
    const V fp = f(scale * x[i] + mean), fm = f(scale * -x[i] + mean);
    for (size_t c = 0; c < N; ++c) kronrod[c] += (fp[c] + fm[c]) * wk[i];
  }
  V value;
  for (size_t c = 0; c < N; ++c) {
    (*error)[c] = std::max(std::fabs(kronrod[c] - gauss[c]),
                           std::fabs(kronrod[c] * std::numeric_limits<double>::epsilon() * 2));
    value[c] = scale * kronrod[c];
  }
  return value;
}

template <unsigned Points = kDefaultKronrodPoints, class F, class V = std::invoke_result_t<const F&, double>>
V adaptive_gauss_kronrod_components(const F& f, double a, double b, const V& abs_tolerance, int depth,
                                    size_t* bisections_left = nullptr, V* error_sum = nullptr) {
  constexpr size_t N = std::tuple_size_v<V>;
  V error;
  const V value = gauss_kronrod_rule<Points>(f, a, b, &error);
  bool met = true;
  for (size_t c = 0; c < N; ++c) met = met && error[c] * (b - a) / 2 <= abs_tolerance[c];
  if (met || depth == 0 || (bisections_left != nullptr && *bisections_left == 0)) {
    if (error_sum != nullptr)
      for (size_t c = 0; c < N; ++c) (*error_sum)[c] += error[c] * (b - a) / 2;
    return value;
  }
  if (bisections_left != nullptr) --*bisections_left;
  const double mid = (a + b) / 2;
  V half = abs_tolerance;
  for (double& t : half) t /= 2;
  const V left = adaptive_gauss_kronrod_components<Points>(f, a, mid, half, depth - 1, bisections_left, error_sum);
  const V right = adaptive_gauss_kronrod_components<Points>(f, mid, b, half, depth - 1, bisections_left, error_sum);
  V sum;
  for (size_t c = 0; c < N; ++c) sum[c] = left[c] + right[c];
  return sum;
}

// adaptive_gauss_kronrod_relative for N components: each component's
// tolerance is relative to its own first estimate.
template <unsigned Points = kDefaultKronrodPoints, class F, class V = std::invoke_result_t<const F&, double>>
V adaptive_gauss_kronrod_relative_components(const F& f, double a, double b, double rel_tolerance, int depth,
                                             int initial_pieces = 1, size_t max_bisections = kUnlimitedBisections,
                                             V* error_sum = nullptr) {
  constexpr size_t N = std::tuple_size_v<V>;
  const auto edge = [&](int i) { return i == initial_pieces ? b : a + (b - a) * i / initial_pieces; };
  V first{};
  for (int i = 0; i < initial_pieces; ++i) {
    V error;
    const V piece = gauss_kronrod_rule<Points>(f, edge(i), edge(i + 1), &error);
    for (size_t c = 0; c < N; ++c) first[c] += piece[c];
  }
  V abs_tolerance;
  for (size_t c = 0; c < N; ++c) abs_tolerance[c] = rel_tolerance * std::fabs(first[c]) / initial_pieces;
  size_t bisections_left = max_bisections;
  size_t* cap = max_bisections == kUnlimitedBisections ? nullptr : &bisections_left;
  V sum{};
  for (int i = 0; i < initial_pieces; ++i) {
    const V piece =
        adaptive_gauss_kronrod_components<Points>(f, edge(i), edge(i + 1), abs_tolerance, depth, cap, error_sum);
    for (size_t c = 0; c < N; ++c) sum[c] += piece[c];
  }
  return sum;
}

// ∫_a^b f by Boost's tanh–sinh rule (which absorbs end-point singularities),
// with two corrections to Boost 1.74 on intervals that are short against
// their distance from 0 (a piece between a cut and an end point):
// - Boost stops short of each end by the spacing of doubles near a/((b − a)/2)
//   and b/((b − a)/2), dropping a fraction ~ (ulp(a) + ulp(b))/(b − a) of the
//   integral (measured: 1.2e-10 of ∫ sin over [0.38, 0.38 + 1e-6]). The
//   integrand is taken over [0, b − a] instead, shifted by a, where the ends
//   lose nothing.
// - Boost scales the integral and L1 by the half-width but returns the error
//   of the integral mapped to [−1, 1] (measured: 1.04e-5 stated for an
//   integral of 4e-17 over one ulp); here the error is in the integral's units.
template <class F>
double tanh_sinh_integral(boost::math::quadrature::tanh_sinh<double>& integrator, const F& f, double a, double b,
                          double tolerance, double* error = nullptr) {
  const double width = b - a;
  double e = 0;
  const double value = integrator.integrate([&](double t) { return f(a + t); }, 0.0, width, tolerance, &e);
  if (error != nullptr) *error = e * width / 2;
  return value;
}

}  // namespace furnace
