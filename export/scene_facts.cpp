#include "export/scene_facts.h"

#include <algorithm>
#include <cmath>
#include <variant>

#include <fmt/format.h>

#include "core/error.h"
#include "core/overloaded.h"

namespace furnace::exporter {

std::string object_material_text(const Scene& scene, size_t index) {
  const Object& o = scene.objects.at(index);
  return fmt::format("'{}' (objects[{}].material.{})", o.name, index, o.material.text());
}

namespace {

// A point of a planar shape's plane.
Vec3 plane_point(const Shape& shape) {
  return std::visit(overloaded{[](const Rectangle& r) { return r.corner; }, [](const Triangle& t) { return t.p0; },
                               [](const Disk& d) { return d.center; }, [](const Sphere& s) { return s.center; }},
                    shape);
}

// Whether `shape` lies in the plane through `origin` with unit normal `n`
// (to 1e-12 of the coordinates' size): light leaving that plane's surface
// goes into an open half-space and never meets such a shape.
bool in_plane(const Shape& shape, const Vec3& origin, const Vec3& n) {
  auto on = [&](const Vec3& p) {
    const double scale = std::max({1.0, std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)});
    return std::fabs(dot(p - origin, n)) <= 1e-12 * scale;
  };
  return std::visit(
      overloaded{[&](const Rectangle& r) {
                   return on(r.corner) && on(r.corner + r.edge_u) && on(r.corner + r.edge_v) &&
                          on(r.corner + r.edge_u + r.edge_v);
                 },
                 [&](const Triangle& t) { return on(t.p0) && on(t.p1) && on(t.p2); },
                 [&](const Disk& d) { return on(d.center) && 1 - std::fabs(dot(normalize(d.normal), n)) <= 1e-12; },
                 [](const Sphere&) { return false; }},
      shape);
}

}  // namespace

std::optional<std::string> not_seen_only_along_normal(const Scene& scene, size_t index) {
  const Object& object = scene.objects.at(index);
  if (!is_planar(object.shape))
    return fmt::format("'{}' is a sphere, which camera rays meet at oblique angles", object.name);
  const Vec3 n = shape_normal(object.shape, Vec3{});
  const double cos_view = std::fabs(dot(n, normalize(scene.camera.forward)));
  if (1 - cos_view > kNormalViewTolerance)
    return fmt::format("'{}' is not perpendicular to the camera's forward direction (|cos| {}), so camera rays "
                       "leave it at oblique angles",
                       object.name, cos_view);
  const Vec3 origin = plane_point(object.shape);
  for (size_t i = 0; i < scene.objects.size(); ++i)
    if (i != index && reflects(scene.objects[i].material) && !in_plane(scene.objects[i].shape, origin, n))
      return fmt::format("the object '{}' reflects light that leaves '{}' at oblique angles back towards the eye",
                         scene.objects[i].name, object.name);
  return std::nullopt;
}

bool reflects(const Material& material) { return material.reflects(); }

bool direct_lighting_is_complete(const Scene& scene) {
  int reflecting = 0;
  for (const Object& o : scene.objects) {
    if (!reflects(o.material)) continue;
    ++reflecting;
    // The direct-lighting answer is claimed (and measured by the peer tests)
    // for a Lambertian reflector only; a scene with any other reflector is
    // checked at the depth rendered. A planar reflector cannot light itself;
    // a sphere's inside can.
    if (!o.material.as<Lambertian>() || !is_planar(o.shape)) return false;
  }
  return reflecting <= 1;
}

int check_max_depth(const Scene& scene, int max_segments) {
  return direct_lighting_is_complete(scene) && max_segments >= 2 ? 2 : max_segments;
}

std::string direct_lighting_clause(const Scene& scene, int max_segments) {
  return check_max_depth(scene, max_segments) == 2 && max_segments != 2
             ? ",\n# which is direct lighting here: light reaches the eye after at most one bounce, off the only "
               "reflector"
             : "";
}

}  // namespace furnace::exporter
