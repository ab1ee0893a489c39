// A disk emitter seen from a receiving point: the scene reduced to the
// parallel-plane picture every disk reference works in (emitter plane at
// height h above p, the light and the central projections of the occluders
// as circles in 2-D coordinates centred on p's foot point).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "analytic/circle_region.h"
#include "core/scene.h"

namespace furnace::analytic {

struct DiskLightView {
  double h = 0;                          // distance from p to the emitter plane, scene units
  Circle2 light;                         // the emitter disk
  std::vector<Circle2> occluder_images;  // central projections from p of parallel disk occluders
  Vec3 toward_light;                     // unit w, from p towards the emitter plane
};

// Classifies the scene around disk emitter `light_index` as seen from p with
// unit normal n; `receiver` (the surface p lies on) is not an occluder.
// Empty when the light sends nothing to p: p is behind its emitting face (or
// either face is emitting: two_sided lights emit from both), in its plane, or
// the whole light is below p's horizon.
// Handled exactly: n parallel to the light's normal, occluders that are disks
// parallel to the light strictly between the two planes. Every other object
// must provably miss the cone from p to the light (height range outside
// (0, h), or bounding ball outside the cone); otherwise, and for a receiver
// tilted against a light that crosses its horizon or lies above it, throws
// furnace::Error naming the scene and the object — or, when
// `unsupported_reason` is given, stores the reason there and returns empty
// (so a caller can fall back to the general exact path, planar_light.h).
std::optional<DiskLightView> disk_light_view(const Scene& scene, size_t light_index, const Vec3& p, const Vec3& n,
                                             std::optional<size_t> receiver,
                                             std::string* unsupported_reason = nullptr);

}  // namespace furnace::analytic
