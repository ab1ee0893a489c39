// Exported cameras and emitters, read back (issue: "exporters caught without
// a peer"). Four cameras furnace's own tests did not export before, each a
// case a camera bug hides in: a wide image of non-square pixels, tilted; a
// tall image on the vertical sensor fit, rotated a quarter turn; an
// off-centre camera; pixels 12.5 times taller than wide. For each, every
// pixel's ray is rebuilt from the exported file and compared with the ray
// furnace traces (camera_readback_tests, label unit):
//  - pbrt-v4: LookAt, Scale -1 1 1, screen window and resolution, mapped as
//    pbrt-v4's orthographic camera maps a raster point (cameras.cpp);
//  - Cycles: the SCENE camera block (matrix, ortho_scale, sensor fit,
//    clip_start, resolution, pixel aspect) mapped as Blender computes an
//    orthographic view plane (BKE_camera_params_compute_viewplane: the
//    sensor-fit side spans ortho_scale, the other side follows from the
//    resolution times the pixel aspect).
// With Blender (blender_readback_tests, label peer; skipped without it, as
// the Cycles peer tests find it), the exported script's own build() runs in
// Blender and Blender reports what it made: the camera's view_frame, matrix
// and clip start, from which each pixel's ray is rebuilt again; and, for a
// scene with every emitter shape one-sided and one two-sided, each
// material's node links (a one-sided emitter's Emission reaches the Mix
// shader's first shader input, chosen when Geometry.Backfacing is 0) and
// every polygon's normal (a one-sided planar emitter's faces point along its
// front normal, a sphere's outward). Negative controls: the sensor fit
// exchanged, pbrt's window axes exchanged and a script wired back to front
// are each detected.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/scene.h"
#include "core/vec3.h"
#include "export/cycles.h"
#include "export/pbrt_v4.h"
#include "tests/export/exported_cameras.h"
#include "tests/export/peer_support.h"

namespace furnace::exporter {
namespace {

using namespace exported_camera;

namespace fs = std::filesystem;

struct CameraCase {
  const char* name;
  const char* camera;  // the scene file's "camera" object
};

// The floor and light are there only to make a valid, exportable scene.
const CameraCase kCameras[] = {
    {"wide_tilted", R"({"type": "orthographic", "center": [0.3, -0.2, 1.5], "forward": [0.15, 0.25, -1],
                        "up": [0.4, 1, 0.1], "size": [3, 1], "resolution": [24, 4]})"},
    {"tall_quarter_turn", R"({"type": "orthographic", "center": [-0.7, 0.4, 2], "forward": [-0.3, 0.2, -1],
                              "up": [1, 0.2, 0], "size": [1, 2.5], "resolution": [6, 20]})"},
    {"off_centre", R"({"type": "orthographic", "center": [5, -3, 1], "forward": [0, 0, -1], "up": [0, 1, 0],
                       "size": [2, 1], "resolution": [16, 8]})"},
    {"thin_pixels", R"({"type": "orthographic", "center": [0.1, 0.2, 0.5], "forward": [0.05, -0.1, -1],
                        "up": [0, 1, 0], "size": [0.04, 2], "resolution": [8, 32]})"},
};

Scene camera_scene(const CameraCase& c) {
  return parse_scene(fmt::format(R"({{
    "name": "{}",
    "camera": {},
    "objects": [
      {{"name": "floor", "shape": {{"type": "rectangle", "corner": [-9, -9, 0], "edge_u": [18, 0, 0],
        "edge_v": [0, 18, 0]}}, "material": {{"type": "lambertian", "albedo": 0.5}}}},
      {{"name": "light", "shape": {{"type": "disk", "center": [0, 0, 3], "normal": [0, 0, -1], "radius": 0.5}},
        "emission": 2}}
    ]}})",
                                 c.name, c.camera),
                     std::string(c.name) + ".json");
}

// The image's extent in scene units, for tolerances.
double camera_scale(const Camera& c) {
  return std::max({c.width, c.height, std::fabs(c.center.x), std::fabs(c.center.y), std::fabs(c.center.z)});
}

// The largest distance between a rebuilt pixel origin and furnace's, and the
// largest angle-like distance between the directions.
struct RayErrors {
  double origin = 0, direction = 0;
};

