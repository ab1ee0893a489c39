#include "analytic/environment.h"

#include <cmath>
#include <variant>
#include <vector>

#include "analytic/disk.h"
#include "analytic/disk_light.h"
#include "analytic/environment_map.h"
#include "analytic/occlusion.h"
#include "analytic/planar_light.h"
#include "analytic/polygon.h"
#include "analytic/sphere.h"
#include "analytic/unsupported.h"

namespace furnace::analytic {

namespace {

// Same threshold as disk_light.cpp: |n₁ × n₂| below it counts as parallel.
constexpr double kParallelSine = 1e-12;

}  // namespace

double projected_solid_angle(const Scene& scene, size_t object, const Vec3& p, const Vec3& n) {
  const Object& o = scene.objects[object];
  if (height_range(o.shape, p, n).hi <= 0) return 0.0;  // wholly below the horizon
  return std::visit(
      overloaded{
          [&](const Rectangle& r) {
            return polygon_irradiance({r.corner - p, r.corner + r.edge_u - p, r.corner + r.edge_u + r.edge_v - p,
                                       r.corner + r.edge_v - p},
                                      n);
          },
          [&](const Triangle& t) { return polygon_irradiance({t.p0 - p, t.p1 - p, t.p2 - p}, n); },
          [&](const Sphere& s) {
            if (length(p - s.center) <= s.radius)
              unsupported_configuration(scene, "a receiving point inside the sphere '" + o.name + "' under an environment");
            return sphere_irradiance(s.center - p, s.radius, n);
          },
          [&](const Disk& d) {
            if (length(cross(normalize(d.normal), n)) > kParallelSine) {
              // A tilted disk: its irradiance as a lone two-sided emitter of unit
              // radiance, by the general planar path (horizon clipping included).
              return planar_light_irradiance(as_lone_unit_emitter(scene, object), 0, p, n, std::nullopt);
            }
            const Vec3 offset = d.center - p;
            const double h = dot(offset, n);
            return disk_irradiance_parallel(d.radius, h, length(offset - n * h));
          }},
      o.shape);
}

std::vector<size_t> environment_blockers(const Scene& scene, const Vec3& p, const Vec3& n,
                                         std::optional<size_t> receiver) {
  std::vector<size_t> blockers;
  for (size_t j = 0; j < scene.objects.size(); ++j)
    if (!(receiver && j == *receiver) && height_range(scene.objects[j].shape, p, n).hi > 0) blockers.push_back(j);
  // Pairwise: the blockers' bounding cones from p must not overlap.
  for (size_t a = 0; a < blockers.size(); ++a)
    for (size_t b = a + 1; b < blockers.size(); ++b) {
      const BoundingSphere ba = bounding_sphere(scene.objects[blockers[a]].shape);
      const BoundingSphere bb = bounding_sphere(scene.objects[blockers[b]].shape);
      const double da = length(ba.center - p), db = length(bb.center - p);
      bool disjoint = da > ba.radius && db > bb.radius;
      if (disjoint) {
        const double half_a = std::asin(ba.radius / da), half_b = std::asin(bb.radius / db);
        const double between = angle_between((ba.center - p) / da, (bb.center - p) / db);
        // A relative margin keeps the test conservative under rounding.
        disjoint = between > (half_a + half_b) * (1 + 1e-12) + 1e-12;
      }
      if (!disjoint)
        unsupported_configuration(scene, "a constant environment hidden by the objects '" +
                                             scene.objects[blockers[a]].name + "' and '" +
                                             scene.objects[blockers[b]].name + "', which may overlap as seen from p,");
    }
  return blockers;
}

double environment_irradiance(const Scene& scene, const Vec3& p, const Vec3& n, std::optional<size_t> receiver) {
  if (!(scene.environment.radiance > 0)) return 0.0;
  if (scene.environment.map) {
    // The map references (environment_map.h) assume an unblocked sky.
    for (size_t j = 0; j < scene.objects.size(); ++j)
      if (!(receiver && j == *receiver) && height_range(scene.objects[j].shape, p, n).hi > 0)
        unsupported_configuration(scene, "the environment map '" + scene.environment.map_file +
                                             "' blocked by the object '" + scene.objects[j].name + "'");
    return scene.environment.radiance * map_irradiance(*scene.environment.map, n);
  }
  // The open sky, computed directly where π − Ω⊥ would cancel: the largest
  // blocker's complement (closed form for a parallel disk, the only blocker
  // that can cover nearly the whole hemisphere without p inside it) minus the
  // other blockers' Ω⊥.
  const std::vector<size_t> blockers = environment_blockers(scene, p, n, receiver);
  std::vector<double> omega;
  size_t largest = 0;
  for (size_t k = 0; k < blockers.size(); ++k) {
    omega.push_back(projected_solid_angle(scene, blockers[k], p, n));
    if (omega[k] > omega[largest]) largest = k;
  }
  double open = kPi;
  if (!blockers.empty()) {
    open = kPi - omega[largest];
    const Object& o = scene.objects[blockers[largest]];
    if (const auto* d = std::get_if<Disk>(&o.shape); d && length(cross(normalize(d->normal), n)) <= kParallelSine) {
      const Vec3 offset = d->center - p;
      const double h = dot(offset, n);
      if (h > 0) open = disk_irradiance_parallel_complement(d->radius, h, length(offset - n * h));
    }
  }
  for (size_t k = 0; k < blockers.size(); ++k)
    if (k != largest) open -= omega[k];
  return scene.environment.radiance * std::fmax(open, 0.0);
}

}  // namespace furnace::analytic
