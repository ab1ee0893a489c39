#include "analytic/emitter.h"

#include <optional>
#include <string>
#include <variant>

#include "analytic/circle_region.h"
#include "analytic/disk_light.h"
#include "analytic/occlusion.h"
#include "analytic/planar_light.h"
#include "analytic/sphere.h"
#include "analytic/sphere_occluded.h"
#include "analytic/unsupported.h"

namespace furnace::analytic {

namespace {

// Whether `object` provably meets no segment from p to a point of the planar
// emitter: every such segment, its light end left out, lies strictly on p's
// side of the emitter's plane, so an object wholly on the other side cannot
// meet it, and one that reaches the plane only from there (a coplanar
// object, say) meets it at most at its light end, which it cannot when the
// two shapes' bounding balls are apart.
bool behind_planar_emitter(const Shape& object, const Vec3& p, const Plane& plane, const BoundingSphere& light_ball) {
  const double s = dot(p - plane.point, plane.normal);
  const ZRange z = height_range(object, plane.point, plane.normal);
  const bool strictly = s > 0 ? z.hi < 0 : z.lo > 0;
  const bool up_to_plane = s > 0 ? z.hi <= 0 : z.lo >= 0;
  if (s == 0 || !up_to_plane) return false;
  if (strictly) return true;
  const BoundingSphere ball = bounding_sphere(object);
  return length(ball.center - light_ball.center) > ball.radius + light_ball.radius;
}

}  // namespace

std::optional<size_t> possible_blocker(const Scene& scene, size_t emitter, const Vec3& p, const Vec3& n,
                                       std::optional<size_t> receiver) {
  const Object& light = scene.objects[emitter];
  const BoundingSphere light_ball = bounding_sphere(light.shape);
  const std::optional<Plane> light_plane = plane_of(light.shape);
  for (size_t j = 0; j < scene.objects.size(); ++j) {
    if (j == emitter || (receiver && j == *receiver)) continue;
    const Object& object = scene.objects[j];
    if (height_range(object.shape, p, n).hi <= 0) continue;
    if (light_plane && behind_planar_emitter(object.shape, p, *light_plane, light_ball)) continue;
    if (!ball_may_meet_ball_cone(bounding_sphere(object.shape), p, light_ball)) continue;
    return j;
  }
  return std::nullopt;
}

void require_unoccluded(const Scene& scene, size_t emitter, const Vec3& p, const Vec3& n,
                        std::optional<size_t> receiver) {
  if (const std::optional<size_t> j = possible_blocker(scene, emitter, p, n, receiver))
    unsupported_configuration(scene, "object '" + scene.objects[*j].name + "', which may block part of the emitter '" +
                                         scene.objects[emitter].name + "' where only an unoccluded emitter is solved,");
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
