// Integrals over the part of a planar polygon above a receiver's horizon, by
// nested adaptive quadrature over the polygon's own parameters. Shared by the
// light-area second moment (light_moments.cpp) and the MIS moments
// (moments.cpp), which differ only in the integrand.
#pragma once

#include <algorithm>
#include <vector>

#include "core/adaptive_quadrature.h"
#include "core/error.h"
#include "core/vec3.h"

namespace furnace::analytic {

// ∫ f(x, m) dA over the polygon (a parallelogram v0 v1 v2 v3 or a triangle
// v0 v1 v2, vertices relative to the receiving point p) restricted to n·x > 0,
// m the polygon's unit normal (winding as given). Parametrisation
// x(s, t) = a0 + s·a1 + t·(b0 + s·b1), |∂x/∂s × ∂x/∂t| = j0 + s·j1; for fixed s,
// n·x is linear in t, so the lit t-interval is exact, and s is split where the
// horizon crosses the edges t = 0 and t = 1. Both levels: Gauss–Kronrod to
// `rel_tolerance` (core/adaptive_quadrature.h), at most `depth` bisections.
template <class F>
double polygon_patch_integral(const std::vector<Vec3>& v, const Vec3& n, double rel_tolerance, int depth, F f) {
  FURNACE_CHECK(v.size() == 3 || v.size() == 4);
  const Vec3 a0 = v[0], a1 = v[1] - v[0];
  Vec3 b0{0, 0, 0}, b1{0, 0, 0};
  double j0 = 0, j1 = 0;
  if (v.size() == 4) {
    b0 = v[3] - v[0];
    j0 = length(cross(a1, b0));
  } else {
    b1 = v[2] - v[1];
    j1 = length(cross(a1, v[2] - v[0]));
  }
  const Vec3 m = normalize(cross(v[1] - v[0], v[2] - v[0]));
  auto point = [&](double s, double t) { return a0 + a1 * s + (b0 + b1 * s) * t; };
  auto inner = [&](double s) {
    const double f0 = dot(n, point(s, 0)), f1 = dot(n, point(s, 1));
    if (f0 <= 0 && f1 <= 0) return 0.0;
    const double lo = f0 < 0 ? f0 / (f0 - f1) : 0.0, hi = f1 < 0 ? f0 / (f0 - f1) : 1.0;
    auto g = [&](double t) { return f(point(s, t), m); };
    return (j0 + j1 * s) * adaptive_gauss_kronrod_relative(g, lo, hi, rel_tolerance, depth);
  };
  std::vector<double> cuts{0, 1};
  for (double t : {0.0, 1.0}) {
    const double g0 = dot(n, point(0, t)), g1 = dot(n, point(1, t));
    if ((g0 < 0) != (g1 < 0)) cuts.push_back(g0 / (g0 - g1));
  }
  std::sort(cuts.begin(), cuts.end());
  double sum = 0;
  for (size_t i = 0; i + 1 < cuts.size(); ++i)
    if (cuts[i + 1] > cuts[i]) sum += adaptive_gauss_kronrod_relative(inner, cuts[i], cuts[i + 1], rel_tolerance, depth);
  return sum;
}

}  // namespace furnace::analytic
