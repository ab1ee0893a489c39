// Every strategy of the table through render() on a GGX floor under a
// constant environment L (nothing else, no interreflection): each pixel sees
// L·E(μo), E the directional albedo ∫ f cos θi dωi at the pixel's view; at
// α = 0.3 E comes from quadrature of eval, at
// α = 1 (D = 1/π, G1 = 2μ/(1 + μ)) E has closed forms:
//   height-correlated, f = ρ/(2π(μo + μi)):  E = ρ·∫0^1 μi/(μo + μi) dμi = ρ·(1 − μo·ln(1 + 1/μo));
//   separable, f = ρ/(π(1 + μo)(1 + μi)):     E = ρ·2/(1 + μo)·∫0^1 μi/(1 + μi) dμi = ρ·2(1 − ln 2)/(1 + μo);
// each checked here against Boost quadrature of GgxBsdf::eval·cos θi.
// Per pixel a z-test with the pixel's own variance at kAlpha (tests/renderer/
// test_support.h). Negative controls: the GGX defects visible at α = 1
// (ggx_separable_as_height_correlated, ggx_d_without_inv_pi,
// ggx_vndf_pdf_without_g1; Λ of α² and an α² stretch are no change at α = 1)
// make every pixel of a strategy that sees them disagree with the reference.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "renderer/bsdf.h"
#include "renderer/render.h"
#include "test_support.h"
#include "tests/renderer/strategy_names.h"

