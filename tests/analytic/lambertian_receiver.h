// A Lambertian surface as a receiver-model BSDF (analytic/receiver.h),
// supplying only its two functions, for the tests that check the machinery
// against the Lambertian closed forms (receiver_test.cpp,
// receiver_planar_test.cpp).
#pragma once

#include <string>
#include <vector>

#include "analytic/receiver.h"
#include "analytic/receiver_integrals.h"

namespace furnace::analytic::receiver_testing {

// f = ρ/π and p_b = cos θ/π (times `pdf_factor`, 1 for the true density);
// `extra_cosine` writes f·cos²θ for f·cos θ (a defect).
class LambertianReceiver final : public ReceiverModel<LambertianReceiver> {
 public:
  LambertianReceiver(const Vec3& n, const Vec3& wo, double albedo, double pdf_factor = 1, bool extra_cosine = false)
      : ReceiverModel(n, wo), albedo_(albedo), pdf_factor_(pdf_factor), extra_cosine_(extra_cosine) {}
  BsdfValue at(double cos_theta, double) const override {
    BsdfValue v;
    const double f = albedo_ / kPi;
    v.f_cos = extra_cosine_ ? f * cos_theta * cos_theta : f * cos_theta;
    v.pdf_solid_angle = pdf_factor_ * cos_theta / kPi;
    v.f_cos2_over_pdf = v.f_cos * v.f_cos / v.pdf_solid_angle;
    return v;
  }
  bool vanishes_below_mirror_plane() const override { return false; }
  std::vector<double> parameters() const override {
    return {double(BsdfType::kLambertian), albedo_, pdf_factor_, extra_cosine_ ? 1.0 : 0.0};
  }
  std::string name() const override { return "a test Lambertian receiver"; }
  Material material() const override { return Material{albedo_, Lambertian{}}; }

 private:
  double albedo_, pdf_factor_;
  bool extra_cosine_;
};

}  // namespace furnace::analytic::receiver_testing
