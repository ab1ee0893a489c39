// Warps from the unit square to the standard domains of light transport.
//
// Every warp is an adjacent trio of free functions:
//   sample_X(u1, u2)  maps a point of [0,1)² to the domain;
//   X_pdf(w)          the density of sample_X in the measure named on its doc
//                     line, 0 outside the support;
//   invert_X(w)       maps a domain point back to the [0,1)² point that
//                     sample_X maps to it (empty optional outside the support).
// Directions are in the local frame: z is the surface normal, unit vectors in,
// unit vectors out. No sampling code here is shared with analytic/.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include "core/vec3.h"

namespace furnace {

inline constexpr double kTwoPi = 2.0 * kPi;
inline constexpr double kPiOver2 = 0.5 * kPi;
inline constexpr double kPiOver4 = 0.25 * kPi;

namespace sampling_detail {

// sqrt that treats tiny negative round-off as 0 rather than producing NaN.
inline double safe_sqrt(double x) { return std::sqrt(std::max(0.0, x)); }

// Azimuth of (x, y) mapped to [0, 1): the inverse of φ = 2π·u.
inline double azimuth_to_unit(double x, double y) {
  double phi = std::atan2(y, x);
  if (phi < 0) phi += kTwoPi;
  const double u = phi / kTwoPi;
  return u < 1.0 ? u : 0.0;  // φ = 2π (from φ just below 0) is the seam at u = 0
}

// sin x and cos x for |x| ≤ π/4 by their Taylor polynomials to x¹⁵ and x¹⁶
// (in powers of x²): the first omitted terms, x¹⁷/17! and x¹⁸/18!, are below
// 5e-17 there, so the error is that of the few roundings, a few 1e-16
// (tests/renderer/sampling_test.cpp measures it against std::sin, std::cos).
// Faster than glibc's sincos, which was a tenth of the light strategies'
// profile; only the warps of this file use it.
struct SinCos {
  double sin, cos;
};
inline SinCos sin_cos_quarter(double x) {
  constexpr double s3 = -1.0 / 6, s5 = 1.0 / 120, s7 = -1.0 / 5040, s9 = 1.0 / 362880, s11 = -1.0 / 39916800,
                   s13 = 1.0 / 6227020800, s15 = -1.0 / 1307674368000;
  constexpr double c4 = 1.0 / 24, c6 = -1.0 / 720, c8 = 1.0 / 40320, c10 = -1.0 / 3628800, c12 = 1.0 / 479001600,
                   c14 = -1.0 / 87178291200, c16 = 1.0 / 20922789888000;
  // Estrin's scheme (pairs, then powers z², z⁴): a shorter dependency chain than Horner's.
  const double z = x * x, z2 = z * z, z4 = z2 * z2;
  const double sin_tail = (s3 + z * s5) + z2 * (s7 + z * s9) + z4 * ((s11 + z * s13) + z2 * s15);
  const double cos_tail = (c4 + z * c6) + z2 * (c8 + z * c10) + z4 * ((c12 + z * c14) + z2 * c16);
  return {x + x * z * sin_tail, 1.0 - 0.5 * z + z * z * cos_tail};
}
// sin and cos of φ = 2π·u for u in [0, 1]: u is reduced to the nearest
// quarter turn q exactly (4u − q is exact by Sterbenz's lemma), and the
// remainder, within ±π/4, goes to sin_cos_quarter.
inline SinCos sin_cos_two_pi(double u) {
  const double t = 4.0 * u;
  const int q = int(t + 0.5);  // t ≥ 0: truncation is floor (and inline, where std::nearbyint is a libm call)
  const SinCos r = sin_cos_quarter((t - q) * kPiOver2);
  switch (q & 3) {
    case 0: return r;
    case 1: return {r.cos, -r.sin};
    case 2: return {-r.sin, -r.cos};
    default: return {-r.cos, r.sin};
  }
}

// Direction from cos θ, sin θ and u2 (φ = 2π·u2).
inline Vec3 spherical_direction(double sin_theta, double cos_theta, double u2) {
  const SinCos phi = sin_cos_two_pi(u2);
  return {sin_theta * phi.cos, sin_theta * phi.sin, cos_theta};
}

// 1 − cos θ of a unit vector, accurate when θ is tiny: (x² + y²)/(1 + z) for
// z > 0, where 1 − z would cancel; the plain difference otherwise.
inline double one_minus_cos_theta(const Vec3& w) {
  return w.z > 0 ? (w.x * w.x + w.y * w.y) / (1.0 + w.z) : 1.0 - w.z;
}

}  // namespace sampling_detail

// ---------------------------------------------------------------------------
// Uniform hemisphere (z ≥ 0): cos θ = u1, φ = 2π·u2.

inline Vec3 sample_uniform_hemisphere(double u1, double u2) {
  const double z = u1;
  const double r = sampling_detail::safe_sqrt((1.0 - z) * (1.0 + z));  // difference of squares
  return sampling_detail::spherical_direction(r, z, u2);
}
// Density in solid angle (sr⁻¹): 1/(2π) on z ≥ 0, 0 below.
inline double uniform_hemisphere_pdf(const Vec3& w) { return w.z >= 0 ? 1.0 / kTwoPi : 0.0; }
inline std::optional<std::array<double, 2>> invert_uniform_hemisphere(const Vec3& w) {
  if (!(w.z >= 0)) return std::nullopt;
  return std::array<double, 2>{std::min(w.z, std::nextafter(1.0, 0.0)),
                               sampling_detail::azimuth_to_unit(w.x, w.y)};
}

// ---------------------------------------------------------------------------
// Uniform disk, Shirley & Chiu 1997 concentric map: squares around the centre
// of [-1,1]² go to circles, preserving area fractions and adjacency.

inline std::array<double, 2> sample_uniform_disk_concentric(double u1, double u2) {
  const double a = 2.0 * u1 - 1.0;
  const double b = 2.0 * u2 - 1.0;
  if (a == 0 && b == 0) return {0.0, 0.0};
  // φ = π/4·(b/a), or π/2 − π/4·(a/b), whose cos and sin are the sin and cos of π/4·(a/b).
  if (std::fabs(a) > std::fabs(b)) {
    const auto phi = sampling_detail::sin_cos_quarter(kPiOver4 * (b / a));
    return {a * phi.cos, a * phi.sin};
  }
  const auto x = sampling_detail::sin_cos_quarter(kPiOver4 * (a / b));
  return {b * x.sin, b * x.cos};
}
// Density in area on the unit disk: 1/π inside (radius ≤ 1), 0 outside.
inline double uniform_disk_pdf(const std::array<double, 2>& p) {
  return p[0] * p[0] + p[1] * p[1] <= 1.0 ? kInvPi : 0.0;
}
inline std::optional<std::array<double, 2>> invert_uniform_disk_concentric(const std::array<double, 2>& p) {
  const double x = p[0], y = p[1];
  const double r = std::hypot(x, y);
  if (!(r <= 1.0)) return std::nullopt;
  if (r == 0) return std::array<double, 2>{0.5, 0.5};
  double a, b;
  if (std::fabs(x) >= std::fabs(y)) {
    // Left/right wedges: the signed radius is a; φ is the angle of the point
    // divided by sign(a), in (−π/4, π/4].
    const double s = std::copysign(1.0, x);
    a = s * r;
    const double phi = std::atan2(s * y, s * x);
    b = a * phi / kPiOver4;
  } else {
    // Top/bottom wedges: the signed radius is b; φ in (π/4, 3π/4).
    const double s = std::copysign(1.0, y);
    b = s * r;
    const double phi = std::atan2(s * y, s * x);
    a = b * (kPiOver2 - phi) / kPiOver4;
  }
  const auto to_unit = [](double v) { return std::clamp(0.5 * (v + 1.0), 0.0, std::nextafter(1.0, 0.0)); };
  return std::array<double, 2>{to_unit(a), to_unit(b)};
}

// ---------------------------------------------------------------------------
// Cosine-weighted hemisphere. Two samplers of the same density:
//  - inversion: sin²θ = u1, φ = 2π·u2 (the CDF of cos θ·sin θ inverted);
//  - Malley: a concentric-disk point lifted to the hemisphere.
// invert_cosine_hemisphere inverts the inversion sampler.

inline Vec3 sample_cosine_hemisphere(double u1, double u2) {
  const double sin_theta = std::sqrt(u1);
  const double cos_theta = std::sqrt(1.0 - u1);  // 1 − u1 is exact for u1 ≥ 1/2 and harmless below
  return sampling_detail::spherical_direction(sin_theta, cos_theta, u2);
}
inline Vec3 sample_cosine_hemisphere_malley(double u1, double u2) {
  const auto d = sample_uniform_disk_concentric(u1, u2);
  const double z = sampling_detail::safe_sqrt(1.0 - d[0] * d[0] - d[1] * d[1]);
  return {d[0], d[1], z};
}
// Density in solid angle (sr⁻¹): cos θ/π on z ≥ 0, 0 below.
inline double cosine_hemisphere_pdf(const Vec3& w) { return w.z > 0 ? w.z * kInvPi : 0.0; }
inline std::optional<std::array<double, 2>> invert_cosine_hemisphere(const Vec3& w) {
  if (!(w.z >= 0)) return std::nullopt;
  const double sin2_theta = std::min(w.x * w.x + w.y * w.y, std::nextafter(1.0, 0.0));
  return std::array<double, 2>{sin2_theta, sampling_detail::azimuth_to_unit(w.x, w.y)};
}
// Inverse of the Malley sampler: the disk point is the projection (x, y).
inline std::optional<std::array<double, 2>> invert_cosine_hemisphere_malley(const Vec3& w) {
  if (!(w.z >= 0)) return std::nullopt;
  return invert_uniform_disk_concentric({w.x, w.y});
}

// ---------------------------------------------------------------------------
// Uniform sphere: cos θ = 1 − 2·u1, φ = 2π·u2.

inline Vec3 sample_uniform_sphere(double u1, double u2) {
  const double z = 1.0 - 2.0 * u1;
  const double r = 2.0 * sampling_detail::safe_sqrt(u1 * (1.0 - u1));  // sin θ = √((1−z)(1+z)) = 2√(u1(1−u1))
  return sampling_detail::spherical_direction(r, z, u2);
}
// Density in solid angle (sr⁻¹): 1/(4π) everywhere.
inline double uniform_sphere_pdf(const Vec3& /*w*/) { return 1.0 / (4.0 * kPi); }
inline std::optional<std::array<double, 2>> invert_uniform_sphere(const Vec3& w) {
  const double u1 = std::clamp(0.5 * (1.0 - w.z), 0.0, std::nextafter(1.0, 0.0));
  return std::array<double, 2>{u1, sampling_detail::azimuth_to_unit(w.x, w.y)};
}

// ---------------------------------------------------------------------------
// Uniform cone of directions around +z with half-angle θmax.
//
// The density involves 1 − cos θmax, which cancels catastrophically for tiny
// cones if computed as 1 − cos. ConeAperture carries it separately; build it
// from sin²θmax (a sphere light: sin²θmax = r²/d²) to keep full precision:
// 1 − cos θmax = sin²θmax/(1 + cos θmax).
struct ConeAperture {
  double cos_theta_max = 1;
  double one_minus_cos_theta_max = 0;