template <class Origin>
RayErrors compare_rays(const Camera& camera, const Vec3& direction, const Origin& origin) {
  RayErrors e;
  for (int py = 0; py < camera.height_px; ++py)
    for (int px = 0; px < camera.width_px; ++px) {
      const Camera::Ray ray = camera.pixel_center_ray(px, py);
      e.origin = std::max(e.origin, length(origin(px, py) - ray.origin));
      e.direction = std::max(e.direction, length(direction - ray.direction));
    }
  return e;
}

#if !FURNACE_READBACK_WITH_BLENDER
// ---------------------------------------------------------------------------
// pbrt-v4.


TEST(CameraReadback, PbrtPixelsStartWhereFurnacesRaysStart) {
  for (const CameraCase& cc : kCameras) {
    const Scene scene = camera_scene(cc);
    const PbrtCamera c = read_pbrt_camera(export_pbrt_v4(scene, {}));
    ASSERT_EQ(c.xres, scene.camera.width_px) << cc.name;
    ASSERT_EQ(c.yres, scene.camera.height_px) << cc.name;
    ASSERT_TRUE(c.mirrored) << cc.name;
    const double tolerance = 1e-14 * camera_scale(scene.camera);
    const RayErrors e = compare_rays(scene.camera, normalize(c.look - c.eye),
                                     [&](int px, int py) { return pbrt_pixel_origin(c, px, py); });
    EXPECT_LE(e.origin, tolerance) << cc.name;
    EXPECT_LE(e.direction, 1e-15) << cc.name;
    // Controls: the window's axes exchanged; the mirror Scale left out.
    PbrtCamera swapped = c, unmirrored = c;
    std::swap(swapped.window[0], swapped.window[2]);
    std::swap(swapped.window[1], swapped.window[3]);
    unmirrored.mirrored = false;
    const double pixel = std::min(scene.camera.width / scene.camera.width_px, scene.camera.height / scene.camera.height_px);
    for (const PbrtCamera* wrong : {&swapped, &unmirrored}) {
      const RayErrors w = compare_rays(scene.camera, normalize(c.look - c.eye),
                                       [&](int px, int py) { return pbrt_pixel_origin(*wrong, px, py); });
      if (wrong == &swapped && scene.camera.width == scene.camera.height) continue;
      EXPECT_GT(w.origin, 0.5 * pixel) << cc.name << ": a control went undetected";
    }
  }
}

#endif  // !FURNACE_READBACK_WITH_BLENDER

// ---------------------------------------------------------------------------
// Cycles.

#if !FURNACE_READBACK_WITH_BLENDER
TEST(CameraReadback, CyclesPixelsStartWhereFurnacesRaysStart) {
  for (const CameraCase& cc : kCameras) {
    const Scene scene = camera_scene(cc);
    const CyclesCamera c = read_cycles_camera(export_cycles(scene, {}));
    ASSERT_EQ(c.xres, scene.camera.width_px) << cc.name;
    ASSERT_EQ(c.yres, scene.camera.height_px) << cc.name;
    const ViewPlane v = view_plane(c, c.sensor_fit);
    // The numbers are written with 17 digits; the origin sums a few products.
    const double tolerance = 1e-14 * camera_scale(scene.camera);
    const RayErrors e = compare_rays(scene.camera, viewing_direction(c.matrix), [&](int px, int py) {
      return cycles_pixel_origin(c.matrix, v, c.xres, c.yres, c.clip_start, px, py);
    });
    EXPECT_LE(e.origin, tolerance) << cc.name << " (" << c.sensor_fit << ")";
    EXPECT_LE(e.direction, 1e-15) << cc.name;
    // Control: the other sensor fit (every case here has a non-square image).
    const ViewPlane other = view_plane(c, c.sensor_fit == "HORIZONTAL" ? "VERTICAL" : "HORIZONTAL");
    const RayErrors w = compare_rays(scene.camera, viewing_direction(c.matrix), [&](int px, int py) {
      return cycles_pixel_origin(c.matrix, other, c.xres, c.yres, c.clip_start, px, py);
    });
    EXPECT_GT(w.origin, 0.1 * std::min(scene.camera.width, scene.camera.height)) << cc.name;
  }
}

#endif  // !FURNACE_READBACK_WITH_BLENDER

#if FURNACE_READBACK_WITH_BLENDER
// ---------------------------------------------------------------------------
// With Blender: the script's build() run in Blender, read back.

