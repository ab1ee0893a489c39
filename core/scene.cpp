#include "core/scene.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <limits>
#include <memory>
#include <sstream>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/error.h"

namespace furnace {

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
namespace lim = scene_limits;

// A JSON value as it appears in a message: one line (dump() escapes control
// characters), cut to a readable length.
std::string shown(const json& v) {
  constexpr size_t kMaxShown = 80;
  std::string text = v.dump();
  if (text.size() > kMaxShown) text = text.substr(0, kMaxShown) + "...";
  return text;
}

// A field name from the file, escaped like a JSON string (no raw control
// characters in a one-line message).
std::string printable(const std::string& name) {
  const std::string quoted = json(name).dump(-1, ' ', false, json::error_handler_t::replace);
  return quoted.substr(1, quoted.size() - 2);
}

// Levenshtein distance: edits (insert, delete, substitute) from a to b.
size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t substitute = diagonal + (a[i - 1] == b[j - 1] ? 0 : 1);
      diagonal = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, substitute});
    }
  }
  return row[b.size()];
}

// The name in `names` closest to `name` (the first of equals).
std::string closest(const std::string& name, const std::vector<std::string>& names) {
  std::string best;
  size_t best_distance = SIZE_MAX;
  for (const std::string& candidate : names) {
    const size_t d = edit_distance(name, candidate);
    if (d < best_distance) {
      best = candidate;
      best_distance = d;
    }
  }
  return best;
}

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

