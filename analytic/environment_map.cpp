#include "analytic/environment_map.h"

#include <algorithm>
#include <cmath>
#include <vector>


#include "core/adaptive_quadrature.h"
#include "core/error.h"

namespace furnace::analytic {

namespace {

// Bisection depth limit of the φ quadrature; each piece is smooth after the
// horizon-crossing split, so depth is spent only at a tangency of the horizon
// and a row edge (a square-root endpoint, error ∝ h^1.5 per level).
constexpr int kMaxDepth = 40;

struct TexelBounds {
  double theta0, theta1, phi0, phi1;
};

TexelBounds bounds(int i, int j, int width, int height) {
  const double d_theta = kPi / height, d_phi = 2 * kPi / width;
  return {i * d_theta, (i + 1) * d_theta, j * d_phi, (j + 1) * d_phi};
}

// Whether angle a (any real) lies in [lo, hi] modulo 2π (hi − lo ≤ 2π).
bool contains_angle(double a, double lo, double hi) {
  double d = std::fmod(a - lo, 2 * kPi);
  if (d < 0) d += 2 * kPi;
  return d <= hi - lo;
}

// ∫_{α}^{β} (n_z cos θ + g sin θ)^power sin θ dθ, closed form (power 1 or 2).
double theta_integral(double nz, double g, double alpha, double beta, int power) {
  const double sum = alpha + beta, diff = beta - alpha;
  if (power == 1) {
    // sin²β − sin²α = sin(β+α) sin(β−α); sin 2β − sin 2α = 2 cos(β+α) sin(β−α).
    return nz * std::sin(sum) * std::sin(diff) / 2 + g * (diff - std::cos(sum) * std::sin(diff)) / 2;
  }
  const double ca = std::cos(alpha), cb = std::cos(beta), sa = std::sin(alpha), sb = std::sin(beta);
  const double cos3 = (ca - cb) * (ca * ca + ca * cb + cb * cb);  // cos³α − cos³β
  const double sin3 = sb * sb * sb - sa * sa * sa;
  return nz * nz * cos3 / 3 + 2 * nz * g * sin3 / 3 + g * g * ((ca - cb) - cos3 / 3);
}

// ∫ g dφ and ∫ g² dφ over [φ0, φ1], g = n_x cos φ + n_y sin φ.
double g_integral(const Vec3& n, double phi0, double phi1) {
  return n.x * (std::sin(phi1) - std::sin(phi0)) - n.y * (std::cos(phi1) - std::cos(phi0));
}
double g2_integral(const Vec3& n, double phi0, double phi1) {
  const double d = phi1 - phi0;
  const double sin2 = std::sin(2 * phi1) - std::sin(2 * phi0);
  const double sinsq = std::sin(phi1 + phi0) * std::sin(phi1 - phi0);  // sin²φ₁ − sin²φ₀
  return (n.x * n.x + n.y * n.y) * d / 2 + (n.x * n.x - n.y * n.y) * sin2 / 4 + n.x * n.y * sinsq;
}

// The whole texel, n·ω ≥ 0 on it.
double closed_form(const Vec3& n, const TexelBounds& b, int power) {
  const double d_phi = b.phi1 - b.phi0;
  const double g1 = g_integral(n, b.phi0, b.phi1);
  if (power == 1) {
    const double sum = b.theta0 + b.theta1, diff = b.theta1 - b.theta0;
    return n.z * d_phi * std::sin(sum) * std::sin(diff) / 2 + g1 * (diff - std::cos(sum) * std::sin(diff)) / 2;
  }
  const double c0 = std::cos(b.theta0), c1 = std::cos(b.theta1), s0 = std::sin(b.theta0), s1 = std::sin(b.theta1);
  const double cos3 = (c0 - c1) * (c0 * c0 + c0 * c1 + c1 * c1);
  const double sin3 = s1 * s1 * s1 - s0 * s0 * s0;
  return n.z * n.z * d_phi * cos3 / 3 + 2 * n.z * g1 * sin3 / 3 + g2_integral(n, b.phi0, b.phi1) * ((c0 - c1) - cos3 / 3);
}

// min and max of n·ω over the texel. For fixed θ, n·ω is n_z cos θ + sin θ·g(φ)
// with sin θ ≥ 0, so its extremes over φ are at g's extremes; g = A cos(φ − φ_n)
// peaks at φ_n and dips at φ_n + π. For fixed g, n_z cos θ + g sin θ =
// R cos(θ − θ*), θ* = atan2(g, n_z), extreme at θ* (max) and θ* + π (min).
struct Range {
  double lo, hi;
};
Range cosine_range(const Vec3& n, const TexelBounds& b) {
  const double a = std::hypot(n.x, n.y), phi_n = std::atan2(n.y, n.x);
  auto g = [&](double phi) { return n.x * std::cos(phi) + n.y * std::sin(phi); };
  double g_lo = std::min(g(b.phi0), g(b.phi1)), g_hi = std::max(g(b.phi0), g(b.phi1));
  if (contains_angle(phi_n, b.phi0, b.phi1)) g_hi = a;
  if (contains_angle(phi_n + kPi, b.phi0, b.phi1)) g_lo = -a;
  auto f = [&](double gv, double theta) { return n.z * std::cos(theta) + gv * std::sin(theta); };
  Range r{std::min(f(g_lo, b.theta0), f(g_lo, b.theta1)), std::max(f(g_hi, b.theta0), f(g_hi, b.theta1))};
  if (contains_angle(std::atan2(g_lo, n.z) + kPi, b.theta0, b.theta1)) r.lo = -std::hypot(n.z, g_lo);
  if (contains_angle(std::atan2(g_hi, n.z), b.theta0, b.theta1)) r.hi = std::hypot(n.z, g_hi);
  return r;
}

// The inner θ integral over the part of [θ0, θ1] where n·ω > 0, at azimuth φ.
double clipped_theta_integral(const Vec3& n, const TexelBounds& b, double phi, int power) {
  const double g = n.x * std::cos(phi) + n.y * std::sin(phi);
  // n_z cos θ + g sin θ = R cos(θ − θ*) > 0 on (θ* − π/2, θ* + π/2) mod 2π;
  // on θ ∈ [0, π] that is one interval [a, a + π] (shifted by 2π when θ* < −π/2).
  double a = std::atan2(g, n.z) - kPi / 2;
  if (a < -kPi) a += 2 * kPi;
  const double alpha = std::max(b.theta0, a), beta = std::min(b.theta1, a + kPi);
  return beta > alpha ? theta_integral(n.z, g, alpha, beta, power) : 0.0;
}

}  // namespace

double texel_solid_angle(int i, int width, int height) {
  const double d_theta = kPi / height;
  return (2 * kPi / width) * 2 * std::sin((i + 0.5) * d_theta) * std::sin(0.5 * d_theta);
}

double texel_cosine_integral(int i, int j, int width, int height, const Vec3& n, int power) {
  FURNACE_CHECK(power == 1 || power == 2);
  const TexelBounds b = bounds(i, j, width, height);
  const Range r = cosine_range(n, b);
  if (r.hi <= 0) return 0.0;
  if (r.lo >= 0) return closed_form(n, b, power);
  // Straddling: split φ where the horizon curve n·ω = 0 crosses a row edge θ_k,
  // cos(φ − φ_n) = −n_z cos θ_k/(A sin θ_k), so each piece is smooth.
  const double a = std::hypot(n.x, n.y), phi_n = std::atan2(n.y, n.x);
  std::vector<double> cuts{b.phi0, b.phi1};
  for (double theta : {b.theta0, b.theta1}) {
    const double denominator = a * std::sin(theta);
    if (!(denominator > 0)) continue;
    const double c = -n.z * std::cos(theta) / denominator;
    if (std::fabs(c) > 1) continue;
    for (double sign : {-1.0, 1.0}) {
      double phi = phi_n + sign * std::acos(c);
      phi -= 2 * kPi * std::floor((phi - b.phi0) / (2 * kPi));  // into [φ0, φ0 + 2π)
      if (phi > b.phi0 && phi < b.phi1) cuts.push_back(phi);
    }
  }
  std::sort(cuts.begin(), cuts.end());
  const double abs_tolerance = kMapQuadratureTolerance * (b.phi1 - b.phi0) * (std::cos(b.theta0) - std::cos(b.theta1));
  double total = 0;
  for (size_t k = 0; k + 1 < cuts.size(); ++k)
    if (cuts[k + 1] > cuts[k])
      total += adaptive_gauss_kronrod([&](double phi) { return clipped_theta_integral(n, b, phi, power); }, cuts[k],
                                      cuts[k + 1], abs_tolerance, kMaxDepth);
  return total;
}

double map_cosine_integral(const LatLongMap& map, const Vec3& n, int cos_power, int value_power) {
  double sum = 0;
  for (int i = 0; i < map.height; ++i)
    for (int j = 0; j < map.width; ++j) {
      const double l = map.texel(i, j);
      if (l == 0) continue;
      sum += (value_power == 2 ? l * l : l) * texel_cosine_integral(i, j, map.width, map.height, n, cos_power);
    }
  return sum;
}

double map_irradiance(const LatLongMap& map, const Vec3& n) { return map_cosine_integral(map, n, 1, 1); }

double map_solid_angle_integral(const LatLongMap& map) {
  double sum = 0;
  for (int i = 0; i < map.height; ++i) {
    double row = 0;
    for (int j = 0; j < map.width; ++j) row += map.texel(i, j);
    sum += row * texel_solid_angle(i, map.width, map.height);
  }
  return sum;
}

bool environment_is_light(const Environment& environment) {
  if (!(environment.radiance > 0)) return false;
  if (!environment.map) return true;
  return std::any_of(environment.map->texels.begin(), environment.map->texels.end(), [](double l) { return l > 0; });
}

double map_uniform_hemisphere_moment(const Environment& environment, const Vec3& n) {
  const double r = environment.radiance;
  return 2 * kPi * r * r * map_cosine_integral(*environment.map, n, 2, 2);
}

double map_cosine_moment(const Environment& environment, const Vec3& n) {
  const double r = environment.radiance;
  return kPi * r * r * map_cosine_integral(*environment.map, n, 1, 2);
}

double map_light_sampling_moment(const Environment& environment, const Vec3& n, size_t light_count) {
  const double r = environment.radiance;
  return double(light_count) * r * r * map_solid_angle_integral(*environment.map) *
         map_cosine_integral(*environment.map, n, 2, 1);
}

}  // namespace furnace::analytic
