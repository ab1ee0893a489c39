// The scene loader: valid files parse into the right structs; every kind of
// bad input is rejected with one sentence naming the file, field and value.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <ostream>
#include <string>
#include <vector>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>
#include <unistd.h>

#include "core/environment_map.h"
#include "core/error.h"
#include "core/scene.h"
#include "tests/core/valid_scene.h"

namespace furnace {
namespace {

const char* kValid = test::kValidSceneJson;

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

// One entry per BsdfType, written independently of kBsdfTypeTable: a switch
// with no default, so adding a type fails this test's build
// (-Werror=switch) until its word is stated here too.
const char* expected_bsdf_word(BsdfType type) {
  switch (type) {
    case BsdfType::kLambertian: return "lambertian";
    case BsdfType::kMirror: return "mirror";
    case BsdfType::kPhong: return "phong";
    case BsdfType::kGgx: return "ggx";
    case BsdfType::kDielectric: return "dielectric";
  }
  return "";
}

// The material of kValid's floor as {"type": word}.
std::string with_floor_material(const std::string& word) {
  std::string json = kValid;
  const std::string from = R"("material": {"type": "lambertian")";
  json.replace(json.find(from), from.size(), R"("material": {"type": ")" + word + "\"" +
                                                  (word == "ggx" ? R"(, "alpha": 0.5)" : word == "dielectric" ? R"(, "eta": 1.5)" : ""));
  return json;
}

// A GGX material's fields: α as given, the Smith form by name, default
// height-correlated (the form of pbrt-v4 and Cycles ≥ 3.5).
TEST(GgxMaterial, FieldsParse) {
  const auto material = [](const std::string& fields) {
    std::string json = kValid;
    const std::string from = R"("material": {"type": "lambertian")";
    json.replace(json.find(from), from.size(), R"("material": {"type": "ggx", )" + fields);
    return parse_scene(json, "ggx.json").objects[0].material;
  };
  const Material defaulted = material(R"("alpha": 0.25)");
  const auto ggx = [](const Material& m) { return std::get<Ggx>(m.bsdf); };
  EXPECT_EQ(defaulted.type(), BsdfType::kGgx);
  EXPECT_EQ(ggx(defaulted).alpha, 0.25);
  EXPECT_EQ(ggx(defaulted).shadowing, MicrofacetShadowing::kHeightCorrelated);
  EXPECT_EQ(ggx(material(R"("alpha": 1, "shadowing": "separable")")).shadowing, MicrofacetShadowing::kSeparable);
  EXPECT_EQ(ggx(material(R"("alpha": 1e-3, "shadowing": "height_correlated")")).shadowing,
            MicrofacetShadowing::kHeightCorrelated);
  for (const MicrofacetShadowingInfo& info : kMicrofacetShadowingTable)
    EXPECT_STREQ(microfacet_shadowing_name(info.shadowing), info.name);
}

TEST(BsdfTypeNames, EveryTypesWordParsesBackToIt) {
  for (const BsdfTypeInfo& info : kBsdfTypeTable) {
    EXPECT_STREQ(bsdf_type_name(info.type), expected_bsdf_word(info.type));
    const Scene s = parse_scene(with_floor_material(bsdf_type_name(info.type)), "material.json");
    EXPECT_EQ(s.objects[0].material.type(), info.type) << info.name;
  }
}

// Negative controls: a word outside the table is refused naming the field,
// the value and every accepted word; a value that is no enumerator is an
// internal error, not a name.
TEST(BsdfTypeNames, AnUnknownWordIsRefusedListingTheTable) {
  try {
    parse_scene(with_floor_material("gxx"), "material.json");
    ADD_FAILURE() << "the unknown material type 'gxx' was accepted";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("objects[0].material.type"), std::string::npos) << message;
    EXPECT_NE(message.find("must be one of lambertian, mirror, phong, ggx, dielectric, got \"gxx\""), std::string::npos) << message;
  }
}

