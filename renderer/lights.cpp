#include "renderer/lights.h"

#include <algorithm>

#include "renderer/sampling.h"

namespace furnace {

AreaSample sample_shape_area(const Shape& shape, double u1, double u2) {
  struct Visitor {
    double u1, u2;
    AreaSample operator()(const Rectangle& r) const {
      return {r.corner + r.edge_u * u1 + r.edge_v * u2, r.normal(), 1.0 / r.area()};
    }
    AreaSample operator()(const Disk& d) const {
      const auto xy = sample_uniform_disk_concentric(u1, u2);
      const Frame f = Frame::from_normal(d.normal);
      return {d.center + f.world_from_local({xy[0] * d.radius, xy[1] * d.radius, 0.0}), d.normal, 1.0 / d.area()};
    }
    AreaSample operator()(const Sphere& s) const {
      const Vec3 n = sample_uniform_sphere(u1, u2);
      return {s.center + n * s.radius, n, 1.0 / s.area()};
    }
    AreaSample operator()(const Triangle& t) const {
      const auto b = sample_uniform_triangle_barycentric(u1, u2);
      return {t.p0 * b[0] + t.p1 * b[1] + t.p2 * b[2], t.normal(), 1.0 / t.area()};
    }
  };
  return std::visit(Visitor{u1, u2}, shape);
}

double shape_area_pdf(const Shape& shape) { return 1.0 / shape_area(shape); }

LightSet::LightSet(const Scene& scene) {
  for (size_t i = 0; i < scene.objects.size(); ++i)
    if (scene.objects[i].is_emitter()) emitters.push_back(i);
  environment = scene.environment.radiance > 0;
  if (environment && scene.environment.map) {
    environment_sampler = std::make_shared<const EnvironmentSampler>(scene.environment.map);
    environment = environment_sampler->has_power();  // a black map sends no light
  }
}

size_t LightSet::select(double u) const {
  // min(): u·count can round up to count for u just below 1.
  return std::min(size_t(u * double(count())), count() - 1);
}

}  // namespace furnace
