// The renderer-level fixture several tests share: a scene whose object 0 is
// a floor at z = 0, its Embree scene and light set, and the floor's shading
// point at the origin (normal +z) seen from above.
#pragma once

#include <memory>

#include "core/scene.h"
#include "renderer/embree_scene.h"
#include "renderer/estimator.h"
#include "renderer/lights.h"
#include "renderer/render.h"

namespace furnace::testing_support {

struct FloorFixture {
  Scene scene;
  std::unique_ptr<EmbreeDevice> device;
  std::unique_ptr<EmbreeScene> rtc;
  std::unique_ptr<LightSet> lights;

  // Call once `scene` is filled in.
  void build(LightSelection selection = LightSelection::kUniform) {
    device = std::make_unique<EmbreeDevice>();
    rtc = std::make_unique<EmbreeScene>(*device, scene);
    lights = std::make_unique<LightSet>(scene, selection);
  }
  // The shading point at the origin on object 0, viewed from direction `wo`.
  ShadingContext context(const Vec3& wo = normalize(Vec3{0.2, 0.1, 1})) const { return context_at({0, 0, 0}, wo); }
  // The same at another point of the floor (z = 0).
  ShadingContext context_at(const Vec3& point, const Vec3& wo = normalize(Vec3{0.2, 0.1, 1})) const {
    SurfaceHit hit;
    hit.object = 0;
    hit.point = point;
    hit.normal = {0, 0, 1};
    hit.front_facing = true;
    return ShadingContext::at(hit, wo, scene.objects[0].material);
  }
};

}  // namespace furnace::testing_support
