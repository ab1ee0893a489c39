// Facts about a furnace scene that every exporter needs, decided once here
// instead of in one exporter: whether an object reflects at all, an object's
// material in a refusal sentence, and which
// `furnace check --max-depth` has the reference a render of the complete
// light transport must match. None branches on the material type: each
// format's one exhaustive visit over the types is in its own writer
// (pbrt_material, cycles_material), and these read the type's table row.
#pragma once

#include <cstddef>
#include <optional>
#include <string>

#include "core/scene.h"

namespace furnace::exporter {

// An object's material as its scene file states it, for refusal sentences:
// 'floor' (objects[0].material.type "lambertian", albedo 0.5), with the
// type's own fields after the albedo: 'strip' (objects[1].material.type
// "ggx", albedo 0.8, alpha 0.3, shadowing "separable").
std::string object_material_text(const Scene& scene, size_t index);

// Why light can leave the object scene.objects[index] towards the eye along a
// direction other than its normal; empty when it cannot. It cannot when the
// object is planar, faces along the camera's forward direction (furnace's
// camera is orthographic, so every camera ray meets it along its normal, to
// within 1 − |cos| ≤ kNormalViewTolerance) and every other object either
// reflects nothing (reflects() false) or lies in its plane (where light
// leaving it never arrives), so the only paths that leave it and reach the
// eye are camera rays. There the two Smith forms of a microfacet BSDF agree
// exactly (Λ(n) = 0), so an exporter may write one for the other. Confirmed
// by rendering: ggx_sky_strips and ggx_disk_occluder, whose strips alternate
// the forms, pass `furnace check` in pbrt-v4 (height-correlated only) and in
// Cycles 3.4 (separable only), K = 16 (docs/checking_pbrt.md,
// docs/checking_cycles.md); at oblique view the other form fails (10 % off).
std::optional<std::string> not_seen_only_along_normal(const Scene& scene, size_t index);
// 1 − |cos θ| ≤ 1e-9 keeps θ below 4.5e-5 rad, where Λ(ω) ≈ α² tan²θ / 4 is
// below 5e-10: far below any Monte Carlo test's resolution.
inline constexpr double kNormalViewTolerance = 1e-9;

// Whether the material reflects any light (Material::reflects: not when its
// type's albedo scales the whole reflection and is 0), so that an exporter
// may write a black object as a black diffuse surface.
bool reflects(const Material& material);

// True when light reaches the eye after at most one bounce, off the only
// reflecting object, a planar Lambertian one (every other object black): any
// depth of 2 or more segments then renders furnace's direct-lighting
// reference, `furnace check --max-depth 2`.
bool direct_lighting_is_complete(const Scene& scene);

// The `furnace check --max-depth` whose reference a render of at most
// `max_segments` path segments (furnace's convention, the camera's segment
// included; kUnlimitedDepth for the complete transport) must match: 2
// (emission + one bounce: direct lighting) when direct_lighting_is_complete()
// and the depth allows one bounce, else max_segments.
int check_max_depth(const Scene& scene, int max_segments);

// The clause an exported file's header adds after "furnace's global
// illumination at <depth>" when check_max_depth() chose direct lighting for
// a deeper render; empty otherwise.
std::string direct_lighting_clause(const Scene& scene, int max_segments);

}  // namespace furnace::exporter
