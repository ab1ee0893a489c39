// Scene-level references: dispatch each emitter/receiver/occluder
// configuration to its closed form, or refuse it with furnace::Error.
#include "analytic/reference.h"

#include <cmath>
#include <string>
#include <variant>

#include "analytic/circle_region.h"
#include "analytic/intersect.h"
#include "analytic/occlusion.h"
#include "core/error.h"

namespace furnace::analytic {

namespace {

// Two unit normals are treated as parallel when |n₁ × n₂| (the sine of the
// angle between them) is below this: a tilt of 1e-12 rad changes E by a
// relative O(1e-12), far below any Monte Carlo test's resolution.
constexpr double kParallelSine = 1e-12;

bool parallel(const Vec3& a, const Vec3& b) { return length(cross(a, b)) <= kParallelSine; }

[[noreturn]] void unsupported(const Scene& scene, const std::string& what) {
  throw Error("scene '" + scene.name + "' (" + scene.source + "): " + what +
              " is outside what the analytic references solve exactly.");
}

// E/L at p (unit normal n) from one-sided disk emitter `light_index`, visible
// past the scene's parallel disk occluders. See circle_region.h.
double disk_light_irradiance(const Scene& scene, size_t light_index, const Vec3& p, const Vec3& n,
                             std::optional<size_t> receiver) {
  const Object& light_object = scene.objects[light_index];
  const Disk& light = std::get<Disk>(light_object.shape);
  const Vec3 nl = normalize(light.normal);
  // Height of p in front of the emitting face; behind it nothing arrives.
  const double h = dot(p - light.center, nl);
  if (!(h > 0)) return 0.0;
  // w points from p towards the emitter plane.
  const Vec3 w = -nl;
  if (!parallel(n, nl)) {
    const ZRange over_horizon = height_range(light_object.shape, p, n);
    if (over_horizon.hi <= 0) return 0.0;  // the whole light is below p's horizon
    unsupported(scene, "the receiver normal at the point (" + std::to_string(p.x) + ", " + std::to_string(p.y) + ", " +
                           std::to_string(p.z) + ") tilted against the disk light '" + light_object.name + "'");
  }
  if (dot(n, w) < 0) return 0.0;  // receiver faces away: the light is below its horizon

  const Frame frame = Frame::from_normal(nl);
  auto in_plane = [&](const Vec3& v) { return std::pair<double, double>{dot(v, frame.s), dot(v, frame.t)}; };
  const Vec3 light_offset = (light.center - p) - w * h;  // in-plane offset of the light centre from p's foot
  const auto [lx, ly] = in_plane(light_offset);
  const Circle2 light_circle{lx, ly, light.radius};

  std::vector<Circle2> images;
  for (size_t j = 0; j < scene.objects.size(); ++j) {
    if (j == light_index || (receiver && j == *receiver)) continue;
    const Object& object = scene.objects[j];
    const ZRange z = height_range(object.shape, p, w);
    if (z.hi <= 0 || z.lo >= h) continue;  // entirely below p's plane or beyond the light plane
    const Disk* disk = std::get_if<Disk>(&object.shape);
    if (disk && parallel(disk->normal, nl)) {
      const double h_o = dot(disk->center - p, w);
      // Central projection from p onto the light plane: scale h/h_o about p's foot.
      const double scale = h / h_o;
      const auto [ox, oy] = in_plane(disk->center - p);
      images.push_back({ox * scale, oy * scale, disk->radius * scale});
      continue;
    }
    if (!ball_may_meet_disk_cone(bounding_sphere(object.shape), p, w, h, light_offset, light.radius)) continue;
    unsupported(scene, "object '" + object.name + "', which may block part of the disk light '" + light_object.name +
                           "' and is not a disk parallel to it,");
  }
  return occluded_disk_irradiance(h, light_circle, images);
}

}  // namespace

std::optional<Hit> intersect(const Scene& scene, const Vec3& origin, const Vec3& direction, double t_min) {
  std::optional<Hit> best;
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    const std::optional<double> t = intersect_shape(scene.objects[i].shape, origin, direction, t_min);
    if (!t || (best && *t >= best->t)) continue;
    const Vec3 point = origin + direction * *t;
    best = Hit{*t, i, point, shape_normal(scene.objects[i].shape, point)};
  }
  return best;
}

double irradiance(const Scene& scene, const Vec3& p, const Vec3& n, std::optional<size_t> receiver) {
  double e = 0;
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    const Object& object = scene.objects[i];
    if (!object.is_emitter() || (receiver && i == *receiver)) continue;
    if (std::holds_alternative<Disk>(object.shape)) {
      e += object.emitted_radiance * disk_light_irradiance(scene, i, p, n, receiver);
      continue;
    }
    unsupported(scene, "the emitter '" + object.name + "' (only disk emitters are solved so far)");
  }
  if (scene.environment.radiance > 0) {
    for (size_t j = 0; j < scene.objects.size(); ++j) {
      if (receiver && j == *receiver) continue;
      if (height_range(scene.objects[j].shape, p, n).hi > 0)
        unsupported(scene, "a constant environment partly hidden by object '" + scene.objects[j].name + "'");
    }
    // Unoccluded hemisphere: ∫ L cos θ dω = π L.
    e += kPi * scene.environment.radiance;
  }
  return e;
}

double pixel_center_radiance(const Scene& scene, int px, int py) {
  const Camera::Ray ray = scene.camera.pixel_center_ray(px, py);
  const std::optional<Hit> hit = intersect(scene, ray.origin, ray.direction);
  if (!hit) return scene.environment.radiance;
  const Object& object = scene.objects[hit->object_index];
  const double cos_view = dot(ray.direction, hit->normal);
  // Emission leaves the front face only.
  const double le = cos_view < 0 ? object.emitted_radiance : 0.0;
  if (object.material.albedo == 0) return le;
  if (object.material.type != BsdfType::kLambertian)
    unsupported(scene, "a camera ray hitting the non-Lambertian, non-black object '" + object.name + "'");
  // Two-sided Lambertian: shade with the normal facing the viewer.
  const Vec3 n = cos_view < 0 ? hit->normal : -hit->normal;
  return le + object.material.albedo * kInvPi * irradiance(scene, hit->point, n, hit->object_index);
}

std::vector<double> reference_image(const Scene& scene) {
  const Camera& camera = scene.camera;
  std::vector<double> image(size_t(camera.width_px) * size_t(camera.height_px));
  for (int py = 0; py < camera.height_px; ++py)
    for (int px = 0; px < camera.width_px; ++px) image[size_t(py) * camera.width_px + px] = pixel_center_radiance(scene, px, py);
  return image;
}

}  // namespace furnace::analytic
