#include "analytic/moments.h"

#include <cmath>
#include <string>
#include <variant>

#include "analytic/circle_region.h"
#include "analytic/disk_light.h"
#include "analytic/environment.h"
#include "analytic/reference.h"

namespace furnace::analytic {

namespace {

// ∫_visible h³/(h²+s²)^(5/2) dA: uniform-hemisphere kernel cos²θ·cos θ'/r².
// G(s) = (1 − c³)/3 with c = h/r; G/s² = (1 + c + c²)/(3r(r + h)), from
// 1 − c = s²/(r(r + h)), so nothing cancels for small s.
double hemisphere_kernel(const DiskLightView& v) {
  const double h = v.h;
  return contour_quadrature(visible_boundary(v.light, v.occluder_images), [h](double s2) {
    const double r = std::sqrt(h * h + s2);
    const double c = h / r;
    return (1 + c + c * c) / (3 * r * (r + h));
  });
}

// ∫_visible h⁴/(h²+s²)⁴ dA: light-area kernel (cos θ cos θ'/r²)².
double area_kernel(const DiskLightView& v) {
  const double h2 = v.h * v.h;
  return contour_quadrature(visible_boundary(v.light, v.occluder_images), [h2](double s2) {
    const double r2 = h2 + s2;
    return (3 * h2 * h2 + 3 * h2 * s2 + s2 * s2) / (6 * h2 * r2 * r2 * r2);
  });
}

}  // namespace

double second_moment(Estimator estimator, const Scene& scene, const Vec3& p, const Vec3& n,
                     std::optional<size_t> receiver) {
  // Lights a light-sampling estimator picks among (uniformly).
  size_t light_count = scene.environment.radiance > 0 ? 1 : 0;
  for (const Object& o : scene.objects) light_count += o.is_emitter() ? 1 : 0;

  double moment = 0;
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    const Object& object = scene.objects[i];
    if (!object.is_emitter() || (receiver && i == *receiver)) continue;
    if (!std::holds_alternative<Disk>(object.shape))
      unsupported_configuration(scene, "the emitter '" + object.name + "' (only disk emitters are solved so far)");
    const auto view = disk_light_view(scene, i, p, n, receiver);
    if (!view) continue;
    const double le = object.emitted_radiance;
    switch (estimator) {
      case Estimator::kUniformHemisphere:
        moment += 2 * kPi * le * le * hemisphere_kernel(*view);
        break;
      case Estimator::kCosineHemisphere:
        moment += kPi * le * le * occluded_disk_irradiance(view->h, view->light, view->occluder_images);
        break;
      case Estimator::kLightArea:
        moment += double(light_count) * shape_area(object.shape) * le * le * area_kernel(*view);
        break;
    }
  }
  const double e_env = environment_irradiance(scene, p, n, receiver);
  if (e_env > 0) {
    const double l_env = scene.environment.radiance;
    switch (estimator) {
      case Estimator::kUniformHemisphere:
        // ∫ cos²θ dω = 2π/3 over the open hemisphere; the cos²-weighted solid
        // angle of blockers is not solved, so a blocked sky is refused.
        if (e_env != kPi * l_env)
          unsupported_configuration(scene, "the uniform-hemisphere second moment under a partly blocked environment");
        moment += 2 * kPi * l_env * l_env * (2 * kPi / 3);
        break;
      case Estimator::kCosineHemisphere:
        moment += kPi * l_env * e_env;
        break;
      case Estimator::kLightArea:  // the environment is sampled cosine-weighted, chosen with pmf 1/K
        moment += double(light_count) * kPi * l_env * e_env;
        break;
    }
  }
  return moment;
}

double pixel_center_second_moment(Estimator estimator, const Scene& scene, int px, int py) {
  const Camera::Ray ray = scene.camera.pixel_center_ray(px, py);
  const std::optional<Hit> hit = intersect(scene, ray.origin, ray.direction);
  if (!hit) return scene.environment.radiance * scene.environment.radiance;
  const Object& object = scene.objects[hit->object_index];
  const double cos_view = dot(ray.direction, hit->normal);
  const double le = (cos_view < 0 || object.two_sided) ? object.emitted_radiance : 0.0;
  if (object.material.albedo == 0) return le * le;
  if (object.material.type != BsdfType::kLambertian)
    unsupported_configuration(scene, "a camera ray hitting the non-Lambertian, non-black object '" + object.name + "'");
  const Vec3 n = cos_view < 0 ? hit->normal : -hit->normal;
  const double k = object.material.albedo * kInvPi;
  const double e = irradiance(scene, hit->point, n, hit->object_index);
  return le * le + 2 * le * k * e + k * k * second_moment(estimator, scene, hit->point, n, hit->object_index);
}

}  // namespace furnace::analytic
