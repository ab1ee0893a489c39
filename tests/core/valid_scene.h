// A small valid scene in the JSON format (one emitter, one receiver, a point
// light and a constant sky), shared by the loader tests: each test edits one
// fragment of it.
#pragma once

namespace furnace::test {

inline constexpr const char* kValidSceneJson = R"({
  "name": "t",
  "camera": {"type": "orthographic", "center": [0, 0, 0.5], "forward": [0, 0, -1], "up": [0, 1, 0],
             "size": [4, 2], "resolution": [8, 4]},
  "environment": {"radiance": 0.25},
  "point_lights": [{"name": "bulb", "position": [0.5, 0, 1], "intensity": 2}],
  "objects": [
    {"name": "floor", "shape": {"type": "rectangle", "corner": [-2, -1, 0], "edge_u": [4, 0, 0], "edge_v": [0, 2, 0]},
     "material": {"type": "lambertian", "albedo": 0.5}},
    {"name": "light", "shape": {"type": "disk", "center": [0, 0, 2], "normal": [0, 0, -2], "radius": 0.5},
     "emission": 3}
  ]
})";

}  // namespace furnace::test
