// Isotropic point lights (delta lights) and the light-selection pmf the
// light-sampling estimators choose lights with, derived here independently of
// the renderer (analytic/ never includes renderer/).
#pragma once

#include <optional>
#include <vector>

#include "core/scene.h"
#include "core/strategy.h"

namespace furnace::analytic {

// Whether the open segment from p to `target` meets no object other than
// `receiver` (double precision, analytic::intersect_shape). The segment is
// p + t·(target − p), t ∈ (0, 1); a hit at t ≥ 1 lies at or past the light.
// Edges are inclusive (intersect.h), so a light exactly on an occluder's
// silhouette counts as hidden; that set of receiving points is a curve on the
// receiver (measure zero), met by a pixel centre only by construction.
bool segment_clear(const Scene& scene, const Vec3& p, const Vec3& target, std::optional<size_t> receiver);

// Irradiance at p (unit normal n) from point light `light` (index into
// Scene::point_lights), the inverse-square law with Lambert's cosine:
//   E = I·max(cos θ, 0)/r²·V,  cos θ = n·(x − p)/r,  r = |x − p|,
// V = segment_clear(p, x) exact (no soft shadow: the light has no extent).
// Units: W·m⁻² (I in W·sr⁻¹). 0 when the light lies on p's plane or behind it.
double point_light_irradiance(const Scene& scene, size_t light, const Vec3& p, const Vec3& n,
                              std::optional<size_t> receiver);

// Σ over every point light of point_light_irradiance.
double point_lights_irradiance(const Scene& scene, const Vec3& p, const Vec3& n, std::optional<size_t> receiver);

// The selection pmf (uniform 1/K, or Φ_l/Σ Φ by power) of every light, in the order: emitters (object order),
// point lights (scene order), the environment last (when its radiance is
// positive). Emitted power Φ:
//   one-sided Lambertian emitter Φ = π·Le·A (a sphere's outside, A = 4πr²);
//   two-sided emitter Φ = 2π·Le·A (it radiates π·Le per unit area from each face);
//   isotropic point light Φ = ∫ I dω = 4π·I;
//   constant environment Φ = L·π·(πR²): the power of radiance L crossing a
//     disk of radius R from one side, R the radius of the scene's bounding
//     sphere, taken as half the diagonal of the axis-aligned box around every
//     shape (disks and spheres by the box of their ball) and every point light.
// The environment's Φ is a convention (the estimator is unbiased for any
// positive value); this one must equal the renderer's for the predicted
// second moment to be the renderer's.
std::vector<double> light_selection_pmf(const Scene& scene, LightSelection selection);

}  // namespace furnace::analytic
