// The GGX receiver (analytic/ggx.h) against its closed forms and identities,
// in double (the 50-digit comparisons are ggx_precision_test.cpp):
//  - α = 1: f and the directional albedo of both Smith forms in closed form
//    (ggx.cpp derives them), from normal view to grazing (μo = 0.05);
//  - the bsdf density: constant 1/(2π(1 + μo)) at α = 1, so the part of it
//    above the horizon (the machinery's integral of p_b) is 1/(1 + μo); at
//    normal view for every α it is P(tan²θm ≤ 1) = 1/(1 + α²) (the GGX slope
//    distribution: ωi = reflect(n, m) is above the horizon iff θm < 45°);
//  - reciprocity f(ωo, ωi) = f(ωi, ωo), and the two Smith forms agreeing at
//    normal view (Λ(n) = 0);
//  - negative controls: the other Smith form, and D without its 1/π, miss
//    the closed forms by far;
//  - the scene-level dispatch (reference.cpp, moments.cpp): a GGX floor under
//    the sky is albedo × sky × directional albedo, and its pixel moments are
//    glossy_second_moment's; refusals of what ggx.h does not solve;
//  - the cost of one sky reference and one sphere-light second moment at
//    α = 0.05 and 1e-3 (printed).
#include "analytic/ggx.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "analytic/glossy.h"
#include "analytic/moments.h"
#include "analytic/receiver_integrals.h"
#include "analytic/reference.h"
#include "core/error.h"

