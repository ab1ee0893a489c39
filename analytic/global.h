// Exact answers for global illumination (emission + direct + indirect light
// to any depth): the scenes of the seed's full path tracer whose radiance is
// known in closed form. Each function states its derivation and its domain;
// global_reference_image() decides from the scene alone which one applies
// and refuses (furnace::Error) a scene that none covers.
//
// Depth is counted in path segments, the camera segment being the first:
// max_segments = 1 sees only emission, 2 adds direct light, and so on;
// kUnlimitedDepth (core/strategy.h) means the full Neumann series.
#pragma once

#include <vector>

#include "core/scene.h"
#include "core/strategy.h"

namespace furnace::analytic {

// A closed enclosure whose every wall (and interior blocker) is Lambertian
// with reflectance ρ and emits Le on the sides that face the interior.
// Radiance is then uniform, L = Le + ρ·L (every direction from every point
// sees a wall of radiance L), so L = Le/(1−ρ); truncated after
// k = max_segments terms of the Neumann series, L_k = Le·Σ_{j<k} ρ^j =
// Le·(1−ρ^k)/(1−ρ). Computed as −expm1(k·log ρ)/(1−ρ) so that ρ → 1 keeps its
// digits; ρ = 1 gives Le·k (Le = ∞·0 excluded: requires ρ < 1 when unlimited).
// Units: those of Le. Domain: 0 ≤ ρ ≤ 1, Le ≥ 0, max_segments ≥ 1.
double uniform_enclosure_radiance(double emitted_radiance, double albedo, int max_segments);

// The white furnace: non-emitting Lambertian objects of reflectance ρ inside
// a constant environment of radiance L_env. A point on a single convex object
// sees only the environment over its whole hemisphere, so after one bounce
// L = ρ·L_env (Lambertian: ∫ (ρ/π) L_env cos θ dω = ρ L_env), for any
// max_segments ≥ 2; with max_segments = 1, L = 0 on the object. With ρ = 1
// and unlimited depth, L = L_env on every surface whatever the geometry
// (energy conservation: nothing is absorbed, nothing is emitted).
double convex_furnace_radiance(double environment_radiance, double albedo, int max_segments);

// Per pixel centre (row-major), the radiance a path tracer limited to
// max_segments must converge to. Covers:
//  - uniform enclosures (scene.closed, no environment, every object
//    Lambertian with one ρ < 1 and one Le, emitters two-sided or planar);
//  - white furnaces (no emitters, every object Lambertian with one ρ:
//    ρ = 1 at unlimited depth, or a single convex object at any depth);
//  - direct-only scenes: at most one reflecting object and it is planar (it
//    cannot see itself), every other object black: light reaches the eye
//    after at most one bounce, so the answer is the direct-lighting reference
//    for max_segments ≥ 2 and the emission alone for max_segments = 1;
//    the only form that accepts point lights (and then without mirrors);
//  - glossy (Phong, GGX) reflectors, all in one plane, no mirror: the same
//    direct-only answer, the receiver model's (reference.h's hit_radiance);
//  - perfect mirrors in front of any of the above: the camera ray is
//    reflected (radiance scaled by the mirror's reflectance) until it meets
//    a non-mirror surface or escapes.
//  - glass scenes (glass.h): a smooth dielectric sphere, or dielectric
//    interfaces in one plane, in a constant environment; their radiance
//    depends on the transport convention, which this form does not take:
//    it refuses a scene with a dielectric (use the form below).
// Throws furnace::Error naming the scene and the reason when none applies.
std::vector<double> global_reference_image(const Scene& scene, int max_segments);
// The same for a renderer of the given transport convention (which matters
// only for scenes with a dielectric).
std::vector<double> global_reference_image(const Scene& scene, int max_segments, TransportConvention convention);

}  // namespace furnace::analytic
