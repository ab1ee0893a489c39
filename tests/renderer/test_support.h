// Helpers shared by the renderer tests: quadrature over directions, a
// one-sample z-test with data-derived variance, scenes built in code.
#pragma once

#include <cmath>
#include <cstring>
#include <functional>
#include <string>

#include <boost/math/distributions/normal.hpp>
#include <boost/math/quadrature/gauss_kronrod.hpp>

#include "core/running_moments.h"
#include "core/scene.h"
#include "renderer/image.h"

namespace furnace::testing_support {

// Two images equal to the bit: size, every pixel's count and moments (compared
// as bytes, so −0 ≠ +0 and NaNs compare by payload), ray and non-finite counts.
inline bool bitwise_equal(const Image& a, const Image& b) {
  if (a.width != b.width || a.height != b.height || a.pixels.size() != b.pixels.size()) return false;
  for (size_t i = 0; i < a.pixels.size(); ++i) {
    const PixelMoments &x = a.pixels[i], &y = b.pixels[i];
    if (x.count != y.count || std::memcmp(&x.mean, &y.mean, sizeof(double)) != 0 ||
        std::memcmp(&x.m2, &y.m2, sizeof(double)) != 0 || std::memcmp(&x.m3, &y.m3, sizeof(double)) != 0 ||
        std::memcmp(&x.m4, &y.m4, sizeof(double)) != 0)
      return false;
  }
  return a.rays == b.rays && a.nonfinite_samples == b.nonfinite_samples;
}

// Family-wise false-alarm rate of each statistical check in these tests;
// every check uses a fixed seed, so the outcome is deterministic anyway.
inline constexpr double kAlpha = 1e-6;

// Two-sided critical value of the standard normal at level alpha (from Boost, never typed in).
inline double z_critical(double alpha) {
  return boost::math::quantile(boost::math::complement(boost::math::normal(), alpha / 2));
}

// Round-off allowance of a mean of exactly constant values, relative:
// summing 2^16 terms in double accumulates at most ~n·ε ≈ 1.5e-11.
inline constexpr double kConstantMeanRelTol = 1e-10;

// True if the sample mean is consistent with `expected` at level kAlpha
// (z-test, data-derived standard error; zero variance allows only round-off).
inline bool mean_consistent(const RunningMoments& w, double expected) {
  const double allowance = z_critical(kAlpha) * w.mean_standard_error() + kConstantMeanRelTol * std::fabs(expected);
  return std::fabs(w.mean - expected) <= allowance;
}

// A mean with its (data-derived) standard error.
struct Estimate {
  double mean = 0;
  double standard_error = 0;
};

// True if two independent estimates are consistent at level kAlpha
// (two-sample z-test).
inline bool means_consistent(const Estimate& a, const Estimate& b) {
  const double se = std::hypot(a.standard_error, b.standard_error);
  const double allowance = z_critical(kAlpha) * se + kConstantMeanRelTol * std::fmax(std::fabs(a.mean), std::fabs(b.mean));
  return std::fabs(a.mean - b.mean) <= allowance;
}
inline bool means_consistent(const RunningMoments& a, const RunningMoments& b) {
  return means_consistent(Estimate{a.mean, a.mean_standard_error()}, Estimate{b.mean, b.mean_standard_error()});
}

// ∫∫ f(w) dω over directions with t = 1 − cos θ in [t_min, t_max], φ in [0, 2π],
// adaptive Gauss–Kronrod in both variables (dω = dt dφ).
inline double integrate_directions(const std::function<double(const Vec3&)>& f, double t_min, double t_max) {
  using boost::math::quadrature::gauss_kronrod;
  constexpr unsigned kMaxDepth = 12;
  constexpr double kTolerance = 1e-12;
  const auto inner = [&](double t) {
    const double z = 1.0 - t;
    const double s = std::sqrt(std::fmax(0.0, t * (2.0 - t)));
    return gauss_kronrod<double, 61>::integrate(
        [&](double phi) { return f({s * std::cos(phi), s * std::sin(phi), z}); }, 0.0, 2.0 * kPi, kMaxDepth,
        kTolerance);
  };
  return gauss_kronrod<double, 61>::integrate(inner, t_min, t_max, kMaxDepth, kTolerance);
}

inline Object make_object(const std::string& name, Shape shape, double albedo = 0, double emission = 0,
                          BsdfParameters bsdf = Lambertian{}) {
  Object o;
  o.name = name;
  o.shape = shape;
  o.material = Material{albedo, bsdf};
  o.emitted_radiance = emission;
  return o;
}

// Camera looking down −z from z = 0.5 at a 2×2 window of `px`×`px` pixels.
inline Camera make_camera(int px) {
  Camera c;
  c.center = {0, 0, 0.5};
  c.forward = {0, 0, -1};
  c.up = {0, 1, 0};
  c.width = c.height = 2;
  c.width_px = c.height_px = px;
  return c;
}

// A Lambertian floor (z = 0, normal +z, 8×8) with albedo rho.
inline Object make_floor(double rho) {
  return make_object("floor", Rectangle{{-4, -4, 0}, {8, 0, 0}, {0, 8, 0}}, rho);
}

}  // namespace furnace::testing_support