std::optional<fs::path> blender() {
  if (const char* forced = std::getenv("FURNACE_BLENDER")) return fs::path(forced);
  return peer::find_on_path("blender");
}

class BlenderReadback : public testing::Test {
 protected:
  void SetUp() override {
    blender_ = blender();
    if (!blender_) {
      const char* path = std::getenv("PATH");
      GTEST_SKIP() << "skipped: no Blender (set FURNACE_BLENDER; tried `blender` on PATH=" << (path ? path : "") << ")";
    }
    dir_ = fs::temp_directory_path() / ("furnace_blender_readback_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override {
    if (!dir_.empty()) fs::remove_all(dir_);
  }
  // Blender's report on `script` (blender_readback.py).
  nlohmann::json read_back(const fs::path& script) {
    const auto r = peer::run(fmt::format("{} -b --factory-startup --python-exit-code 1 --python {} -- {}",
                                         peer::quoted(*blender_), peer::quoted(FURNACE_BLENDER_READBACK_PY),
                                         peer::quoted(script)));
    const std::string tag = "FURNACE-READBACK ";
    const size_t at = r.output.find(tag);
    if (r.exit_code != 0 || at == std::string::npos) {
      ADD_FAILURE() << "Blender failed on " << script << ": " << r.output;
      return nlohmann::json();
    }
    return nlohmann::json::parse(r.output.substr(at + tag.size(), r.output.find('\n', at) - at - tag.size()));
  }
  std::optional<fs::path> blender_;
  fs::path dir_;
};

TEST_F(BlenderReadback, CameraPixelsStartWhereFurnacesRaysStart) {
  for (const CameraCase& cc : kCameras) {
    const Scene scene = camera_scene(cc);
    CyclesOptions small;
    small.sphere_subdivisions = 0;
    small.emitter_grid = 1;
    const fs::path script = dir_ / (std::string(cc.name) + ".py");
    write_cycles(scene, small, script);
    const nlohmann::json b = read_back(script);
    if (b.is_null()) continue;
    EXPECT_EQ(b["type"], "ORTHO") << cc.name;
    EXPECT_EQ(b["resolution"], nlohmann::json::array({scene.camera.width_px, scene.camera.height_px, 100})) << cc.name;
    EXPECT_EQ(b["shift"], nlohmann::json::array({0.0, 0.0})) << cc.name;
    double m[3][4];
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 4; ++k) m[i][k] = b["matrix_world"][i][k];
    ViewPlane v{1e300, -1e300, 1e300, -1e300};
    for (const auto& corner : b["frame"]) {
      v.xmin = std::min(v.xmin, double(corner[0])), v.xmax = std::max(v.xmax, double(corner[0]));
      v.ymin = std::min(v.ymin, double(corner[1])), v.ymax = std::max(v.ymax, double(corner[1]));
    }
    // Blender keeps matrices and camera data in float: 2^-22 of the largest coordinate.
    const double tolerance = 0x1p-22 * 4 * camera_scale(scene.camera);
    const RayErrors e = compare_rays(scene.camera, viewing_direction(m), [&](int px, int py) {
      return cycles_pixel_origin(m, v, scene.camera.width_px, scene.camera.height_px, b["clip_start"], px, py);
    });
    std::printf("Blender read-back %-18s (%s): worst pixel origin %.3g (tolerance %.3g), direction %.3g\n", cc.name,
                std::string(b["sensor_fit"]).c_str(), e.origin, tolerance, e.direction);
    EXPECT_LE(e.origin, tolerance) << cc.name;
    EXPECT_LE(e.direction, 1e-6) << cc.name;
  }
}