namespace furnace::analytic {
namespace {

// The requirement on the references (ggx_precision_test.cpp); the
// closed forms here are double expressions good to a few ε.
constexpr double kPrecisionTarget = 1e-13;
// A negative control must miss by more than this.
constexpr double kControlMiss = 1e-6;

constexpr MicrofacetShadowing kSeparable = MicrofacetShadowing::kSeparable;
constexpr MicrofacetShadowing kHeightCorrelated = MicrofacetShadowing::kHeightCorrelated;

const Vec3 kNormal{0, 0, 1};
Vec3 view_of(double cos_theta_o) { return {-std::sqrt((1 - cos_theta_o) * (1 + cos_theta_o)), 0, cos_theta_o}; }

// r·ωi for n·ωo = μo, n·ωi = μi and the azimuth φ between ωi and r:
// μoμi + sin θo sin θi cos φ (a consistent pair of cosines).
double cos_alpha_at(double mu_o, double mu_i, double phi) {
  return mu_o * mu_i + std::sqrt((1 - mu_o) * (1 + mu_o) * (1 - mu_i) * (1 + mu_i)) * std::cos(phi);
}
const double kAzimuths[] = {0.0, 1.0, 2.5, kPi};

// 2(1 − ln 2)ρ/(1 + μo) and ρ(1 − μo ln((1 + μo)/μo)) (ggx.cpp).
double alpha_one_albedo(MicrofacetShadowing form, double albedo, double mu_o) {
  switch (form) {
    case MicrofacetShadowing::kSeparable: return 2 * (1 - std::log(2.0)) * albedo / (1 + mu_o);
    case MicrofacetShadowing::kHeightCorrelated: return albedo * (1 - mu_o * std::log1p(1 / mu_o));
  }
  return NAN;
}

TEST(GgxClosedForms, AlphaOneBrdf) {
  // f = ρ/(π(1 + μo)(1 + μi)) or ρ/(2π(μo + μi)), whatever the azimuth (cos α).
  for (double mu_o : {1.0, 0.5, 0.2, 0.05})
    for (double mu_i : {0.9, 0.3, 0.01})
      for (double phi : kAzimuths) {
        const double cos_alpha = cos_alpha_at(mu_o, mu_i, phi);
        const double sep = ggx_brdf(0.7, 1, kSeparable, mu_o, mu_i, cos_alpha);
        const double hc = ggx_brdf(0.7, 1, kHeightCorrelated, mu_o, mu_i, cos_alpha);
        EXPECT_NEAR(sep * kPi * (1 + mu_o) * (1 + mu_i) / 0.7, 1, 8e-16);
        EXPECT_NEAR(hc * 2 * kPi * (mu_o + mu_i) / 0.7, 1, 8e-16);
      }
}

TEST(GgxClosedForms, AlphaOneDirectionalAlbedo) {
  double worst = 0;
  for (MicrofacetShadowing form : {kSeparable, kHeightCorrelated})
    for (double mu_o : {1.0, 0.5, 0.2, 0.05}) {
      const GgxReceiver rx(kNormal, view_of(mu_o), 0.8, 1, form);
      const double got = directional_albedo(rx), want = alpha_one_albedo(form, 0.8, mu_o);
      const double rel = std::fabs(got / want - 1);
      worst = std::max(worst, rel);
      EXPECT_LT(rel, kPrecisionTarget) << microfacet_shadowing_name(form) << ", mu_o " << mu_o;
    }
  std::printf("[ ggx ] alpha 1 directional albedo vs closed forms: worst relative error %.3g\n", worst);
}

TEST(GgxClosedForms, OtherSmithFormAndDWithoutInvPiAreCaught) {
  // Negative controls at an oblique view: the height-correlated receiver
  // against the separable closed form, and a receiver whose D lacks 1/π (π
  // times the albedo: the same numbers) against the true closed form.
  const GgxReceiver hc(kNormal, view_of(0.5), 0.8, 1, kHeightCorrelated);
  const double other = std::fabs(directional_albedo(hc) / alpha_one_albedo(kSeparable, 0.8, 0.5) - 1);
  const GgxReceiver no_inv_pi(kNormal, view_of(0.5), 0.8 * kPi, 1, kHeightCorrelated);
  const double pi = std::fabs(directional_albedo(no_inv_pi) / alpha_one_albedo(kHeightCorrelated, 0.8, 0.5) - 1);
  std::printf("[ ggx ] controls: other Smith form misses by %.3g, D without 1/pi by %.3g\n", other, pi);
  EXPECT_GT(other, kControlMiss);
  EXPECT_GT(pi, kControlMiss);
}

// A receiver whose "f·cos θ" is the GGX receiver's bsdf density: the
// machinery's integral of it is ∫_{n·ω>0} p_b dω, the fraction of bsdf
// samples that are not failed.
class GgxDensity final : public ReceiverModel<GgxDensity> {
 public:
  explicit GgxDensity(const GgxReceiver& g) : ReceiverModel(g.n, g.wo), ggx_(g) {}
  BsdfValue at(double cos_theta, double cos_alpha) const override {
    return at_direction(cos_theta, cos_alpha, 1 - cos_alpha);
  }
  BsdfValue at_direction(double cos_theta, double cos_alpha, double one_minus_cos_alpha) const {
    BsdfValue v = ggx_.at_direction(cos_theta, cos_alpha, one_minus_cos_alpha);
    v.f_cos = v.pdf_solid_angle;
    return v;
  }
  bool vanishes_below_mirror_plane() const override { return false; }
  std::vector<double> parameters() const override { return {-1}; }
  std::string name() const override { return "the GGX density"; }
  Material material() const override { return ggx_.material(); }

