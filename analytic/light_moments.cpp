#include "analytic/light_moments.h"

#include <algorithm>
#include <cmath>

#include <boost/math/quadrature/tanh_sinh.hpp>

#include "analytic/polygon.h"
#include "analytic/polygon_patch.h"
#include "core/error.h"

namespace furnace::analytic {

namespace {

// ∫ max(a + b cos ψ, 0)² dψ over ψ ∈ (−π, π].
double ring_cos2(double a, double b) {
  if (b <= std::fabs(a)) return a > 0 ? 2 * kPi * (a * a + 0.5 * b * b) : 0.0;
  const double psi = std::acos(std::clamp(-a / b, -1.0, 1.0));
  return 2 * ((a * a + 0.5 * b * b) * psi + 2 * a * b * std::sin(psi) + 0.25 * b * b * std::sin(2 * psi));
}

// ∫_0^α sin γ·weight(γ)·ring_cos2(cos γ cos β, sin γ sin β) dγ.
template <class Weight>
double cone_integral(const Vec3& center, double R, const Vec3& n, Weight weight) {
  const double D = length(center);
  FURNACE_CHECK(D > R && R > 0);
  const double alpha = std::asin(R / D);
  const double cos_b = dot(n, center) / D, sin_b = length(cross(n, center)) / D;
  if (cos_b <= -std::sin(alpha)) return 0.0;  // wholly below the horizon
  auto f = [&](double gamma) {
    return std::sin(gamma) * weight(gamma) * ring_cos2(std::cos(gamma) * cos_b, std::sin(gamma) * sin_b);
  };
  boost::math::quadrature::tanh_sinh<double> integrator;
  const double gamma_h = std::fabs(kPi / 2 - std::atan2(sin_b, cos_b));
  if (gamma_h > 0 && gamma_h < alpha)
    return integrator.integrate(f, 0.0, gamma_h, 1e-13) + integrator.integrate(f, gamma_h, alpha, 1e-13);
  return integrator.integrate(f, 0.0, alpha, 1e-13);
}

}  // namespace

double sphere_cos2_solid_angle(const Vec3& center, double R, const Vec3& n) {
  return cone_integral(center, R, n, [](double) { return 1.0; });
}

double sphere_area_kernel(const Vec3& center, double R, const Vec3& n) {
  const double D = length(center);
  return cone_integral(center, R, n, [&](double gamma) {
    const double q = std::sqrt(std::fmax(0.0, (R - D * std::sin(gamma)) * (R + D * std::sin(gamma))));
    const double r = (D - R) * (D + R) / (D * std::cos(gamma) + q);
    return (q / R) / (r * r);
  });
}

double polygon_cos2_solid_angle(const std::vector<Vec3>& vertices, const Vec3& n) {
  const std::vector<Vec3> clipped = clip_to_hemisphere(vertices, n);
  const size_t count = clipped.size();
  if (count < 3) return 0.0;
  std::vector<Vec3> u;
  for (const Vec3& v : clipped) u.push_back(normalize(v));
  // Solid angle: signed fan of Van Oosterom–Strackee triangles.
  double sigma = 0;
  for (size_t k = 1; k + 1 < count; ++k) {
    const Vec3 &a = u[0], &b = u[k], &c = u[k + 1];
    sigma += 2 * std::atan2(dot(a, cross(b, c)), 1 + dot(a, b) + dot(b, c) + dot(c, a));
  }
  double first = 0, edges = 0;
  for (size_t i = 0; i < count; ++i) {
    const Vec3& a = u[i];
    const Vec3& next = u[(i + 1) % count];
    const Vec3 c = cross(a, next);
    const double c_len = length(c);
    if (!(c_len > 0)) continue;
    const double theta = std::atan2(c_len, dot(a, next));
    const Vec3 ni = c / c_len;
    const Vec3 b = cross(ni, a);  // unit, ⟂ a, in the edge's plane, towards `next`
    const double half_sin = std::sin(0.5 * theta);
    first += theta * dot(ni, n);
    edges += dot(ni, n) * (dot(n, a) * std::sin(theta) + dot(n, b) * 2 * half_sin * half_sin);
  }
  const double s = first >= 0 ? 1.0 : -1.0;
  return (std::fabs(sigma) + s * edges) / 3;
}

double polygon_area_kernel(const std::vector<Vec3>& vertices, const Vec3& n) {
  return polygon_patch_integral(vertices, n, 1e-12, 20, [&](const Vec3& x, const Vec3& m) {
    const double r2 = length_squared(x);
    const double geometric = std::fmax(dot(n, x), 0.0) * std::fabs(dot(m, x)) / (r2 * r2);  // cos θ cos θ'/r²
    return geometric * geometric;
  });
}

double sphere_solid_angle(double D, double R) {
  FURNACE_CHECK(D > R && R > 0);
  const double s2 = (R / D) * (R / D);  // sin²α
  return 2 * kPi * s2 / (1 + std::sqrt((1 - R / D) * (1 + R / D)));
}

double polygon_solid_angle(const std::vector<Vec3>& vertices) {
  FURNACE_CHECK(vertices.size() >= 3);
  const Vec3 a = normalize(vertices[0]);
  double sigma = 0;
  for (size_t k = 1; k + 1 < vertices.size(); ++k) {
    const Vec3 b = normalize(vertices[k]), c = normalize(vertices[k + 1]);
    sigma += 2 * std::atan2(dot(a, cross(b, c)), 1 + dot(a, b) + dot(b, c) + dot(c, a));
  }
  return std::fabs(sigma);
}

}  // namespace furnace::analytic
