// The receiver model's scene-level side (receiver.h): the lights it solves,
// the environment memo, and the forms that dispatch to each receiver's
// instantiation of the machinery (receiver_integrals.h).
#include "analytic/receiver.h"

#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "analytic/error_ledger.h"
#include "analytic/occlusion.h"
#include "analytic/point_light.h"
#include "analytic/unsupported.h"
#include "core/error.h"

namespace furnace::analytic {

namespace {

struct MemoKey {
  int what;  // −1: the mean, else the Strategy
  int selection;
  Vec3 n, wo;
  std::vector<double> parameters;  // Receiver::parameters()
  double radiance, pmf;
  bool operator==(const MemoKey& o) const {
    return what == o.what && selection == o.selection && n.x == o.n.x && n.y == o.n.y && n.z == o.n.z &&
           wo.x == o.wo.x && wo.y == o.wo.y && wo.z == o.wo.z && parameters == o.parameters &&
           radiance == o.radiance && pmf == o.pmf;
  }
};
constexpr size_t kMemoEntries = 16;

// A memoised value with the relative error its quadratures reported to the
// ErrorLedger, reported again on every hit (as if computed anew).
struct Memoised {
  double value, relative_error;
};

template <class Compute>
double environment_memo(const MemoKey& key, Compute compute) {
  thread_local std::vector<std::pair<MemoKey, Memoised>> memo;
  for (const auto& [k, m] : memo)
    if (k == key) {
      ErrorLedger::report(m.relative_error, 1.0);
      return m.value;
    }
  Memoised m{};
  {
    ErrorLedger ledger;
    m.value = compute();
    m.relative_error = ledger.take_relative();
  }
  ErrorLedger::report(m.relative_error, 1.0);
  if (memo.size() == kMemoEntries) memo.erase(memo.begin());
  memo.emplace_back(key, m);
  return m.value;
}

// The memo key when the environment is the only light, else none.
std::optional<MemoKey> environment_only_key(const std::vector<ReceiverLight>& lights, const Receiver& r, int what,
                                            LightSelection selection) {
  if (lights.size() != 1 || !lights[0].environment) return std::nullopt;
  return MemoKey{what, int(selection), r.n, r.wo, r.parameters(), lights[0].radiance, lights[0].pmf};
}

}  // namespace

Vec3 Receiver::mirror() const { return normalize(n * (2 * dot(n, wo)) - wo); }

std::vector<ReceiverLight> receiver_lights(const Scene& scene, const Vec3& p, const Vec3& n, size_t receiver,
                                           LightSelection selection, const std::string& who) {
  if (!scene.point_lights.empty()) unsupported_configuration(scene, "point lights over " + who);
  const std::vector<double> pmf = light_selection_pmf(scene, selection);
  std::vector<ReceiverLight> lights;
  size_t index = 0;
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    const Object& object = scene.objects[i];
    if (!object.is_emitter()) continue;
    const double pmf_i = pmf[index++];
    if (i == receiver) continue;
    const auto* sphere = std::get_if<Sphere>(&object.shape);
    if (!sphere) {
      // A disk, rectangle or triangle: its visible region, or nothing when none of it reaches p.
      std::optional<PlanarEmitter> planar = planar_emitter(scene, i, p, n, receiver, who);
      if (planar) lights.push_back(ReceiverLight{false, {}, 0, object.emitted_radiance, pmf_i, std::move(planar)});
      continue;
    }
    if (!(length(sphere->center - p) > sphere->radius))
      unsupported_configuration(scene, "a receiving point (" + who + ") on or inside the sphere light '" + object.name + "'");
    // Objects that may block the sphere: above the horizon and meeting the cone from p over it.
    const BoundingSphere ball{sphere->center, sphere->radius};
    for (size_t j = 0; j < scene.objects.size(); ++j)
      if (j != i && j != receiver && above_horizon(scene.objects[j], p, n) &&
          ball_may_meet_ball_cone(bounding_sphere(scene.objects[j].shape), p, ball))
        unsupported_configuration(scene, "the object '" + scene.objects[j].name +
                                             "' which may block the sphere light '" + object.name + "' seen from " +
                                             who + " (only unoccluded sphere lights are solved)");
    lights.push_back(ReceiverLight{false, sphere->center - p, sphere->radius, object.emitted_radiance, pmf_i});
  }
  if (scene.environment.radiance > 0) {
    if (scene.environment.map) unsupported_configuration(scene, "an environment map over " + who);
    for (size_t j = 0; j < scene.objects.size(); ++j)
      if (j != receiver && above_horizon(scene.objects[j], p, n))
        unsupported_configuration(scene, "the environment blocked by '" + scene.objects[j].name + "' over " + who);
    lights.push_back(ReceiverLight{true, {}, 0, scene.environment.radiance, pmf.back()});
  }
  return lights;
}

double light_reflectance(const Receiver& receiver, const ReceiverLight& light) {
  return receiver.light_reflectance(light);
}

double reflected_radiance(const Receiver& receiver, const std::vector<ReceiverLight>& lights) {
  // Each light's error relative to the sum (ErrorSum): a faint light's poorly
  // resolved reflectance does not swamp the bound of the whole.
  ErrorSum errors;
  double radiance = 0;
  for (const ReceiverLight& light : lights)
    radiance += errors.term([&] { return light.radiance * light_reflectance(receiver, light); });
  errors.report(radiance);
  return radiance;
}

double receiver_second_moment(Strategy strategy, const Receiver& receiver, const std::vector<ReceiverLight>& lights) {
  return receiver.second_moment(strategy, lights);
}

double receiver_reflected_radiance(const Scene& scene, const Vec3& p, const Receiver& receiver, size_t index) {
  const std::vector<ReceiverLight> lights =
      receiver_lights(scene, p, receiver.n, index, LightSelection::kUniform, receiver.name());
  auto compute = [&] { return reflected_radiance(receiver, lights); };
  const auto key = environment_only_key(lights, receiver, -1, LightSelection::kUniform);
  return key ? environment_memo(*key, compute) : compute();
}

double receiver_second_moment(Strategy strategy, const Scene& scene, const Vec3& p, const Receiver& receiver,
                              size_t index, LightSelection selection) {
  if (is_path_tracer(strategy))
    unsupported_configuration(scene, "the path tracer '" + strategy_name(strategy) + "' over " + receiver.name());
  const std::vector<ReceiverLight> lights = receiver_lights(scene, p, receiver.n, index, selection, receiver.name());
  const auto key = environment_only_key(lights, receiver, int(strategy), selection);
  auto compute = [&] { return receiver_second_moment(strategy, receiver, lights); };
  return key ? environment_memo(*key, compute) : compute();
}

}  // namespace furnace::analytic
