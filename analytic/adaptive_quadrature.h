// Adaptive Gauss–Kronrod quadrature that terminates on tiny intervals.
//
// Boost 1.74's own recursive mode of gauss_kronrod::integrate compares the
// error estimate of a piece rescaled to [−1, 1] with a tolerance on the
// unscaled integral, so on a short interval (a sphere light subtending 1e-12 sr
// is a cone of half-angle 1e-6) it can never meet the tolerance and bisects
// everything to full depth, nested integrals multiplying the cost (minutes per
// pixel). Here Boost's 31-point rule is applied once per piece (its own error
// estimate, rescaled by the half-width) and pieces are bisected until their
// error meets an absolute tolerance shared out by halving.
#pragma once

#include <cmath>

#include <boost/math/quadrature/gauss_kronrod.hpp>

namespace furnace::analytic {

// ∫_a^b f to an absolute tolerance, at most `depth` bisection levels.
template <class F>
double adaptive_gauss_kronrod(const F& f, double a, double b, double abs_tolerance, int depth) {
  double error = 0;
  const double value = boost::math::quadrature::gauss_kronrod<double, 31>::integrate(f, a, b, 0, 0.0, &error);
  if (error * (b - a) / 2 <= abs_tolerance || depth == 0) return value;
  const double mid = (a + b) / 2;
  return adaptive_gauss_kronrod(f, a, mid, abs_tolerance / 2, depth - 1) +
         adaptive_gauss_kronrod(f, mid, b, abs_tolerance / 2, depth - 1);
}

// The same to a tolerance relative to a first one-rule estimate of |∫f|.
template <class F>
double adaptive_gauss_kronrod_relative(const F& f, double a, double b, double rel_tolerance, int depth) {
  double error = 0;
  const double first = boost::math::quadrature::gauss_kronrod<double, 31>::integrate(f, a, b, 0, 0.0, &error);
  return adaptive_gauss_kronrod(f, a, b, rel_tolerance * std::fabs(first), depth);
}

}  // namespace furnace::analytic
