// The normalised Phong lobe as a Receiver (phong.h); the integrals are the
// receiver model's (receiver.cpp).
#include "analytic/phong.h"

#include <cmath>
#include <string>
#include <vector>

#include "analytic/receiver_integrals.h"

namespace furnace::analytic {

namespace {

// cos^e α for cos α > 0, else 0: the lobe's shape, computed once per
// direction (PhongReceiver::at) for f, p_b and their ratio.
double lobe_power(double exponent, double cos_alpha) {
  return cos_alpha > 0 ? std::pow(cos_alpha, exponent) : 0.0;
}

// The lobe density's normalisation (e+1)/(2π): ∫ cos^e α dω over cos α > 0 is
// 2π/(e+1). `power` = lobe_power(exponent, cos_alpha).
double lobe_density(double exponent, double cos_alpha, double power) {
  return cos_alpha > 0 ? (exponent + 1) / (2 * kPi) * power : 0.0;
}

// phong_brdf from the lobe's power = lobe_power(exponent, cos_alpha): the
// very same expression, so the very same double.
double phong_brdf_from_power(double albedo, double exponent, double cos_alpha, double power) {
  return cos_alpha > 0 ? albedo * (exponent + 2) / (2 * kPi) * power : 0.0;
}

}  // namespace

double phong_brdf(double albedo, double exponent, double cos_alpha) {
  return phong_brdf_from_power(albedo, exponent, cos_alpha, lobe_power(exponent, cos_alpha));
}

PhongReceiver::PhongReceiver(const Vec3& n, const Vec3& wo, double albedo, double exponent)
    : ReceiverModel(n, wo),
      albedo(albedo),
      exponent(exponent),
      bsdf_ratio_(albedo * albedo * (exponent + 2) * (exponent + 2) / (2 * kPi * (exponent + 1))) {}

// inline (a hint): the machinery (receiver_integrals.h, instantiated below)
// calls it at every quadrature node; only this file calls it directly.
inline BsdfValue PhongReceiver::at(double cos_theta, double cos_alpha) const {
  const double power = lobe_power(exponent, cos_alpha);
  BsdfValue value;
  value.f_cos = phong_brdf_from_power(albedo, exponent, cos_alpha, power) * cos_theta;
  value.pdf_solid_angle = lobe_density(exponent, cos_alpha, power);
  value.f_cos2_over_pdf = cos_alpha > 0 ? bsdf_ratio_ * power * cos_theta * cos_theta : 0.0;
  return value;
}

std::vector<double> PhongReceiver::parameters() const { return {double(BsdfType::kPhong), albedo, exponent}; }

template class ReceiverModel<PhongReceiver>;

}  // namespace furnace::analytic