namespace furnace {
namespace {

constexpr uint64_t kSeed = 0x66c7f;
constexpr double kRho = 0.8, kEnvironment = 1.5;
// 4096 samples a pixel: each pixel's z-test detects a relative bias of
// 2.5–31 % (printed; BSDF sampling and MIS 2.5–6.5 %, cosine and light
// sampling of the α = 0.3 lobe at 80° the weakest) with probability kPower;
// the 16 pixels of an image are 16 such tests.
constexpr int kSpp = 4096;
constexpr double kPower = 0.9;

// The views of the floor: the camera is orthographic, so every pixel of an
// image sees the floor at the same θo (separable and height-correlated G2
// agree at θo = 0, where Λ(ωo) = 0).
const std::vector<double> kViewsDeg{0, 60, 80};
// α = 1 against the closed forms; α = 0.3 against quadrature (a lobe narrow
// enough to matter, wide enough that uniform-hemisphere sampling's estimate
// is not dominated by rare lobe hits at this sample count).
const std::vector<double> kFloorAlphas{1.0, 0.3};

Scene ggx_floor(MicrofacetShadowing shadowing, double view_deg, double alpha = 1) {
  Scene scene;
  scene.name = "ggx_floor";
  scene.camera = testing_support::make_camera(4);
  const double t = view_deg * kPi / 180;
  scene.camera.forward = {0, std::sin(t), -std::cos(t)};
  scene.camera.up = {0, std::cos(t), std::sin(t)};
  // A 0.1-wide window 2 units back along the view: every origin stays above
  // the floor (z ≥ 2 cos 80° − 0.05 > 0.29) and every ray meets it within
  // 0.3 of the origin, far inside its 8 × 8.
  scene.camera.width = scene.camera.height = 0.1;
  scene.camera.center = -2.0 * scene.camera.forward;
  Object floor = testing_support::make_floor(kRho);
  floor.material.bsdf = Ggx{alpha, shadowing, std::nullopt};
  scene.objects.push_back(floor);
  scene.environment.radiance = kEnvironment;
  return scene;
}

// The closed forms of the header (albedo ρ).
double directional_albedo(double mu_o, MicrofacetShadowing shadowing) {
  switch (shadowing) {
    case MicrofacetShadowing::kHeightCorrelated: return kRho * (1 - mu_o * std::log1p(1 / mu_o));
    case MicrofacetShadowing::kSeparable: return kRho * 2 * (1 - std::log(2.0)) / (1 + mu_o);
  }
  return 0;
}

// E at α < 1 (no closed form): adaptive quadrature of GgxBsdf::eval·cos θi
// over the hemisphere; eval itself is tested against 50 digits in
// ggx_test.cpp, so this tests the sampling, weights and strategies.
double directional_albedo(double mu_o, const Material& m) {
  const Ggx& g = std::get<Ggx>(m.bsdf);
  if (g.alpha == 1) return directional_albedo(mu_o, g.shadowing);
  const GgxBsdf b{kRho, g.alpha, g.shadowing};
  const Vec3 wo{std::sqrt((1 - mu_o) * (1 + mu_o)), 0, mu_o};
  return testing_support::integrate_directions([&](const Vec3& wi) { return b.eval(wo, wi) * wi.z; }, 0, 1);
}

TEST(GgxFurnace, ClosedFormsAgreeWithQuadratureOfEval) {
  for (MicrofacetShadowing sh : {MicrofacetShadowing::kSeparable, MicrofacetShadowing::kHeightCorrelated})
    for (double mu : {1.0, 0.7, 0.3, 0.05}) {
      const GgxBsdf b{kRho, 1.0, sh};
      const Vec3 wo{std::sqrt((1 - mu) * (1 + mu)), 0, mu};
      const double e = testing_support::integrate_directions([&](const Vec3& wi) { return b.eval(wo, wi) * wi.z; }, 0, 1);
      EXPECT_NEAR(e / directional_albedo(mu, sh), 1.0, 1e-9) << microfacet_shadowing_name(sh) << " mu " << mu;
    }
}

struct Misses {
  int pixels = 0, inconsistent = 0;
  double worst_detectable = 0;  // largest relative bias the pixels' z-tests would detect
};
Misses render_misses(const Scene& scene, Strategy strategy, Defect defect) {
  RenderOptions o;
  o.strategy = strategy;
  o.defect = defect;
  o.spp = kSpp;
  o.seed = kSeed;
  const Image image = render(scene, o);
  EXPECT_EQ(image.nonfinite_samples, 0u);
  Misses m;
  // Every pixel of the orthographic camera sees the floor at the same θo.
  const double mu_o = -scene.camera.pixel_center_ray(0, 0).direction.z;
  const double expected = kEnvironment * directional_albedo(mu_o, scene.objects[0].material);
  for (int py = 0; py < image.height; ++py)
    for (int px = 0; px < image.width; ++px) {
      const PixelMoments& p = image.at(px, py);
      ++m.pixels;

      m.inconsistent += testing_support::mean_consistent(p, expected) ? 0 : 1;
      // (z_{1−α/2} + z_{power})·SE: the bias found with probability kPower.
      const double z = testing_support::z_critical(testing_support::kAlpha) + testing_support::z_critical(2 * (1 - kPower));
      m.worst_detectable = std::fmax(m.worst_detectable, z * p.mean_standard_error() / expected);
    }
  return m;
}

using FurnaceParam = std::tuple<Strategy, MicrofacetShadowing>;
class GgxFurnaceFloor : public testing::TestWithParam<FurnaceParam> {};

TEST_P(GgxFurnaceFloor, EveryPixelIsEnvironmentTimesDirectionalAlbedo) {
  const auto [strategy, shadowing] = GetParam();
  for (double alpha : kFloorAlphas)
    for (double view : kViewsDeg) {
      const Misses m = render_misses(ggx_floor(shadowing, view, alpha), strategy, Defect::kNone);
      std::cout << "  " << strategy_name(strategy) << " " << microfacet_shadowing_name(shadowing) << " alpha " << alpha
                << " at " << view << " deg: " << m.inconsistent << "/" << m.pixels
                << " pixels inconsistent, detectable relative bias <= " << m.worst_detectable << "\n";
      EXPECT_EQ(m.inconsistent, 0) << "alpha " << alpha << " view " << view;
    }
}

std::vector<Strategy> every_strategy() {
  std::vector<Strategy> s = direct_strategies();
  for (Strategy p : path_tracing_strategies()) s.push_back(p);
  return s;
}

INSTANTIATE_TEST_SUITE_P(
    Strategies, GgxFurnaceFloor,
    testing::Combine(testing::ValuesIn(every_strategy()),
                     testing::Values(MicrofacetShadowing::kSeparable, MicrofacetShadowing::kHeightCorrelated)),
    [](const auto& info) {
      return testing_support::camel_case(strategy_name(std::get<0>(info.param))) +
             (std::get<1>(info.param) == MicrofacetShadowing::kSeparable ? "Separable" : "HeightCorrelated");
    });

// Each defect with a strategy that sees it: π·D scales f and the BSDF pdf
// alike (the bsdf strategy's weight is unchanged), so cosine sampling shows
// it; the density without G1 shows only in BSDF sampling's weight.
TEST(GgxFurnaceControl, DefectsAreDetected) {
  const std::vector<std::pair<Defect, Strategy>> controls{
      {Defect::kGgxSeparableAsHeightCorrelated, Strategy::kCosineHemisphere},
      {Defect::kGgxDWithoutInvPi, Strategy::kCosineHemisphere},
      {Defect::kGgxVndfPdfWithoutG1, Strategy::kBsdf}};
  for (const auto& [d, strategy] : controls) {
    const Misses m = render_misses(ggx_floor(MicrofacetShadowing::kHeightCorrelated, 80), strategy, d);
    std::cout << "  " << strategy_name(strategy) << " + " << defect_name(d) << " at 80 deg: " << m.inconsistent << "/"
              << m.pixels << " pixels inconsistent\n";
    EXPECT_EQ(m.inconsistent, m.pixels) << defect_name(d);
  }
}

}  // namespace
}  // namespace furnace
