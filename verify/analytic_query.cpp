#include "verify/analytic_query.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <optional>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "analytic/error_ledger.h"
#include "analytic/glass.h"
#include "analytic/glass_light.h"
#include "analytic/glossy.h"
#include "analytic/moments.h"
#include "analytic/receiver.h"
#include "analytic/reference.h"
#include "core/error.h"
#include "core/strategy.h"

namespace furnace::verify {

namespace {

// The object p lies on, if any: the first surface a short ray from just
// above p back along −n meets within a relative distance of p. Excluded from
// the occluders like a renderer's hit surface.
std::optional<size_t> receiver_at(const Scene& scene, const Vec3& p, const Vec3& n) {
  // Relative offset: 1e-9 of the point's magnitude (double precision leaves
  // ~7 digits of margin), at least 1e-9 scene units.
  const double delta = 1e-9 * std::fmax(1.0, max_abs_component(p));
  const auto hit = analytic::intersect(scene, p + n * delta, -n, 0);
  if (hit && hit->t <= 2 * delta) return hit->object_index;
  return std::nullopt;
}

// The view direction of a glossy query: --view, else the camera's (every
// furnace camera is orthographic: the direction toward it is −forward).
struct View {
  Vec3 direction;
  const char* source;
};
View view_of(const Scene& scene, const AnalyticQuery& q, const std::string& receiver_name) {
  View view = q.view ? View{normalize(*q.view), "--view"} : View{-scene.camera.forward, "the camera"};
  view.direction = view.direction + Vec3(0, 0, 0);  // −0 components to +0, for the printed direction
  if (!(dot(view.direction, q.normal) > 0))
    throw Error(fmt::format("scene file '{}': the view direction ({:.17g}, {:.17g}, {:.17g}) from {} is not above the "
                            "horizon of the receiver '{}' at the point (normal ({:.17g}, {:.17g}, {:.17g})); give "
                            "--view toward the side the normal faces.",
                            scene.source, view.direction.x, view.direction.y, view.direction.z, view.source,
                            receiver_name, q.normal.x, q.normal.y, q.normal.z));
  return view;
}

// The BSDF's name and parameters, as the JSON and the text show them: the
// material the receiver says it models, each field as the scene file names it.
nlohmann::ordered_json bsdf_json(const Material& m) {
  nlohmann::ordered_json j;
  j["type"] = bsdf_type_name(m.type());
  j["albedo"] = m.albedo;
  for (const MaterialField& f : m.fields()) {
    if (f.word)
      j[f.name] = f.word;
    else
      j[f.name] = f.number;
  }
  return j;
}
std::string bsdf_text(const nlohmann::ordered_json& bsdf) {
  std::string text = bsdf["type"].get<std::string>() + " (";
  bool first = true;
  for (const auto& [key, value] : bsdf.items()) {
    if (key == "type") continue;
    text += (first ? "" : ", ") + key + " " +
            (value.is_string() ? value.get<std::string>() : fmt::format("{:.17g}", value.get<double>()));
    first = false;
  }
  return text + ")";
}

// The JSON answer's opening of a receiver seen along a view (glossy, dielectric).
nlohmann::ordered_json view_query_json(const Scene& scene, const AnalyticQuery& q, const std::string& receiver,
                                       const nlohmann::ordered_json& bsdf, const View& view) {
  nlohmann::ordered_json j;
  j["scene"] = scene.name;
  j["point"] = {q.point.x, q.point.y, q.point.z};
  j["normal"] = {q.normal.x, q.normal.y, q.normal.z};
  j["receiver"] = receiver;
  j["bsdf"] = bsdf;
  j["view"] = {view.direction.x, view.direction.y, view.direction.z};
  j["view_source"] = view.source;
  return j;
}

// A value computed under an ErrorLedger, with the bound its quadratures report.
struct BoundedValue {
  double value = 0, bound = 0;
};
template <class F>
BoundedValue with_ledger(const F& f) {
  const analytic::ErrorLedger ledger;
  const double value = f();
  return {value, ledger.bound(value)};
}

// Each requested estimator's row (`defaults` when none is requested) in the
// text and the JSON: E[Y²] and its bound from second_moment(strategy) (a
// BoundedValue), and the variance E[Y²] − L² with its bound (both terms'
// bounds and the subtraction's own rounding). An estimator second_moment
// refuses (furnace::Error) is named unsupported, with the reason.
template <class SecondMoment>
void estimator_rows(const std::vector<Strategy>& requested, const std::vector<Strategy>& defaults, double radiance,
                    double radiance_bound, nlohmann::ordered_json& j, std::string& text,
                    const SecondMoment& second_moment) {
  for (const Strategy strategy : requested.empty() ? defaults : requested) {
    const std::string& est = strategy_name(strategy);
    std::string moment_text, variance_text;
    try {
      const BoundedValue m2 = second_moment(strategy);
      const double variance = m2.value - radiance * radiance;
      const double variance_bound = m2.bound + 2 * std::fabs(radiance) * radiance_bound +
                                    radiance_bound * radiance_bound +
                                    std::numeric_limits<double>::epsilon() * std::fabs(m2.value);
      j["estimators"][est] = {{"second_moment", m2.value},
                              {"second_moment_error_bound", m2.bound},
                              {"variance", variance},
                              {"variance_error_bound", variance_bound}};
      moment_text = fmt::format("{:.17g} ± {:.2g}", m2.value, m2.bound);
      variance_text = fmt::format("{:.17g} ± {:.2g}", variance, variance_bound);
    } catch (const Error& err) {
      j["estimators"][est] = {{"unsupported", err.what()}};
      moment_text = "unsupported";
      variance_text = err.what();
    }
    text += fmt::format("  {:<20} E[Y^2] {:<34} Var {}\n", est, moment_text, variance_text);
  }
}

// Every direct strategy: the default rows of a receiver-model query.
std::vector<Strategy> direct_strategies() {
  std::vector<Strategy> out;
  for (const StrategyInfo& info : kStrategyTable)
    if (!is_path_tracer(info.strategy)) out.push_back(info.strategy);
  return out;
}

// The glossy receiver's answer: its radiance toward the view and each direct
// strategy's single-sample estimator of it. Each value's bound is what the
// receiver model's nested quadratures report to an ErrorLedger (their own
// error estimates) plus round-off, as for a Lambertian receiver.
std::string answer_glossy_query(const Scene& original, const AnalyticQuery& q, size_t receiver, bool json) {
  Scene scene = original;
  Material& material = scene.objects[receiver].material;
  if (q.albedo) material.albedo = *q.albedo;
  const std::string& name = scene.objects[receiver].name;
  const View view = view_of(scene, q, name);
  const nlohmann::ordered_json bsdf =
      bsdf_json(analytic::glossy_receiver(scene, q.normal, view.direction, receiver)->material());
  double radiance = 0, radiance_bound = 0;
  {
    analytic::ErrorLedger ledger;
    radiance = analytic::glossy_reflected_radiance(scene, q.point, q.normal, view.direction, receiver);
    radiance_bound = ledger.bound(radiance);
  }
  if (!std::isfinite(radiance))
    throw Error(fmt::format("scene file '{}': the exact radiance at the point is {}, not a finite number (an "
                            "emission or radiance too large for double precision).",
                            scene.source, radiance));

  nlohmann::ordered_json j = view_query_json(scene, q, name, bsdf, view);
  j["radiance"] = radiance;
  j["radiance_error_bound"] = radiance_bound;
  std::string text = fmt::format(
      "scene {}, point ({:.17g}, {:.17g}, {:.17g}), normal ({:.17g}, {:.17g}, {:.17g}), receiver {}\n"
      "BSDF {}, view ({:.17g}, {:.17g}, {:.17g}) from {}\n"
      "radiance L toward the view  {:.17g} ± {:.2g}\n"
      "single-sample estimators of L: second moment E[Y^2] and variance Var Y = E[Y^2] - L^2 (± error bounds)\n",
      scene.name, q.point.x, q.point.y, q.point.z, q.normal.x, q.normal.y, q.normal.z, name, bsdf_text(bsdf),
      view.direction.x, view.direction.y, view.direction.z, view.source, radiance, radiance_bound);
  estimator_rows(q.estimators, direct_strategies(), radiance, radiance_bound, j, text, [&](Strategy strategy) {
    return with_ledger(
        [&] { return analytic::glossy_second_moment(strategy, scene, q.point, q.normal, view.direction, receiver); });
  });
  return json ? j.dump(2) + "\n" : text;
}

// A dielectric receiver with planar lights behind it (analytic/glass_light.h):
// the radiance transmitted toward the view in the query's convention and
// each direct strategy's E[Y²], bounds from the receiver model's ErrorLedger.
std::string answer_glass_light_query(const Scene& original, const AnalyticQuery& q, size_t receiver, bool json) {
  Scene scene = original;
  Object& object = scene.objects[receiver];
  if (q.albedo) object.material.albedo = *q.albedo;
  View view = q.view ? View{normalize(*q.view), "--view"} : View{-scene.camera.forward, "the camera"};
  view.direction = view.direction + Vec3(0, 0, 0);  // −0 components to +0, for the printed direction
  const bool inside = dot(view.direction, shape_normal(object.shape, q.point)) < 0;
  double radiance = 0, radiance_bound = 0;
  {
    analytic::ErrorLedger ledger;
    radiance = analytic::glass_light_radiance(scene, q.point, view.direction, receiver, q.convention);
    radiance_bound = ledger.bound(radiance);
  }
  nlohmann::ordered_json j = view_query_json(scene, q, object.name, bsdf_json(object.material), view);
  j["view_side"] = inside ? "inside" : "outside";
  j["convention"] = transport_convention_name(q.convention);
  j["radiance"] = radiance;
  j["radiance_error_bound"] = radiance_bound;
  std::string text = fmt::format(
      "scene {}, point ({:.17g}, {:.17g}, {:.17g}), normal ({:.17g}, {:.17g}, {:.17g}), receiver {}\n"
      "BSDF {}, view ({:.17g}, {:.17g}, {:.17g}) from {}, {} the glass, lights behind it, convention {}\n"
      "radiance L toward the view  {:.17g} ± {:.2g}\n"
      "single-sample estimators of L: second moment E[Y^2] and variance Var Y = E[Y^2] - L^2 (± error bounds)\n",
      scene.name, q.point.x, q.point.y, q.point.z, q.normal.x, q.normal.y, q.normal.z, object.name,
      bsdf_text(bsdf_json(object.material)), view.direction.x, view.direction.y, view.direction.z, view.source,
      inside ? "inside" : "outside", transport_convention_name(q.convention), radiance, radiance_bound);
  estimator_rows(q.estimators, direct_strategies(), radiance, radiance_bound, j, text, [&](Strategy strategy) {
    return with_ledger([&] {
      return analytic::glass_light_second_moment(strategy, scene, q.point, view.direction, receiver, q.convention,
                                                 LightSelection::kUniform);
    });
  });
  return json ? j.dump(2) + "\n" : text;
}

// A dielectric receiver (analytic/glass.h): in a glass scene of planar
// interfaces under a constant environment (or a sky on one side), the radiance toward the view
// (from either side: a view behind the object's front normal looks from
// inside, where the far side's relative index is 1/η) in the query's
// transport convention, a·L·(E_R + s·E_T), and the second moments of bsdf,
// the MIS strategies and (rough) light sampling alone
// (dielectric_interface_mis_moments); the hemisphere strategies are not
// modelled there. The error bound is
// the quadrature tolerance (relative) for a rough interface, round-off for a
// smooth one.
std::string answer_dielectric_query(const Scene& original, const AnalyticQuery& q, size_t receiver, bool json) {
  Scene scene = original;
  Object& object = scene.objects[receiver];
  if (q.albedo) object.material.albedo = *q.albedo;
  if (auto reason = analytic::glass_scene_refusal(scene))
    throw Error(fmt::format("scene file '{}': the dielectric receiver '{}' has an exact answer only in a glass scene "
                            "(analytic/glass.h), and this one is not: {}.",
                            scene.source, object.name, *reason));
  if (!is_planar(object.shape))
    throw Error(fmt::format("scene file '{}': the dielectric receiver '{}' is a sphere, whose radiance at a point "
                            "depends on the whole path inside it; only planar interfaces are answered at a point.",
                            scene.source, object.name));
  View view = q.view ? View{normalize(*q.view), "--view"} : View{-scene.camera.forward, "the camera"};
  view.direction = view.direction + Vec3(0, 0, 0);  // −0 components to +0, for the printed direction
  const Vec3 front = shape_normal(object.shape, q.point);
  const double cos_front = dot(view.direction, front);
  if (cos_front == 0)
    throw Error(fmt::format("scene file '{}': the view direction from {} lies in the plane of the dielectric receiver "
                            "'{}'.",
                            scene.source, view.source, object.name));
  const Dielectric& d = *object.material.as<Dielectric>();
  const bool inside = cos_front < 0;
  const double eta = inside ? 1 / d.eta : d.eta;
  const double mu = std::fabs(cos_front);
  const analytic::InterfaceAlbedo e = analytic::dielectric_interface_albedo(d, eta, mu, q.convention);
  const double a = object.material.albedo, l_env = scene.environment.radiance;
  const double s = analytic::transmission_scale(eta, q.convention);
  // A sky on one side (a map constant on each hemisphere): each lobe sees
  // its own side's radiance.
  const analytic::InterfaceEnvironment env = analytic::interface_environment(scene, inside ? -front : front);
  const double radiance = env.map ? a * (env.view * e.reflection + s * env.far * e.transmission)
                                  : a * l_env * (e.reflection + s * e.transmission);
  const double relative_bound = (d.smooth() ? 0.0 : analytic::kGlassQuadratureTolerance) +
                                64 * std::numeric_limits<double>::epsilon();
  const double radiance_bound = relative_bound * std::fabs(radiance);
  double m2 = a * a * l_env * l_env * e.second_moment;
  if (env.map) {
    const analytic::InterfaceLobeMoments lobes = analytic::dielectric_interface_lobe_moments(d, eta, mu, q.convention);
    m2 = a * a * (env.view * env.view * lobes.reflection + env.far * env.far * lobes.transmission);
  }
  const double m2_bound = relative_bound * m2;
  const nlohmann::ordered_json bsdf = bsdf_json(object.material);
  nlohmann::ordered_json j = view_query_json(scene, q, object.name, bsdf, view);
  j["view_side"] = inside ? "inside" : "outside";
  j["convention"] = transport_convention_name(q.convention);
  j["reflection_albedo"] = e.reflection;
  j["reflection_albedo_error_bound"] = relative_bound * e.reflection;
  j["transmission_albedo"] = e.transmission;
  j["transmission_albedo_error_bound"] = relative_bound * e.transmission;
  if (env.map) {
    // radiance × texel: one rounding.
    j["environment_radiance_view_side"] = env.view;
    j["environment_radiance_view_side_error_bound"] = std::numeric_limits<double>::epsilon() * env.view;
    j["environment_radiance_far_side"] = env.far;
    j["environment_radiance_far_side_error_bound"] = std::numeric_limits<double>::epsilon() * env.far;
  }
  j["radiance"] = radiance;
  j["radiance_error_bound"] = radiance_bound;
  std::string text = fmt::format(
      "scene {}, point ({:.17g}, {:.17g}, {:.17g}), normal ({:.17g}, {:.17g}, {:.17g}), receiver {}\n"
      "BSDF {}, view ({:.17g}, {:.17g}, {:.17g}) from {}, {} the glass (relative index {:.17g}), convention {}\n"
      "directional albedos: reflection {:.17g}, transmission {:.17g} (times {:.17g} in this convention)\n"
      "radiance L toward the view  {:.17g} ± {:.2g}\n"
      "single-sample estimators of L: second moment E[Y^2] and variance Var Y = E[Y^2] - L^2 (± error bounds)\n",
      scene.name, q.point.x, q.point.y, q.point.z, q.normal.x, q.normal.y, q.normal.z, object.name, bsdf_text(bsdf),
      view.direction.x, view.direction.y, view.direction.z, view.source, inside ? "inside" : "outside", eta,
      transport_convention_name(q.convention), e.reflection, e.transmission, s, radiance, radiance_bound);
  if (env.map)
    text.insert(text.find("radiance L toward"),
                fmt::format("sky on one side: environment radiance {:.17g} on the view's side, {:.17g} on the far "
                            "side\n",
                            env.view, env.far));
  // The MIS strategies (and light sampling alone at a rough interface) under
  // the constant environment: dielectric_interface_mis_moments.
  std::vector<Strategy> defaults{Strategy::kBsdf, Strategy::kMisBalance, Strategy::kMisPower,
                                 Strategy::kMisOneSample};
  if (!d.smooth()) defaults.insert(defaults.end(), {Strategy::kLightArea, Strategy::kLightSolidAngle});
  std::optional<analytic::InterfaceMisMoments> mis;
  estimator_rows(q.estimators, defaults, radiance, radiance_bound, j, text, [&](Strategy strategy) {
    if (strategy == Strategy::kBsdf) return BoundedValue{m2, m2_bound};
    if (std::find(defaults.begin(), defaults.end(), strategy) == defaults.end())
      throw Error("the second moment of this estimator at a dielectric is not modelled");
    if (!mis)
      mis = env.map ? analytic::dielectric_interface_mis_moments(d, eta, mu, q.convention, env)
                    : analytic::dielectric_interface_mis_moments(d, eta, mu, q.convention);
    const double scale = env.map ? a * a : a * a * l_env * l_env;
    const double round_off = 64 * std::numeric_limits<double>::epsilon();
    const auto bounded = [&](double value, double bound) {
      return BoundedValue{scale * value, scale * (bound + round_off * value)};
    };
    switch (strategy) {
      case Strategy::kMisBalance: return bounded(mis->balance, mis->balance_bound);
      case Strategy::kMisPower: return bounded(mis->power, mis->power_bound);
      case Strategy::kMisOneSample: return bounded(mis->one_sample, mis->one_sample_bound);
      default: return bounded(mis->light, mis->light_bound);
    }
  });
  return json ? j.dump(2) + "\n" : text;
}

}  // namespace

std::string answer_analytic_query(const Scene& scene, const AnalyticQuery& q, bool json) {
  const std::optional<size_t> receiver = receiver_at(scene, q.point, q.normal);
  if (receiver) {
    const Object& object = scene.objects[*receiver];
    if (object.material.info().glossy) return answer_glossy_query(scene, q, *receiver, json);
    if (object.material.as<Dielectric>())
      return analytic::has_glass_light(scene) ? answer_glass_light_query(scene, q, *receiver, json)
                                              : answer_dielectric_query(scene, q, *receiver, json);
    if (object.material.as<Mirror>() && (q.albedo ? *q.albedo : object.material.albedo) > 0)
      throw Error(fmt::format("scene file '{}': the receiver '{}' at the point is a mirror, a delta lobe with no "
                              "reference at a point (its radiance is the radiance along the mirrored ray).",
                              scene.source, object.name));
  }
  const double albedo = q.albedo ? *q.albedo : (receiver ? scene.objects[*receiver].material.albedo : 1.0);
  double e = 0, e_bound = 0;
  {
    const analytic::ErrorLedger ledger;
    e = analytic::irradiance(scene, q.point, q.normal, receiver);
    e_bound = ledger.bound(e);
  }
  const double radiance = albedo * kInvPi * e;
  if (!std::isfinite(e) || !std::isfinite(radiance))
    throw Error(fmt::format("scene file '{}': the exact irradiance at the point is {}, not a finite number (an "
                            "emission, radiance or intensity too large for double precision).",
                            scene.source, e));
  const double radiance_bound = albedo * kInvPi * e_bound;

  nlohmann::ordered_json j;
  j["scene"] = scene.name;
  j["point"] = {q.point.x, q.point.y, q.point.z};
  j["normal"] = {q.normal.x, q.normal.y, q.normal.z};
  j["receiver"] = receiver ? scene.objects[*receiver].name : std::string("none");
  j["bsdf"] = {{"type", bsdf_type_name(BsdfType::kLambertian)}, {"albedo", albedo}};
  j["albedo"] = albedo;
  j["irradiance"] = e;
  j["irradiance_error_bound"] = e_bound;
  j["radiance"] = radiance;
  j["radiance_error_bound"] = radiance_bound;
  std::string text = fmt::format(
      "scene {}, point ({:.17g}, {:.17g}, {:.17g}), normal ({:.17g}, {:.17g}, {:.17g}), receiver {}\n"
      "irradiance E                {:.17g} ± {:.2g}\n"
      "radiance (albedo {:.17g})  {:.17g} ± {:.2g}\n"
      "single-sample estimators of E: second moment E[Y^2] and variance Var Y = E[Y^2] - E^2 (± error bounds)\n",
      scene.name, q.point.x, q.point.y, q.point.z, q.normal.x, q.normal.y, q.normal.z,
      j["receiver"].get<std::string>(), e, e_bound, albedo, radiance, radiance_bound);
  // The estimators asked for; by default every strategy with its own
  // variance model (bsdf shares cosine_hemisphere's).
  std::vector<Strategy> defaults;
  for (const StrategyInfo& info : kStrategyTable)
    if (info.variance_model == info.strategy) defaults.push_back(info.strategy);
  estimator_rows(q.estimators, defaults, e, e_bound, j, text, [&](Strategy strategy) {
    const StrategyInfo& est = strategy_info(strategy);
    if (!est.variance_model)
      throw Error(fmt::format("the estimator {} has no single-sample second-moment model in analytic/.", est.name));
    return with_ledger([&] { return analytic::second_moment(*est.variance_model, scene, q.point, q.normal, receiver); });
  });
  if (json) {
    // Round-trip precision: nlohmann prints doubles with max_digits10 (17).
    return j.dump(2) + "\n";
  }
  return text;
}

}  // namespace furnace::verify
