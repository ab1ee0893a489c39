#include "analytic/emitter.h"

#include <string>
#include <variant>

#include "analytic/circle_region.h"
#include "analytic/disk_light.h"
#include "analytic/occlusion.h"
#include "analytic/planar_light.h"
#include "analytic/sphere.h"
#include "analytic/sphere_occluded.h"

namespace furnace::analytic {

void require_unoccluded(const Scene& scene, size_t emitter, const Vec3& p, const Vec3& n,
                        std::optional<size_t> receiver) {
  const Object& light = scene.objects[emitter];
  const BoundingSphere light_ball = bounding_sphere(light.shape);
  for (size_t j = 0; j < scene.objects.size(); ++j) {
    if (j == emitter || (receiver && j == *receiver)) continue;
    const Object& object = scene.objects[j];
    if (height_range(object.shape, p, n).hi <= 0) continue;
    if (!ball_may_meet_ball_cone(bounding_sphere(object.shape), p, light_ball)) continue;
    unsupported_configuration(scene, "object '" + object.name + "', which may block part of the emitter '" + light.name +
                                         "' where only an unoccluded emitter is solved,");
  }
}

double emitter_irradiance(const Scene& scene, size_t emitter, const Vec3& p, const Vec3& n,
                          std::optional<size_t> receiver) {
  const Object& light = scene.objects[emitter];
  auto polygon = [&] { return planar_light_irradiance(scene, emitter, p, n, receiver); };
  return std::visit(
      overloaded{[&](const Disk&) {
                   // Fast path (hand-rolled circle Booleans, closed-form arcs); the
                   // general exact path when it does not apply.
                   std::string reason;
                   if (const auto view = disk_light_view(scene, emitter, p, n, receiver, &reason))
                     return occluded_disk_irradiance(view->h, view->light, view->occluder_images);
                   return reason.empty() ? 0.0 : planar_light_irradiance(scene, emitter, p, n, receiver);
                 },
                 [&](const Sphere& sphere) {
                   if (length(p - sphere.center) <= sphere.radius) {
                     if (!light.two_sided) return 0.0;  // inside a one-sided (outward) emitter: nothing arrives
                     unsupported_configuration(scene,
                                               "a receiving point inside the two-sided sphere light '" + light.name + "'");
                   }
                   // Snyder's closed form when nothing can block; quadrature over exact
                   // limits when every possible blocker is planar (sphere_occluded.h).
                   return sphere_light_irradiance(scene, emitter, p, n, receiver);
                 },
                 [&](const Rectangle&) { return polygon(); }, [&](const Triangle&) { return polygon(); }},
      light.shape);
}

}  // namespace furnace::analytic
