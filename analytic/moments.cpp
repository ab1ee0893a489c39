// second_moment and the pixel estimators' second moments (moments.h): the
// Lambertian receiver's estimators from the emitter kernels
// (light_moments.h, light_solid_angle_moments.h), the point lights, the
// environment and MIS (mis_moments.h); a glossy hit by its receiver model
// (glossy.h, receiver.h).
#include "analytic/moments.h"

#include <array>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "analytic/emitter.h"
#include "analytic/environment.h"
#include "analytic/environment_map.h"
#include "analytic/error_ledger.h"
#include "analytic/glossy.h"
#include "analytic/light_moments.h"
#include "analytic/light_solid_angle_moments.h"
#include "analytic/mis_moments.h"
#include "analytic/reference.h"
#include "analytic/unsupported.h"
#include "core/error.h"

namespace furnace::analytic {

namespace {

// How a single-technique estimator at a Lambertian receiver draws its
// direction (moments.h states each one's E[Y²]).
enum class Technique { kUniformHemisphere, kCosineHemisphere, kLightArea, kLightSolidAngle };

// A direct strategy's estimator at a Lambertian receiver: one technique, or
// (no technique) MIS of cosine and light_solid_angle samples with the
// table's mis_beta (1 balance, 2 power, 0 one-sample).
struct LambertianEstimator {
  std::optional<Technique> technique;
  int mis_beta = 0;
};

// The strategies with a variance model (the table's variance_model: bsdf
// sampling of a Lambertian surface is cosine sampling). A path tracer has no
// single-sample estimator: second_moment refuses it before asking.
LambertianEstimator lambertian_estimator(Strategy strategy) {
  switch (strategy) {
    case Strategy::kUniformHemisphere: return {Technique::kUniformHemisphere};
    case Strategy::kCosineHemisphere:
    case Strategy::kBsdf: return {Technique::kCosineHemisphere};
    case Strategy::kLightArea: return {Technique::kLightArea};
    case Strategy::kLightSolidAngle: return {Technique::kLightSolidAngle};
    case Strategy::kMisBalance:
    case Strategy::kMisPower:
    case Strategy::kMisOneSample: return {std::nullopt, strategy_info(strategy).mis_beta};
    case Strategy::kPathNaive:
    case Strategy::kPathMis: break;
  }
  FURNACE_CHECK(false && "a strategy without a variance model, refused by second_moment");
  return {};
}

// Point lights: a light-sampling estimator that picks point light l (pmf P_l)
// returns E_l/P_l exactly, so it adds P_l·(E_l/P_l)² = E_l²/P_l to E[Y²].
// `pmf` is light_selection_pmf (emitters first, then the point lights).
// The hemisphere estimators never see a point light: refused.
double point_lights_second_moment(Technique technique, const Scene& scene, const Vec3& p, const Vec3& n,
                                  std::optional<size_t> receiver, const std::vector<double>& pmf) {
  if (scene.point_lights.empty()) return 0.0;
  if (technique != Technique::kLightArea && technique != Technique::kLightSolidAngle)
    unsupported_configuration(scene, "point lights, which a hemisphere estimator cannot sample,");
  size_t first = 0;
  for (const Object& o : scene.objects) first += o.is_emitter() ? 1 : 0;
  double moment = 0;
  for (size_t l = 0; l < scene.point_lights.size(); ++l) {
    const double e = point_light_irradiance(scene, l, p, n, receiver);
    moment += e * e / pmf[first + l];
  }
  return moment;
}

}  // namespace

double second_moment(Strategy strategy, const Scene& scene, const Vec3& p, const Vec3& n,
                     std::optional<size_t> receiver, LightSelection selection) {
  if (!has_variance_model(strategy))
    unsupported_configuration(scene, "the strategy '" + strategy_name(strategy) +
                                         "', which has no variance model,");
  const LambertianEstimator estimator = lambertian_estimator(strategy);
  if (!estimator.technique) {
    // mis_second_moments models emitters, point lights and a constant sky.
    if (scene.environment.map) unsupported_configuration(scene, "MIS under an environment map");
    const int beta = estimator.mis_beta;  // 0: one-sample MIS
    const std::array<double, 2> moments =
        mis_second_moments(scene, p, n, receiver, beta != 0, light_selection_pmf(scene, selection));
    return moments[beta == 2 ? 1 : 0];
  }
  const Technique technique = *estimator.technique;
  // Selection pmf of every light (emitters, point lights, environment), and
  // 1/pmf of the i-th emitter object in object order.
  const std::vector<double> pmf = light_selection_pmf(scene, selection);
  std::vector<double> inverse_pmf_of_object(scene.objects.size(), 0.0);
  size_t light = 0;
  for (size_t i = 0; i < scene.objects.size(); ++i)
    if (scene.objects[i].is_emitter()) inverse_pmf_of_object[i] = 1.0 / pmf[light++];

  double moment = 0;
  ErrorSum errors;
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    const Object& object = scene.objects[i];
    if (!object.is_emitter() || (receiver && i == *receiver)) continue;
    const double le = object.emitted_radiance;
    moment += errors.term([&]() -> double {
      switch (technique) {
        case Technique::kUniformHemisphere:
          return 2 * kPi * le * le * emitter_cos2_kernel(scene, i, p, n, receiver);
        case Technique::kCosineHemisphere:
          return kPi * le * le * emitter_irradiance(scene, i, p, n, receiver);
        case Technique::kLightArea:
          return inverse_pmf_of_object[i] * shape_area(object.shape) * le * le *
                 emitter_area_kernel(scene, i, p, n, receiver);
        case Technique::kLightSolidAngle:
          return inverse_pmf_of_object[i] * le * le * solid_angle_emitter_kernel(scene, i, p, n, receiver);
      }
      return 0.0;  // unreachable: every technique has its case
    });
  }
  moment += errors.term([&] { return point_lights_second_moment(technique, scene, p, n, receiver, pmf); });
  // E of the environment under its own ledger: its error counts only where
  // a term below is proportional to it.
  double e_env = 0, e_env_relative_error = 0;
  {
    ErrorLedger ledger;
    e_env = environment_irradiance(scene, p, n, receiver);
    e_env_relative_error = ledger.take_relative();
  }
  auto proportional_to_e_env = [&](double value) {
    ErrorLedger::report(e_env_relative_error, 1.0);
    return value;
  };
  if (e_env > 0 && scene.environment.map) {  // unblocked (environment_irradiance refuses blockers)
    switch (technique) {
      case Technique::kUniformHemisphere:
        moment += errors.term([&] { return map_uniform_hemisphere_moment(scene.environment, n); });
        break;
      case Technique::kCosineHemisphere:
        moment += errors.term([&] { return map_cosine_moment(scene.environment, n); });
        break;
      case Technique::kLightArea:  // the map's texel sampling, chosen with pmf P_env (last)
      case Technique::kLightSolidAngle:
        moment += errors.term([&] { return map_light_sampling_moment(scene.environment, n, 1) / pmf.back(); });
        break;
    }
  } else if (e_env > 0) {
    const double l_env = scene.environment.radiance;
    switch (technique) {
      case Technique::kUniformHemisphere: {
        // ∫ cos²θ dω = 2π/3 over the hemisphere, minus what the blockers hide;
        // the blockers' errors count against what stays visible.
        ErrorSum hidden_errors;
        double hidden = 0;
        for (size_t j : environment_blockers(scene, p, n, receiver))
          hidden += hidden_errors.term([&] { return blocker_cos2_solid_angle(scene, j, p, n); });
        const double visible = std::fmax(2 * kPi / 3 - hidden, 0.0);
        moment += errors.term([&] {
          hidden_errors.report(visible);
          return 2 * kPi * l_env * l_env * visible;
        });
        break;
      }
      case Technique::kCosineHemisphere:
        moment += errors.term([&] { return proportional_to_e_env(kPi * l_env * e_env); });
        break;
      case Technique::kLightArea:  // the environment is sampled cosine-weighted, chosen with pmf P_env (last)
      case Technique::kLightSolidAngle:
        moment += errors.term([&] { return proportional_to_e_env(kPi * l_env * e_env / pmf.back()); });
        break;
    }
  }
  errors.report(moment);
  return moment;
}