  static ConeAperture from_cos(double cos_theta_max) {
    const double c = std::clamp(cos_theta_max, -1.0, 1.0);
    return {c, 1.0 - c};  // no better information than c itself exists here
  }
  static ConeAperture from_sin2(double sin2_theta_max) {
    const double s2 = std::clamp(sin2_theta_max, 0.0, 1.0);
    const double c = std::sqrt(1.0 - s2);
    return {c, s2 / (1.0 + c)};  // difference of squares: (1 − c)(1 + c) = s²
  }
};

// Slack of the cone support test. A sample drawn with u1 just below 1 lies on
// the rim, and a direction that went through a frame change (world ↔ local)
// carries a few ulps of absolute error per component; without slack
// pdf(sample) could read 0 for rim samples of tiny cones. Both allowances are
// far below anything a statistical test resolves.
inline constexpr double kConeSupportSlack = 1e-12;               // relative, on 1 − cos θmax
inline constexpr double kDirectionRoundoff = 16 * 0x1.0p-53;     // absolute, per direction component
inline double cone_support_limit(const ConeAperture& cone) {
  // 1 − cos θ grows as θ·dθ near the rim: an angular error δ moves it by ≈ 2·√(1 − cos θmax)·δ.
  const double om = cone.one_minus_cos_theta_max;
  return om * (1.0 + kConeSupportSlack) + 2.0 * std::sqrt(om) * kDirectionRoundoff + kDirectionRoundoff * kDirectionRoundoff;
}

inline Vec3 sample_uniform_cone(double u1, double u2, const ConeAperture& cone) {
  const double t = u1 * cone.one_minus_cos_theta_max;  // t = 1 − cos θ, uniform in [0, 1 − cos θmax)
  const double cos_theta = 1.0 - t;
  const double sin_theta = sampling_detail::safe_sqrt(t * (2.0 - t));  // sin²θ = (1−cos θ)(1+cos θ)
  return sampling_detail::spherical_direction(sin_theta, cos_theta, u2);
}
inline Vec3 sample_uniform_cone(double u1, double u2, double cos_theta_max) {
  return sample_uniform_cone(u1, u2, ConeAperture::from_cos(cos_theta_max));
}
// Density in solid angle (sr⁻¹): 1/(2π(1 − cos θmax)) inside the cone, 0 outside.
inline double uniform_cone_pdf(const Vec3& w, const ConeAperture& cone) {
  if (!(cone.one_minus_cos_theta_max > 0)) return 0.0;  // a zero-width cone is a delta: no density
  const double t = sampling_detail::one_minus_cos_theta(w);
  if (!(t <= cone_support_limit(cone))) return 0.0;
  return 1.0 / (kTwoPi * cone.one_minus_cos_theta_max);
}
inline double uniform_cone_pdf(const Vec3& w, double cos_theta_max) {
  return uniform_cone_pdf(w, ConeAperture::from_cos(cos_theta_max));
}
inline std::optional<std::array<double, 2>> invert_uniform_cone(const Vec3& w, const ConeAperture& cone) {
  if (uniform_cone_pdf(w, cone) == 0) return std::nullopt;
  const double t = sampling_detail::one_minus_cos_theta(w);
  const double u1 = std::min(t / cone.one_minus_cos_theta_max, std::nextafter(1.0, 0.0));
  return std::array<double, 2>{u1, sampling_detail::azimuth_to_unit(w.x, w.y)};
}
inline std::optional<std::array<double, 2>> invert_uniform_cone(const Vec3& w, double cos_theta_max) {
  return invert_uniform_cone(w, ConeAperture::from_cos(cos_theta_max));
}

// ---------------------------------------------------------------------------
// Area-uniform barycentric coordinates (b0, b1, b2) on a triangle:
// √u1 picks the distance from vertex 0 with density ∝ length, u2 the position
// along that cross-section.

inline std::array<double, 3> sample_uniform_triangle_barycentric(double u1, double u2) {
  const double su = std::sqrt(u1);
  const double b0 = 1.0 - su;
  const double b1 = u2 * su;
  return {b0, b1, std::max(0.0, 1.0 - b0 - b1)};
}
// Density in the area of the (b1, b2) parameter triangle (area 1/2): 2 inside, 0 outside.
// On a world triangle of area A the density in area is 1/A.
inline double uniform_triangle_barycentric_pdf(const std::array<double, 3>& b) {
  return b[0] >= 0 && b[1] >= 0 && b[2] >= 0 ? 2.0 : 0.0;
}
inline std::optional<std::array<double, 2>> invert_uniform_triangle_barycentric(const std::array<double, 3>& b) {
  if (uniform_triangle_barycentric_pdf(b) == 0) return std::nullopt;
  const double su = b[1] + b[2];  // = 1 − b0 without cancellation
  const double u1 = std::min(su * su, std::nextafter(1.0, 0.0));
  const double u2 = su > 0 ? std::min(b[1] / su, std::nextafter(1.0, 0.0)) : 0.0;
  return std::array<double, 2>{u1, u2};
}

// ---------------------------------------------------------------------------
// Normalised Phong lobe around +z (the mirror direction, in the lobe frame):
// cos α = u1^(1/(n+1)), φ = 2π·u2, so the density is (n+1)/(2π)·cos^n α.

inline Vec3 sample_phong_lobe(double u1, double u2, double exponent) {
  // 1 − u1 ∈ (0, 1] keeps cos α > 0 and pow well defined for every exponent.
  const double cos_alpha = std::pow(1.0 - u1, 1.0 / (exponent + 1.0));
  const double sin_alpha = sampling_detail::safe_sqrt((1.0 - cos_alpha) * (1.0 + cos_alpha));
  return sampling_detail::spherical_direction(sin_alpha, cos_alpha, u2);
}
// Density in solid angle (sr⁻¹): (n+1)/(2π)·cos^n α on cos α > 0, 0 elsewhere.
inline double phong_lobe_pdf(const Vec3& w, double exponent) {
  return w.z > 0 ? (exponent + 1.0) / kTwoPi * std::pow(w.z, exponent) : 0.0;
}
inline std::optional<std::array<double, 2>> invert_phong_lobe(const Vec3& w, double exponent) {
  if (!(w.z > 0)) return std::nullopt;
  const double u1 = std::clamp(1.0 - std::pow(w.z, exponent + 1.0), 0.0, std::nextafter(1.0, 0.0));
  return std::array<double, 2>{u1, sampling_detail::azimuth_to_unit(w.x, w.y)};
}

}  // namespace furnace
