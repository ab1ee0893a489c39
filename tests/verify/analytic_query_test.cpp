// `furnace analytic --json` carries an error bound beside every value it
// computes: on every built-in scene, at the point a few camera rays hit, each
// number of the answer other than the query's own inputs (point, normal,
// albedo) has a sibling "<name>_error_bound" that is a finite number ≥ 0, and
// every estimator is either unsupported (with its reason) or carries all four
// of second moment, variance and their bounds.
#include <cmath>
#include <limits>
#include <cstdio>
#include <filesystem>
#include <set>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "analytic/error_ledger.h"
#include "analytic/glossy.h"
#include "analytic/phong.h"
#include "analytic/receiver.h"
#include "analytic/reference.h"
#include "core/error.h"
#include "analytic/glass.h"
#include "core/scene.h"
#include "verify/analytic_query.h"

namespace furnace::verify {
namespace {

// The query's inputs, echoed back: not computed, so no bound.
const std::set<std::string> kInputs{"point", "normal", "albedo"};

// Checks every numeric member of `object` (not an input) against its bound;
// returns how many values were checked.
int check_bounds(const nlohmann::json& object, const std::string& where) {
  int checked = 0;
  for (const auto& [key, value] : object.items()) {
    if (!value.is_number() || kInputs.count(key) || (key.size() > 12 && key.substr(key.size() - 12) == "_error_bound"))
      continue;
    const std::string bound_key = key + "_error_bound";
    EXPECT_TRUE(object.contains(bound_key)) << where << ": '" << key << "' has no '" << bound_key << "'";
    if (!object.contains(bound_key)) continue;
    const nlohmann::json& bound = object[bound_key];
    EXPECT_TRUE(bound.is_number() && std::isfinite(bound.get<double>()) && bound.get<double>() >= 0)
        << where << ": '" << bound_key << "' is " << bound.dump();
    ++checked;
  }
  return checked;
}

TEST(AnalyticQueryJson, EveryValueCarriesAnErrorBound) {
  int scenes = 0, queries = 0, values = 0;
  for (const auto& entry : std::filesystem::directory_iterator(FURNACE_SCENE_DIR)) {
    if (entry.path().extension() != ".json") continue;
    const Scene scene = load_scene(entry.path());
    ++scenes;
    const int w = scene.camera.width_px, h = scene.camera.height_px;
    for (const auto& [px, py] : {std::pair{w / 2, h / 2}, std::pair{w / 4, h / 4}, std::pair{3 * w / 4, 3 * h / 4}}) {
      const Camera::Ray ray = scene.camera.pixel_center_ray(px, py);
      const auto hit = analytic::intersect(scene, ray.origin, ray.direction);
      if (!hit) continue;
      AnalyticQuery q;
      q.point = hit->point;
      q.normal = dot(hit->normal, ray.direction) < 0 ? hit->normal : -hit->normal;
      const std::string where = scene.name + " pixel (" + std::to_string(px) + ", " + std::to_string(py) + ")";
      nlohmann::json answer;
      try {
        answer = nlohmann::json::parse(answer_analytic_query(scene, q, true));
      } catch (const Error&) {
        continue;  // the irradiance itself is outside what analytic/ solves here
      }
      ++queries;
      values += check_bounds(answer, where);
      ASSERT_TRUE(answer.contains("estimators")) << where;
      for (const auto& [name, estimator] : answer["estimators"].items()) {
        if (estimator.contains("unsupported")) {
          EXPECT_TRUE(estimator["unsupported"].is_string()) << where << " " << name;
          continue;
        }
        for (const char* key : {"second_moment", "variance"})
          EXPECT_TRUE(estimator.contains(key)) << where << " " << name << " has no " << key;
        values += check_bounds(estimator, where + " " + name);
      }
    }
  }
  std::printf("[ analytic --json ] %d scenes, %d queries, %d values, each with a finite error bound\n", scenes, queries,
              values);
  EXPECT_GT(queries, 20);
}

// A glossy receiver is answered with its own BSDF toward a view direction,
// never as a Lambertian surface: glossy_environment's Phong n = 10 strip,
// seen by the scene's camera at 70° from the normal, where the horizon cuts
// the lobe (the Lambertian answer would be L_env·ρ = 1.2).
struct GlossyQuery : testing::Test {
  Scene scene = load_scene(std::string(FURNACE_SCENE_DIR) + "/glossy_environment.json");
  AnalyticQuery q;
  size_t receiver = 0;  // phong10
  GlossyQuery() {
    q.point = {-0.75, 0, 0};
    q.normal = {0, 0, 1};
  }
  nlohmann::json answer() const { return nlohmann::json::parse(answer_analytic_query(scene, q, true)); }
};

TEST_F(GlossyQuery, ViewFromTheCameraAndTheReceiversOwnBsdf) {
  const nlohmann::json a = answer();
  const Vec3 wo = -scene.camera.forward;
  EXPECT_EQ(a["receiver"], "phong10");
  EXPECT_EQ(a["bsdf"]["type"], "phong");
  EXPECT_EQ(a["bsdf"]["exponent"].get<double>(), 10.0);
  EXPECT_EQ(a["view_source"], "the camera");
  EXPECT_EQ(a["view"][1].get<double>(), wo.y);
  EXPECT_EQ(a["view"][2].get<double>(), wo.z);
  const double expected = analytic::glossy_reflected_radiance(scene, q.point, q.normal, wo, receiver);
  EXPECT_EQ(a["radiance"].get<double>(), expected);
  const double lambertian = scene.environment.radiance * scene.objects[receiver].material.albedo;
  EXPECT_GT(std::fabs(a["radiance"].get<double>() - lambertian), 0.1 * lambertian);  // the horizon cuts the lobe
  // Every direct strategy, each the Phong estimator's moment; none is the
  // Lambertian one (cosine sampling of a Lambertian sky has variance 0).
  EXPECT_EQ(a["estimators"].size(), direct_strategies().size());
  for (Strategy s : direct_strategies()) {
    const nlohmann::json& e = a["estimators"][strategy_name(s)];
    EXPECT_EQ(e["second_moment"].get<double>(),
              analytic::glossy_second_moment(s, scene, q.point, q.normal, wo, receiver))
        << strategy_name(s);
    EXPECT_GT(e["variance"].get<double>(), 0.0) << strategy_name(s);
  }
}

TEST_F(GlossyQuery, ViewOptionAndAlbedoOverride) {
  q.view = Vec3(0, 0, 1);
  q.estimators = {Strategy::kBsdf};
  const nlohmann::json normal_view = answer();
  EXPECT_EQ(normal_view["view_source"], "--view");
  // At normal view no lobe direction is below the horizon: the albedo ρ.
  EXPECT_NEAR(normal_view["radiance"].get<double>(), 1.2, 1e-12);
  q.albedo = 0.4;  // f scales with the albedo, E[Y²] with its square
  const nlohmann::json half = answer();
  EXPECT_DOUBLE_EQ(half["radiance"].get<double>(), 0.5 * normal_view["radiance"].get<double>());
  EXPECT_DOUBLE_EQ(half["estimators"]["bsdf"]["second_moment"].get<double>(),
                   0.25 * normal_view["estimators"]["bsdf"]["second_moment"].get<double>());
}

TEST_F(GlossyQuery, ViewBelowTheHorizonIsRefusedNamingIt) {
  q.view = Vec3(0, 0.3, -1);
  try {
    answer();
    ADD_FAILURE() << "a view below the horizon was answered";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("not above the horizon of the receiver 'phong10'"), std::string::npos)
        << e.what();
  }
}

// A GGX receiver: ggx_oblique_sky_78's separable α = 1 strip under the sky,
// seen by the camera at cos θo = 0.2; its directional albedo has the closed
// form 2(1 − ln 2)ρ/(1 + μo) (analytic/ggx.cpp derives it).
TEST(AnalyticQueryGgx, RadianceOfTheReceiversOwnMicrofacets) {
  const Scene scene = load_scene(std::string(FURNACE_SCENE_DIR) + "/ggx_oblique_sky_78.json");
  AnalyticQuery q;
  q.point = {-0.75, 0, 0};
  q.normal = {0, 0, 1};
  const nlohmann::json a = nlohmann::json::parse(answer_analytic_query(scene, q, true));
  EXPECT_EQ(a["receiver"], "ggx_a1_sep");
  EXPECT_EQ(a["bsdf"]["type"], "ggx");
  EXPECT_EQ(a["bsdf"]["alpha"].get<double>(), 1.0);
  EXPECT_EQ(a["bsdf"]["shadowing"], "separable");
  const double mu_o = -scene.camera.forward.z;
  const double rho = scene.objects[0].material.albedo;
  const double closed_form = scene.environment.radiance * 2 * (1 - std::log(2.0)) * rho / (1 + mu_o);
  EXPECT_NEAR(a["radiance"].get<double>(), closed_form, 1e-12 * closed_form);
  // The bound is what the quadratures report (an ErrorLedger), not a fixed
  // tolerance: it covers the actual error, stays small, and is not the
  // requested 2·kReceiverQuadratureTolerance + 64 ε.
  const double bound = a["radiance_error_bound"].get<double>();
  EXPECT_LE(std::fabs(a["radiance"].get<double>() - closed_form), bound);
  EXPECT_LT(bound, 1e-8 * closed_form);
  const double fixed = closed_form * (2 * analytic::kReceiverQuadratureTolerance +
                                      analytic::kRoundoffUlps * std::numeric_limits<double>::epsilon());
  EXPECT_GT(std::fabs(bound - fixed), 1e-3 * fixed) << "the bound is the requested tolerance, not a measured one";
  for (Strategy s : direct_strategies()) {
    EXPECT_GT(a["estimators"][strategy_name(s)]["variance"].get<double>(), 0.0) << strategy_name(s);
    EXPECT_GT(a["estimators"][strategy_name(s)]["second_moment_error_bound"].get<double>(), 0.0) << strategy_name(s);
  }
}

// A smooth glass interface (glass_smooth_outside_60: η 1.5, constant
// environment 1) answered toward an explicit view from either side, against
// Fresnel's amplitudes written out here: r⊥ = (c − η ct)/(c + η ct),
// r∥ = (η c − ct)/(η c + ct), ct from Snell, R = (r⊥² + r∥²)/2; the radiance
// convention sees R + T/η′² (η′ the far side's index over the viewer's).
double textbook_fresnel(double c, double eta) {
  const double s2 = 1 - c * c;
  const double st2 = s2 / (eta * eta);
  if (st2 >= 1) return 1;
  const double ct = std::sqrt(1 - st2);
  const double r_perp = (c - eta * ct) / (c + eta * ct), r_par = (eta * c - ct) / (eta * c + ct);
  return (r_perp * r_perp + r_par * r_par) / 2;
}
TEST(AnalyticQueryDielectric, ExplicitViewFromEitherSideAgainstFresnelByHand) {
  const Scene scene = load_scene(std::string(FURNACE_SCENE_DIR) + "/glass_smooth_outside_60.json");
  AnalyticQuery q;
  q.point = {0.1, 0.2, 0};
  q.normal = {0, 0, 1};
  const auto radiance = [&] { return nlohmann::json::parse(answer_analytic_query(scene, q, true))["radiance"].get<double>(); };
  const double camera_default = radiance();
  // The camera's own direction given explicitly: the same answer.
  q.view = -scene.camera.forward;
  EXPECT_EQ(radiance(), camera_default);
  const double r60 = textbook_fresnel(0.5, 1.5);
  EXPECT_NEAR(camera_default, r60 + (1 - r60) / 2.25, 1e-14);
  // From inside at 30° (below the plane): η′ = 1/1.5, what is transmitted gains η² = 2.25.
  const double c30 = std::sqrt(3.0) / 2;
  q.view = Vec3(0, -0.5, -c30);
  const double r30 = textbook_fresnel(c30, 1 / 1.5);
  EXPECT_NEAR(radiance(), r30 + (1 - r30) * 2.25, 1e-13);
  // From inside past the critical angle (60° > 41.8°): total internal reflection, 1 exactly.
  q.view = Vec3(0, -c30, -0.5);
  EXPECT_NEAR(radiance(), 1.0, 1e-15);
  // The none convention: nothing scaled, 1 from either side.
  q.convention = TransportConvention::kNone;
  q.view = -scene.camera.forward;
  EXPECT_NEAR(radiance(), 1.0, 1e-15);
  // Negative control: the hand value at 60° is not what another view gives.
  q.convention = TransportConvention::kRadiance;
  q.view = Vec3(0, -std::sqrt(0.5), std::sqrt(0.5));
  EXPECT_GT(std::fabs(radiance() - (r60 + (1 - r60) / 2.25)), 1e-3);
}

// A sky on one side (glass_sky_inside_30: radiance 1 above the plane, 0
// below): at the smooth strip, from above at 60° only the reflection R shows
// the sky, from below at 30° only the transmission 2.25·(1 − R′), by hand;
// the bsdf strategy's E[Y²] is the lit lobe's alone. Negative control: the
// same views under the constant environment see both lobes.
TEST(AnalyticQueryDielectric, SkyOnOneSideShowsOneLobeFromEachSide) {
  Scene scene = load_scene(std::string(FURNACE_SCENE_DIR) + "/glass_sky_inside_30.json");
  AnalyticQuery q;
  q.point = {-0.9, 0.2, 0};  // the smooth strip
  q.normal = {0, 0, 1};
  const auto answer = [&] { return nlohmann::json::parse(answer_analytic_query(scene, q, true)); };
  const double c30 = std::sqrt(3.0) / 2;
  const double t30 = 2.25 * (1 - textbook_fresnel(c30, 1 / 1.5));
  const nlohmann::json below = answer();  // the camera's view, from below at 30°
  EXPECT_NEAR(below["radiance"].get<double>(), t30, 1e-14);
  EXPECT_EQ(below["environment_radiance_view_side"], 0.0);
  EXPECT_EQ(below["environment_radiance_far_side"], 1.0);
  EXPECT_NEAR(below["estimators"]["bsdf"]["second_moment"].get<double>(), 2.25 * t30, 1e-13);
  q.view = Vec3(0, -c30, 0.5);  // from above at 60°
  const double r60 = textbook_fresnel(0.5, 1.5);
  EXPECT_NEAR(answer()["radiance"].get<double>(), r60, 1e-15);
  scene.environment.map.reset();
  EXPECT_NEAR(answer()["radiance"].get<double>(), r60 + (1 - r60) / 2.25, 1e-14);
  q.view.reset();
  EXPECT_GT(std::fabs(answer()["radiance"].get<double>() - t30), 0.01);
}

// A rough interface's answer is the directional albedos of analytic/glass.h,
// bounded by their quadrature tolerance; a glass sphere is refused at a point.
TEST(AnalyticQueryDielectric, RoughInterfaceAndSphere) {
  const Scene strips = load_scene(std::string(FURNACE_SCENE_DIR) + "/glass_rough_outside_60.json");
  AnalyticQuery q;
  q.point = {-0.75, 0, 0};
  q.normal = {0, 0, 1};
  const nlohmann::json a = nlohmann::json::parse(answer_analytic_query(strips, q, true));
  EXPECT_EQ(a["receiver"], "glass_a0.1");
  EXPECT_EQ(a["view_side"], "outside");
  const double e_r = a["reflection_albedo"].get<double>(), e_t = a["transmission_albedo"].get<double>();
  EXPECT_DOUBLE_EQ(a["radiance"].get<double>(), e_r + e_t / 2.25);
  EXPECT_GT(e_r, 0.0);
  EXPECT_LT(e_r + e_t, 1.0);  // a rough interface loses what its model sends to the wrong side
  EXPECT_GT(a["radiance_error_bound"].get<double>(), 0.0);
  // Every direct strategy that samples the BSDF or the environment has its
  // second moment (dielectric_interface_mis_moments at albedo 1, L 1); the
  // hemisphere ones are refused (the negative control).
  ASSERT_EQ(strips.objects[0].name, "glass_a0.1");
  const Dielectric& d = *strips.objects[0].material.as<Dielectric>();
  const analytic::InterfaceMisMoments mis =
      analytic::dielectric_interface_mis_moments(d, 1.5, -strips.camera.forward.z, TransportConvention::kRadiance);
  const nlohmann::json& est = a["estimators"];
  EXPECT_EQ(est["mis_balance"]["second_moment"].get<double>(), mis.balance);
  EXPECT_EQ(est["mis_power"]["second_moment"].get<double>(), mis.power);
  EXPECT_EQ(est["mis_one_sample"]["second_moment"].get<double>(), mis.one_sample);
  EXPECT_EQ(est["light_area"]["second_moment"].get<double>(), mis.light);
  EXPECT_EQ(est["light_solid_angle"]["second_moment"].get<double>(), mis.light);
  EXPECT_GT(est["mis_balance"]["second_moment_error_bound"].get<double>(), 0.0);
  // The variance E[Y²] − L² is at most the bsdf strategy's for power MIS here, and positive.
  EXPECT_GT(est["mis_power"]["variance"].get<double>(), 0.0);
  EXPECT_FALSE(est.contains("cosine_hemisphere"));
  q.estimators = {Strategy::kCosineHemisphere};
  const nlohmann::json refused = nlohmann::json::parse(answer_analytic_query(strips, q, true));
  EXPECT_TRUE(refused["estimators"]["cosine_hemisphere"].contains("unsupported")) << refused.dump();
  q.estimators.clear();
  const Scene sphere = load_scene(std::string(FURNACE_SCENE_DIR) + "/glass_sphere.json");
  q.point = {0, 0, 1};
  try {
    answer_analytic_query(sphere, q, false);
    ADD_FAILURE() << "a point on the glass sphere was answered";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("is a sphere"), std::string::npos) << e.what();
  }
}

TEST(AnalyticQueryMirror, AMirrorReceiverIsRefused) {
  const Scene scene = load_scene(std::string(FURNACE_SCENE_DIR) + "/mirror_disk.json");
  AnalyticQuery q;
  q.point = {0.2, 0.1, 0};
  q.normal = {0, 0, 1};
  try {
    answer_analytic_query(scene, q, false);
    ADD_FAILURE() << "a mirror receiver was answered";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'mirror' at the point is a mirror"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace furnace::verify
