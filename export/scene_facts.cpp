#include "export/scene_facts.h"

#include <fmt/format.h>

#include "core/error.h"

namespace furnace::exporter {

std::string object_material_text(const Scene& scene, size_t index) {
  const Object& o = scene.objects.at(index);
  return fmt::format("'{}' (objects[{}].material.type \"{}\", albedo {})", o.name, index,
                     bsdf_type_name(o.material.type), o.material.albedo);
}

bool reflects(const Material& material) {
  switch (material.type) {
    case BsdfType::kLambertian:  // ρ/π
    case BsdfType::kMirror:      // ρ times the specular delta
    case BsdfType::kPhong:       // the albedo times a normalised lobe
    case BsdfType::kGgx:         // the albedo times D·G2/(4 cos θo cos θi)
      return material.albedo > 0;
  }
  unknown_bsdf_type(material.type);
}

bool direct_lighting_is_complete(const Scene& scene) {
  int reflecting = 0;
  for (const Object& o : scene.objects) {
    if (!reflects(o.material)) continue;
    ++reflecting;
    switch (o.material.type) {
      case BsdfType::kLambertian:
        // A planar reflector cannot light itself; a sphere's inside can.
        if (!is_planar(o.shape)) return false;
        break;
      // The direct-lighting answer is claimed (and measured by the peer
      // tests) for a Lambertian reflector only; a scene with any other
      // reflector is checked at the depth rendered.
      case BsdfType::kMirror:
      case BsdfType::kPhong:
      case BsdfType::kGgx:
        return false;
    }
  }
  return reflecting <= 1;
}

int check_max_depth(const Scene& scene, int max_segments) {
  return direct_lighting_is_complete(scene) && max_segments >= 2 ? 2 : max_segments;
}

std::string direct_lighting_clause(const Scene& scene, int max_segments) {
  return check_max_depth(scene, max_segments) == 2 && max_segments != 2
             ? ",\n# which is direct lighting here: light reaches the eye after at most one bounce, off the only "
               "reflector"
             : "";
}

void unknown_bsdf_type(BsdfType type) {
  const std::string what = fmt::format("BsdfType value {} is no enumerator of BsdfType", static_cast<int>(type));
  check_failed(what.c_str(), __FILE__, __LINE__);
}

}  // namespace furnace::exporter
