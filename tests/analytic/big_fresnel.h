// The exact unpolarised dielectric Fresnel reflectance in 50 digits, written
// from the s and p amplitudes and Snell's law (not analytic/fresnel.h's
// form), for the glass precision tests (glass_precision_test.cpp,
// glass_light_precision_test.cpp).
#pragma once

#include <boost/multiprecision/cpp_bin_float.hpp>

namespace furnace::big_fresnel {

using Big = boost::multiprecision::cpp_bin_float_50;

// F at cos θ = c for the far side's index relative to the near side's, eta;
// 1 under total internal reflection.
inline Big dielectric(const Big& c, const Big& eta) {
  const Big sin_t2 = (1 - c * c) / (eta * eta);
  if (sin_t2 >= 1) return Big(1);
  const Big ct = sqrt(1 - sin_t2);
  const Big rs = (c - eta * ct) / (c + eta * ct), rp = (eta * c - ct) / (eta * c + ct);
  return (rs * rs + rp * rp) / 2;
}

}  // namespace furnace::big_fresnel
