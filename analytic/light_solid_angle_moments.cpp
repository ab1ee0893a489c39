// The light_solid_angle estimator's kernel per emitter (light_solid_angle_moments.h).
#include "analytic/light_solid_angle_moments.h"

#include <cmath>
#include <variant>

#include "analytic/emitter.h"
#include "analytic/light_moments.h"
#include "analytic/planar_light.h"
#include "core/strategy.h"

namespace furnace::analytic {

double solid_angle_emitter_kernel(const Scene& scene, size_t i, const Vec3& p, const Vec3& n,
                                  std::optional<size_t> receiver) {
  const Object& object = scene.objects[i];
  auto area_fallback = [&] {
    return shape_area(object.shape) * emitter_area_kernel(scene, i, p, n, receiver);
  };
  // Nothing of it reaches p (behind a one-sided light, edge-on, below the
  // horizon or wholly hidden): every sample is 0, whatever the method.
  auto reaches_p = [&] { return emitter_irradiance(scene, i, p, n, receiver) != 0; };
  // Triangles and rectangles seen from their emitting side (a two-sided light
  // from behind is sampled as its mirror twin: the same Ω).
  auto polygon_kernel = [&](const auto& polygon) {
    if (!reaches_p()) return 0.0;
    const double omega = polygon_solid_angle(polygon_vertices_relative(polygon, p));
    if (!(omega >= kMinSampledSolidAngle)) return area_fallback();
    return omega * planar_light_cos2_solid_angle(scene, i, p, n, receiver);
  };
  return std::visit(
      overloaded{[&](const Disk&) { return area_fallback(); },
                 [&](const Rectangle& r) {
                   const double lu = length(r.edge_u), lv = length(r.edge_v);
                   if (!(std::fabs(dot(r.edge_u, r.edge_v)) <= kPerpendicularTolerance * lu * lv)) return area_fallback();
                   return polygon_kernel(r);
                 },
                 [&](const Triangle& t) { return polygon_kernel(t); },
                 [&](const Sphere& sphere) {
                   if (!reaches_p()) return 0.0;
                   const Vec3 center = sphere.center - p;
                   const double D = length(center);
                   if (!(D > sphere.radius)) return area_fallback();  // on or inside: the renderer has no cone
                   require_unoccluded(scene, i, p, n, receiver);
                   return sphere_solid_angle(D, sphere.radius) * sphere_cos2_solid_angle(center, sphere.radius, n);
                 }},
      object.shape);
}

}  // namespace furnace::analytic