// Reads fields of one JSON object, naming the full field path in errors.
// Every field name it is asked about (read or tested) is a known field of this
// object; reject_unknown_fields() then refuses any other key, so a misspelt
// optional field is an error instead of a silent default.
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
  bool has(const std::string& field) const {
    know(field);
    return j_.contains(field);
  }

  const json& require(const std::string& field) const {
    if (!has(field)) {
      // A misspelling of a required field is the likeliest cause.
      for (const auto& item : j_.items())
        if (edit_distance(item.key(), field) <= 2)
          fail(field, fmt::format("is missing (is '{}' a misspelling of it?)", printable(item.key())));
      fail(field, "is missing");
    }
    return j_.at(field);
  }
  double number(const std::string& field) const {
    const json& v = require(field);
    if (!v.is_number()) fail(field, fmt::format("must be a number, got {}", shown(v)));
    const double x = v.get<double>();
    if (!std::isfinite(x)) fail(field, fmt::format("must be finite, got {}", shown(v)));
    return x;
  }
  // A number in [lo, hi]; `unit` names the unit in the message.
  double number_in(const std::string& field, double lo, double hi, const char* unit = "") const {
    const double x = number(field);
    if (!(x >= lo && x <= hi)) fail(field, fmt::format("must be in [{:g}, {:g}]{}, got {}", lo, hi, unit, shown(j_.at(field))));
    return x;
  }
  // 0, or a radiometric value in [kMinRadiometric, kMaxRadiometric].
  double radiometric_or_zero(const std::string& field, const char* unit) const {
    if (!has(field)) return 0.0;
    const double x = number(field);
    if (!(x == 0 || (x >= lim::kMinRadiometric && x <= lim::kMaxRadiometric)))
      fail(field, fmt::format("must be 0 or in [{:g}, {:g}] {}, got {}", lim::kMinRadiometric, lim::kMaxRadiometric,
                              unit, shown(j_.at(field))));
    return x;
  }
  bool boolean_or(const std::string& field, bool fallback) const {
    if (!has(field)) return fallback;
    const json& v = j_.at(field);
    if (!v.is_boolean()) fail(field, fmt::format("must be true or false, got {}", shown(v)));
    return v.get<bool>();
  }
  std::string string(const std::string& field) const {
    const json& v = require(field);
    if (!v.is_string()) fail(field, fmt::format("must be a string, got {}", shown(v)));
    return v.get<std::string>();
  }
  // Three finite numbers, each |x| <= bound.
  Vec3 vec3(const std::string& field, double bound) const {
    const json& v = require(field);
    if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() || !v[2].is_number())
      fail(field, fmt::format("must be an array of 3 numbers, got {}", shown(v)));
    const Vec3 r{v[0].get<double>(), v[1].get<double>(), v[2].get<double>()};
    if (!is_finite(r)) fail(field, fmt::format("must be finite, got {}", shown(v)));
    // Embree converts to float: a non-zero component below float's normal
    // range becomes 0 (or a denormal) there while the references keep it, so
    // the renderer and the references would see different scenes.
    for (int i = 0; i < 3; ++i)
      if (r[i] != 0 && std::fabs(r[i]) < std::numeric_limits<float>::min())
        fail(field, fmt::format("has the component {:g}, non-zero but below float's normal range ({:g}), got {}", r[i],
                                std::numeric_limits<float>::min(), shown(v)));
    if (!(max_abs_component(r) <= bound))
      fail(field, fmt::format("must have every component within ±{:g} scene units, got {}", bound, shown(v)));
    return r;
  }
  Vec3 point(const std::string& field) const { return vec3(field, lim::kMaxCoordinate); }
  Vec3 edge(const std::string& field) const { return vec3(field, lim::kMaxLength); }
  // A direction, normalised.
  Vec3 direction(const std::string& field) const {
    const Vec3 v = vec3(field, lim::kMaxCoordinate);
    const double len = length(v);
    if (!(len >= lim::kMinDirectionLength))
      fail(field, fmt::format("must be a non-zero direction (length at least {:g}), got {}", lim::kMinDirectionLength,
                              shown(j_.at(field))));
    return v / len;
  }
  // A length of a shape whose largest coordinate is `extent`: within
  // [kMinLength, kMaxLength] and resolvable in float at that extent.
  void check_length(const std::string& field, double value, double extent, const char* what) const {
    if (!(value >= lim::kMinLength && value <= lim::kMaxLength))
      fail(field, fmt::format("gives {} {:g}, outside [{:g}, {:g}] scene units", what, value, lim::kMinLength,
                              lim::kMaxLength));
    if (!(value >= lim::kMinRelativeLength * extent))
      fail(field, fmt::format("gives {} {:g}, below 2^-20 of the largest coordinate {:g}: degenerate within "
                              "float round-off", what, value, extent));
  }
  Reader object(const std::string& field) const {
    const json& v = require(field);
    if (!v.is_object()) fail(field, fmt::format("must be an object, got {}", shown(v)));
    return Reader(v, source_, qualify(field));
  }
  // Refuses every key of this object that no read asked about, naming the
  // closest known one. `owner` ("a ggx material"), when given, names whose
  // fields they are, and `owner_of` names what else a key may belong to
  // ("a phong material"; empty for none).
  void reject_unknown_fields(const std::string& owner = "",
                             const std::function<std::string(const std::string&)>& owner_of = nullptr) const {
    for (const auto& item : j_.items()) {
      if (std::find(known_.begin(), known_.end(), item.key()) != known_.end()) continue;
      if (owner.empty())
        fail(printable(item.key()), fmt::format("is not a known field here (did you mean '{}'? known: {})",
                                                closest(item.key(), known_), joined(known_)));
      const std::string other = owner_of ? owner_of(item.key()) : std::string();
      if (!other.empty())
        fail(printable(item.key()), fmt::format("is a field of {}, not of {} (the fields of {}: {})", other, owner,
                                                owner, joined(known_)));
      fail(printable(item.key()), fmt::format("is not a field of {} (did you mean '{}'? the fields of {}: {})", owner,
                                              closest(item.key(), known_), owner, joined(known_)));
    }
  }
  const std::string& source() const { return source_; }

 private:
  void know(const std::string& field) const {
    if (std::find(known_.begin(), known_.end(), field) == known_.end()) known_.push_back(field);
  }

  const json& j_;
  std::string source_;
  std::string path_;
  mutable std::vector<std::string> known_;  // field names asked about, in order
};

double largest_coordinate(std::initializer_list<Vec3> points) {
  double m = 0;
  for (const Vec3& p : points) m = std::fmax(m, max_abs_component(p));
  return m;
}

// |a × b| ≥ kMinSine·|a|·|b|: the two are not parallel within round-off.
bool spans_plane(const Vec3& a, const Vec3& b) {
  return length(cross(a, b)) >= lim::kMinSine * length(a) * length(b);
}

// Distance from p to the segment a-b.
double distance_to_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double t = std::clamp(dot(p - a, ab) / dot(ab, ab), 0.0, 1.0);
  return length(p - (a + ab * t));
}

