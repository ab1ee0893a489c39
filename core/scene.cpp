#include "core/scene.h"

#include <cstdio>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/error.h"

namespace furnace {

void check_failed(const char* condition, const char* file, int line) {
  std::fprintf(stderr, "furnace: internal check failed: %s at %s:%d\n", condition, file, line);
  std::abort();
}

Camera::Ray Camera::pixel_center_ray(int px, int py) const {
  const Vec3 f = normalize(forward);
  const Vec3 right = normalize(cross(f, up));
  const Vec3 true_up = cross(right, f);
  const double sx = ((px + 0.5) / width_px - 0.5) * width;
  const double sy = (0.5 - (py + 0.5) / height_px) * height;
  return {center + right * sx + true_up * sy, f};
}

Vec3 shape_normal(const Shape& shape, const Vec3& p) {
  struct Visitor {
    Vec3 p;
    Vec3 operator()(const Rectangle& r) const { return r.normal(); }
    Vec3 operator()(const Disk& d) const { return d.normal; }
    Vec3 operator()(const Sphere& s) const { return normalize(p - s.center); }
    Vec3 operator()(const Triangle& t) const { return t.normal(); }
  };
  return std::visit(Visitor{p}, shape);
}

double shape_area(const Shape& shape) {
  return std::visit([](const auto& s) { return s.area(); }, shape);
}

namespace {

using nlohmann::json;

// Reads fields of one JSON object, naming the full field path in errors.
class Reader {
 public:
  Reader(const json& j, std::string source, std::string path)
      : j_(j), source_(std::move(source)), path_(std::move(path)) {}

  [[noreturn]] void fail(const std::string& field, const std::string& what) const {
    throw Error(fmt::format("scene file '{}': field '{}' {}.", source_, qualify(field), what));
  }
  std::string qualify(const std::string& field) const {
    return path_.empty() ? field : path_ + "." + field;
  }
  bool has(const std::string& field) const { return j_.contains(field); }

  const json& require(const std::string& field) const {
    if (!j_.contains(field)) fail(field, "is missing");
    return j_.at(field);
  }
  double number(const std::string& field) const {
    const json& v = require(field);
    if (!v.is_number()) fail(field, fmt::format("must be a number, got {}", v.dump()));
    const double x = v.get<double>();
    if (!std::isfinite(x)) fail(field, fmt::format("must be finite, got {}", v.dump()));
    return x;
  }
  double number_or(const std::string& field, double fallback) const {
    return has(field) ? number(field) : fallback;
  }
  double positive(const std::string& field) const {
    const double x = number(field);
    if (!(x > 0)) fail(field, fmt::format("must be positive, got {}", x));
    return x;
  }
  double non_negative_or(const std::string& field, double fallback) const {
    if (!has(field)) return fallback;
    const double x = number(field);
    if (x < 0) fail(field, fmt::format("must be non-negative, got {}", x));
    return x;
  }
  bool boolean_or(const std::string& field, bool fallback) const {
    if (!has(field)) return fallback;
    const json& v = j_.at(field);
    if (!v.is_boolean()) fail(field, fmt::format("must be true or false, got {}", v.dump()));
    return v.get<bool>();
  }
  std::string string(const std::string& field) const {
    const json& v = require(field);
    if (!v.is_string()) fail(field, fmt::format("must be a string, got {}", v.dump()));
    return v.get<std::string>();
  }
  Vec3 vec3(const std::string& field) const {
    const json& v = require(field);
    if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() || !v[2].is_number())
      fail(field, fmt::format("must be an array of 3 numbers, got {}", v.dump()));
    const Vec3 r{v[0].get<double>(), v[1].get<double>(), v[2].get<double>()};
    if (!is_finite(r)) fail(field, fmt::format("must be finite, got {}", v.dump()));
    return r;
  }
  Vec3 unit_vec3(const std::string& field) const {
    const Vec3 v = vec3(field);
    const double len = length(v);
    if (!(len > 0)) fail(field, "must be a non-zero direction, got [0, 0, 0]");
    return v / len;
  }
  Reader object(const std::string& field) const {
    const json& v = require(field);
    if (!v.is_object()) fail(field, fmt::format("must be an object, got {}", v.dump()));
    return Reader(v, source_, qualify(field));
  }
  const json& raw() const { return j_; }
  const std::string& source() const { return source_; }
  const std::string& path() const { return path_; }

