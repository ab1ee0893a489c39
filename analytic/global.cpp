#include "analytic/global.h"

#include <cmath>
#include <optional>
#include <string>

#include <fmt/format.h>

#include "analytic/glass.h"
#include "analytic/reference.h"
#include "core/error.h"

namespace furnace::analytic {

double uniform_enclosure_radiance(double emitted_radiance, double albedo, int max_segments) {
  FURNACE_CHECK(albedo >= 0 && albedo <= 1 && max_segments >= 1);
  if (max_segments == kUnlimitedDepth) {
    FURNACE_CHECK(albedo < 1);
    return emitted_radiance / (1.0 - albedo);
  }
  if (albedo == 1) return emitted_radiance * max_segments;
  if (albedo == 0) return emitted_radiance;
  // 1 − ρ^k = −expm1(k·ln ρ): no cancellation when ρ^k is close to 1.
  return emitted_radiance * -std::expm1(double(max_segments) * std::log(albedo)) / (1.0 - albedo);
}

double convex_furnace_radiance(double environment_radiance, double albedo, int max_segments) {
  FURNACE_CHECK(albedo >= 0 && albedo <= 1 && max_segments >= 1);
  return max_segments >= 2 ? albedo * environment_radiance : 0.0;
}

namespace {

[[noreturn]] void no_closed_form(const Scene& scene, const std::string& reason) {
  throw Error(fmt::format("scene '{}' ({}) has no closed-form global-illumination answer: {}.", scene.name,
                          scene.source, reason));
}

bool is_mirror(const Object& o) { return o.material.as<Mirror>() != nullptr; }

// The centroid of a planar shape (a point on it, away from its edges).
Vec3 planar_center(const Shape& s) {
  return std::visit(overloaded{[](const Rectangle& r) { return r.corner + (r.edge_u + r.edge_v) * 0.5; },
                               [](const Disk& d) { return d.center; },
                               [](const Sphere&) -> Vec3 {
                                 FURNACE_CHECK(false && "classify() refuses a sphere before this");
                               },
                               [](const Triangle& t) { return (t.p0 + t.p1 + t.p2) / 3.0; }},
                    s);
}

// Whether the reflecting objects (albedo > 0, mirrors excluded) are all
// planar and lie in one plane: then no light reflected by one reaches
// another (each sends light into a half-space above that plane, where
// nothing else reflects), so light reaches the eye after at most one bounce.
// One plane: every normal parallel to the first's and every centroid within
// a relative round-off of its plane.
bool reflectors_share_one_plane(const Scene& scene) {
  std::optional<Plane> first;
  for (const Object& o : scene.objects) {
    if (is_mirror(o) || !(o.material.albedo > 0)) continue;
    const std::optional<Plane> plane = plane_of(o.shape);
    if (!plane) return false;
    if (!first) {
      first = plane;
      continue;
    }
    const Vec3 c = planar_center(o.shape);
    // Relative to the scene's scale: a few hundred ulps, as the receiver model's coplanar test.
    const double scale = std::fmax(1.0, std::fmax(max_abs_component(c), max_abs_component(first->point)));
    if (length(cross(plane->normal, first->normal)) > 1e-13 || std::fabs(dot(c - first->point, first->normal)) > 1e-13 * scale)
      return false;
  }
  return true;
}

enum class Kind { kEnclosure, kFurnace, kDirectOnly };

struct Classification {
  Kind kind;
  double albedo = 0;
  double emitted_radiance = 0;
};

// Decides which closed form covers the non-mirror objects of the scene.
Classification classify(const Scene& scene, int max_segments) {
  // Glossy reflectors (Phong, GGX): only the direct-only form, for
  // reflectors in one plane and no closed enclosure; their direct light is
  // the receiver model's (reference.h's hit_radiance).
  for (const Object& o : scene.objects) {
    if (!o.material.info().glossy || !(o.material.albedo > 0)) continue;
    if (scene.closed || !reflectors_share_one_plane(scene))
      no_closed_form(scene, fmt::format("the glossy object '{}' ({}) has a closed form only as one of reflectors in "
                                        "one plane, which light leaves after one bounce",
                                        o.name, bsdf_type_name(o.material.type())));
    for (const Object& m : scene.objects)
      if (is_mirror(m) && m.material.albedo > 0)
        no_closed_form(scene, fmt::format("the mirror '{}' beside the glossy object '{}'", m.name, o.name));
    return {Kind::kDirectOnly, 0, 0};
  }
  std::optional<double> albedo, emission;
  bool uniform = true;
  int reflecting = 0, non_mirror = 0;
  bool reflecting_planar = true;
  for (const Object& o : scene.objects) {
    if (is_mirror(o)) {
      if (o.is_emitter()) no_closed_form(scene, fmt::format("mirror '{}' also emits", o.name));
      continue;
    }
    if (!o.material.as<Lambertian>() && o.material.albedo > 0)
      no_closed_form(scene, fmt::format("object '{}' is neither Lambertian nor a mirror", o.name));
    ++non_mirror;
    if (!albedo) albedo = o.material.albedo, emission = o.emitted_radiance;
    uniform = uniform && o.material.albedo == *albedo && o.emitted_radiance == *emission;
    if (o.material.albedo > 0) {
      ++reflecting;
      reflecting_planar = reflecting_planar && is_planar(o.shape);
    }
  }
  // Point lights: only the direct-only form covers them (its direct term,
  // irradiance(), includes them). A closed enclosure with a point light is not
  // uniform; a mirror would carry their light along delta–delta paths that no
  // path tracer samples (a point light seen in a mirror, or its caustic).
  if (!scene.point_lights.empty()) {
    if (scene.closed) no_closed_form(scene, "a closed enclosure with point lights is not uniform");
    for (const Object& o : scene.objects)
      if (is_mirror(o)) no_closed_form(scene, fmt::format("mirror '{}' would reflect a point light", o.name));
  }
  if (scene.closed) {
    if (scene.environment.radiance > 0) no_closed_form(scene, "it is closed but has an environment");
    if (!uniform || non_mirror == 0)
      no_closed_form(scene, "a closed enclosure needs one albedo and one emission on every object");
    if (*albedo >= 1 && max_segments == kUnlimitedDepth)
      no_closed_form(scene, "a closed enclosure of albedo 1 has infinite radiance at unlimited depth");
    for (size_t i = 0; i < scene.objects.size(); ++i) {
      const Object& o = scene.objects[i];
      if (!o.is_emitter() || o.two_sided) continue;
      if (!is_planar(o.shape))
        no_closed_form(scene, fmt::format("sphere '{}' emits outward only, not into the enclosure (set two_sided)",
                                          o.name));
      // A one-sided planar emitter must be a wall: its front faces the
      // interior (a ray from its centre along the normal meets the enclosure)
      // and its back faces outside (the opposite ray meets nothing). An
      // interior blocker that emits on one side only breaks the uniformity.
      const Vec3 c = planar_center(o.shape);
      const Vec3 n = shape_normal(o.shape, c);
      const double offset = 1e-9 * std::fmax(1.0, max_abs_component(c));  // relative, against self-hits
      const bool front_inside = intersect(scene, c + n * offset, n, 0).has_value();
      const bool back_outside = !intersect(scene, c - n * offset, -n, 0).has_value();
      if (!front_inside || !back_outside)
        no_closed_form(scene, fmt::format("one-sided emitter '{}' is not a wall facing the interior (set two_sided "
                                          "for interior blockers)",
                                          o.name));
    }
    return {Kind::kEnclosure, *albedo, *emission};
  }
  bool any_emitter = !scene.point_lights.empty();
  for (const Object& o : scene.objects) any_emitter = any_emitter || o.is_emitter();
  if (scene.environment.map) {
    // Under a map no furnace closed form holds; a single planar reflector
    // sees no other surface, so its global illumination is direct lighting.
    if (reflecting <= 1 && reflecting_planar) return {Kind::kDirectOnly, 0, 0};
    no_closed_form(scene, fmt::format("the environment map '{}' lights more than one reflecting object (or a "
                                      "reflecting sphere)",
                                      scene.environment.map_file));
  }
  if (scene.environment.radiance > 0 && !any_emitter) {
    if (!uniform) no_closed_form(scene, "a furnace needs one albedo on every object");
    const double rho = albedo.value_or(0);
    const bool single_convex = non_mirror <= 1;
    if (single_convex) return {Kind::kFurnace, rho, 0};
    if (rho == 1 && max_segments == kUnlimitedDepth) return {Kind::kFurnace, rho, 0};
    no_closed_form(scene, "a furnace with several objects is exact only for albedo 1 at unlimited depth");
  }
  if (reflecting <= 1 && reflecting_planar) return {Kind::kDirectOnly, 0, 0};
  no_closed_form(scene, "more than one reflecting object (or a reflecting sphere) under direct light");
}

// Radiance leaving a non-mirror hit towards the viewer.
double leaving_radiance(const Scene& scene, const Classification& c, const Hit& hit, const Vec3& direction,
                        int segments_left) {
  const Object& o = scene.objects[hit.object_index];
  const bool front = dot(direction, hit.normal) < 0;
  switch (c.kind) {
    case Kind::kEnclosure:
      return uniform_enclosure_radiance(c.emitted_radiance, c.albedo, segments_left);
    case Kind::kFurnace: {
      const bool white_unlimited = c.albedo == 1 && segments_left == kUnlimitedDepth;
      return white_unlimited ? scene.environment.radiance
                             : convex_furnace_radiance(scene.environment.radiance, c.albedo, segments_left);
    }
    case Kind::kDirectOnly: {
      const double le = (front || o.two_sided) ? o.emitted_radiance : 0.0;
      if (segments_left < 2 || o.material.albedo == 0) return le;
      if (o.material.info().glossy) return hit_radiance(scene, hit, direction);  // le + the receiver model's direct light
      const Vec3 n = front ? hit.normal : -hit.normal;
      return le + o.material.albedo * kInvPi * irradiance(scene, hit.point, n, hit.object_index);
    }
  }
  return 0;
}

}  // namespace

std::vector<double> global_reference_image(const Scene& scene, int max_segments, TransportConvention convention) {
  if (has_dielectric(scene)) return glass_reference_image(scene, max_segments, convention, false);
  return global_reference_image(scene, max_segments);
}

std::vector<double> global_reference_image(const Scene& scene, int max_segments) {
  if (max_segments < 1) throw Error(fmt::format("max_segments must be at least 1, got {}.", max_segments));
  if (has_dielectric(scene))
    no_closed_form(scene, "it has a dielectric, whose answer depends on the transport convention (not given)");
  const Classification c = classify(scene, max_segments);
  const Camera& camera = scene.camera;
  std::vector<double> image(size_t(camera.width_px) * size_t(camera.height_px));
  // A chain of mirrors longer than this is a scene error (two parallel mirrors).
  constexpr int kMaxMirrorChain = 64;
  for (int py = 0; py < camera.height_px; ++py) {
    for (int px = 0; px < camera.width_px; ++px) {
      Camera::Ray ray = camera.pixel_center_ray(px, py);
      double throughput = 1;
      int segments_left = max_segments;
      double value = 0;
      double t_min = 0;
      for (int chain = 0;; ++chain) {
        if (chain > kMaxMirrorChain) no_closed_form(scene, "a camera ray is trapped between mirrors");
        const std::optional<Hit> hit = intersect(scene, ray.origin, ray.direction, t_min);
        if (!hit) {
          value = throughput * environment_radiance(scene.environment, ray.direction);
          break;
        }
        const Object& o = scene.objects[hit->object_index];
        if (!is_mirror(o)) {
          value = throughput * leaving_radiance(scene, c, *hit, ray.direction, segments_left);
          break;
        }
        // Perfect mirror: one deterministic continuation, reflectance ρ_m.
        if (segments_left != kUnlimitedDepth && --segments_left < 1) break;
        throughput *= o.material.albedo;
        const Vec3 n = hit->normal;
        const Vec3 reflected = ray.direction - n * (2 * dot(ray.direction, n));
        ray = {hit->point, normalize(reflected)};
        // Relative offset against self-intersection: the reflected ray leaves
        // the mirror's plane, so a tiny t scaled by the point's magnitude is safe.
        t_min = 1e-9 * std::fmax(1.0, max_abs_component(hit->point));
      }
      image[size_t(py) * camera.width_px + px] = value;
    }
  }
  return image;
}

}  // namespace furnace::analytic