// Distance from p to the flat polygon corner + s·u + t·v (s, t ≥ 0; s + t ≤ 1
// for a triangle, s, t ≤ 1 for a parallelogram): to the plane where p
// projects inside, else to the nearest edge.
double distance_to_flat(const Vec3& p, const Vec3& corner, const Vec3& u, const Vec3& v, bool triangle) {
  const Vec3 d = p - corner;
  const double uu = dot(u, u), uv = dot(u, v), vv = dot(v, v);
  const double det = uu * vv - uv * uv;  // > 0: the edges are not parallel (checked on load)
  const double s = (vv * dot(d, u) - uv * dot(d, v)) / det;
  const double t = (uu * dot(d, v) - uv * dot(d, u)) / det;
  const bool inside = s >= 0 && t >= 0 && (triangle ? s + t <= 1 : s <= 1 && t <= 1);
  if (inside) return std::fabs(dot(d, normalize(cross(u, v))));
  if (triangle)
    return std::fmin(distance_to_segment(p, corner, corner + u),
                     std::fmin(distance_to_segment(p, corner + u, corner + v), distance_to_segment(p, corner + v, corner)));
  const Vec3 far = corner + u + v;
  return std::fmin(std::fmin(distance_to_segment(p, corner, corner + u), distance_to_segment(p, corner, corner + v)),
                   std::fmin(distance_to_segment(p, far, corner + u), distance_to_segment(p, far, corner + v)));
}

// Distance from p to the surface of a shape.
double distance_to_surface(const Shape& shape, const Vec3& p) {
  struct Visitor {
    Vec3 p;
    double operator()(const Rectangle& r) const { return distance_to_flat(p, r.corner, r.edge_u, r.edge_v, false); }
    double operator()(const Triangle& t) const { return distance_to_flat(p, t.p0, t.p1 - t.p0, t.p2 - t.p0, true); }
    double operator()(const Sphere& s) const { return std::fabs(length(p - s.center) - s.radius); }
    double operator()(const Disk& d) const {
      const double height = dot(p - d.center, d.normal);
      const double radial = length((p - d.center) - d.normal * height);
      return radial <= d.radius ? std::fabs(height) : std::hypot(height, radial - d.radius);
    }
  };
  return std::visit(Visitor{p}, shape);
}

Shape parse_shape(const Reader& r) {
  const std::string type = r.string("type");
  if (type == "rectangle") {
    Rectangle rect{r.point("corner"), r.edge("edge_u"), r.edge("edge_v")};
    const double extent = largest_coordinate({rect.corner, rect.corner + rect.edge_u, rect.corner + rect.edge_v,
                                              rect.corner + rect.edge_u + rect.edge_v});
    r.check_length("edge_u", length(rect.edge_u), extent, "an edge of length");
    r.check_length("edge_v", length(rect.edge_v), extent, "an edge of length");
    if (!spans_plane(rect.edge_u, rect.edge_v))
      r.fail("edge_v", fmt::format("is parallel to edge_u within round-off (sine of their angle below {:g})",
                                   lim::kMinSine));
    return rect;
  }
  if (type == "disk") {
    Disk disk{r.point("center"), r.direction("normal"), r.number("radius")};
    r.check_length("radius", disk.radius, largest_coordinate({disk.center}), "a radius of");
    return disk;
  }
  if (type == "sphere") {
    Sphere sphere{r.point("center"), r.number("radius")};
    r.check_length("radius", sphere.radius, largest_coordinate({sphere.center}), "a radius of");
    return sphere;
  }
  if (type == "triangle") {
    Triangle tri{r.point("p0"), r.point("p1"), r.point("p2")};
    const double extent = largest_coordinate({tri.p0, tri.p1, tri.p2});
    r.check_length("p1", length(tri.p1 - tri.p0), extent, "an edge p0-p1 of length");
    r.check_length("p2", length(tri.p2 - tri.p1), extent, "an edge p1-p2 of length");
    r.check_length("p2", length(tri.p0 - tri.p2), extent, "an edge p2-p0 of length");
    const double longest = std::fmax(length(tri.p1 - tri.p0), std::fmax(length(tri.p2 - tri.p1), length(tri.p0 - tri.p2)));
    // Twice the area over the longest edge squared: the sine of the angle
    // between the two edges meeting at the longest one's ends, at most.
    if (!(2 * tri.area() >= lim::kMinSine * longest * longest))
      r.fail("p2", fmt::format("makes p0, p1, p2 collinear within round-off (twice the area over the longest edge "
                               "squared below {:g})", lim::kMinSine));
    return tri;
  }
  r.fail("type", fmt::format("must be one of rectangle, disk, sphere, triangle, got \"{}\"", printable(type)));
}

