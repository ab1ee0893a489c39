// The scene loader: valid files parse into the right structs; every kind of
// bad input is rejected with one sentence naming the file, field and value.
#include <gtest/gtest.h>

#include <string>

#include "core/error.h"
#include "core/scene.h"

namespace furnace {
namespace {

const char* kValid = R"({
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

TEST(SceneLoader, ParsesValidScene) {
  const Scene s = parse_scene(kValid, "valid.json");
  EXPECT_EQ(s.name, "t");
  EXPECT_EQ(s.camera.width_px, 8);
  EXPECT_EQ(s.camera.height_px, 4);
  EXPECT_EQ(s.environment.radiance, 0.25);
  ASSERT_EQ(s.objects.size(), 2u);
  EXPECT_EQ(s.objects[0].material.albedo, 0.5);
  EXPECT_FALSE(s.objects[0].is_emitter());
  EXPECT_EQ(s.objects[1].emitted_radiance, 3.0);
  const auto& disk = std::get<Disk>(s.objects[1].shape);
  EXPECT_EQ(disk.normal, Vec3(0, 0, -1));  // normalised on load
  ASSERT_EQ(s.point_lights.size(), 1u);
  EXPECT_EQ(s.point_lights[0].name, "bulb");
  EXPECT_EQ(s.point_lights[0].position, Vec3(0.5, 0, 1));
  EXPECT_EQ(s.point_lights[0].intensity, 2.0);
}

TEST(SceneLoader, PixelCenterRaysCoverTheImagePlane) {
  const Scene s = parse_scene(kValid, "valid.json");
  const auto top_left = s.camera.pixel_center_ray(0, 0);
  EXPECT_DOUBLE_EQ(top_left.origin.x, -2 + 0.25);  // pixel width 4/8 = 0.5
  EXPECT_DOUBLE_EQ(top_left.origin.y, 1 - 0.25);   // pixel height 2/4 = 0.5, row 0 at the top
  EXPECT_EQ(top_left.direction, Vec3(0, 0, -1));
}

struct BadInput {
  const char* name;
  const char* from;  // substring of kValid to replace
  const char* to;
  const char* expected_field;
  const char* expected_value;
};

class SceneLoaderRejects : public testing::TestWithParam<BadInput> {};

TEST_P(SceneLoaderRejects, NamingFileFieldAndValue) {
  std::string text = kValid;
  const BadInput& b = GetParam();
  const size_t at = text.find(b.from);
  ASSERT_NE(at, std::string::npos) << b.from;
  text.replace(at, std::string(b.from).size(), b.to);
  try {
    parse_scene(text, "bad.json");
    FAIL() << "accepted bad input " << b.to;
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("'bad.json'"), std::string::npos) << msg;
    EXPECT_NE(msg.find(b.expected_field), std::string::npos) << msg;
    EXPECT_NE(msg.find(b.expected_value), std::string::npos) << msg;
    EXPECT_EQ(msg.back(), '.') << "one sentence: " << msg;
  }
}

INSTANTIATE_TEST_SUITE_P(
    SceneLoader, SceneLoaderRejects,
    testing::Values(BadInput{"NegativeRadius", "\"radius\": 0.5", "\"radius\": -1", "objects[1].shape.radius", "-1"},
                    BadInput{"UnknownShape", "\"type\": \"disk\"", "\"type\": \"disc\"", "objects[1].shape.type", "disc"},
                    BadInput{"AlbedoAboveOne", "\"albedo\": 0.5", "\"albedo\": 1.5", "objects[0].material.albedo", "1.5"},
                    BadInput{"StringNumber", "\"emission\": 3", "\"emission\": \"3\"", "objects[1].emission", "\"3\""},
                    BadInput{"ZeroNormal", "[0, 0, -2]", "[0, 0, 0]", "objects[1].shape.normal", "[0, 0, 0]"},
                    BadInput{"ShortVector", "\"center\": [0, 0, 2]", "\"center\": [0, 2]", "objects[1].shape.center", "[0,2]"},
                    BadInput{"ZeroResolution", "[8, 4]", "[0, 4]", "camera.resolution", "[0,4]"},
                    BadInput{"MissingCamera", "\"camera\"", "\"kamera\"", "camera", "missing"},
                    BadInput{"ZeroIntensity", "\"intensity\": 2", "\"intensity\": 0", "point_lights[0].intensity", "0"},
                    BadInput{"NegativeIntensity", "\"intensity\": 2", "\"intensity\": -3", "point_lights[0].intensity", "-3"},
                    BadInput{"PointLightPosition", "[0.5, 0, 1]", "[0.5, 1]", "point_lights[0].position", "[0.5,1]"},
                    BadInput{"PointLightsNotArray", "\"point_lights\": [{\"name\": \"bulb\", \"position\": [0.5, 0, 1], \"intensity\": 2}]",
                             "\"point_lights\": 7", "point_lights", "7"},
                    BadInput{"NotJson", "\"name\": \"t\",", "\"name\": \"t\",,", "not valid JSON", "byte"}),
    [](const testing::TestParamInfo<BadInput>& info) { return std::string(info.param.name); });

TEST(SceneLoader, MissingFileIsNamed) {
  try {
    load_scene("/nonexistent/scene.json");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/scene.json"), std::string::npos);
  }
}

}  // namespace
}  // namespace furnace
