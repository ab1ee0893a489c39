// Scene-level references: dispatch each emitter/receiver/occluder
// configuration to its closed form, or refuse it with furnace::Error.
#include "analytic/reference.h"

#include "analytic/error_ledger.h"

#include <cmath>
#include <string>
#include <variant>

#include "analytic/disk_light.h"
#include "analytic/emitter.h"
#include "analytic/environment.h"
#include "analytic/glossy.h"
#include "analytic/intersect.h"
#include "analytic/point_light.h"
#include "analytic/unsupported.h"
#include "core/error.h"

namespace furnace::analytic {

std::optional<Hit> intersect(const Scene& scene, const Vec3& origin, const Vec3& direction, double t_min) {
  std::optional<Hit> best;
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    const std::optional<double> t = intersect_shape(scene.objects[i].shape, origin, direction, t_min);
    if (!t || (best && *t >= best->t)) continue;
    const Vec3 point = origin + direction * *t;
    best = Hit{*t, i, point, shape_normal(scene.objects[i].shape, point)};
  }
  return best;
}

double irradiance(const Scene& scene, const Vec3& p, const Vec3& n, std::optional<size_t> receiver) {
  double e = 0;
  ErrorSum errors;
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    const Object& object = scene.objects[i];
    if (!object.is_emitter() || (receiver && i == *receiver)) continue;
    e += errors.term([&] { return object.emitted_radiance * emitter_irradiance(scene, i, p, n, receiver); });
  }
  e += errors.term([&] { return point_lights_irradiance(scene, p, n, receiver); });
  e += errors.term([&] { return environment_irradiance(scene, p, n, receiver); });
  errors.report(e);
  return e;
}

double pixel_center_radiance(const Scene& scene, int px, int py) {
  const Camera::Ray ray = scene.camera.pixel_center_ray(px, py);
  return ray_radiance(scene, ray.origin, ray.direction);
}

double ray_radiance(const Scene& scene, const Vec3& origin, const Vec3& direction) {
  const std::optional<Hit> hit = intersect(scene, origin, direction);
  if (!hit) return environment_radiance(scene.environment, direction);
  return hit_radiance(scene, *hit, direction);
}

double hit_radiance(const Scene& scene, const Hit& hit, const Vec3& direction) {
  const Object& object = scene.objects[hit.object_index];
  const double cos_view = dot(direction, hit.normal);
  // Emission leaves the front face only, both faces of a two_sided object.
  const double le = (cos_view < 0 || object.two_sided) ? object.emitted_radiance : 0.0;
  if (object.material.albedo == 0) return le;
  // Shade with the normal facing the viewer (two-sided surfaces).
  const Vec3 n = cos_view < 0 ? hit.normal : -hit.normal;
  if (object.material.info().glossy)  // the lobe integrated over the lights (glossy.h)
    return le + glossy_reflected_radiance(scene, hit.point, n, -direction, hit.object_index);
  if (object.material.as<Lambertian>())
    return le + object.material.albedo * kInvPi * irradiance(scene, hit.point, n, hit.object_index);
  // A mirror, a delta lobe, has no receiver model.
  unsupported_configuration(scene, "a camera ray hitting the non-Lambertian, non-black object '" + object.name + "'");
}

std::vector<double> reference_image(const Scene& scene) {
  const Camera& camera = scene.camera;
  std::vector<double> image(size_t(camera.width_px) * size_t(camera.height_px));
  for (int py = 0; py < camera.height_px; ++py)
    for (int px = 0; px < camera.width_px; ++px) image[size_t(py) * camera.width_px + px] = pixel_center_radiance(scene, px, py);
  return image;
}

}  // namespace furnace::analytic
