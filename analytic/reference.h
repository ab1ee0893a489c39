// Exact references for whole scenes: what every pixel of a furnace render must
// converge to. This is the only analytic/ header verify/ needs; it dispatches
// to the closed forms in the other analytic/ headers.
//
// Never includes renderer/ or Embree: camera rays are intersected here in
// double precision, independently of the renderer's Embree geometry.
#pragma once

#include <optional>
#include <vector>

#include "core/scene.h"

namespace furnace::analytic {

// First intersection of a ray with the scene's shapes (double precision),
// t > t_min. Empty on a miss.
struct Hit {
  double t;
  size_t object_index;
  Vec3 point;
  Vec3 normal;  // front (geometric) normal of the shape at `point`
};
std::optional<Hit> intersect(const Scene& scene, const Vec3& origin, const Vec3& direction, double t_min = 0);

// Irradiance E(p, n) = Σ_lights ∫ Le V cos θ dω at point p with unit normal n,
// over the part of each emitter visible from p past every other object and
// above p's horizon, plus the constant environment over its visible part.
// `receiver` is excluded from the occluders (the surface p lies on).
// Throws furnace::Error naming the scene and objects when the configuration is
// outside what the library solves exactly. Solved (see emitter.h):
//  - disk lights with a parallel receiver and parallel disk occluders: closed
//    form (Howell B-13) or hand-rolled circle Booleans + closed-form arcs;
//  - disk, rectangle and triangle lights with any receiver tilt (horizon
//    clipped) behind parallel disks and planar polygons strictly between:
//    exact CGAL Booleans + contour integral (Lambert edges, quadrature arcs);
//  - unoccluded sphere lights (Snyder, horizon straddle included);
//  - a constant environment minus non-overlapping blockers;
//  - point lights: I·max(cos θ, 0)/r² past an exact segment test (point_light.h).
double irradiance(const Scene& scene, const Vec3& p, const Vec3& n, std::optional<size_t> receiver);

// Radiance the camera sees through the centre of pixel (px, py) for direct
// lighting only: Le(x) + (ρ/π)·E(x) at the first hit x of a Lambertian
// surface, Le(x) + glossy_reflected_radiance (glossy.h) at a glossy (Phong,
// GGX) surface; the environment radiance on a miss.
double pixel_center_radiance(const Scene& scene, int px, int py);

// The same quantity for any camera ray (origin, unit direction): what
// pixel_center_radiance evaluates at the pixel centre's ray.
double ray_radiance(const Scene& scene, const Vec3& origin, const Vec3& direction);

// The same quantity at a surface point `hit` reached along the unit
// `direction`: its emission toward the viewer plus the direct light its BSDF
// reflects there (Lambertian, Phong, GGX; a mirror is refused).
double hit_radiance(const Scene& scene, const Hit& hit, const Vec3& direction);

// All pixel centres, row-major (index = py * width + px).
std::vector<double> reference_image(const Scene& scene);

}  // namespace furnace::analytic
