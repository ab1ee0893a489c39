// Test-only independent evaluation of ∫ h²/(h²+s²)² dA over "light disk minus
// occluder disks", by nested quadrature in polar coordinates (φ, s) about the
// foot point. The visible s-intervals along each direction come from
// ray–circle intersections and a midpoint membership test (not from the arc
// Boolean under test); the outer φ integral is split at every direction where
// the interval structure changes (tangents and circle–circle crossings).
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <boost/math/quadrature/tanh_sinh.hpp>

#include "analytic/disk.h"
#include "core/vec3.h"

namespace furnace::analytic::testing_support {

// Integrates g(s) over the visible part of the ray from the origin in
// direction (cos φ, sin φ); g is the radial integrand (including the s of dA).
template <class RadialIntegrand>
double ray_integral(double phi, const Circle2& light, const std::vector<Circle2>& occluders, RadialIntegrand g) {
  using boost::math::quadrature::gauss_kronrod;
  const double ex = std::cos(phi), ey = std::sin(phi);
  std::vector<double> cuts{0.0};
  auto add_roots = [&](const Circle2& c) {
    const double b = ex * c.cx + ey * c.cy;  // s² − 2bs + |c|² − r² = 0
    const double disc = b * b - (c.cx * c.cx + c.cy * c.cy - c.radius * c.radius);
    if (disc < 0) return;
    const double root = std::sqrt(disc);
    for (double s : {b - root, b + root})
      if (s > 0) cuts.push_back(s);
  };
  add_roots(light);
  for (const Circle2& o : occluders) add_roots(o);
  std::sort(cuts.begin(), cuts.end());
  auto inside = [](double x, double y, const Circle2& c) { return std::hypot(x - c.cx, y - c.cy) < c.radius; };
  double sum = 0;
  for (size_t i = 0; i + 1 < cuts.size(); ++i) {
    const double a = cuts[i], b = cuts[i + 1];
    if (!(b > a)) continue;
    const double m = 0.5 * (a + b);
    bool visible = inside(m * ex, m * ey, light);
    for (const Circle2& o : occluders) visible = visible && !inside(m * ex, m * ey, o);
    if (visible) sum += gauss_kronrod<double, 31>::integrate(g, a, b, 8, 1e-12);
  }
  return sum;
}

// Directions where the set of visible s-intervals changes: tangents from the
// origin to each circle, and directions of circle–circle crossing points.
inline std::vector<double> breakpoints(const Circle2& light, const std::vector<Circle2>& occluders) {
  std::vector<Circle2> all{light};
  all.insert(all.end(), occluders.begin(), occluders.end());
  std::vector<double> phis{-kPi, kPi};
  for (size_t i = 0; i < all.size(); ++i) {
    const Circle2& c = all[i];
    const double D = std::hypot(c.cx, c.cy);
    if (D > c.radius) {
      const double half = std::asin(c.radius / D);
      phis.push_back(std::atan2(c.cy, c.cx) + half);
      phis.push_back(std::atan2(c.cy, c.cx) - half);
    }
    for (size_t j = i + 1; j < all.size(); ++j) {
      const Circle2& e = all[j];
      const double d = std::hypot(e.cx - c.cx, e.cy - c.cy);
      if (!(d > std::fabs(c.radius - e.radius) && d < c.radius + e.radius)) continue;
      const double a = (d * d + c.radius * c.radius - e.radius * e.radius) / (2 * d);
      const double hc = std::sqrt(std::max(0.0, c.radius * c.radius - a * a));
      const double ux = (e.cx - c.cx) / d, uy = (e.cy - c.cy) / d;
      for (double sign : {-1.0, 1.0}) {
        const double x = c.cx + a * ux - sign * hc * uy, y = c.cy + a * uy + sign * hc * ux;
        phis.push_back(std::atan2(y, x));
      }
    }
  }
  for (double& p : phis) p = std::remainder(p, 2 * kPi);
  phis.push_back(-kPi);
  phis.push_back(kPi);
  std::sort(phis.begin(), phis.end());
  return phis;
}

// ∫ over the visible region of f(s)·s ds dφ with f the area integrand.
template <class AreaIntegrand>
double region_quadrature(const Circle2& light, const std::vector<Circle2>& occluders, AreaIntegrand f) {
  // tanh–sinh for the outer integral: at a tangent direction the visible
  // interval's end moves like √(φ − φ_t), an endpoint singularity that
  // tanh–sinh absorbs and Gauss–Kronrod does not.
  boost::math::quadrature::tanh_sinh<double> integrator;
  auto outer = [&](double phi) { return ray_integral(phi, light, occluders, [&](double s) { return f(s) * s; }); };
  const std::vector<double> phis = breakpoints(light, occluders);
  double sum = 0;
  for (size_t i = 0; i + 1 < phis.size(); ++i)
    if (phis[i + 1] > phis[i]) sum += integrator.integrate(outer, phis[i], phis[i + 1], 1e-13);
  return sum;
}

// The parallel-plane irradiance kernel: ∫ h²/(h²+s²)² dA = E/L.
inline double visible_irradiance_quadrature(double h, const Circle2& light, const std::vector<Circle2>& occluders) {
  return region_quadrature(light, occluders, [h](double s) { return h * h / ((h * h + s * s) * (h * h + s * s)); });
}

}  // namespace furnace::analytic::testing_support