// A material type's fields read through the JSON object's Reader.
class JsonMaterialFields final : public MaterialFieldReader {
 public:
  explicit JsonMaterialFields(const Reader& r) : r_(r) {}
  // A nested object's fields, owning its Reader.
  explicit JsonMaterialFields(std::unique_ptr<Reader> owned) : owned_(std::move(owned)), r_(*owned_) {}
  std::unique_ptr<MaterialFieldReader> object(const std::string& field) const override {
    return std::make_unique<JsonMaterialFields>(std::make_unique<Reader>(r_.object(field)));
  }
  [[noreturn]] void refuse(const std::string& field, const std::string& what) const override { r_.fail(field, what); }
  void reject_unknown_fields() const override { r_.reject_unknown_fields(); }
  bool has(const std::string& field) const override { return r_.has(field); }
  double number_in(const std::string& field, double lo, double hi) const override {
    return r_.number_in(field, lo, hi);
  }
  size_t word_in(const std::string& field, const std::vector<const char*>& words) const override {
    const std::string word = r_.string(field);
    std::vector<std::string> names;
    for (size_t i = 0; i < words.size(); ++i) {
      if (word == words[i]) return i;
      names.emplace_back(words[i]);
    }
    r_.fail(field, fmt::format("must be one of {}, got \"{}\"", joined(names), printable(word)));
  }

 private:
  std::unique_ptr<Reader> owned_;
  const Reader& r_;
};

// The material: its type's word, the common albedo, then the type's own
// fields (its struct's parse(), core/material.h). A field of another type
// is refused naming this type's fields.
Material parse_material(const Reader& r) {
  Material m;
  const std::string type = r.string("type");
  const auto row = std::find_if(kBsdfTypeTable.begin(), kBsdfTypeTable.end(),
                                [&](const BsdfTypeInfo& info) { return type == info.name; });
  if (row == kBsdfTypeTable.end()) {
    std::string accepted;
    for (const BsdfTypeInfo& info : kBsdfTypeTable) accepted += (accepted.empty() ? "" : ", ") + std::string(info.name);
    r.fail("type", fmt::format("must be one of {}, got \"{}\"", accepted, printable(type)));
  }
  // Albedo above 1 creates energy; the furnace tests rely on ρ ≤ 1.
  if (r.has("albedo")) m.albedo = r.number_in("albedo", 0, 1);
  m.bsdf = parse_parameters(row->type, JsonMaterialFields(r));
  // The first other type whose struct has the field, for the refusal.
  const auto owner_of = [](const std::string& field) {
    for (const BsdfTypeInfo& info : kBsdfTypeTable)
      for (const MaterialField& f : Material{0, default_parameters(info.type)}.fields())
        if (field == f.name) return fmt::format("a {} material", info.name);
    return std::string();
  };
  r.reject_unknown_fields(fmt::format("a {} material", row->name), owner_of);
  return m;
}

Camera parse_camera(const Reader& r) {
  Camera c;
  const std::string type = r.string("type");
  if (type != "orthographic") r.fail("type", fmt::format("must be \"orthographic\", got \"{}\"", printable(type)));
  c.center = r.point("center");
  c.forward = r.direction("forward");
  c.up = r.direction("up");
  if (!spans_plane(c.forward, c.up))
    r.fail("up", fmt::format("must not be parallel to forward (sine of their angle below {:g})", lim::kMinSine));
  const json& size = r.require("size");
  if (!size.is_array() || size.size() != 2 || !size[0].is_number() || !size[1].is_number())
    r.fail("size", fmt::format("must be two numbers [width, height], got {}", shown(size)));
  c.width = size[0].get<double>();
  c.height = size[1].get<double>();
  const double extent = max_abs_component(c.center);
  r.check_length("size", c.width, extent, "a width of");
  r.check_length("size", c.height, extent, "a height of");
  const json& res = r.require("resolution");
  // nlohmann stores a non-negative integer as unsigned, a negative one as signed.
  const auto in_range = [](const json& v) {
    return v.is_number_unsigned() && v.get<uint64_t>() >= 1 && v.get<uint64_t>() <= uint64_t(lim::kMaxResolution);
  };
  if (!res.is_array() || res.size() != 2 || !in_range(res[0]) || !in_range(res[1]))
    r.fail("resolution", fmt::format("must be two integers in [1, {}], got {}", lim::kMaxResolution, shown(res)));
  c.width_px = res[0].get<int>();
  c.height_px = res[1].get<int>();
  const uint64_t pixels = uint64_t(c.width_px) * uint64_t(c.height_px);
  if (pixels > lim::kMaxPixels)
    r.fail("resolution", fmt::format("is {}, {} pixels needing {:.1f} GiB at {} bytes per pixel, above the {} GiB "
                                     "budget ({} pixels at most)", shown(res), pixels,
                                     double(pixels * lim::kBytesPerPixel) / double(uint64_t(1) << 30),
                                     lim::kBytesPerPixel, lim::kPixelMemoryBudget >> 30, lim::kMaxPixels));
  return c;
}

