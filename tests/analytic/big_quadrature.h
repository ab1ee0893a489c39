// 50-digit Gauss–Kronrod quadrature of vector-valued integrands for the
// precision tests (ggx_precision_test.cpp, glass_precision_test.cpp): each
// writes its integrands from the definitions and integrates them here.
// Values is a std::array<Big, N>: every component shares the nodes.
#pragma once

#include <algorithm>
#include <cstddef>
#include <functional>
#include <vector>

#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <boost/multiprecision/cpp_bin_float.hpp>

namespace furnace::big_quadrature {

using Big = boost::multiprecision::cpp_bin_float_50;
template <class Values>
using Integrand = std::function<Values(const Big&)>;

// The 61-point Kronrod rule on [a, b]; *error per component is |Kronrod −
// Gauss(30)|, the rule's error estimate.
template <class Values>
Values rule(const Integrand<Values>& f, const Big& a, const Big& b, Values* error) {
  using Kronrod = boost::math::quadrature::gauss_kronrod<Big, 61>;
  using Gauss = boost::math::quadrature::gauss<Big, 30>;
  static const auto& x = Kronrod::abscissa();
  static const auto& wk = Kronrod::weights();
  static const auto& wg = Gauss::weights();
  const Big mean = (a + b) / 2, scale = (b - a) / 2;
  Values kronrod{}, gauss{};
  const Values f0 = f(mean);
  for (size_t c = 0; c < f0.size(); ++c) kronrod[c] = f0[c] * wk[0];  // 0 is no Gauss node (30 points)
  for (size_t i = 1; i < x.size(); ++i) {
    const Values fp = f(mean + scale * x[i]), fm = f(mean - scale * x[i]);
    for (size_t c = 0; c < f0.size(); ++c) {
      kronrod[c] += (fp[c] + fm[c]) * wk[i];
      if (i % 2 == 1) gauss[c] += (fp[c] + fm[c]) * wg[i / 2];
    }
  }
  Values value;
  for (size_t c = 0; c < value.size(); ++c) {
    (*error)[c] = abs(kronrod[c] - gauss[c]) * scale;
    value[c] = kronrod[c] * scale;
  }
  return value;
}

// [a, b] bisected until each component's error estimate meets its absolute
// tolerance (halved at each level) or `depth` levels are used up; `value`
// and `error` are the rule's on [a, b], already computed.
template <class Values>
Values adaptive(const Integrand<Values>& f, const Big& a, const Big& b, const Values& tolerance, int depth,
                const Values& value, const Values& error) {
  bool met = true;
  for (size_t c = 0; c < value.size(); ++c) met = met && error[c] <= tolerance[c];
  if (met || depth == 0) return value;
  Values half = tolerance;
  for (Big& t : half) t /= 2;
  const Big mid = (a + b) / 2;
  Values left_error, right_error;
  const Values left_value = rule(f, a, mid, &left_error), right_value = rule(f, mid, b, &right_error);
  Values sum = adaptive(f, a, mid, half, depth - 1, left_value, left_error);
  const Values right = adaptive(f, mid, b, half, depth - 1, right_value, right_error);
  for (size_t c = 0; c < sum.size(); ++c) sum[c] += right[c];
  return sum;
}

// ∫ f over [cuts.front(), cuts.back()] split at the cuts, each component to
// `relative_tolerance` of a first estimate (one rule per piece), or to the
// absolute `floor` where that is larger (none: nullptr), at most
// `depth` bisection levels per piece. Each piece [a, b] in t ∈ [0, 1] of
// x = a + (b − a)(3t² − 2t³), dx = 6(b − a)t(1 − t) dt: a square-root end
// point (an arc's end as a ring passes a kink, a sphere's rim in the area
// density, 1 − F at total internal reflection) becomes smooth.
template <class Values>
Values integrate(const Integrand<Values>& f, std::vector<Big> cuts, double relative_tolerance, int depth,
                 const Values* floor = nullptr) {
  std::sort(cuts.begin(), cuts.end());
  cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
  std::vector<Integrand<Values>> pieces;
  for (size_t i = 0; i + 1 < cuts.size(); ++i) {
    const Big a = cuts[i], w = cuts[i + 1] - cuts[i];
    pieces.push_back([&f, a, w](const Big& t) {
      Values v = f(a + w * t * t * (3 - 2 * t));
      const Big jacobian = 6 * w * t * (1 - t);
      for (Big& e : v) e *= jacobian;
      return v;
    });
  }
  Values first{};
  std::vector<Values> values(pieces.size()), errors(pieces.size());
  for (size_t i = 0; i < pieces.size(); ++i) {
    values[i] = rule(pieces[i], Big(0), Big(1), &errors[i]);
    for (size_t c = 0; c < first.size(); ++c) first[c] += values[i][c];
  }
  Values tolerance;
  const double count = double(std::max<size_t>(pieces.size(), 1));
  for (size_t c = 0; c < first.size(); ++c) {
    tolerance[c] = Big(relative_tolerance) * abs(first[c]);
    if (floor != nullptr && (*floor)[c] > tolerance[c]) tolerance[c] = (*floor)[c];
    tolerance[c] /= count;
  }
  Values sum{};
  for (size_t i = 0; i < pieces.size(); ++i) {
    const Values piece = adaptive(pieces[i], Big(0), Big(1), tolerance, depth, values[i], errors[i]);
    for (size_t c = 0; c < sum.size(); ++c) sum[c] += piece[c];
  }
  return sum;
}

}  // namespace furnace::big_quadrature