// Every emitter shape one-sided (disk, rectangle, triangle, sphere) and a
// two-sided disk.
const char* kEmitters = R"({
  "name": "every_emitter",
  "camera": {"type": "orthographic", "center": [0, 0, 3], "forward": [0, 0, -1], "up": [0, 1, 0],
             "size": [4, 4], "resolution": [8, 8]},
  "objects": [
    {"name": "floor", "shape": {"type": "rectangle", "corner": [-3, -3, 0], "edge_u": [6, 0, 0], "edge_v": [0, 6, 0]},
     "material": {"type": "lambertian", "albedo": 0.5}},
    {"name": "disk", "shape": {"type": "disk", "center": [-1, -1, 2], "normal": [0.2, 0.1, -1], "radius": 0.3},
     "emission": 3},
    {"name": "rect", "shape": {"type": "rectangle", "corner": [0.5, 0.5, 2], "edge_u": [0, 0.5, 0.1],
     "edge_v": [0.5, 0, 0]}, "emission": 2},
    {"name": "tri", "shape": {"type": "triangle", "p0": [-1, 1, 2], "p1": [-1, 1.5, 2], "p2": [-0.5, 1, 2.1]},
     "emission": 2},
    {"name": "ball", "shape": {"type": "sphere", "center": [1, -1, 1], "radius": 0.2}, "emission": 1},
    {"name": "both", "shape": {"type": "disk", "center": [0, 0, 2.5], "normal": [0, 0, -1], "radius": 0.2},
     "emission": 1, "two_sided": true}
  ]})";

bool has_link(const nlohmann::json& links, const std::vector<nlohmann::json>& link) {
  for (const auto& l : links)
    if (l == nlohmann::json(link)) return true;
  return false;
}

// The failures of `b` (a read-back of kEmitters' export) against the scene:
// one line per wrong emitter.
std::vector<std::string> emitter_failures(const Scene& scene, const nlohmann::json& b) {
  std::vector<std::string> failures;
  for (const Object& o : scene.objects) {
    if (!o.is_emitter()) continue;
    const nlohmann::json& links = b["materials"][o.name];
    const bool front_only = has_link(links, {"NEW_GEOMETRY", "Backfacing", "MIX_SHADER", 0}) &&
                            has_link(links, {"EMISSION", "Emission", "MIX_SHADER", 1}) &&
                            !has_link(links, {"EMISSION", "Emission", "MIX_SHADER", 2});
    const bool both = has_link(links, {"EMISSION", "Emission", "OUTPUT_MATERIAL", 0}) &&
                      !has_link(links, {"NEW_GEOMETRY", "Backfacing", "MIX_SHADER", 0});
    if (o.two_sided ? !both : !front_only) failures.push_back(o.name + ": node links " + links.dump());
    if (o.two_sided) continue;
    // Faces: front = furnace's front normal (planar) or outward (sphere).
    double worst = 1;
    for (const auto& face : b["faces"][o.name]) {
      const Vec3 n{face[0][0], face[0][1], face[0][2]}, centre{face[1][0], face[1][1], face[1][2]};
      const Vec3 front = is_planar(o.shape) ? shape_normal(o.shape, centre)
                                            : normalize(centre - std::get<Sphere>(o.shape).center);
      worst = std::min(worst, dot(n, front));
    }
    if (b["faces"][o.name].empty() || worst < (is_planar(o.shape) ? 1 - 1e-6 : 0.5))
      failures.push_back(fmt::format("{}: a face points {:.3g} along the front", o.name, worst));
  }
  return failures;
}

TEST_F(BlenderReadback, OneSidedEmittersEmitFromTheirFrontsOnly) {
  const Scene scene = parse_scene(kEmitters, "every_emitter.json");
  CyclesOptions small;
  small.sphere_subdivisions = 0;
  small.emitter_grid = 1;
  const fs::path script = dir_ / "every_emitter.py";
  write_cycles(scene, small, script);
  const nlohmann::json b = read_back(script);
  ASSERT_FALSE(b.is_null());
  const std::vector<std::string> failures = emitter_failures(scene, b);
  EXPECT_TRUE(failures.empty()) << testing::PrintToString(failures);
  // Control: the script wired back to front (emission on the Mix shader's
  // back-face input) is caught for every one-sided emitter.
  std::string text = peer::read_text(script);
  const std::string wiring = "links.new(emitted, front_only.inputs[1])";
  ASSERT_NE(text.find(wiring), std::string::npos) << "the builder's wiring line moved";
  text.replace(text.find(wiring), wiring.size(), "links.new(emitted, front_only.inputs[2])");
  const fs::path wrong = dir_ / "every_emitter_back_to_front.py";
  std::ofstream(wrong) << text;
  const nlohmann::json bw = read_back(wrong);
  ASSERT_FALSE(bw.is_null());
  EXPECT_EQ(emitter_failures(scene, bw).size(), 4u) << testing::PrintToString(emitter_failures(scene, bw));
}

#endif  // FURNACE_READBACK_WITH_BLENDER

}  // namespace
}  // namespace furnace::exporter
