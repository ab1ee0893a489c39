// The scene description shared by renderer/ and analytic/ (neither includes
// the other). Plain structs; load_scene() parses the JSON scene format
// documented in README.md. All radiometric quantities are gray (one channel):
// radiance in W·m⁻²·sr⁻¹, lengths in scene units, reflectance dimensionless.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "core/environment_map.h"
#include "core/material.h"
#include "core/overloaded.h"
#include "core/vec3.h"

namespace furnace {

// A parallelogram corner + s·edge_u + t·edge_v, s,t ∈ [0,1].
// Its front normal is normalize(cross(edge_u, edge_v)).
struct Rectangle {
  Vec3 corner, edge_u, edge_v;
  Vec3 normal() const { return normalize(cross(edge_u, edge_v)); }
  double area() const { return length(cross(edge_u, edge_v)); }
  // The four corners in order around the boundary (counter-clockwise about the normal).
  std::array<Vec3, 4> corners() const { return {corner, corner + edge_u, corner + edge_u + edge_v, corner + edge_v}; }
};

// A flat disk; `normal` (unit) is its front side.
struct Disk {
  Vec3 center, normal;
  double radius = 0;
  double area() const { return kPi * radius * radius; }
};

// A sphere; its front side faces outward.
struct Sphere {
  Vec3 center;
  double radius = 0;
  double area() const { return 4.0 * kPi * radius * radius; }
};

// A triangle p0, p1, p2; front normal normalize(cross(p1 - p0, p2 - p0)).
struct Triangle {
  Vec3 p0, p1, p2;
  Vec3 normal() const { return normalize(cross(p1 - p0, p2 - p0)); }
  double area() const { return 0.5 * length(cross(p1 - p0, p2 - p0)); }
};

// Code that branches on the kind of shape does so with
// std::visit(overloaded{...}, shape) and one case per alternative
// (core/overloaded.h), so a new alternative fails to compile until every
// such branch handles it.
using Shape = std::variant<Rectangle, Disk, Sphere, Triangle>;

// Whether the shape lies in one plane (every shape but the sphere).
inline bool is_planar(const Shape& shape) {
  return std::visit(overloaded{[](const Rectangle&) { return true; }, [](const Disk&) { return true; },
                               [](const Sphere&) { return false; }, [](const Triangle&) { return true; }},
                    shape);
}

// A flat shape's plane: a point on it and its front normal.
struct Plane {
  Vec3 point, normal;
};
// The plane of a flat shape; empty for a sphere.
inline std::optional<Plane> plane_of(const Shape& shape) {
  return std::visit(overloaded{[](const Rectangle& r) { return std::optional<Plane>(Plane{r.corner, r.normal()}); },
                               [](const Disk& d) { return std::optional<Plane>(Plane{d.center, d.normal}); },
                               [](const Sphere&) { return std::optional<Plane>(); },
                               [](const Triangle& t) { return std::optional<Plane>(Plane{t.p0, t.normal()}); }},
                    shape);
}

struct Object {
  std::string name;
  Shape shape;
  Material material;
  // Uniform Lambertian emission Le, radiance leaving the front side only
  // (a sphere's front is its outside). 0 for non-emitters.
  double emitted_radiance = 0;
  // Emits (and is meant to be seen) on both sides: the walls and interior
  // blockers of a closed enclosure, a sphere light seen from inside.
  bool two_sided = false;
  bool is_emitter() const { return emitted_radiance > 0; }
};

// Radiance arriving from every direction not blocked by geometry: the
// constant `radiance`, or, when `map` is set, radiance·map(ω) (an image-based
// environment, core/environment_map.h; directions in world space, z up).
struct Environment {
  double radiance = 0;
  std::shared_ptr<const LatLongMap> map;  // empty: constant environment
  std::string map_file;                   // the map's path as loaded, for messages
};

// An isotropic point light (a delta light: no ray can hit it): radiant
// intensity I in W·sr⁻¹ in every direction, so a point at distance r
// receives irradiance I·max(cos θ, 0)/r² when the segment to it is clear.
struct PointLight {
  std::string name;
  Vec3 position;
  double intensity = 0;
};

// THE miss radiance along unit direction `dir` (every reader of the
// environment goes through it): radiance·map(dir) with a map, else radiance.
inline double environment_radiance(const Environment& environment, const Vec3& dir) {
  return environment.map ? environment.radiance * environment.map->lookup(dir) : environment.radiance;
}

// Orthographic camera: one ray per pixel centre, all parallel to `forward`,
// starting on the image plane through `center`. Pixel (0,0) is the top-left:
// x grows along right = cross(forward, up), y grows along -up.
struct Camera {
  Vec3 center{0, 0, 1};
  Vec3 forward{0, 0, -1};
  Vec3 up{0, 1, 0};
  double width = 1, height = 1;  // extent of the image plane, scene units
  int width_px = 16, height_px = 16;

