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

// ∫_patch w(max(cos θ, 0), |cos θ'|, r) dA seen from p with unit normal n;
// the default weight cos θ·|cos θ'|/r² gives the projected solid angle.
template <class Weight>
double patch_integral(const Patch& patch, const Vec3& p, const Vec3& n, Weight weight) {
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
      return weight(std::fmax(dot(n, x), 0.0) / r, std::fabs(dot(patch.normal, x)) / r, r);
    };
    return (patch.jacobian0 + patch.jacobian1 * s) * gauss_kronrod<double, 61>::integrate(f, lo, hi, 7, 1e-13);
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

inline double patch_projected_solid_angle(const Patch& patch, const Vec3& p, const Vec3& n) {
  return patch_integral(patch, p, n, [](double c, double c_light, double r) { return c * c_light / (r * r); });
}

// ∫_{cone} max(cos θ, 0)^power dω over the directions to a sphere of radius R
// centred at `center` (relative to p): cone coordinates (γ, ψ) about the
// centre direction, dω = sin γ dγ dψ, cos θ = cos γ cos β + sin γ sin β cos ψ.
inline double sphere_projected_solid_angle(const Vec3& center, double R, const Vec3& n, int power = 1) {
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
    auto f = [&](double psi) { return std::pow(std::fmax(a + b * std::cos(psi), 0.0), power); };
    return 2 * std::sin(gamma) * gauss_kronrod<double, 61>::integrate(f, 0.0, psi_max, 7, 1e-13);
  };
  // Kink in γ where the horizon starts to cut the ring (cos γ cos β = ± sin γ sin β).
  std::vector<double> cuts{0, alpha};
  const double gamma_h = std::fabs(std::atan2(cos_b, sin_b));
  if (gamma_h > 0 && gamma_h < alpha) cuts.insert(cuts.begin() + 1, gamma_h);
  // Outer: tanh–sinh, since ψ_max = acos(·) has a √ singularity at the cuts.
  boost::math::quadrature::tanh_sinh<double> outer;
  double sum = 0;
  for (size_t i = 0; i + 1 < cuts.size(); ++i) sum += outer.integrate(inner, cuts[i], cuts[i + 1], 1e-12);
  return sum;
}

// ∫ over the sphere's surface points facing p of (max(cos θ, 0)·cos θ'/r²)² dA,
// in spherical coordinates (ϑ, φ) on the sphere about the direction from its
// centre to p (facing p: ϑ < acos(R/D)), dA = R² sin ϑ dϑ dφ; the horizon's
// kink in φ is avoided by integrating the positive part between the roots of
// n·(x − p) = 0, which is A + B cos φ + C sin φ on each ring.
template <class Weight>
double sphere_surface_integral(const Vec3& center, double R, const Vec3& n, Weight weight);

inline double sphere_area_kernel_quadrature(const Vec3& center, double R, const Vec3& n) {
  return sphere_surface_integral(center, R, n, [](double c, double c_light, double r) {
    const double g = c * c_light / (r * r);
    return g * g;
  });
}

// ∫ over the sphere's surface points facing p (and above p's horizon) of
// weight(max(cos θ, 0), cos θ', r) dA, by the parametrisation described above.
template <class Weight>
double sphere_surface_integral(const Vec3& center, double R, const Vec3& n, Weight weight) {
  using boost::math::quadrature::gauss_kronrod;
  const double D = length(center);
  const Vec3 axis = -center / D;  // from the centre towards p (p at the origin)
  const Frame frame = Frame::from_normal(axis);
  auto ring = [&](double vartheta) {
    const double sv = std::sin(vartheta), cv = std::cos(vartheta);
    auto point = [&](double phi) {
      return center + (frame.s * (sv * std::cos(phi)) + frame.t * (sv * std::sin(phi)) + axis * cv) * R;
    };
    auto f = [&](double phi) {
      const Vec3 x = point(phi);
      const Vec3 normal = (x - center) / R;
      const double r = std::sqrt(length_squared(x));
      const double c = std::fmax(dot(n, x), 0.0) / r, c_light = std::fmax(-dot(normal, x), 0.0) / r;
      return weight(c, c_light, r);
    };
    // n·x = A + B cos φ + C sin φ = A + M cos(φ − φ0).
    const double A = dot(n, center + axis * (R * cv));
    const double B = R * sv * dot(n, frame.s), C = R * sv * dot(n, frame.t);
    const double M = std::hypot(B, C), phi0 = std::atan2(C, B);
    double lo = -kPi, hi = kPi;
    if (M > std::fabs(A)) {
      const double half = std::acos(-A / M);
      lo = phi0 - half, hi = phi0 + half;
    } else if (A <= 0) {
      return 0.0;
    }
    return R * R * sv * gauss_kronrod<double, 61>::integrate(f, lo, hi, 7, 1e-12);
  };
  // Split ϑ where the horizon starts or stops cutting the rings: A = ±M,
  // i.e. cos(ϑ ± δ) = −(n·c)/R with δ = atan2(|n⊥|, n·axis).
  const double top = std::acos(R / D);
  const double n_axis = dot(n, axis), n_perp = length(n - axis * n_axis);
  const double delta = std::atan2(n_perp, n_axis);
  const double c0 = -dot(n, center) / R;
  std::vector<double> cuts{0.0, top};
  if (std::fabs(c0) <= 1) {
    const double base = std::acos(c0);
    for (double candidate : {base - delta, base + delta, -base - delta, -base + delta})
      if (candidate > 0 && candidate < top) cuts.push_back(candidate);
  }
  std::sort(cuts.begin(), cuts.end());
  boost::math::quadrature::tanh_sinh<double> outer;
  double sum = 0;
  for (size_t i = 0; i + 1 < cuts.size(); ++i)
    if (cuts[i + 1] > cuts[i]) sum += outer.integrate(ring, cuts[i], cuts[i + 1], 1e-11);
  return sum;
}

}  // namespace furnace::analytic::testing_support
