// Test-only independent quadratures of projected solid angles
// Ω⊥ = ∫ max(cos θ, 0) dω for planar patches and spheres, written from the
// definitions with Boost Gauss–Kronrod, splitting at the horizon kinks.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <boost/math/quadrature/tanh_sinh.hpp>

#include "core/vec3.h"

namespace furnace::analytic::testing_support {

// A planar patch x(s, t) = a0 + s·a1 + t·(b0 + s·b1), s, t ∈ [0, 1], with
// area element |∂x/∂s × ∂x/∂t| = jacobian0 + s·jacobian1 (true for
// parallelograms, b1 = 0, and for triangles in the collapsed map).
struct Patch {
  Vec3 a0, a1, b0, b1;
  double jacobian0, jacobian1;
  Vec3 normal;  // unit normal of the patch's plane (either side)
};

inline Patch rectangle_patch(const Vec3& corner, const Vec3& u, const Vec3& v) {
  return {corner, u, v, {0, 0, 0}, length(cross(u, v)), 0, normalize(cross(u, v))};
}
// x = p0 + s·e1 + t·s·(e2 − e1): the triangle p0, p1, p2 with Jacobian s·|e1 × e2|.
inline Patch triangle_patch(const Vec3& p0, const Vec3& p1, const Vec3& p2) {
  const Vec3 e1 = p1 - p0, e2 = p2 - p0;
  return {p0, e1, {0, 0, 0}, e2 - e1, 0, length(cross(e1, e2)), normalize(cross(e1, e2))};
}

// ∫_patch max(cos θ, 0)·|cos θ'|/r² dA seen from p with unit normal n.
inline double patch_projected_solid_angle(const Patch& patch, const Vec3& p, const Vec3& n) {
  using boost::math::quadrature::gauss_kronrod;
  auto point = [&](double s, double t) { return patch.a0 + patch.a1 * s + (patch.b0 + patch.b1 * s) * t - p; };
  auto inner = [&](double s) {
    // n·x is linear in t: integrate only where it is ≥ 0.
    const double f0 = dot(n, point(s, 0)), f1 = dot(n, point(s, 1));
    double lo = 0, hi = 1;
    if (f0 < 0 && f1 < 0) return 0.0;
    if (f0 < 0) lo = f0 / (f0 - f1);
    if (f1 < 0) hi = f0 / (f0 - f1);
    auto f = [&](double t) {
      const Vec3 x = point(s, t);
      const double r2 = length_squared(x);
      const double r = std::sqrt(r2);
      return std::fmax(dot(n, x), 0.0) / r * std::fabs(dot(patch.normal, x)) / r / r2;
    };
    return (patch.jacobian0 + patch.jacobian1 * s) * gauss_kronrod<double, 61>::integrate(f, lo, hi, 15, 1e-13);
  };
  // Kinks in s where the horizon crosses the t = 0 or t = 1 edge.
  std::vector<double> cuts{0, 1};
  for (double t : {0.0, 1.0}) {
    const double g0 = dot(n, point(0, t)), g1 = dot(n, point(1, t));
    if ((g0 < 0) != (g1 < 0)) cuts.push_back(g0 / (g0 - g1));
  }
  std::sort(cuts.begin(), cuts.end());
  // Outer: tanh–sinh, since the horizon's end point moves like √ near the cuts.
  boost::math::quadrature::tanh_sinh<double> outer;
  double sum = 0;
  for (size_t i = 0; i + 1 < cuts.size(); ++i)
    if (cuts[i + 1] > cuts[i]) sum += outer.integrate(inner, cuts[i], cuts[i + 1], 1e-13);
  return sum;
}

// ∫_{cone} max(cos θ, 0) dω over the directions to a sphere of radius R
// centred at `center` (relative to p): cone coordinates (γ, ψ) about the
// centre direction, dω = sin γ dγ dψ, cos θ = cos γ cos β + sin γ sin β cos ψ.
inline double sphere_projected_solid_angle(const Vec3& center, double R, const Vec3& n) {
  using boost::math::quadrature::gauss_kronrod;
  const double D = length(center);
  const double alpha = std::asin(R / D);
  const double cos_b = dot(n, center) / D;
  const double sin_b = length(cross(n, center)) / D;
  auto inner = [&](double gamma) {
    const double a = std::cos(gamma) * cos_b, b = std::sin(gamma) * sin_b;
    // cos θ ≥ 0 for cos ψ ≥ −a/b: ψ ∈ [0, ψ_max], doubled by symmetry.
    double psi_max = kPi;
    if (b > 0) {
      const double c = -a / b;
      if (c >= 1) return 0.0;
      if (c > -1) psi_max = std::acos(c);
    } else if (a < 0) {
      return 0.0;
    }
    auto f = [&](double psi) { return std::fmax(a + b * std::cos(psi), 0.0); };
    return 2 * std::sin(gamma) * gauss_kronrod<double, 61>::integrate(f, 0.0, psi_max, 15, 1e-13);
  };
  // Kink in γ where the horizon starts to cut the ring (cos γ cos β = ± sin γ sin β).
  std::vector<double> cuts{0, alpha};
  const double gamma_h = std::fabs(std::atan2(cos_b, sin_b));
  if (gamma_h > 0 && gamma_h < alpha) cuts.insert(cuts.begin() + 1, gamma_h);
  // Outer: tanh–sinh, since ψ_max = acos(·) has a √ singularity at the cuts.
  boost::math::quadrature::tanh_sinh<double> outer;
  double sum = 0;
  for (size_t i = 0; i + 1 < cuts.size(); ++i) sum += outer.integrate(inner, cuts[i], cuts[i + 1], 1e-13);
  return sum;
}

}  // namespace furnace::analytic::testing_support
