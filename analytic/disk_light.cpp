#include "analytic/disk_light.h"

#include <cmath>
#include <string>
#include <variant>

#include "analytic/occlusion.h"
#include "analytic/unsupported.h"
#include "core/error.h"

namespace furnace::analytic {

namespace {

// Two unit normals are treated as parallel when |n₁ × n₂| (the sine of the
// angle between them) is below this: a tilt of 1e-12 rad changes E by a
// relative O(1e-12), far below any Monte Carlo test's resolution.
constexpr double kParallelSine = 1e-12;

bool parallel(const Vec3& a, const Vec3& b) { return length(cross(a, b)) <= kParallelSine; }

std::string point_text(const Vec3& p) {
  return "(" + std::to_string(p.x) + ", " + std::to_string(p.y) + ", " + std::to_string(p.z) + ")";
}

}  // namespace

std::optional<DiskLightView> disk_light_view(const Scene& scene, size_t light_index, const Vec3& p, const Vec3& n,
                                             std::optional<size_t> receiver, std::string* unsupported_reason) {
  auto refuse = [&](const std::string& what) -> std::optional<DiskLightView> {
    if (!unsupported_reason) unsupported_configuration(scene, what);
    *unsupported_reason = what;
    return std::nullopt;
  };
  const Object& light_object = scene.objects[light_index];
  const Disk& light = std::get<Disk>(light_object.shape);
  Vec3 emitting_normal = normalize(light.normal);
  double h = dot(p - light.center, emitting_normal);
  // A two-sided light emits from its back face too: use the face p sees.
  if (h < 0 && light_object.two_sided) {
    emitting_normal = -emitting_normal;
    h = -h;
  }
  if (!(h > 0)) return std::nullopt;  // behind the emitting face, or in its plane
  const Vec3 w = -emitting_normal;     // from p towards the emitter plane
  if (!parallel(n, emitting_normal)) {
    if (height_range(light_object.shape, p, n).hi <= 0) return std::nullopt;  // wholly below the horizon
    return refuse("the receiver normal at " + point_text(p) + " tilted against the disk light '" + light_object.name + "'");
  }
  if (dot(n, w) < 0) return std::nullopt;  // receiver faces away: the light is below its horizon

  const Frame frame = Frame::from_normal(emitting_normal);
  auto in_plane = [&](const Vec3& v) { return std::pair<double, double>{dot(v, frame.s), dot(v, frame.t)}; };
  const Vec3 light_offset = (light.center - p) - w * h;  // light centre relative to p's foot, in the plane
  DiskLightView view;
  view.h = h;
  view.toward_light = w;
  const auto [lx, ly] = in_plane(light_offset);
  view.light = {lx, ly, light.radius};

  for (size_t j = 0; j < scene.objects.size(); ++j) {
    if (j == light_index || (receiver && j == *receiver)) continue;
    const Object& object = scene.objects[j];
    const ZRange z = height_range(object.shape, p, w);
    if (z.hi <= 0 || z.lo >= h) continue;  // entirely below p's plane or beyond the light's plane
    // A disk parallel to the light has an exact image; anything else refuses
    // if it may block.
    const Disk* disk = std::visit(overloaded{[](const Disk& d) { return &d; },
                                             [](const Rectangle&) -> const Disk* { return nullptr; },
                                             [](const Sphere&) -> const Disk* { return nullptr; },
                                             [](const Triangle&) -> const Disk* { return nullptr; }},
                                  object.shape);
    if (disk && parallel(disk->normal, emitting_normal)) {
      // Central projection from p onto the light plane: a homothety of ratio h/h_o about p's foot.
      const double scale = h / dot(disk->center - p, w);
      const auto [ox, oy] = in_plane(disk->center - p);
      view.occluder_images.push_back({ox * scale, oy * scale, disk->radius * scale});
      continue;
    }
    if (!ball_may_meet_disk_cone(bounding_sphere(object.shape), p, w, h, light_offset, light.radius)) continue;
    return refuse("object '" + object.name + "', which may block part of the disk light '" + light_object.name +
                  "' and is not a disk parallel to it,");
  }
  return view;
}

}  // namespace furnace::analytic
