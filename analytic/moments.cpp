#include "analytic/moments.h"

#include <cmath>
#include <string>
#include <variant>

#include "analytic/circle_region.h"
#include "analytic/disk_light.h"
#include "analytic/emitter.h"
#include "analytic/light_moments.h"
#include "analytic/planar_light.h"
#include "analytic/environment.h"
#include "analytic/environment_map.h"
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

std::vector<Vec3> polygon_vertices_relative(const Shape& shape, const Vec3& p) {
  if (const auto* r = std::get_if<Rectangle>(&shape))
    return {r->corner - p, r->corner + r->edge_u - p, r->corner + r->edge_u + r->edge_v - p, r->corner + r->edge_v - p};
  const auto& t = std::get<Triangle>(shape);
  return {t.p0 - p, t.p1 - p, t.p2 - p};
}

// ∫_object max(cos θ, 0)² dω: the cos²-weighted solid angle an environment
// blocker hides from the uniform-hemisphere estimator.
double blocker_cos2_solid_angle(const Scene& scene, size_t j, const Vec3& p, const Vec3& n) {
  const Object& o = scene.objects[j];
  if (const auto* s = std::get_if<Sphere>(&o.shape)) return sphere_cos2_solid_angle(s->center - p, s->radius, n);
  if (const auto* d = std::get_if<Disk>(&o.shape)) {
    if (length(cross(normalize(d->normal), n)) > 1e-12)
      unsupported_configuration(scene, "the uniform-hemisphere moment of an environment blocked by the tilted disk '" +
                                           o.name + "'");
    const Vec3 offset = d->center - p;
    const double h = dot(offset, n);
    const Frame f = Frame::from_normal(n);
    DiskLightView view;
    view.h = h;
    view.light = {dot(offset, f.s), dot(offset, f.t), d->radius};
    return hemisphere_kernel(view);
  }
  return polygon_cos2_solid_angle(polygon_vertices_relative(o.shape, p), n);
}

// Per-emitter kernels: K_hemisphere = ∫_visible cos²θ dω, K_area = ∫_visible (cos θ cos θ'/r²)² dA.
double emitter_kernel(Estimator estimator, const Scene& scene, size_t i, const Vec3& p, const Vec3& n,
                      std::optional<size_t> receiver) {
  const Object& object = scene.objects[i];
  const bool hemisphere = estimator == Estimator::kUniformHemisphere;
  if (std::holds_alternative<Disk>(object.shape)) {
    std::string reason;
    const auto view = disk_light_view(scene, i, p, n, receiver, &reason);
    if (view) return hemisphere ? hemisphere_kernel(*view) : area_kernel(*view);
    if (reason.empty()) return 0.0;
    if (hemisphere) return planar_light_cos2_solid_angle(scene, i, p, n, receiver);  // exact planar path
    unsupported_configuration(scene, reason + " (for the light-area second moment)");
  }
  if (std::holds_alternative<Sphere>(object.shape)) {
    if (emitter_irradiance(scene, i, p, n, receiver) == 0) return 0.0;  // nothing of it reaches p
    require_unoccluded(scene, i, p, n, receiver);
    const Sphere& sphere = std::get<Sphere>(object.shape);
    return hemisphere ? sphere_cos2_solid_angle(sphere.center - p, sphere.radius, n)
                      : sphere_area_kernel(sphere.center - p, sphere.radius, n);
  }
  // Rectangles and triangles: the exact planar path handles occluders and the
  // horizon for the cos² kernel; the light-area kernel needs an unoccluded light.
  if (hemisphere) return planar_light_cos2_solid_angle(scene, i, p, n, receiver);
  if (emitter_irradiance(scene, i, p, n, receiver) == 0) return 0.0;
  require_unoccluded(scene, i, p, n, receiver);
  return polygon_area_kernel(polygon_vertices_relative(object.shape, p), n);
}

}  // namespace

double second_moment(Estimator estimator, const Scene& scene, const Vec3& p, const Vec3& n,
                     std::optional<size_t> receiver) {
  // Lights a light-sampling estimator picks among (uniformly).
  size_t light_count = environment_is_light(scene.environment) ? 1 : 0;
  for (const Object& o : scene.objects) light_count += o.is_emitter() ? 1 : 0;

  double moment = 0;
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    const Object& object = scene.objects[i];
    if (!object.is_emitter() || (receiver && i == *receiver)) continue;
    const double le = object.emitted_radiance;
    switch (estimator) {
      case Estimator::kUniformHemisphere:
        moment += 2 * kPi * le * le * emitter_kernel(estimator, scene, i, p, n, receiver);
        break;
      case Estimator::kCosineHemisphere:
        moment += kPi * le * le * emitter_irradiance(scene, i, p, n, receiver);
        break;
      case Estimator::kLightArea:
        moment += double(light_count) * shape_area(object.shape) * le * le * emitter_kernel(estimator, scene, i, p, n, receiver);
        break;
    }
  }
  const double e_env = environment_irradiance(scene, p, n, receiver);
  if (e_env > 0 && scene.environment.map) {  // unblocked (environment_irradiance refuses blockers)
    switch (estimator) {
      case Estimator::kUniformHemisphere: moment += map_uniform_hemisphere_moment(scene.environment, n); break;
      case Estimator::kCosineHemisphere: moment += map_cosine_moment(scene.environment, n); break;
      case Estimator::kLightArea: moment += map_light_sampling_moment(scene.environment, n, light_count); break;
    }
  } else if (e_env > 0) {
    const double l_env = scene.environment.radiance;
    switch (estimator) {
      case Estimator::kUniformHemisphere: {
        // ∫ cos²θ dω = 2π/3 over the hemisphere, minus what the blockers hide.
        double hidden = 0;
        for (size_t j : environment_blockers(scene, p, n, receiver)) hidden += blocker_cos2_solid_angle(scene, j, p, n);
        moment += 2 * kPi * l_env * l_env * std::fmax(2 * kPi / 3 - hidden, 0.0);
        break;
      }
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
  if (!hit) return std::pow(environment_radiance(scene.environment, ray.direction), 2);
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
