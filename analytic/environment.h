// The constant environment's contribution at a receiving point.
#pragma once

#include <optional>
#include <vector>

#include "core/scene.h"

namespace furnace::analytic {

// Projected solid angle Ω⊥ = ∫ max(cos θ, 0) dω that one object covers as
// seen from p with unit normal n (the object's irradiance per unit radiance if
// it glowed with L = 1 on the side facing p):
//   rectangle, triangle: polygon_irradiance (Lambert, clipped to the horizon);
//   sphere: sphere_irradiance (Snyder, horizon straddle included);
//   disk parallel to the receiver plane: disk_irradiance_parallel (Howell B-13);
//   tilted disk: the general planar path (planar_light.h) for the disk as a
//   lone two-sided emitter of unit radiance;
//   disk wholly below the horizon: 0.
// Throws furnace::Error for p inside a sphere.
double projected_solid_angle(const Scene& scene, size_t object, const Vec3& p, const Vec3& n);

// The objects above p's horizon other than `receiver`, checked pairwise
// non-overlapping as seen from p (see environment_irradiance); throws
// furnace::Error when two may overlap.
std::vector<size_t> environment_blockers(const Scene& scene, const Vec3& p, const Vec3& n,
                                         std::optional<size_t> receiver);

// E_env = ∫_{visible sky} L_env cos θ dω at p with unit normal n:
//   E_env = L_env·(π − Σ_objects Ω⊥(object)),
// with π − Ω⊥ of the largest blocker computed directly when it is a parallel
// disk (disk_irradiance_parallel_complement: no cancellation when it hides
// nearly the whole sky),
// the sum over the objects above p's horizon other than `receiver`. Exact
// when no two of them overlap as seen from p; that is checked with their
// bounding cones (ball of centre c, radius r seen under half-angle
// asin(r/|c − p|)): two cones are disjoint when the angle between their axes
// exceeds the sum of the half-angles. Throws furnace::Error (naming the
// objects) when two blockers may overlap, when p lies in a blocker's bounding
// ball while another blocker exists, or when a blocker has no closed form.
// 0 when L_env = 0. Units: W·m⁻² (those of L_env times sr).
// With an environment map: L_env·map_irradiance(map, n) (environment_map.h)
// when no object other than `receiver` rises above p's horizon; throws
// furnace::Error naming the map and the object otherwise.
double environment_irradiance(const Scene& scene, const Vec3& p, const Vec3& n, std::optional<size_t> receiver);

}  // namespace furnace::analytic