namespace {

// pixel_center_second_moment's steps for N second moments at once:
// glossy(p, n, wo, receiver) gives the N glossy estimators' E[Y²] at a
// glossy hit (glossy.h), lambertian(p, n, receiver) the N irradiance
// estimators' at a Lambertian one.
template <size_t N, class Glossy, class LambertianMoments>
std::array<double, N> pixel_center_moments(const Scene& scene, int px, int py, Glossy glossy,
                                           LambertianMoments lambertian) {
  std::array<double, N> out;
  const Camera::Ray ray = scene.camera.pixel_center_ray(px, py);
  const std::optional<Hit> hit = intersect(scene, ray.origin, ray.direction);
  if (!hit) {
    out.fill(std::pow(environment_radiance(scene.environment, ray.direction), 2));
    return out;
  }
  const Object& object = scene.objects[hit->object_index];
  const double cos_view = dot(ray.direction, hit->normal);
  const double le = (cos_view < 0 || object.two_sided) ? object.emitted_radiance : 0.0;
  if (object.material.albedo == 0) {
    out.fill(le * le);
    return out;
  }
  const Vec3 n = cos_view < 0 ? hit->normal : -hit->normal;
  if (object.material.info().glossy) {
    // Y_px = Le + Y with Y the glossy estimator (glossy.h), emission constant.
    const double e = glossy_reflected_radiance(scene, hit->point, n, -ray.direction, hit->object_index);
    const std::array<double, N> m = glossy(hit->point, n, -ray.direction, hit->object_index);
    for (size_t i = 0; i < N; ++i) out[i] = le * le + 2 * le * e + m[i];
    return out;
  }
  if (object.material.as<Lambertian>()) {
    const double k = object.material.albedo * kInvPi;
    const double e = irradiance(scene, hit->point, n, hit->object_index);
    const std::array<double, N> m = lambertian(hit->point, n, hit->object_index);
    for (size_t i = 0; i < N; ++i) out[i] = le * le + 2 * le * k * e + k * k * m[i];
    return out;
  }
  // A mirror, a delta lobe, has no receiver model.
  unsupported_configuration(scene, "a camera ray hitting the non-Lambertian, non-black object '" + object.name + "'");
}

}  // namespace