// JSON path of the value being parsed, kept by the parser callback: names the
// field of a parse error and refuses duplicated keys (which nlohmann would
// silently resolve to the last one).
class ParsePath {
 public:
  explicit ParsePath(std::string source) : source_(std::move(source)) {}

  bool on_event(json::parse_event_t event, const json& parsed) {
    switch (event) {
      case json::parse_event_t::object_start:
      case json::parse_event_t::array_start:
        frames_.push_back({event == json::parse_event_t::array_start, 0, {}, {}});
        break;
      case json::parse_event_t::object_end:
      case json::parse_event_t::array_end:
        if (!frames_.empty()) frames_.pop_back();
        count_element();
        break;
      case json::parse_event_t::key: {
        Frame& f = frames_.back();
        f.key = parsed.get<std::string>();
        if (std::find(f.keys.begin(), f.keys.end(), f.key) != f.keys.end())
          throw Error(fmt::format("scene file '{}': field '{}' appears twice.", source_, path()));
        f.keys.push_back(f.key);
        break;
      }
      case json::parse_event_t::value:
        count_element();
        break;
    }
    return true;
  }

  // e.g. "objects[1].shape.radius"; empty at the top level.
  std::string path() const {
    std::string p;
    for (const Frame& f : frames_) {
      if (f.array) p += fmt::format("[{}]", f.elements);
      else if (!f.key.empty() || !f.keys.empty()) p += (p.empty() ? "" : ".") + printable(f.key);
    }
    return p;
  }

 private:
  struct Frame {
    bool array;
    size_t elements;                // array: elements completed, the index of the one being read
    std::string key;                // object: the key being read
    std::vector<std::string> keys;  // object: keys seen
  };
  void count_element() {
    if (!frames_.empty() && frames_.back().array) ++frames_.back().elements;
  }

  std::string source_;
  std::vector<Frame> frames_;
};

// nlohmann's message without its "[json.exception.…] " prefix and final period.
std::string json_reason(const json::exception& e) {
  std::string reason = e.what();
  const size_t bracket = reason.find("] ");
  if (bracket != std::string::npos) reason = reason.substr(bracket + 2);
  while (!reason.empty() && (reason.back() == '.' || reason.back() == ' ')) reason.pop_back();
  return reason;
}

json parse_json(const std::string& json_text, const std::string& source) {
  ParsePath path(source);
  const auto where = [&] {
    const std::string p = path.path();
    return p.empty() ? std::string() : fmt::format(" in field '{}'", p);
  };
  try {
    return json::parse(json_text, [&](int, json::parse_event_t event, json& parsed) {
      return path.on_event(event, parsed);
    });
  } catch (const json::parse_error& e) {
    throw Error(fmt::format("scene file '{}' is not valid JSON (byte {}{}): {}.", source, e.byte, where(),
                            json_reason(e)));
  } catch (const json::out_of_range& e) {
    // A number beyond double range (1e309): nlohmann refuses it while parsing.
    throw Error(fmt::format("scene file '{}'{} holds a number beyond the range of double: {}.", source,
                            where().empty() ? "" : ": field '" + path.path() + "'", json_reason(e)));
  } catch (const json::exception& e) {
    throw Error(fmt::format("scene file '{}' cannot be read as JSON{}: {}.", source, where(), json_reason(e)));
  }
}