TEST(BsdfTypeNamesDeathTest, AValueThatIsNoEnumeratorIsAnInternalError) {
  EXPECT_DEATH(bsdf_type_name(static_cast<BsdfType>(7)), "BsdfType value 7 is no enumerator of BsdfType");
  // Nor does it make a material: no default alternative is chosen for it.
  EXPECT_DEATH(default_parameters(static_cast<BsdfType>(7)), "BsdfType value 7 is no enumerator of BsdfType");
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

void PrintTo(const BadInput& c, std::ostream* os) { *os << c.name; }

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
                    BadInput{"ZeroNormal", "[0, 0, -2]", "[0, 0, 0]", "objects[1].shape.normal", "[0,0,0]"},
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

// ---------------------------------------------------------------------------
// Image-based environments: "environment": {"radiance": L, "map": "file.exr"},
// the map relative to the scene file's directory.

// A scratch directory per test process, removed at the end of each test.
class EnvironmentMapLoader : public testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() / ("furnace_env_test_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  // A scene file in dir_ whose environment uses `map_name`.
  std::filesystem::path write_scene(const std::string& map_name) const {
    std::string text = kValid;
    const std::string from = "\"environment\": {\"radiance\": 0.25}";
    text.replace(text.find(from), from.size(), "\"environment\": {\"radiance\": 0.25, \"map\": \"" + map_name + "\"}");
    const auto path = dir_ / "scene.json";
    std::ofstream(path) << text;
    return path;
  }

  // An RGB FLOAT file with the given channel values (same size).
  void write_rgb(const std::filesystem::path& path, int width, int height, std::vector<float> r, std::vector<float> g,
                 std::vector<float> b) const {
    Imf::Header header(width, height);
    Imf::FrameBuffer frame;
    const size_t stride = sizeof(float);
    std::vector<float>* planes[] = {&r, &g, &b};
    const char* names[] = {"R", "G", "B"};
    for (int k = 0; k < 3; ++k) {
      header.channels().insert(names[k], Imf::Channel(Imf::FLOAT));
      frame.insert(names[k], Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(planes[k]->data()), stride, stride * width));
    }
    Imf::OutputFile file(path.string().c_str(), header);
    file.setFrameBuffer(frame);
    file.writePixels(height);
  }

  // Loading the scene must fail with one sentence holding every fragment.
  void expect_rejected(const std::filesystem::path& scene, const std::vector<std::string>& fragments) const {
    try {
      load_scene(scene);
      FAIL() << "accepted " << scene;
    } catch (const Error& e) {
      const std::string msg = e.what();
      for (const std::string& f : fragments) EXPECT_NE(msg.find(f), std::string::npos) << f << " not in: " << msg;
      EXPECT_EQ(msg.back(), '.') << msg;
      EXPECT_EQ(msg.find(". "), std::string::npos) << "one sentence: " << msg;
    }
  }

  std::filesystem::path dir_;
};

TEST_F(EnvironmentMapLoader, LoadsGrayMapRelativeToTheSceneFile) {
  LatLongMap map;
  map.width = 4;
  map.height = 2;
  map.texels = {0, 1, 2, 3, 4, 5, 6, 7};
  write_latlong_exr(dir_ / "sky.exr", map);
  const Scene s = load_scene(write_scene("sky.exr"));
  ASSERT_TRUE(s.environment.map);
  EXPECT_EQ(s.environment.map->texels, map.texels);
  EXPECT_EQ(s.environment.map_file, (dir_ / "sky.exr").string());
  // Row 0 is the upper hemisphere (θ < π/2), columns follow φ = atan2(y, x) ∈ [0, 2π).
  const double q = std::sqrt(0.5);
  EXPECT_EQ(environment_radiance(s.environment, Vec3(q, 0.1, q)), 0.25 * 0);   // φ ≈ 0.1, θ = π/4
  EXPECT_EQ(environment_radiance(s.environment, Vec3(-q, 0.1, q)), 0.25 * 1);  // φ ≈ π − 0.1
  EXPECT_EQ(environment_radiance(s.environment, Vec3(-q, -0.1, q)), 0.25 * 2); // φ ≈ π + 0.1
  EXPECT_EQ(environment_radiance(s.environment, Vec3(q, -0.1, -q)), 0.25 * 7); // φ ≈ 2π − 0.1, θ = 3π/4
  EXPECT_EQ(environment_radiance(s.environment, Vec3(0, 0, 1)), 0.25 * 0);     // the pole: row 0, φ = 0
  EXPECT_EQ(environment_radiance(s.environment, Vec3(0, 0, -1)), 0.25 * 4);    // θ = π clamps to the last row
  // The constant environment is unchanged.
  EXPECT_EQ(environment_radiance(parse_scene(kValid, "valid.json").environment, Vec3(0, 0, -1)), 0.25);
}

