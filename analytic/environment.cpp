#include "analytic/environment.h"

#include "analytic/disk_light.h"
#include "analytic/occlusion.h"

namespace furnace::analytic {

double environment_irradiance(const Scene& scene, const Vec3& p, const Vec3& n, std::optional<size_t> receiver) {
  if (!(scene.environment.radiance > 0)) return 0.0;
  for (size_t j = 0; j < scene.objects.size(); ++j) {
    if (receiver && j == *receiver) continue;
    if (height_range(scene.objects[j].shape, p, n).hi > 0)
      unsupported_configuration(scene, "a constant environment partly hidden by object '" + scene.objects[j].name + "'");
  }
  return kPi * scene.environment.radiance;
}

}  // namespace furnace::analytic