 private:
  GgxReceiver ggx_;
};

TEST(GgxDensity, AlphaOneIsConstantAndItsMassAboveTheHorizonIsOneOverOnePlusMu) {
  double worst = 0;
  for (double mu_o : {1.0, 0.5, 0.2, 0.05}) {
    const GgxReceiver rx(kNormal, view_of(mu_o), 0.8, 1, kSeparable);
    for (double mu_i : {0.9, 0.3, 0.01})
      for (double phi : kAzimuths)
        EXPECT_NEAR(rx.at(mu_i, cos_alpha_at(mu_o, mu_i, phi)).pdf_solid_angle * 2 * kPi * (1 + mu_o), 1, 8e-16);
    const double mass = light_reflectance(GgxDensity(rx), ReceiverLight{true, {}, 0, 1, 1});
    worst = std::max(worst, std::fabs(mass * (1 + mu_o) - 1));
  }
  std::printf("[ ggx ] alpha 1: mass of p_b above the horizon vs 1/(1 + mu_o): worst relative error %.3g\n", worst);
  EXPECT_LT(worst, kPrecisionTarget);
}

TEST(GgxDensity, NormalViewMassAboveTheHorizonIsTheSlopeDistributionsCdf) {
  double worst = 0;
  for (double alpha : {scene_limits::kMinGgxAlpha, 0.01, 0.05, 0.3, 1.0}) {
    const GgxReceiver rx(kNormal, kNormal, 0.8, alpha, kHeightCorrelated);
    const double mass = light_reflectance(GgxDensity(rx), ReceiverLight{true, {}, 0, 1, 1});
    const double rel = std::fabs(mass * (1 + alpha * alpha) - 1);
    worst = std::max(worst, rel);
    EXPECT_LT(rel, kPrecisionTarget) << "alpha " << alpha;
  }
  std::printf("[ ggx ] normal view: mass of p_b above the horizon vs 1/(1 + alpha^2): worst relative error %.3g\n",
              worst);
}

TEST(GgxBrdf, ReciprocalAndFormsAgreeAtNormalView) {
  for (double alpha : {scene_limits::kMinGgxAlpha, 0.1, 0.7})
    for (MicrofacetShadowing form : {kSeparable, kHeightCorrelated})
      for (double mu_o : {0.9, 0.4, 0.05})
        for (double mu_i : {0.8, 0.2})
          for (double phi : kAzimuths) {
            // cos α = 2μoμi − ωo·ωi is symmetric in the two directions (both
            // sides round differently: a few ε).
            const double cos_alpha = cos_alpha_at(mu_o, mu_i, phi);
            const double a = ggx_brdf(0.8, alpha, form, mu_o, mu_i, cos_alpha);
            const double b = ggx_brdf(0.8, alpha, form, mu_i, mu_o, cos_alpha);
            EXPECT_NEAR(a / b, 1, 1e-15) << alpha << " " << mu_o << " " << mu_i << " " << cos_alpha;
          }
  for (double alpha : {0.01, 0.3})
    for (double mu_i : {0.9, 0.2}) {
      const double sep = ggx_brdf(0.8, alpha, kSeparable, 1, mu_i, mu_i);
      const double hc = ggx_brdf(0.8, alpha, kHeightCorrelated, 1, mu_i, mu_i);
      EXPECT_NEAR(sep / hc, 1, 4e-16);
    }
}

// ---------------------------------------------------------------------------
// Scene level.

Scene ggx_scene(double alpha, MicrofacetShadowing form, bool environment) {
  Scene scene;
  scene.name = "ggx_test";
  scene.source = "ggx_test";
  const Material m{0.8, Ggx{alpha, form, std::nullopt}};
  scene.objects.push_back({"floor", Rectangle{{-3, -3, 0}, {6, 0, 0}, {0, 6, 0}}, m, 0});
  if (environment) scene.environment.radiance = 1.5;
  else scene.objects.push_back({"light", Sphere{{1.0, 0.05, 0.9}, 0.3}, {}, 4.0});
  // Orthographic, looking down at the floor 37° from grazing (μo = 0.6).
  scene.camera.center = {-2, 0, 1.5};
  scene.camera.forward = {0.8, 0, -0.6};
  scene.camera.up = {0, 0, 1};
  scene.camera.width_px = 8;
  scene.camera.height_px = 8;
  return scene;
}

TEST(GgxReference, PixelUnderTheSkyIsAlbedoTimesSkyTimesDirectionalAlbedo) {
  for (MicrofacetShadowing form : {kSeparable, kHeightCorrelated}) {
    const Scene scene = ggx_scene(0.2, form, true);
    const Camera::Ray ray = scene.camera.pixel_center_ray(4, 5);
    const GgxReceiver rx(kNormal, -ray.direction, 0.8, 0.2, form);
    // directional_albedo carries the albedo (f does).
    EXPECT_NEAR(pixel_center_radiance(scene, 4, 5) / (1.5 * directional_albedo(rx)) - 1, 0, 1e-14);
    const std::optional<Hit> hit = intersect(scene, ray.origin, ray.direction);
    ASSERT_TRUE(hit);
    for (Strategy s : direct_strategies())
      EXPECT_EQ(pixel_center_second_moment(s, scene, 4, 5),
                glossy_second_moment(s, scene, hit->point, kNormal, -ray.direction, 0))
          << strategy_name(s);
    const std::array<double, 2> mis = pixel_center_multi_sample_mis_second_moments(scene, 4, 5);
    EXPECT_EQ(mis[0], pixel_center_second_moment(Strategy::kMisBalance, scene, 4, 5));
    EXPECT_EQ(mis[1], pixel_center_second_moment(Strategy::kMisPower, scene, 4, 5));
  }
}

TEST(GgxMoments, ExceedTheSquaredMean) {
  // Var Y > 0 for every sampled estimator (Jensen).
  const Scene scene = ggx_scene(0.1, kHeightCorrelated, false);
  const Vec3 wo = view_of(0.6);
  const double mean = glossy_reflected_radiance(scene, {0, 0, 0}, kNormal, wo, 0);
  EXPECT_GT(mean, 0);
  for (Strategy s : direct_strategies())
    EXPECT_GT(glossy_second_moment(s, scene, {0, 0, 0}, kNormal, wo, 0), mean * mean) << strategy_name(s);
}

TEST(GgxReference, RefusesWhatItDoesNotSolve) {
  const Vec3 wo = view_of(0.6);
  Scene point = ggx_scene(0.1, kSeparable, false);
  point.point_lights.push_back({"p", {0, 0, 1}, 1.0});
  EXPECT_THROW(glossy_reflected_radiance(point, {0, 0, 0}, kNormal, wo, 0), Error);
  Scene disk = ggx_scene(0.1, kSeparable, false);
  disk.objects[1].shape = Disk{{0, 0, 1}, {0, 0, -1}, 0.3};  // a disk light is solved; behind a sphere it is not
  disk.objects.push_back({"blocker", Sphere{{0, 0, 0.5}, 0.1}, {}, 0});
  EXPECT_THROW(glossy_reflected_radiance(disk, {0, 0, 0}, kNormal, wo, 0), Error);
  Scene blocked = ggx_scene(0.1, kSeparable, true);
  blocked.objects.push_back({"blocker", Sphere{{0, 0, 2}, 0.5}, {}, 0});
  EXPECT_THROW(glossy_reflected_radiance(blocked, {0, 0, 0}, kNormal, wo, 0), Error);
  EXPECT_THROW(glossy_second_moment(Strategy::kPathMis, ggx_scene(0.1, kSeparable, false), {0, 0, 0}, kNormal, wo, 0),
               Error);
  EXPECT_THROW(glossy_reflected_radiance(ggx_scene(0.1, kSeparable, true), {0, 0, 0}, kNormal, {0.6, 0, -0.8}, 0), Error);
}

TEST(GgxReference, Cost) {
  // One sky reference (the radiance: the machinery, not the scene-level memo)
  // and one sphere-light E[Y²] (mis_balance: four integrals) per α.
  for (double alpha : {0.05, scene_limits::kMinGgxAlpha}) {
    const GgxReceiver rx(kNormal, view_of(0.5), 0.8, alpha, kHeightCorrelated);
    const Vec3 r = rx.mirror();
    auto seconds = [](auto f) {
      const auto start = std::chrono::steady_clock::now();
      const double v = f();
      EXPECT_GT(v, 0);
      return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    };
    const double sky = seconds([&] { return reflected_radiance(rx, {ReceiverLight{true, {}, 0, 1.5, 1}}); });
    const std::vector<ReceiverLight> sphere{ReceiverLight{false, normalize(r + Vec3{0, 0.05, 0}) * 2.0, 0.2, 4, 1}};
    const double mis = seconds([&] { return receiver_second_moment(Strategy::kMisBalance, rx, sphere); });
    const double bsdf = seconds([&] { return receiver_second_moment(Strategy::kBsdf, rx, sphere); });
    std::printf("[ ggx ] cost at alpha %g, mu_o 0.5: sky radiance %.3g s, sphere mis_balance E[Y^2] %.3g s, "
                "sphere bsdf E[Y^2] %.3g s\n",
                alpha, sky, mis, bsdf);
  }
}

}  // namespace
}  // namespace furnace::analytic
