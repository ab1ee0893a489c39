#include "renderer/lights.h"

#include <algorithm>
#include <limits>

#include "renderer/sampling.h"

namespace furnace {

AreaSampler::AreaSampler(const Shape& shape) : shape_(shape), pdf_area_(1.0 / shape_area(shape)) {
  std::visit(overloaded{[&](const Rectangle& r) { normal_ = r.normal(); },
                        [&](const Disk& d) {
                          normal_ = d.normal;
                          frame_ = Frame::from_normal(d.normal);
                        },
                        [](const Sphere&) {},
                        [&](const Triangle& t) { normal_ = t.normal(); }},
             shape);
}

namespace {

// Axis-aligned box of a shape (spheres by their centre ± r).
void grow_box(const Shape& shape, Vec3& lo, Vec3& hi) {
  auto add = [&](const Vec3& p) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  };
  auto add_ball = [&](const Vec3& c, double r) {
    add(c - Vec3(r, r, r));
    add(c + Vec3(r, r, r));
  };
  std::visit(overloaded{[&](const Rectangle& r) {
                          for (const Vec3& p : r.corners()) add(p);
                        },
                        [&](const Disk& d) { add_ball(d.center, d.radius); },  // the disk's ball bounds it
                        [&](const Sphere& s) { add_ball(s.center, s.radius); },
                        [&](const Triangle& t) {
                          for (const Vec3& p : {t.p0, t.p1, t.p2}) add(p);
                        }},
             shape);
}

// Radius of the scene's bounding sphere: half the diagonal of the box of
// every shape and point light (0 for an empty scene).
double scene_bounding_radius(const Scene& scene) {
  const double inf = std::numeric_limits<double>::infinity();
  Vec3 lo{inf, inf, inf}, hi{-inf, -inf, -inf};
  for (const Object& o : scene.objects) grow_box(o.shape, lo, hi);
  for (const PointLight& l : scene.point_lights) grow_box(Sphere{l.position, 0.0}, lo, hi);
  return lo.x <= hi.x ? 0.5 * length(hi - lo) : 0.0;
}

}  // namespace

LightSet::LightSet(const Scene& scene, LightSelection selection_) : selection(selection_) {
  for (size_t i = 0; i < scene.objects.size(); ++i)
    if (scene.objects[i].is_emitter()) {
      emitters.push_back(i);
      area_samplers_.emplace_back(scene.objects[i].shape);
    }
  for (size_t i = 0; i < scene.point_lights.size(); ++i) point_lights.push_back(i);
  environment = scene.environment.radiance > 0;
  if (environment && scene.environment.map) {
    environment_sampler = std::make_shared<const EnvironmentSampler>(scene.environment.map);
    environment = environment_sampler->has_power();  // a black map sends no light
  }

  // Emitted powers (lights.h states the conventions).
  for (size_t i : emitters) {
    const Object& o = scene.objects[i];
    power_.push_back((o.two_sided ? 2 : 1) * kPi * o.emitted_radiance * shape_area(o.shape));
  }
  for (size_t i : point_lights) power_.push_back(4 * kPi * scene.point_lights[i].intensity);
  if (environment) {
    // A map radiates like a constant sky of its mean radiance L·Σ map·Ω/(4π).
    const double mean = environment_sampler ? environment_sampler->integral() / (4 * kPi) : 1.0;
    const double r = scene_bounding_radius(scene);
    power_.push_back(kPi * scene.environment.radiance * mean * kPi * r * r);
  }
  if (count() == 0) return;
  double total = 0;
  for (double p : power_) total += p;
  const bool by_power = selection == LightSelection::kPower && total > 0;
  for (double p : power_) pmf_.push_back(by_power ? p / total : 1.0 / double(count()));
  double running = 0;
  for (double p : pmf_) cdf_.push_back(running += p);
  cdf_.back() = 1.0;  // exact, so that every u < 1 selects a light
}

size_t LightSet::light_of_object(size_t object) const {
  const auto it = std::lower_bound(emitters.begin(), emitters.end(), object);
  return it != emitters.end() && *it == object ? size_t(it - emitters.begin()) : count();
}

size_t LightSet::select(double u) const {
  // Uniform: the direct formula ⌊u·count⌋; min(): u·count can round up to
  // count for u just below 1.
  if (selection == LightSelection::kUniform) return std::min(size_t(u * double(count())), count() - 1);
  // Power: the first light whose CDF exceeds u (lights of pmf 0 are never chosen).
  const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), u);
  return std::min(size_t(it - cdf_.begin()), count() - 1);
}

}  // namespace furnace
