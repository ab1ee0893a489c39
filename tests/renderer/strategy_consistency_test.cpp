// The consistency MIS relies on, through the renderer's strategies on the
// committed scenes (scenes/*.json), at the first hits of camera rays, for
// every direct strategy of the table:
//  - direction strategies (uniform_hemisphere, cosine_hemisphere, bsdf):
//    sample().pdf == pdf(ctx, wi) and weight == eval·cos θ/pdf;
//  - the MIS strategies (mis_balance, mis_power, mis_one_sample): both of
//    the strategies they draw from (bsdf and light_solid_angle);
//  - light strategies (light_area, light_solid_angle): for an unoccluded
//    sample, the pdf() of the direction and the hit its ray finds equals the
//    pdf sample() reported (environment samples: the ray escapes), and
//    weight == eval·cos θ/pdf.
// Negative control: Defect::kPdfOffByConstant must break the weight identity
// for every strategy kind.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <memory>
#include <string>
#include <tuple>
#include <variant>

#include "renderer/direct_strategies.h"
#include "renderer/embree_scene.h"
#include "renderer/light_strategy.h"
#include "renderer/lights.h"
#include "tests/test_names.h"

namespace furnace {
namespace {

constexpr uint64_t kSeed = 0xc0515;
constexpr int kPixelStride = 5;          // every 5th pixel in x and y
constexpr int kSamplesPerPoint = 64;
constexpr double kEps = 2.220446049250313e-16;
// Exact identities (same arithmetic up to a division): a few ulps.
constexpr double kExactRelTol = 16 * kEps;
// The light pdf of a traced hit: Embree's float hit refined in double (see
// tests/renderer/strategy_test.cpp).
constexpr double kTracedPdfRelTol = 1e-5;

struct World {
  Scene scene;
  std::unique_ptr<EmbreeDevice> device;
  std::unique_ptr<EmbreeScene> rtc;
  std::unique_ptr<LightSet> lights;
  // `receiver`: when given, the material of every non-black object (a GGX
  // surface for the GGX battery); emission is unchanged.
  explicit World(const std::string& file, const Material* receiver = nullptr)
      : scene(load_scene(std::string(FURNACE_SCENE_DIR) + "/" + file)) {
    if (receiver != nullptr)
      for (Object& o : scene.objects)
        if (o.material.albedo > 0) o.material = *receiver;
    device = std::make_unique<EmbreeDevice>();
    rtc = std::make_unique<EmbreeScene>(*device, scene);
    lights = std::make_unique<LightSet>(scene);
  }
  // Shading contexts at the camera rays' first hits on non-black surfaces.
  std::vector<ShadingContext> contexts() const {
    std::vector<ShadingContext> out;
    for (int py = 0; py < scene.camera.height_px; py += kPixelStride)
      for (int px = 0; px < scene.camera.width_px; px += kPixelStride) {
        const Camera::Ray ray = scene.camera.pixel_center_ray(px, py);
        const auto hit = rtc->intersect(ray.origin, ray.direction);
        if (!hit) continue;
        const Material& m = scene.objects[hit->object].material;
        if (!(m.albedo > 0)) continue;
        out.push_back(ShadingContext::at(*hit, -ray.direction, m));
      }
    return out;
  }
};

const std::vector<std::string> kScenes{"sphere_light.json", "rectangle_light.json", "three_lights.json",
                                       "environment_blocker.json", "polygon_occluder.json", "disk_occluder.json"};

double expected_weight(const ShadingContext& ctx, const Vec3& wi_world, double pdf) {
  const Vec3 wi_local = ctx.frame.local_from_world(wi_world);
  return ctx.bsdf.eval(ctx.wo_local, wi_local) * std::fmax(wi_local.z, 0.0) / pdf;
}

struct Counts {
  int checked = 0;
  int pdf_mismatches = 0;
  int weight_mismatches = 0;
  double worst_relative = 0;  // largest relative deviation of a pdf or weight seen
};

// |a/b − 1|, the deviation each check compares with its tolerance.
double relative_deviation(double a, double b) { return b != 0 ? std::fabs(a - b) / std::fabs(b) : (a == b ? 0.0 : 1.0); }

template <class Strategy>
Counts check_direction_strategy(const World& w, const Strategy& strategy) {
  Counts c;
  uint64_t point = 0;
  for (const ShadingContext& ctx : w.contexts()) {
    ++point;
    for (int i = 0; i < kSamplesPerPoint; ++i) {
      Rng rng(kSeed, point, uint64_t(i));
      const auto s = strategy.sample(ctx, next_uniform3(rng));
      if (!s || s->delta) continue;
      ++c.checked;
      const double pdf = strategy.pdf(ctx, s->wi_world);
      if (!(std::fabs(pdf - s->pdf_solid_angle) <= kExactRelTol * pdf)) ++c.pdf_mismatches;
      const double weight = expected_weight(ctx, s->wi_world, pdf);
      if (!(std::fabs(weight - s->weight) <= kExactRelTol * weight)) ++c.weight_mismatches;
      c.worst_relative = std::fmax(c.worst_relative, std::fmax(relative_deviation(s->pdf_solid_angle, pdf),
                                                                relative_deviation(s->weight, weight)));
    }
  }
  return c;
}

Counts check_light_strategy(const World& w, EmitterSampling mode, Defect defect) {
  const LightStrategy strategy{w.rtc.get(), w.lights.get(), mode, defect};
  Counts c;
  uint64_t point = 0;
  TraceCounters counters;
  for (const ShadingContext& ctx : w.contexts()) {
    ++point;
    for (int i = 0; i < kSamplesPerPoint; ++i) {
      Rng rng(kSeed, point, uint64_t(i));
      const auto s = strategy.sample(ctx, next_uniform3(rng));
      if (!s || !light_visible(*w.rtc, *s, counters)) continue;
      const auto hit = trace_from(*w.rtc, ctx, s->wi_world, counters);
      ++c.checked;
      // The traced ray starts at the shading point itself and meets the light
      // at its refined hit point, which differs from the sampled point by
      // round-off only.
      const double tol = hit ? kTracedPdfRelTol : kExactRelTol;
      const double pdf = strategy.pdf(ctx, s->wi_world, hit);
      if (!(std::fabs(pdf / s->pdf_solid_angle - 1) <= tol)) ++c.pdf_mismatches;
      const double weight = expected_weight(ctx, s->wi_world, s->pdf_solid_angle);
      if (!(std::fabs(weight - s->weight) <= kExactRelTol * weight)) ++c.weight_mismatches;
      c.worst_relative = std::fmax(c.worst_relative, relative_deviation(s->weight, weight));
    }
  }
  return c;
}

Counts& operator+=(Counts& a, const Counts& b) {
  a.checked += b.checked;
  a.pdf_mismatches += b.pdf_mismatches;
  a.weight_mismatches += b.weight_mismatches;
  a.worst_relative = std::fmax(a.worst_relative, b.worst_relative);
  return a;
}

// The checks of a direct strategy, by what it samples. Every enumerator is
// named and there is no default: a new strategy fails the build here
// (-Werror=switch) until this battery knows how to check it.
Counts check(const World& w, Strategy strategy, Defect defect) {
  switch (strategy) {
    case Strategy::kUniformHemisphere: return check_direction_strategy(w, UniformHemisphereStrategy{defect});
    case Strategy::kCosineHemisphere: return check_direction_strategy(w, CosineHemisphereStrategy{defect});
    case Strategy::kBsdf: return check_direction_strategy(w, BsdfStrategy{defect});
    case Strategy::kLightArea: return check_light_strategy(w, EmitterSampling::kArea, defect);
    case Strategy::kLightSolidAngle: return check_light_strategy(w, EmitterSampling::kSolidAngle, defect);
    // MIS draws its samples from bsdf and light_solid_angle and weighs them by
    // those two strategies' pdf(): both must agree with what they sample.
    case Strategy::kMisBalance:
    case Strategy::kMisPower:
    case Strategy::kMisOneSample: {
      Counts c = check_direction_strategy(w, BsdfStrategy{defect});
      c += check_light_strategy(w, EmitterSampling::kSolidAngle, defect);
      return c;
    }
    case Strategy::kPathNaive:
    case Strategy::kPathMis: break;
  }
  ADD_FAILURE() << strategy_name(strategy) << " is not a direct strategy";
  return {};
}

// Every direct strategy of core/strategy.h's table.
const std::vector<Strategy> kStrategies = direct_strategies();

class StrategyConsistency : public testing::TestWithParam<std::string> {};

TEST_P(StrategyConsistency, PdfOfSampledDirectionAndWeightAgree) {
  const World w(GetParam());
  for (Strategy s : kStrategies) {
    const Counts c = check(w, s, Defect::kNone);
    std::cout << "  " << GetParam() << " " << strategy_name(s) << ": " << c.checked << " samples, "
              << c.pdf_mismatches << " pdf and " << c.weight_mismatches << " weight mismatches\n";
    EXPECT_GT(c.checked, 100) << strategy_name(s);
    EXPECT_EQ(c.pdf_mismatches, 0) << strategy_name(s);
    EXPECT_EQ(c.weight_mismatches, 0) << strategy_name(s);
  }
}

// Negative control: with the pdf in the weight 1.1× the true one, every
// checked sample's weight disagrees with eval·cos/pdf.
TEST_P(StrategyConsistency, PdfOffByConstantIsDetected) {
  const World w(GetParam());
  for (Strategy s : kStrategies) {
    const Counts c = check(w, s, Defect::kPdfOffByConstant);
    std::cout << "  " << GetParam() << " " << strategy_name(s) << "+pdf_off_by_constant: " << c.weight_mismatches
              << "/" << c.checked << " weight mismatches\n";
    EXPECT_GT(c.checked, 100) << strategy_name(s);
    EXPECT_EQ(c.weight_mismatches, c.checked) << strategy_name(s);
  }
}

// Negative control of the pdf check: uniform-hemisphere samples checked
// against the cosine strategy's pdf, and light_solid_angle samples against
// area sampling's pdf (the same on scenes whose emitters are all disks,
// sampled by area in both modes; different wherever a cone or spherical
// polygon is used).
TEST_P(StrategyConsistency, WrongPdfIsDetected) {
  const World w(GetParam());
  int checked = 0, mismatches = 0;
  uint64_t point = 0;
  const UniformHemisphereStrategy uniform;
  const CosineHemisphereStrategy cosine;
  for (const ShadingContext& ctx : w.contexts()) {
    ++point;
    for (int i = 0; i < kSamplesPerPoint; ++i) {
      Rng rng(kSeed, point, uint64_t(i));
      const auto s = uniform.sample(ctx, next_uniform3(rng));
      if (!s) continue;
      ++checked;
      const double wrong = cosine.pdf(ctx, s->wi_world);
      mismatches += std::fabs(wrong - s->pdf_solid_angle) <= kExactRelTol * s->pdf_solid_angle ? 0 : 1;
    }
  }
  std::cout << "  " << GetParam() << " uniform_hemisphere vs cosine pdf: " << mismatches << "/" << checked
            << " mismatches\n";
  EXPECT_GT(mismatches, checked * 9 / 10);

  const LightStrategy solid{w.rtc.get(), w.lights.get(), EmitterSampling::kSolidAngle, Defect::kNone};
  const LightStrategy area{w.rtc.get(), w.lights.get(), EmitterSampling::kArea, Defect::kNone};
  int light_checked = 0, light_mismatches = 0;
  TraceCounters counters;
  point = 0;
  for (const ShadingContext& ctx : w.contexts()) {
    ++point;
    for (int i = 0; i < kSamplesPerPoint; ++i) {
      Rng rng(kSeed, point, uint64_t(i));
      const auto s = solid.sample(ctx, next_uniform3(rng));
      if (!s || !light_visible(*w.rtc, *s, counters)) continue;
      const auto hit = trace_from(*w.rtc, ctx, s->wi_world, counters);
      ++light_checked;
      light_mismatches += std::fabs(area.pdf(ctx, s->wi_world, hit) / s->pdf_solid_angle - 1) <= 1e-3 ? 0 : 1;
    }
  }
  std::cout << "  " << GetParam() << " light_solid_angle vs area pdf: " << light_mismatches << "/" << light_checked
            << " mismatches\n";
  bool has_solid_angle_emitter = false;
  for (const Object& o : w.scene.objects)
    has_solid_angle_emitter = has_solid_angle_emitter || (o.is_emitter() && !std::holds_alternative<Disk>(o.shape));
  if (has_solid_angle_emitter) {
    EXPECT_GT(light_mismatches, light_checked / 10);
  }
  else EXPECT_EQ(light_mismatches, 0);
}

// The same battery with every non-black surface GGX, for both forms of G2
// and roughnesses from near-specular to 1, with its pdf_off_by_constant
// control. The direction strategies' pdf() and eval() see wi after a
// world → local round trip, which a narrow GGX lobe would amplify (D(h)
// moves by up to ~2δ/α relative for a change δ of h); on these scenes the
// receivers are axis-aligned, the round trip is exact (worst deviation
// measured: 0) and the exact tolerance holds.
class StrategyConsistencyGgx : public testing::TestWithParam<std::tuple<std::string, double, MicrofacetShadowing>> {};

TEST_P(StrategyConsistencyGgx, PdfOfSampledDirectionAndWeightAgree) {
  const auto& [file, alpha, shadowing] = GetParam();
  Material ggx{0.8, Ggx{alpha, shadowing, std::nullopt}};
  const World w(file, &ggx);
  for (Strategy s : kStrategies) {
    const Counts c = check(w, s, Defect::kNone);
    std::cout << "  " << file << " ggx " << alpha << " " << microfacet_shadowing_name(shadowing) << " "
              << strategy_name(s) << ": " << c.checked << " samples, " << c.pdf_mismatches << " pdf and "
              << c.weight_mismatches << " weight mismatches, worst relative deviation " << c.worst_relative << "\n";
    EXPECT_GT(c.checked, 100) << strategy_name(s);
    EXPECT_EQ(c.pdf_mismatches, 0) << strategy_name(s);
    EXPECT_EQ(c.weight_mismatches, 0) << strategy_name(s);
    const Counts control = check(w, s, Defect::kPdfOffByConstant);
    EXPECT_EQ(control.weight_mismatches, control.checked) << strategy_name(s) << " + pdf_off_by_constant";
  }
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, StrategyConsistencyGgx,
    testing::Combine(testing::Values("sphere_light.json", "rectangle_light.json", "environment_blocker.json"),
                     testing::Values(1e-2, 0.3, 1.0),
                     testing::Values(MicrofacetShadowing::kSeparable, MicrofacetShadowing::kHeightCorrelated)),
    [](const auto& info) {
      const std::string file = std::get<0>(info.param);
      const double alpha = std::get<1>(info.param);
      return testing_support::camel_case(file.substr(0, file.find('.'))) + "Alpha" +
             (alpha == 1e-2 ? "0p01" : alpha == 0.3 ? "0p3" : "1") +
             (std::get<2>(info.param) == MicrofacetShadowing::kSeparable ? "Separable" : "HeightCorrelated");
    });

INSTANTIATE_TEST_SUITE_P(Scenes, StrategyConsistency, testing::ValuesIn(kScenes), [](const auto& info) {
  return testing_support::camel_case(info.param.substr(0, info.param.find('.')));
});

}  // namespace
}  // namespace furnace
