// The cameras an exported file describes, read back as the renderer reads
// them and turned into each pixel's ray, for tests that compare them with
// the rays furnace traces (pbrt_v4_export_test.cpp, cycles_export_test.cpp,
// camera_readback_test.cpp).
#pragma once

#include <regex>
#include <sstream>
#include <string>

#include "core/vec3.h"

namespace furnace::exporter::exported_camera {

// pbrt-v4: LookAt (after `Scale -1 1 1` or not), screen window, resolution.
struct PbrtCamera {
  Vec3 eye, look, up;
  double window[4] = {};  // xmin xmax ymin ymax
  int xres = 0, yres = 0;
  bool mirrored = false;  // `Scale -1 1 1` right before LookAt
};

inline PbrtCamera read_pbrt_camera(const std::string& text) {
  PbrtCamera c;
  std::smatch m;
  if (std::regex_search(text, m, std::regex(R"(\n(Scale -1 1 1\n)?LookAt ([-+0-9.][^\n]*)\n)"))) {
    c.mirrored = m[1].matched;
    std::istringstream line(m[2].str());
    line >> c.eye.x >> c.eye.y >> c.eye.z >> c.look.x >> c.look.y >> c.look.z >> c.up.x >> c.up.y >> c.up.z;
  }
  if (std::regex_search(text, m, std::regex(R"("float screenwindow" \[([^\]]*)\])"))) {
    std::istringstream numbers(m[1].str());
    for (double& w : c.window) numbers >> w;
  }
  if (std::regex_search(text, m, std::regex(R"("integer xresolution" (\d+) "integer yresolution" (\d+))"))) {
    c.xres = std::stoi(m[1].str());
    c.yres = std::stoi(m[2].str());
  }
  return c;
}

// pbrt-v4's orthographic camera, jitter off: raster (px + ½, py + ½) maps
// linearly onto the screen window (raster y down, screen y up); the screen
// point is the camera-space point (sx, sy, 0); LookAt sends camera z to the
// viewing direction and y to the true up; camera x is cross(up, direction),
// or cross(direction, up) after `Scale -1 1 1`.
inline Vec3 pbrt_pixel_origin(const PbrtCamera& c, int px, int py) {
  const Vec3 direction = normalize(c.look - c.eye);
  const Vec3 x = normalize(c.mirrored ? cross(direction, c.up) : cross(c.up, direction));
  const Vec3 y = normalize(c.mirrored ? cross(x, direction) : cross(direction, x));
  const double sx = c.window[0] + (px + 0.5) / c.xres * (c.window[1] - c.window[0]);
  const double sy = c.window[3] - (py + 0.5) / c.yres * (c.window[3] - c.window[2]);
  return c.eye + x * sx + y * sy;
}

// Cycles: the SCENE block of an exported script (resolution, pixel aspect,
// camera matrix, ortho_scale, sensor fit, clip_start).
struct CyclesCamera {
  double matrix[3][4] = {};
  double ortho_scale = 0, clip_start = 0;
  std::string sensor_fit;
  int xres = 0, yres = 0;
  double aspect_x = 1, aspect_y = 1;
};

inline double parse_number(const std::string& s) { return std::stod(s); }

inline CyclesCamera read_cycles_camera(const std::string& text) {
  CyclesCamera c;
  std::smatch m;
  const std::string num = R"(([-+0-9.eE]+))";
  if (std::regex_search(text, m, std::regex("'resolution': \\(" + num + ", " + num + "\\)")))
    c.xres = int(parse_number(m[1])), c.yres = int(parse_number(m[2]));
  if (std::regex_search(text, m, std::regex("'pixel_aspect': \\(" + num + ", " + num + "\\)")))
    c.aspect_x = parse_number(m[1]), c.aspect_y = parse_number(m[2]);
  std::string rest = text.substr(text.find("'matrix': ("));
  const std::regex row("\\(" + num + ", " + num + ", " + num + ", " + num + "\\)");
  for (int i = 0; i < 3 && std::regex_search(rest, m, row); ++i) {
    for (int k = 0; k < 4; ++k) c.matrix[i][k] = parse_number(m[k + 1]);
    rest = m.suffix();
  }
  if (std::regex_search(text, m, std::regex("'ortho_scale': " + num + ",\\s*'sensor_fit': '(\\w+)'")))
    c.ortho_scale = parse_number(m[1]), c.sensor_fit = m[2].str();
  if (std::regex_search(text, m, std::regex("'clip_start': " + num))) c.clip_start = parse_number(m[1]);
  return c;
}

// Blender's orthographic view plane in camera space: x from xmin to xmax,
// y from ymin to ymax (BKE_camera_params_compute_viewplane with zoom 1, no
// shift): the sensor-fit side spans ortho_scale, ycor = aspect_y/aspect_x.
struct ViewPlane {
  double xmin, xmax, ymin, ymax;
};
inline ViewPlane view_plane(const CyclesCamera& c, const std::string& fit) {
  const double ycor = c.aspect_y / c.aspect_x;
  const bool horizontal =
      fit == "HORIZONTAL" || (fit == "AUTO" && c.aspect_x * c.xres >= c.aspect_y * c.yres);
  const double pixsize = c.ortho_scale / (horizontal ? c.xres : ycor * c.yres);
  return {-0.5 * c.xres * pixsize, 0.5 * c.xres * pixsize, -0.5 * ycor * c.yres * pixsize,
          0.5 * ycor * c.yres * pixsize};
}

// A camera-space point to world space by the 3×4 matrix.
inline Vec3 to_world(const double m[3][4], const Vec3& p) {
  return {m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3], m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3],
          m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3]};
}
inline Vec3 viewing_direction(const double m[3][4]) { return normalize(Vec3{-m[0][2], -m[1][2], -m[2][2]}); }

// Where a Cycles orthographic ray of pixel (px, py) starts: the pixel centre
// of the view plane (raster y down), on the near clip plane.
inline Vec3 cycles_pixel_origin(const double m[3][4], const ViewPlane& v, int xres, int yres, double clip_start, int px,
                         int py) {
  const double x = v.xmin + (px + 0.5) / xres * (v.xmax - v.xmin);
  const double y = v.ymax - (py + 0.5) / yres * (v.ymax - v.ymin);
  return to_world(m, {x, y, -clip_start});
}

}  // namespace furnace::exporter::exported_camera