double pixel_center_second_moment(Strategy strategy, const Scene& scene, int px, int py, LightSelection selection) {
  return pixel_center_moments<1>(
      scene, px, py,
      [&](const Vec3& p, const Vec3& n, const Vec3& wo, size_t receiver) {
        return std::array<double, 1>{glossy_second_moment(strategy, scene, p, n, wo, receiver, selection)};
      },
      [&](const Vec3& p, const Vec3& n, size_t receiver) {
        return std::array<double, 1>{second_moment(strategy, scene, p, n, receiver, selection)};
      })[0];
}

std::array<double, 2> pixel_center_multi_sample_mis_second_moments(const Scene& scene, int px, int py,
                                                                   LightSelection selection) {
  return pixel_center_moments<2>(
      scene, px, py,
      [&](const Vec3& p, const Vec3& n, const Vec3& wo, size_t receiver) {
        // The glossy estimators have no shared quadrature: one each.
        return std::array<double, 2>{glossy_second_moment(Strategy::kMisBalance, scene, p, n, wo, receiver, selection),
                                     glossy_second_moment(Strategy::kMisPower, scene, p, n, wo, receiver, selection)};
      },
      [&](const Vec3& p, const Vec3& n, size_t receiver) {
        return multi_sample_mis_second_moments(scene, p, n, receiver, selection);
      });
}

}  // namespace furnace::analytic
