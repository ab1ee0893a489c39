#include "analytic/small_emitter.h"

#include <cmath>

#include <boost/math/quadrature/gauss.hpp>

#include "analytic/polygon_normal.h"

namespace furnace::analytic {

namespace {

constexpr unsigned kGaussPoints = 16;
using Rule = boost::math::quadrature::gauss<double, kGaussPoints>;

// Gauss–Legendre nodes and weights mapped to [0, 1] (Boost stores the
// non-negative half of the symmetric rule on [−1, 1]).
struct UnitRule {
  double x[kGaussPoints], w[kGaussPoints];
  UnitRule() {
    const auto& a = Rule::abscissa();
    const auto& wt = Rule::weights();
    unsigned k = 0;
    for (size_t i = 0; i < a.size(); ++i) {
      const double signs[2] = {-1.0, 1.0};
      for (double sign : signs) {
        if (a[i] == 0 && sign > 0) continue;  // the centre node once (odd rules)
        x[k] = 0.5 * (1 + sign * a[i]);
        w[k] = 0.5 * wt[i];
        ++k;
      }
    }
  }
};

const UnitRule& unit_rule() {
  static const UnitRule rule;
  return rule;
}

// cos θ·cos θ'/r² at x (relative to p) on a plane of unit normal m.
double kernel(const Vec3& x, const Vec3& n, const Vec3& m) {
  const double r2 = length_squared(x);
  return std::fmax(dot(n, x), 0.0) * std::fabs(dot(m, x)) / (r2 * r2);
}

}  // namespace

double polygon_angular_size(const std::vector<Vec3>& vertices) {
  double diameter = 0, nearest = INFINITY;
  for (size_t i = 0; i < vertices.size(); ++i) {
    nearest = std::fmin(nearest, length(vertices[i]));
    for (size_t j = i + 1; j < vertices.size(); ++j) diameter = std::fmax(diameter, length(vertices[j] - vertices[i]));
  }
  const double distance = nearest - diameter;
  return distance > 0 ? diameter / distance : INFINITY;
}

namespace {

// The fan rule of small_polygon_irradiance for any kernel(x, n, m).
template <class Kernel>
double small_polygon_rule(const std::vector<Vec3>& v, const Vec3& n, Kernel kernel) {
  const UnitRule& g = unit_rule();
  const Vec3 m = polygon_normal(v);
  double sum = 0;
  for (size_t i = 1; i + 1 < v.size(); ++i) {
    const Vec3 e1 = v[i] - v[0], e2 = v[i + 1] - v[i];
    const double jacobian = length(cross(e1, e2));
    double triangle = 0;
    for (unsigned a = 0; a < kGaussPoints; ++a) {
      const double s = g.x[a];
      double row = 0;
      for (unsigned b = 0; b < kGaussPoints; ++b) row += g.w[b] * kernel(v[0] + (e1 + e2 * g.x[b]) * s, n, m);
      triangle += g.w[a] * s * row;
    }
    sum += jacobian * triangle;
  }
  return sum;
}

}  // namespace

double small_polygon_irradiance(const std::vector<Vec3>& v, const Vec3& n) {
  return small_polygon_rule(v, n, kernel);
}

double small_polygon_area_kernel(const std::vector<Vec3>& v, const Vec3& n) {
  return small_polygon_rule(v, n, [](const Vec3& x, const Vec3& n, const Vec3& m) {
    const double k = kernel(x, n, m);
    return k * k;
  });
}

namespace {

// ∫ kernel(max(n·x, 0), m·x, |x|²) dA over the lit segment of a disk (centre
// relative to p, unit normal m, radius R), by the segment map documented at
// small_disk_irradiance in small_emitter.h.
template <class Kernel>
double small_disk_rule(const Vec3& center, const Vec3& m, double R, const Vec3& n, Kernel kernel) {
  using Rule16 = boost::math::quadrature::gauss<double, 16>;
  // In-plane gradient of n·x: n·x = n·c + |g|·β along e2 = g/|g|.
  const Vec3 g = n - m * dot(n, m);
  const double g_len = length(g);
  const Vec3 e2 = g_len > 0 ? g / g_len : Frame::from_normal(m).s;
  const Vec3 e1 = cross(e2, m);
  const double n_c = dot(n, center);
  // Lit: β ≥ β0 = −n·c/|g| (all of the disk when |g| = 0 and n·c > 0).
  double psi0 = -kPi / 2;
  if (g_len > 0) {
    const double beta0 = -n_c / g_len;
    if (beta0 >= R) return 0.0;
    if (beta0 > -R) psi0 = std::asin(beta0 / R);
  } else if (!(n_c > 0)) {
    return 0.0;
  }
  auto over_psi = [&](double psi) {
    const double sp = std::sin(psi), cp = std::cos(psi);
    const double beta = R * sp, half_chord = R * cp;
    auto over_tau = [&](double tau) {
      const Vec3 x = center + e1 * (tau * half_chord) + e2 * beta;
      // n·x from its exact decomposition: keeps the grazing side accurate.
      return kernel(std::fmax(n_c + g_len * beta, 0.0), dot(m, x), length_squared(x));
    };
    return half_chord * R * cp * Rule16::integrate(over_tau, -1.0, 1.0);
  };
  return Rule16::integrate(over_psi, psi0, kPi / 2);
}

}  // namespace

double small_disk_irradiance(const Vec3& center, const Vec3& m, double R, const Vec3& n) {
  return small_disk_rule(center, m, R, n, [](double cos_part, double m_x, double r2) {
    return cos_part * std::fabs(m_x) / (r2 * r2);
  });
}

double small_disk_area_kernel(const Vec3& center, const Vec3& m, double R, const Vec3& n) {
  return small_disk_rule(center, m, R, n, [](double cos_part, double m_x, double r2) {
    const double r4 = r2 * r2;
    const double k = cos_part * m_x / r4;
    return k * k;
  });
}

}  // namespace furnace::analytic
