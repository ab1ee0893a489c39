// Scene-level references: dispatch each emitter/receiver/occluder
// configuration to its closed form, or refuse it with furnace::Error.
#include "analytic/reference.h"

#include <cmath>
#include <string>
#include <variant>

#include "analytic/circle_region.h"
#include "analytic/disk_light.h"
#include "analytic/environment.h"
#include "analytic/intersect.h"
#include "analytic/occlusion.h"
#include "analytic/planar_light.h"
#include "analytic/sphere.h"
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

namespace {

// Refuses the configuration unless no object other than the light and the
// receiver can meet the hull of p and the light's bounding ball above p's
// horizon (objects wholly below the horizon block only directions with
// cos θ ≤ 0, which carry no irradiance).
void require_unblocked(const Scene& scene, size_t light_index, const Vec3& p, const Vec3& n,
                       std::optional<size_t> receiver) {
  const Object& light = scene.objects[light_index];
  const BoundingSphere light_ball = bounding_sphere(light.shape);
  for (size_t j = 0; j < scene.objects.size(); ++j) {
    if (j == light_index || (receiver && j == *receiver)) continue;
    const Object& object = scene.objects[j];
    if (height_range(object.shape, p, n).hi <= 0) continue;
    if (!ball_may_meet_ball_cone(bounding_sphere(object.shape), p, light_ball)) continue;
    unsupported_configuration(scene, "object '" + object.name + "', which may block part of the emitter '" + light.name +
                                         "' (only disk occluders of parallel disk lights are solved so far),");
  }
}

// E/L from a sphere emitter seen from outside (its front is its outside).
double sphere_light_irradiance(const Scene& scene, size_t i, const Vec3& p, const Vec3& n,
                               std::optional<size_t> receiver) {
  const Object& light = scene.objects[i];
  const Sphere& sphere = std::get<Sphere>(light.shape);
  if (length(p - sphere.center) <= sphere.radius) {
    if (!light.two_sided) return 0.0;  // inside a one-sided (outward) emitter: nothing arrives
    unsupported_configuration(scene, "a receiving point inside the two-sided sphere light '" + light.name + "'");
  }
  const double e = sphere_irradiance(sphere.center - p, sphere.radius, n);
  if (e == 0) return 0.0;
  require_unblocked(scene, i, p, n, receiver);
  return e;
}

}  // namespace

double irradiance(const Scene& scene, const Vec3& p, const Vec3& n, std::optional<size_t> receiver) {
  double e = 0;
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    const Object& object = scene.objects[i];
    if (!object.is_emitter() || (receiver && i == *receiver)) continue;
    double e_over_l = 0;
    if (std::holds_alternative<Disk>(object.shape)) {
      // Fast path (hand-rolled circle Booleans, closed-form arcs); the general
      // exact path when it does not apply.
      std::string reason;
      if (const auto view = disk_light_view(scene, i, p, n, receiver, &reason))
        e_over_l = occluded_disk_irradiance(view->h, view->light, view->occluder_images);
      else if (!reason.empty())
        e_over_l = planar_light_irradiance(scene, i, p, n, receiver);
    } else if (std::holds_alternative<Sphere>(object.shape)) {
      e_over_l = sphere_light_irradiance(scene, i, p, n, receiver);
    } else {
      e_over_l = planar_light_irradiance(scene, i, p, n, receiver);
    }
    e += object.emitted_radiance * e_over_l;
  }
  return e + environment_irradiance(scene, p, n, receiver);
}

double pixel_center_radiance(const Scene& scene, int px, int py) {
  const Camera::Ray ray = scene.camera.pixel_center_ray(px, py);
  const std::optional<Hit> hit = intersect(scene, ray.origin, ray.direction);
  if (!hit) return scene.environment.radiance;
  const Object& object = scene.objects[hit->object_index];
  const double cos_view = dot(ray.direction, hit->normal);
  // Emission leaves the front face only, both faces of a two_sided object.
  const double le = (cos_view < 0 || object.two_sided) ? object.emitted_radiance : 0.0;
  if (object.material.albedo == 0) return le;
  if (object.material.type != BsdfType::kLambertian)
    unsupported_configuration(scene, "a camera ray hitting the non-Lambertian, non-black object '" + object.name + "'");
  // Two-sided Lambertian: shade with the normal facing the viewer.
  const Vec3 n = cos_view < 0 ? hit->normal : -hit->normal;
  return le + object.material.albedo * kInvPi * irradiance(scene, hit->point, n, hit->object_index);
}

std::vector<double> reference_image(const Scene& scene) {
  const Camera& camera = scene.camera;
  std::vector<double> image(size_t(camera.width_px) * size_t(camera.height_px));
  for (int py = 0; py < camera.height_px; ++py)
    for (int px = 0; px < camera.width_px; ++px) image[size_t(py) * camera.width_px + px] = pixel_center_radiance(scene, px, py);
  return image;
}

}  // namespace furnace::analytic