TEST_F(EnvironmentMapLoader, EqualRgbIsGray) {
  write_rgb(dir_ / "rgb.exr", 2, 1, {0.5f, 2.0f}, {0.5f, 2.0f}, {0.5f, 2.0f});
  const Scene s = load_scene(write_scene("rgb.exr"));
  ASSERT_TRUE(s.environment.map);
  EXPECT_EQ(s.environment.map->texels, (std::vector<double>{0.5, 2.0}));
}

TEST_F(EnvironmentMapLoader, RejectsMissingFile) {
  expect_rejected(write_scene("nowhere.exr"),
                  {"scene.json", "environment.map", "nowhere.exr", "does not exist"});
}

TEST_F(EnvironmentMapLoader, RejectsUnreadableFile) {
  std::ofstream(dir_ / "junk.exr") << "not an OpenEXR file";
  expect_rejected(write_scene("junk.exr"), {"scene.json", "environment.map", "junk.exr", "cannot read"});
}

TEST_F(EnvironmentMapLoader, RejectsNonGrayMap) {
  write_rgb(dir_ / "color.exr", 2, 1, {0.5f, 2.0f}, {0.5f, 2.5f}, {0.5f, 2.0f});
  expect_rejected(write_scene("color.exr"),
                  {"scene.json", "environment.map", "color.exr", "row 0, column 1", "G = 2.5", "gray"});
}

TEST_F(EnvironmentMapLoader, RejectsNegativeTexel) {
  LatLongMap map;
  map.width = 3;
  map.height = 2;
  map.texels = {1, 1, 1, 1, -0.5, 1};
  write_latlong_exr(dir_ / "negative.exr", map);
  expect_rejected(write_scene("negative.exr"),
                  {"scene.json", "environment.map", "negative.exr", "row 1, column 1", "'Y'", "-0.5"});
}

TEST_F(EnvironmentMapLoader, RejectsNonFiniteTexel) {
  LatLongMap map;
  map.width = 2;
  map.height = 1;
  map.texels = {std::numeric_limits<double>::infinity(), 1};
  write_latlong_exr(dir_ / "inf.exr", map);
  expect_rejected(write_scene("inf.exr"), {"environment.map", "inf.exr", "row 0, column 0", "inf"});
}

// A committed map is what scripts/make_environment_map.cpp writes with
// `options`, texel for texel.
void expect_reproducible(const std::filesystem::path& dir, const std::string& options, const std::string& name) {
  const auto regenerated = dir / ("regenerated_" + name);
  const std::string command = std::string(FURNACE_MAKE_ENVIRONMENT_MAP) + options + " " + regenerated.string();
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  const LatLongMap committed = load_latlong_exr(std::string(FURNACE_SCENE_DIR) + "/" + name);
  const LatLongMap fresh = load_latlong_exr(regenerated);
  EXPECT_EQ(committed.width, fresh.width) << name;
  EXPECT_EQ(committed.height, fresh.height) << name;
  EXPECT_EQ(committed.texels, fresh.texels) << name;
}

// scenes/sky_above.exr (--sky-above): 1 above the horizon, 0 below.
TEST_F(EnvironmentMapLoader, CommittedSkyAboveMapIsReproducibleFromItsGenerator) {
  expect_reproducible(dir_, " --sky-above", "sky_above.exr");
  const LatLongMap committed = load_latlong_exr(std::string(FURNACE_SCENE_DIR) + "/sky_above.exr");
  EXPECT_EQ(committed.lookup({0, 0.6, 0.8}), 1.0);
  EXPECT_EQ(committed.lookup({0, 0.6, -0.8}), 0.0);
}

// scenes/environment_map.exr (no option).
TEST_F(EnvironmentMapLoader, CommittedMapIsReproducibleFromItsGenerator) {
  expect_reproducible(dir_, "", "environment_map.exr");
}

}  // namespace
}  // namespace furnace