Scene parse_scene_json(const json& j, const std::string& source) {
  if (!j.is_object())
    throw Error(fmt::format("scene file '{}' must hold a JSON object at the top level, got {}.", source, shown(j)));
  const Reader top(j, source, "");
  Scene scene;
  scene.source = source;
  scene.name = top.has("name") ? top.string("name") : std::filesystem::path(source).stem().string();
  {
    const Reader camera = top.object("camera");
    scene.camera = parse_camera(camera);
    camera.reject_unknown_fields();
  }
  scene.closed = top.boolean_or("closed", false);
  if (top.has("environment")) {
    const Reader env = top.object("environment");
    scene.environment.radiance = env.radiometric_or_zero("radiance", "W·m⁻²·sr⁻¹");
    if (env.has("map")) {
      // Relative to the scene file's directory.
      const std::filesystem::path map_path = std::filesystem::path(source).parent_path() / env.string("map");
      try {
        scene.environment.map = std::make_shared<const LatLongMap>(load_latlong_exr(map_path));
      } catch (const Error& e) {
        std::string reason = e.what();  // one sentence: joined into this one without its period
        if (!reason.empty() && reason.back() == '.') reason.pop_back();
        env.fail("map", fmt::format("is '{}', but {}", printable(env.string("map")), reason));
      }
      scene.environment.map_file = map_path.string();
      // The radiance the map can reach is bounded like every other radiance.
      double brightest = 0;
      for (double t : scene.environment.map->texels) brightest = std::fmax(brightest, t);
      if (scene.environment.radiance * brightest > lim::kMaxRadiometric)
        env.fail("map", fmt::format("is '{}', whose largest texel {:g} times radiance {:g} exceeds {:g} W·m⁻²·sr⁻¹",
                                    printable(env.string("map")), brightest, scene.environment.radiance,
                                    lim::kMaxRadiometric));
    }
    env.reject_unknown_fields();
  }
  const json& objects = top.require("objects");
  if (!objects.is_array()) top.fail("objects", fmt::format("must be an array, got {}", shown(objects)));
  for (size_t i = 0; i < objects.size(); ++i) {
    const std::string path = fmt::format("objects[{}]", i);
    if (!objects[i].is_object()) top.fail(path, fmt::format("must be an object, got {}", shown(objects[i])));
    const Reader o(objects[i], source, path);
    Object obj;
    obj.name = o.has("name") ? o.string("name") : path;
    {
      const Reader shape = o.object("shape");
      obj.shape = parse_shape(shape);
      shape.reject_unknown_fields();
    }
    if (o.has("material")) {
      const Reader material = o.object("material");
      obj.material = parse_material(material);
    }
    obj.emitted_radiance = o.radiometric_or_zero("emission", "W·m⁻²·sr⁻¹");
    obj.two_sided = o.boolean_or("two_sided", false);
    o.reject_unknown_fields();
    scene.objects.push_back(std::move(obj));
  }
  if (top.has("point_lights")) {
    const json& lights = top.require("point_lights");
    if (!lights.is_array()) top.fail("point_lights", fmt::format("must be an array, got {}", shown(lights)));
    for (size_t i = 0; i < lights.size(); ++i) {
      const std::string path = fmt::format("point_lights[{}]", i);
      if (!lights[i].is_object()) top.fail(path, fmt::format("must be an object, got {}", shown(lights[i])));
      const Reader l(lights[i], source, path);
      PointLight light;
      light.name = l.has("name") ? l.string("name") : path;
      light.position = l.point("position");
      light.intensity = l.number_in("intensity", lim::kMinRadiometric, lim::kMaxRadiometric, " W·sr⁻¹");
      l.reject_unknown_fields();
      // Irradiance I·cos θ/r² has no bound at the light: one on (or within
      // round-off of) a surface gives that surface an infinite reference.
      // At least kMinLength away, I/r² ≤ 1e8/1e-12 = 1e20.
      const double clearance = std::fmax(lim::kMinLength, lim::kMinRelativeLength * max_abs_component(light.position));
      for (size_t k = 0; k < scene.objects.size(); ++k) {
        const double distance = distance_to_surface(scene.objects[k].shape, light.position);
        if (!(distance >= clearance))
          l.fail("position", fmt::format("is {:g} from the surface of objects[{}] ('{}'), closer than {:g}: a point "
                                         "light on a surface gives it infinite irradiance",
                                         distance, k, printable(scene.objects[k].name), clearance));
      }
      scene.point_lights.push_back(std::move(light));
    }
  }
  top.reject_unknown_fields();
  return scene;
}

}  // namespace

Scene parse_scene(const std::string& json_text, const std::string& source) {
  const json j = parse_json(json_text, source);
  try {
    return parse_scene_json(j, source);
  } catch (const json::exception& e) {
    // Every access above is type-checked first; this keeps any that is not a
    // sentence rather than an abort.
    throw Error(fmt::format("scene file '{}' has a value of an unexpected type: {}.", source, json_reason(e)));
  }
}

Scene load_scene(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw Error(fmt::format("cannot open scene file '{}'.", path.string()));
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_scene(ss.str(), path.string());
}

}  // namespace furnace
