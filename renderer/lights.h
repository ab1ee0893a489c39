// Light sources: the scene's emitters (one-sided, Lambertian), its point
// lights, and the environment when its radiance is positive (and, for a map,
// some texel is); the selection pmf among them and the sampling of points on
// their shapes.
#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <variant>
#include <vector>

#include "core/scene.h"
#include "core/strategy.h"
#include "renderer/environment_sampler.h"
#include "renderer/sampling.h"

namespace furnace {

// A point on a shape with its front normal and its density in area (m⁻²).
struct AreaSample {
  Vec3 point;
  Vec3 normal;
  double pdf_area = 0;
};

// Points uniform on one shape's area: rectangles by the bilinear map, disks
// by the concentric map, triangles by the barycentric warp, spheres by the
// uniform sphere warp. The shape's constants (its density 1/area, a flat
// shape's front normal, a disk's frame) are computed once, at construction:
// LightSet keeps one sampler per emitter, so no sample recomputes them.
class AreaSampler {
 public:
  explicit AreaSampler(const Shape& shape);
  // (get_if, not std::visit: a value std::visit returns goes through memory,
  // and reading it back stalled the light strategies' profile.)
  AreaSample sample(double u1, double u2) const {
    static_assert(std::variant_size_v<Shape> == 4, "AreaSampler::sample handles every shape");
    if (const Rectangle* r = std::get_if<Rectangle>(&shape_))
      return {r->corner + r->edge_u * u1 + r->edge_v * u2, normal_, pdf_area_};
    if (const Disk* d = std::get_if<Disk>(&shape_)) {
      const auto xy = sample_uniform_disk_concentric(u1, u2);
      return {d->center + frame_.world_from_local({xy[0] * d->radius, xy[1] * d->radius, 0.0}), d->normal, pdf_area_};
    }
    if (const Sphere* s = std::get_if<Sphere>(&shape_)) {
      const Vec3 n = sample_uniform_sphere(u1, u2);
      return {s->center + n * s->radius, n, pdf_area_};
    }
    const Triangle& t = std::get<Triangle>(shape_);
    const auto b = sample_uniform_triangle_barycentric(u1, u2);
    return {t.p0 * b[0] + t.p1 * b[1] + t.p2 * b[2], normal_, pdf_area_};
  }
  // Density in area of sample(): 1/area on the shape.
  double pdf_area() const { return pdf_area_; }
  // The front normal at a point `p` of the shape (core's shape_normal, with a
  // flat shape's normal computed once).
  Vec3 normal_at(const Vec3& p) const {
    if (const Sphere* s = std::get_if<Sphere>(&shape_)) return scene_normalize(p - s->center);
    return normal_;
  }

 private:
  Shape shape_;
  Vec3 normal_;   // a flat shape's front normal
  Frame frame_;   // a disk's frame about its normal
  double pdf_area_ = 0;
};

// One point by AreaSampler (its constants computed for this call alone).
inline AreaSample sample_shape_area(const Shape& shape, double u1, double u2) {
  return AreaSampler(shape).sample(u1, u2);
}

// THE area → solid-angle conversion (the only place it is written):
// p_ω = p_A · r² / cos θ', θ' the angle at the light point between its normal
// and the direction back to the receiver. 0 when cos θ' ≤ 0 (the receiver sees
// the light edge-on or from behind, where a one-sided light has no density;
// two-sided lights pass |cos θ'|).
inline double solid_angle_pdf_from_area(double pdf_area, double distance_squared, double cos_theta_light) {
  return cos_theta_light > 0 ? pdf_area * distance_squared / cos_theta_light : 0.0;
}

// The lights a light-sampling strategy chooses among: every emitter (object
// order), then every point light (scene order), then the environment (if its
// radiance is positive). Light index i < emitters.size() is an emitter, the
// next point_lights.size() indices are point lights, the last the environment.
//
// Selection pmf: uniform 1/K, or proportional to the emitted power Φ
// (LightSelection::kPower):
//   one-sided Lambertian emitter  Φ = π·Le·A  (a sphere's outside: A = 4πr²),
//   two-sided emitter             Φ = 2π·Le·A,
//   isotropic point light         Φ = 4π·I,
//   constant environment          Φ = π·L·(π R²), R the radius of the scene's
//     bounding sphere (the centre and half-diagonal of the axis-aligned box of
//     every shape and point light): the power a sky of radiance L sends
//     through a disk of radius R. A convention only: any positive value is
//     unbiased because sample() and pdf() use the same pmf.
// A light of zero power (never: emitters have Le > 0, point lights I > 0)
// would get pmf 0. select() inverts the CDF; sample() and pdf() read pmf().
struct LightSet {
  explicit LightSet(const Scene& scene, LightSelection selection = LightSelection::kUniform);

  std::vector<size_t> emitters;       // object indices
  std::vector<size_t> point_lights;   // indices into Scene::point_lights
  bool environment = false;
  LightSelection selection = LightSelection::kUniform;
  // Importance sampling of an image-based environment (empty for a constant one).
  std::shared_ptr<const EnvironmentSampler> environment_sampler;

  size_t count() const { return emitters.size() + point_lights.size() + (environment ? 1 : 0); }
  bool is_emitter(size_t light) const { return light < emitters.size(); }
  bool is_point_light(size_t light) const { return light >= emitters.size() && light < emitters.size() + point_lights.size(); }
  bool is_environment(size_t light) const { return environment && light == count() - 1; }
  // Selection probability of light index `light`.
  double pmf(size_t light) const { return light < pmf_.size() ? pmf_[light] : 0.0; }
  // Light index of object `object` if it is an emitter, else count().
  size_t light_of_object(size_t object) const;
  // Light index from a uniform number in [0, 1), by inversion of the CDF.
  size_t select(double u) const;
  // The area sampler of emitter light index `light` (< emitters.size()).
  const AreaSampler& area_sampler(size_t light) const { return area_samplers_[light]; }
  // Emitted power Φ of every light (the formulas above), in light-index order.
  const std::vector<double>& powers() const { return power_; }

 private:
  std::vector<AreaSampler> area_samplers_;  // one per emitter, in light-index order
  std::vector<double> power_, pmf_, cdf_;  // cdf_[i] = Σ_{j ≤ i} pmf_[j], cdf_.back() == 1
};

}  // namespace furnace