 private:
  const json& j_;
  std::string source_;
  std::string path_;
};

Shape parse_shape(const Reader& r) {
  const std::string type = r.string("type");
  if (type == "rectangle") {
    Rectangle rect{r.vec3("corner"), r.vec3("edge_u"), r.vec3("edge_v")};
    if (!(rect.area() > 0)) r.fail("edge_u", "and edge_v must span a non-degenerate rectangle");
    return rect;
  }
  if (type == "disk") return Disk{r.vec3("center"), r.unit_vec3("normal"), r.positive("radius")};
  if (type == "sphere") return Sphere{r.vec3("center"), r.positive("radius")};
  if (type == "triangle") {
    Triangle tri{r.vec3("p0"), r.vec3("p1"), r.vec3("p2")};
    if (!(tri.area() > 0)) r.fail("p0", "with p1 and p2 must span a non-degenerate triangle");
    return tri;
  }
  r.fail("type", fmt::format("must be one of rectangle, disk, sphere, triangle, got \"{}\"", type));
}

Material parse_material(const Reader& r) {
  Material m;
  const std::string type = r.string("type");
  if (type == "lambertian") m.type = BsdfType::kLambertian;
  else if (type == "mirror") m.type = BsdfType::kMirror;
  else if (type == "phong") m.type = BsdfType::kPhong;
  else r.fail("type", fmt::format("must be one of lambertian, mirror, phong, got \"{}\"", type));
  m.albedo = r.non_negative_or("albedo", 0.0);
  // Albedo above 1 creates energy; the furnace tests rely on ρ ≤ 1.
  if (m.albedo > 1) r.fail("albedo", fmt::format("must be at most 1, got {}", m.albedo));
  if (m.type == BsdfType::kPhong) m.phong_exponent = r.non_negative_or("exponent", 1.0);
  return m;
}

Camera parse_camera(const Reader& r) {
  Camera c;
  const std::string type = r.string("type");
  if (type != "orthographic") r.fail("type", fmt::format("must be \"orthographic\", got \"{}\"", type));
  c.center = r.vec3("center");
  c.forward = r.unit_vec3("forward");
  c.up = r.unit_vec3("up");
  if (!(length(cross(c.forward, c.up)) > 1e-9)) r.fail("up", "must not be parallel to forward");
  const json& size = r.require("size");
  if (!size.is_array() || size.size() != 2 || !size[0].is_number() || !size[1].is_number() ||
      !(size[0].get<double>() > 0) || !(size[1].get<double>() > 0))
    r.fail("size", fmt::format("must be two positive numbers [width, height], got {}", size.dump()));
  c.width = size[0].get<double>();
  c.height = size[1].get<double>();
  const json& res = r.require("resolution");
  if (!res.is_array() || res.size() != 2 || !res[0].is_number_integer() || !res[1].is_number_integer() ||
      res[0].get<long>() < 1 || res[1].get<long>() < 1 || res[0].get<long>() > 16384 ||
      res[1].get<long>() > 16384)
    r.fail("resolution", fmt::format("must be two integers in [1, 16384], got {}", res.dump()));
  c.width_px = res[0].get<int>();
  c.height_px = res[1].get<int>();
  return c;
}

}  // namespace

Scene parse_scene(const std::string& json_text, const std::string& source) {
  json j;
  try {
    j = json::parse(json_text);
  } catch (const json::parse_error& e) {
    throw Error(fmt::format("scene file '{}' is not valid JSON (byte {}): {}.", source, e.byte, e.what()));
  }
  if (!j.is_object()) throw Error(fmt::format("scene file '{}' must hold a JSON object at the top level.", source));
  const Reader top(j, source, "");
  Scene scene;
  scene.source = source;
  scene.name = top.has("name") ? top.string("name") : std::filesystem::path(source).stem().string();
  scene.camera = parse_camera(top.object("camera"));
  scene.closed = top.boolean_or("closed", false);
  if (top.has("environment")) {
    const Reader env = top.object("environment");
    scene.environment.radiance = env.non_negative_or("radiance", 0.0);
    if (env.has("map")) {
      // Relative to the scene file's directory.
      const std::filesystem::path map_path = std::filesystem::path(source).parent_path() / env.string("map");
      try {
        scene.environment.map = std::make_shared<const LatLongMap>(load_latlong_exr(map_path));
      } catch (const Error& e) {
        std::string reason = e.what();  // one sentence: joined into this one without its period
        if (!reason.empty() && reason.back() == '.') reason.pop_back();
        env.fail("map", fmt::format("is '{}', but {}", env.string("map"), reason));
      }
      scene.environment.map_file = map_path.string();
    }
  }
  const json& objects = top.require("objects");
  if (!objects.is_array()) top.fail("objects", "must be an array");
  for (size_t i = 0; i < objects.size(); ++i) {
    const std::string path = fmt::format("objects[{}]", i);
    if (!objects[i].is_object()) top.fail(path, fmt::format("must be an object, got {}", objects[i].dump()));
    const Reader o(objects[i], source, path);
    Object obj;
    obj.name = o.has("name") ? o.string("name") : path;
    obj.shape = parse_shape(o.object("shape"));
    if (o.has("material")) obj.material = parse_material(o.object("material"));
    obj.emitted_radiance = o.non_negative_or("emission", 0.0);
    obj.two_sided = o.boolean_or("two_sided", false);
    scene.objects.push_back(std::move(obj));
  }
  if (top.has("point_lights")) {
    const json& lights = top.require("point_lights");
    if (!lights.is_array()) top.fail("point_lights", fmt::format("must be an array, got {}", lights.dump()));
    for (size_t i = 0; i < lights.size(); ++i) {
      const std::string path = fmt::format("point_lights[{}]", i);
      if (!lights[i].is_object()) top.fail(path, fmt::format("must be an object, got {}", lights[i].dump()));
      const Reader l(lights[i], source, path);
      PointLight light;
      light.name = l.has("name") ? l.string("name") : path;
      light.position = l.vec3("position");
      light.intensity = l.positive("intensity");
      scene.point_lights.push_back(std::move(light));
    }
  }
  return scene;
}

Scene load_scene(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw Error(fmt::format("cannot open scene file '{}'.", path.string()));
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_scene(ss.str(), path.string());
}

}  // namespace furnace