  struct Ray { Vec3 origin, direction; };
  // The ray through the centre of pixel (px, py).
  Ray pixel_center_ray(int px, int py) const;
};

struct Scene {
  std::string name;
  std::string source;  // file it was loaded from, for error messages
  Camera camera;
  std::vector<Object> objects;
  Environment environment;
  std::vector<PointLight> point_lights;
  // The author's statement that the objects bound a closed enclosure around
  // the camera (no ray from inside escapes). Needed by the uniform-enclosure
  // closed form Le/(1−ρ), which cannot check closure itself.
  bool closed = false;
};

// The ranges load_scene() enforces (README.md's field table states them).
// Every number of a scene file is finite and inside these bounds, so that the
// renderer's double arithmetic, Embree's float rays and the exact references
// all stay finite and accurate; anything outside is refused, never clamped.
namespace scene_limits {
// |coordinate| of every point (camera centre, corners, centres, vertices,
// point-light positions). Embree intersects in float: a sphere test forms
// fourth powers of coordinates, 1e24 here against float's 3.4e38 (at 1e10
// they overflow), and ray origins stay far inside Embree's valid range
// (|x| < 1.8e19). The stability tests move scenes to 2e3 and scale them to 1e4.
inline constexpr double kMaxCoordinate = 1e6;
// Lengths (radii, edge vectors' components, camera size): from 1e-6 (twelve
// decades around the unit scale; the stability tests scale to 1e-4) up to
// the width of the coordinate range.
inline constexpr double kMinLength = 1e-6;
inline constexpr double kMaxLength = 2 * kMaxCoordinate;
// A length smaller than this fraction of its shape's largest coordinate spans
// fewer than 8 float steps (float's spacing is at most 2^-23 of a value):
// Embree's float geometry cannot resolve it, so the shape is degenerate.
inline constexpr double kMinRelativeLength = 0x1p-20;
// The sine of the angle between two edges (rectangle, triangle) or between the
// camera's forward and up: below it the two are parallel within the same
// float round-off (8 float steps of 2^-23).
inline constexpr double kMinSine = 1e-6;
// Directions (normals, forward, up) are normalised on load; their components
// are bounded like coordinates, and a vector shorter than this is a zero
// vector written with round-off.
inline constexpr double kMinDirectionLength = 1e-6;
// Radiance (emission, environment radiance times its largest map texel) in
// W·m⁻²·sr⁻¹ and point-light intensity in W·sr⁻¹: 0 (absent) or in
// [kMinRadiometric, kMaxRadiometric]. The top is five times the sun's
// radiance (2e7); its square, the scale of a second moment, is 1e16, leaving
// 22 decades of float (the EXR channels) and 290 of double for geometric
// factors. The bottom keeps light powers, and the power-selection
// probabilities made from them, normal doubles (no denormals, no underflow).
inline constexpr double kMinRadiometric = 1e-6;
inline constexpr double kMaxRadiometric = 1e8;
// Material parameters' ranges (kMaxPhongExponent, kMinGgxAlpha): core/material.h.
// Pixels per image side.
inline constexpr int kMaxResolution = 16384;
// Memory: a render holds per pixel its running moments (40 bytes) and a
// verification run adds the reference, the predicted variance, the per-pixel
// test results and the image-mean inputs; kBytesPerPixel bounds the whole
// (measured peak resident memory of `furnace verify` per pixel, with margin).
// A camera needing more than kPixelMemoryBudget is refused on load.
inline constexpr uint64_t kBytesPerPixel = 512;
inline constexpr uint64_t kPixelMemoryBudget = uint64_t(2) << 30;  // 2 GiB
inline constexpr uint64_t kMaxPixels = kPixelMemoryBudget / kBytesPerPixel;
}  // namespace scene_limits

// Parses a scene file. Throws furnace::Error with a sentence naming the file,
// the field (its JSON path, e.g. objects[2].shape.radius) and the offending
// value on any malformed or unphysical input: invalid JSON, a number beyond
// double range, a wrong type, a missing, unknown (misspelt: the closest known
// name is suggested) or duplicated field, a number outside scene_limits, or
// geometry degenerate within round-off.
Scene load_scene(const std::filesystem::path& path);
// Same, from JSON text; `source` names the text in error messages.
Scene parse_scene(const std::string& json_text, const std::string& source);

// Geometric front normal of a shape at a point on it.
Vec3 shape_normal(const Shape& shape, const Vec3& p);
double shape_area(const Shape& shape);

}  // namespace furnace
