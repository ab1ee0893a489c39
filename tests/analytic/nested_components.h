// One pass of the two-pass nested adaptive Gauss–Kronrod the glass tests'
// independent integrals use (glass_light_test.cpp, glass_mis_test.cpp), over
// arrays of components. The coarse pass (no whole yet) takes each piece to
// `relative` of itself in 8 levels, only to estimate each component's whole;
// the fine pass takes absolute tolerances relative × |whole| per component,
// divided by `outer_divisor` for an outer piece and by `inner_divisor` for an
// inner one (each test shares its tolerance out over its pieces), in 14
// levels: a relative tolerance per piece would chase round-off in pieces
// that hold nothing of a component.
#pragma once

#include <cmath>
#include <cstddef>

#include "core/adaptive_quadrature.h"

namespace furnace::analytic {

template <class V>
class NestedPass {
 public:
  NestedPass(double relative, const V* whole, double outer_divisor, double inner_divisor)
      : relative_(relative), fine_(whole != nullptr) {
    if (!fine_) return;
    for (size_t k = 0; k < outer_.size(); ++k) {
      outer_[k] = relative * std::fabs((*whole)[k]) / outer_divisor;
      inner_[k] = relative * std::fabs((*whole)[k]) / inner_divisor;
    }
  }
  // ∫ f over [a, b] as an outer or an inner piece.
  template <class F>
  V outer(const F& f, double a, double b) const {
    return fine_ ? adaptive_gauss_kronrod_components(f, a, b, outer_, 14)
                 : adaptive_gauss_kronrod_relative_components(f, a, b, relative_, 8);
  }
  template <class F>
  V inner(const F& f, double a, double b) const {
    return fine_ ? adaptive_gauss_kronrod_components(f, a, b, inner_, 14)
                 : adaptive_gauss_kronrod_relative_components(f, a, b, relative_, 8);
  }

 private:
  double relative_;
  bool fine_;
  V outer_{}, inner_{};
};

// sum += scale · piece, per component.
template <class V>
void add_scaled(V& sum, const V& piece, double scale = 1) {
  for (size_t k = 0; k < sum.size(); ++k) sum[k] += scale * piece[k];
}

}  // namespace furnace::analytic
