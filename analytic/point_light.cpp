#include "analytic/point_light.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <variant>

#include "analytic/environment_map.h"
#include "analytic/intersect.h"

namespace furnace::analytic {

bool segment_clear(const Scene& scene, const Vec3& p, const Vec3& target, std::optional<size_t> receiver) {
  const Vec3 d = target - p;  // unnormalised: t = 1 is the light
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    if (receiver && i == *receiver) continue;
    const std::optional<double> t = intersect_shape(scene.objects[i].shape, p, d, 0.0);
    if (t && *t < 1) return false;
  }
  return true;
}

double point_light_irradiance(const Scene& scene, size_t light, const Vec3& p, const Vec3& n,
                              std::optional<size_t> receiver) {
  const PointLight& l = scene.point_lights[light];
  const Vec3 to_light = l.position - p;
  const double r2 = length_squared(to_light);
  const double cos_theta = dot(n, to_light) / std::sqrt(r2);
  if (!(cos_theta > 0)) return 0.0;
  if (!segment_clear(scene, p, l.position, receiver)) return 0.0;
  return l.intensity * cos_theta / r2;
}

double point_lights_irradiance(const Scene& scene, const Vec3& p, const Vec3& n, std::optional<size_t> receiver) {
  double e = 0;
  for (size_t i = 0; i < scene.point_lights.size(); ++i) e += point_light_irradiance(scene, i, p, n, receiver);
  return e;
}

namespace {

// The two corners of the axis-aligned box around a shape.
std::pair<Vec3, Vec3> shape_box(const Shape& shape) {
  auto ball = [](const Vec3& c, double r) { return std::make_pair(c - Vec3(r, r, r), c + Vec3(r, r, r)); };
  auto box = [](const std::vector<Vec3>& v) {
    Vec3 lo = v[0], hi = v[0];
    for (const Vec3& q : v) {
      lo = {std::min(lo.x, q.x), std::min(lo.y, q.y), std::min(lo.z, q.z)};
      hi = {std::max(hi.x, q.x), std::max(hi.y, q.y), std::max(hi.z, q.z)};
    }
    return std::make_pair(lo, hi);
  };
  return std::visit(
      overloaded{[&](const Disk& d) { return ball(d.center, d.radius); },
                 [&](const Sphere& s) { return ball(s.center, s.radius); },
                 [&](const Rectangle& r) {
                   return box({r.corner, r.corner + r.edge_u, r.corner + r.edge_v, r.corner + r.edge_u + r.edge_v});
                 },
                 [&](const Triangle& t) { return box({t.p0, t.p1, t.p2}); }},
      shape);
}

double bounding_radius(const Scene& scene) {
  std::vector<std::pair<Vec3, Vec3>> boxes;
  for (const Object& o : scene.objects) boxes.push_back(shape_box(o.shape));
  for (const PointLight& l : scene.point_lights) boxes.push_back({l.position, l.position});
  if (boxes.empty()) return 0.0;
  Vec3 lo = boxes[0].first, hi = boxes[0].second;
  for (const auto& [a, b] : boxes) {
    lo = {std::min(lo.x, a.x), std::min(lo.y, a.y), std::min(lo.z, a.z)};
    hi = {std::max(hi.x, b.x), std::max(hi.y, b.y), std::max(hi.z, b.z)};
  }
  return 0.5 * length(hi - lo);
}

}  // namespace

std::vector<double> light_selection_pmf(const Scene& scene, LightSelection selection) {
  std::vector<double> power;
  for (const Object& o : scene.objects)
    if (o.is_emitter()) power.push_back((o.two_sided ? 2 * kPi : kPi) * o.emitted_radiance * shape_area(o.shape));
  for (const PointLight& l : scene.point_lights) power.push_back(4 * kPi * l.intensity);
  if (environment_is_light(scene.environment)) {
    // A map radiates like a constant sky of its mean radiance L·Σ map·Ω/(4π).
    const double mean =
        scene.environment.map ? map_solid_angle_integral(*scene.environment.map) / (4 * kPi) : 1.0;
    const double r = bounding_radius(scene);
    power.push_back(scene.environment.radiance * mean * kPi * (kPi * r * r));
  }
  double total = 0;
  for (double p : power) total += p;
  std::vector<double> pmf;
  for (double p : power)
    pmf.push_back(selection == LightSelection::kPower && total > 0 ? p / total : 1.0 / double(power.size()));
  return pmf;
}

}  // namespace furnace::analytic
