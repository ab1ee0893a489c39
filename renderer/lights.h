// Light sources: the scene's emitters (one-sided, Lambertian) plus the
// environment when its radiance is positive (and, for a map, some texel is),
// and the sampling of points on their shapes.
#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <vector>

#include "core/scene.h"
#include "renderer/environment_sampler.h"

namespace furnace {

// A point on a shape with its front normal and its density in area (m⁻²).
struct AreaSample {
  Vec3 point;
  Vec3 normal;
  double pdf_area = 0;
};

// A point uniform on the shape's area: rectangles by the bilinear map, disks
// by the concentric map, triangles by the barycentric warp, spheres by the
// uniform sphere warp.
AreaSample sample_shape_area(const Shape& shape, double u1, double u2);
// Density in area of sample_shape_area: 1/area on the shape.
double shape_area_pdf(const Shape& shape);

// THE area → solid-angle conversion (the only place it is written):
// p_ω = p_A · r² / cos θ', θ' the angle at the light point between its normal
// and the direction back to the receiver. 0 when cos θ' ≤ 0 (the receiver sees
// the light edge-on or from behind, where a one-sided light has no density;
// two-sided lights pass |cos θ'|).
inline double solid_angle_pdf_from_area(double pdf_area, double distance_squared, double cos_theta_light) {
  return cos_theta_light > 0 ? pdf_area * distance_squared / cos_theta_light : 0.0;
}

// The lights a light-sampling strategy chooses among, uniformly: every
// emitter, then the environment (if its radiance is positive).
struct LightSet {
  explicit LightSet(const Scene& scene);

  std::vector<size_t> emitters;  // object indices
  bool environment = false;
  // Importance sampling of an image-based environment (empty for a constant one).
  std::shared_ptr<const EnvironmentSampler> environment_sampler;

  size_t count() const { return emitters.size() + (environment ? 1 : 0); }
  double selection_pmf() const { return count() > 0 ? 1.0 / double(count()) : 0.0; }
  // Light index from a uniform number in [0, 1); == emitters.size() is the environment.
  size_t select(double u) const;
};

}  // namespace furnace
