// The strict scene schema: every numeric range of scene_limits is enforced on
// both sides (one test per bound: the value at the bound is accepted, the
// value just beyond it is refused naming the file, the field and the value),
// unknown and duplicated fields are refused naming the closest known name,
// numbers beyond double range and wrong types are sentences, geometry
// degenerate within round-off is refused, and every built-in scene stays
// valid under the transforms of the stability tests.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <ostream>
#include <sstream>
#include <set>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/scene.h"
#include "tests/core/valid_scene.h"

namespace furnace {
namespace {

namespace lim = scene_limits;

// A small valid scene; each case below replaces one fragment of it.
const char* kBase = test::kValidSceneJson;

std::string with(const std::string& from, const std::string& to) {
  std::string text = kBase;
  const size_t at = text.find(from);
  if (at == std::string::npos) throw std::logic_error("fragment not in the base scene: " + from);
  return text.replace(at, from.size(), to);
}

// The message of the furnace::Error that parsing `text` throws ("" if none).
std::string rejection(const std::string& text) {
  try {
    parse_scene(text, "bad.json");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

// A number written with every digit (the boundary values are not round).
std::string num(double x) { return fmt::format("{:.17g}", x); }

// One bound: `fragment` of kBase replaced by `pattern` with `{}` standing for
// the value; `at_bound` must be accepted, `beyond` refused naming `field`.
struct Bound {
  std::string name;
  std::string fragment;
  std::string pattern;
  double at_bound;
  double beyond;
  std::string field;
};

void PrintTo(const Bound& b, std::ostream* os) { *os << b.name; }

// Just beyond a bound: one part in 10⁶ (far above round-off, far below any
// value a scene would mean).
double above(double x) { return x == 0 ? 1e-9 : x * (1 + 1e-6); }
double below(double x) { return x == 0 ? -1e-9 : x * (1 - 1e-6); }

std::vector<Bound> bounds() {
  const std::string disk = R"("center": [0, 0, 2], "normal": [0, 0, -2], "radius": 0.5)";
  const std::string floor = R"("corner": [-2, -1, 0], "edge_u": [4, 0, 0], "edge_v": [0, 2, 0])";
  const std::string light_shape = R"({"type": "disk", "center": [0, 0, 2], "normal": [0, 0, -2], "radius": 0.5})";
  const std::string lambertian = R"("material": {"type": "lambertian", "albedo": 0.5})";
  const double c = lim::kMaxCoordinate, l = lim::kMaxLength, m = lim::kMinLength;
  const double r0 = lim::kMinRadiometric, r1 = lim::kMaxRadiometric;
  // The largest square-ish image within the pixel budget, and one row more.
  const int side = 1 << 11;
  static_assert(lim::kMaxPixels == uint64_t(1 << 11) * (1 << 11), "pixel budget case assumes a 2048² budget");
  return {
      {"CoordinateMax", "\"center\": [0, 0, 0.5]", "\"center\": [0, 0, {}]", c, above(c), "camera.center"},
      {"CoordinateMin", "[0.5, 0, 1]", "[{}, 0, 1]", -c, above(-c), "point_lights[0].position"},
      // The smallest non-zero component float represents as a normal number.
      {"ComponentBelowFloat", "[0.5, 0, 1]", "[0.5, {}, 1]", std::numeric_limits<float>::min(),
       std::numeric_limits<float>::min() * (1 - 1e-6), "point_lights[0].position"},
      // The light over the floor (z = 0) at height z: its distance to the surface.
      {"PointLightClearance", "[0.5, 0, 1]", "[0.5, 0, {}]", m, below(m), "point_lights[0].position"},
      {"RadiusMax", "\"radius\": 0.5", "\"radius\": {}", l, above(l), "objects[1].shape.radius"},
      {"RadiusMin", disk, "\"center\": [0, 0, 0.5], \"normal\": [0, 0, -1], \"radius\": {}", m, below(m),
       "objects[1].shape.radius"},
      // Relative to the shape's largest coordinate, 1000: 2^-20·1000.
      {"RadiusRelativeMin", disk, "\"center\": [0, 0, 1000], \"normal\": [0, 0, -1], \"radius\": {}",
       lim::kMinRelativeLength * 1000, below(lim::kMinRelativeLength * 1000), "objects[1].shape.radius"},
      {"EdgeMax", "\"edge_u\": [4, 0, 0]", "\"edge_u\": [{}, 0, 0]", l, above(l), "objects[0].shape.edge_u"},
      {"EdgeMin", floor, "\"corner\": [0, 0, 0], \"edge_u\": [{}, 0, 0], \"edge_v\": [0, 1e-6, 0]", m, below(m),
       "objects[0].shape.edge_u"},
      // edge_v = [4, t, 0] against edge_u = [4, 0, 0]: sine t/√(16 + t²) ≈ t/4.
      {"EdgesParallel", "\"edge_v\": [0, 2, 0]", "\"edge_v\": [4, {}, 0]", 4 * lim::kMinSine * (1 + 1e-6),
       4 * lim::kMinSine * (1 - 1e-6), "objects[0].shape.edge_v"},
      // p2 at height h over the unit edge p0-p1: twice the area over the longest edge squared ≈ h.
      {"TriangleCollinear", light_shape,
       R"({"type": "triangle", "p0": [0, 0, 2], "p1": [1, 0, 2], "p2": [0.5, {}, 2]})",
       lim::kMinSine * (1 + 1e-6), lim::kMinSine * (1 - 1e-6), "objects[1].shape.p2"},
      {"TriangleEdgeMin", light_shape, R"({"type": "triangle", "p0": [0, 0, 0], "p1": [{}, 0, 0], "p2": [0, 1e-6, 0]})",
       m, below(m), "objects[1].shape.p1"},
      {"DirectionLengthMin", "\"normal\": [0, 0, -2]", "\"normal\": [0, 0, {}]", -lim::kMinDirectionLength,
       -below(lim::kMinDirectionLength), "objects[1].shape.normal"},
      // up = [0, t, 1] against forward = [0, 0, -1]: sine t/√(1 + t²).
      {"CameraUpParallel", "\"up\": [0, 1, 0]", "\"up\": [0, {}, 1]", lim::kMinSine * (1 + 1e-6),
       lim::kMinSine * (1 - 1e-6), "camera.up"},
      {"CameraSizeMin", "\"size\": [4, 2]", "\"size\": [4, {}]", m, below(m), "camera.size"},
      {"CameraSizeMax", "\"size\": [4, 2]", "\"size\": [{}, 2]", l, above(l), "camera.size"},
      {"ResolutionMax", "\"resolution\": [8, 4]", "\"resolution\": [{}, 4]", lim::kMaxResolution,
       lim::kMaxResolution + 1, "camera.resolution"},
      {"ResolutionMin", "\"resolution\": [8, 4]", "\"resolution\": [8, {}]", 1, 0, "camera.resolution"},
      {"PixelBudget", "\"resolution\": [8, 4]", fmt::format("\"resolution\": [{}, {{}}]", side), side, side + 1,
       "camera.resolution"},
      {"EmissionMax", "\"emission\": 3", "\"emission\": {}", r1, above(r1), "objects[1].emission"},
      {"EmissionMin", "\"emission\": 3", "\"emission\": {}", r0, below(r0), "objects[1].emission"},
      {"EnvironmentRadianceMax", "\"radiance\": 0.25", "\"radiance\": {}", r1, above(r1), "environment.radiance"},
      {"EnvironmentRadianceMin", "\"radiance\": 0.25", "\"radiance\": {}", r0, below(r0), "environment.radiance"},
      {"IntensityMax", "\"intensity\": 2", "\"intensity\": {}", r1, above(r1), "point_lights[0].intensity"},
      {"IntensityMin", "\"intensity\": 2", "\"intensity\": {}", r0, below(r0), "point_lights[0].intensity"},
      {"AlbedoMax", "\"albedo\": 0.5", "\"albedo\": {}", 1, above(1), "objects[0].material.albedo"},
      {"AlbedoMin", "\"albedo\": 0.5", "\"albedo\": {}", 0, below(0), "objects[0].material.albedo"},
      {"PhongExponentMax", lambertian, "\"material\": {\"type\": \"phong\", \"albedo\": 0.5, \"exponent\": {}}",
       lim::kMaxPhongExponent, above(lim::kMaxPhongExponent), "objects[0].material.exponent"},
      {"PhongExponentMin", lambertian, "\"material\": {\"type\": \"phong\", \"albedo\": 0.5, \"exponent\": {}}", 0,
       below(0), "objects[0].material.exponent"},
      {"GgxAlphaMax", lambertian, "\"material\": {\"type\": \"ggx\", \"albedo\": 0.5, \"alpha\": {}}", 1, above(1),
       "objects[0].material.alpha"},
      {"GgxAlphaMin", lambertian, "\"material\": {\"type\": \"ggx\", \"albedo\": 0.5, \"alpha\": {}}",
       lim::kMinGgxAlpha, below(lim::kMinGgxAlpha), "objects[0].material.alpha"},
  };
}

class SceneBound : public testing::TestWithParam<Bound> {};

TEST_P(SceneBound, AcceptedAtTheBoundRefusedBeyond) {
  const Bound& b = GetParam();
  const auto text = [&](double x) {
    std::string value = num(x);
    std::string pattern = b.pattern;
    return with(b.fragment, pattern.replace(pattern.find("{}"), 2, value));
  };
  const std::string inside = rejection(text(b.at_bound));
  EXPECT_EQ(inside, "") << "the bound " << num(b.at_bound) << " itself is refused";
  const std::string outside = rejection(text(b.beyond));
  ASSERT_NE(outside, "") << num(b.beyond) << " is accepted";
  EXPECT_NE(outside.find("'bad.json'"), std::string::npos) << outside;
  EXPECT_NE(outside.find("'" + b.field + "'"), std::string::npos) << outside;
  EXPECT_EQ(outside.back(), '.') << outside;
  EXPECT_EQ(outside.find('\n'), std::string::npos) << outside;
}

INSTANTIATE_TEST_SUITE_P(SceneSchema, SceneBound, testing::ValuesIn(bounds()),
                         [](const testing::TestParamInfo<Bound>& info) { return info.param.name; });

// Refusals beyond the ranges: each names the file, the field and a fragment
// of the reason or value.
struct Refusal {
  std::string name;
  std::string fragment;
  std::string replacement;
  std::vector<std::string> expected;  // substrings of the message
};

void PrintTo(const Refusal& r, std::ostream* os) { *os << r.name; }

class SceneRefusal : public testing::TestWithParam<Refusal> {};

TEST_P(SceneRefusal, OneSentenceNamingFileAndField) {
  const Refusal& r = GetParam();
  const std::string message = rejection(with(r.fragment, r.replacement));
  ASSERT_NE(message, "") << "accepted";
  EXPECT_NE(message.find("'bad.json'"), std::string::npos) << message;
  for (const std::string& e : r.expected) EXPECT_NE(message.find(e), std::string::npos) << e << " not in: " << message;
  EXPECT_EQ(message.back(), '.') << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

INSTANTIATE_TEST_SUITE_P(
    SceneSchema, SceneRefusal,
    testing::Values(
        // Misspelt or unknown fields at every level, with the closest known name.
        Refusal{"MisspeltAlbedo", "\"albedo\": 0.5", "\"albdeo\": 0.5",
                {"'objects[0].material.albdeo'", "did you mean 'albedo'"}},
        Refusal{"MisspeltEmission", "\"emission\": 3", "\"emision\": 3", {"'objects[1].emision'", "'emission'"}},
        Refusal{"MisspeltTwoSided", "\"emission\": 3", "\"emission\": 3, \"two_side\": true",
                {"'objects[1].two_side'", "'two_sided'"}},
        Refusal{"UnknownTopLevel", "\"name\": \"t\"", "\"name\": \"t\", \"closd\": true", {"'closd'", "'closed'"}},
        Refusal{"UnknownCamera", "\"size\": [4, 2]", "\"size\": [4, 2], \"fov\": 45", {"'camera.fov'", "known:"}},
        Refusal{"UnknownEnvironment", "\"radiance\": 0.25", "\"radience\": 0.25",
                {"'environment.radience'", "'radiance'"}},
        Refusal{"UnknownShapeField", "\"radius\": 0.5", "\"radius\": 0.5, \"corner\": [0, 0, 0]",
                {"'objects[1].shape.corner'", "'center'"}},
        Refusal{"UnknownPointLightField", "\"intensity\": 2", "\"intensity\": 2, \"power\": 5",
                {"'point_lights[0].power'", "did you mean"}},
        Refusal{"ExponentOnLambertian", "\"albedo\": 0.5", "\"albedo\": 0.5, \"exponent\": 10",
                {"'objects[0].material.exponent'", "is a field of a phong material, not of a lambertian material",
                 "the fields of a lambertian material: type, albedo"}},
        Refusal{"AlphaOnPhong", "\"type\": \"lambertian\", \"albedo\": 0.5",
                "\"type\": \"phong\", \"albedo\": 0.5, \"alpha\": 0.1",
                {"'objects[0].material.alpha'", "is a field of a ggx material, not of a phong material",
                 "the fields of a phong material: type, albedo, exponent"}},
        Refusal{"ExponentOnGgx", "\"type\": \"lambertian\", \"albedo\": 0.5",
                "\"type\": \"ggx\", \"albedo\": 0.5, \"alpha\": 0.1, \"exponent\": 10",
                {"'objects[0].material.exponent'", "is a field of a phong material, not of a ggx material",
                 "the fields of a ggx material: type, albedo, alpha, shadowing"}},
        Refusal{"MisspeltMaterialField", "\"type\": \"lambertian\", \"albedo\": 0.5",
                "\"type\": \"ggx\", \"albedo\": 0.5, \"alpah\": 0.1",
                {"'objects[0].material.alpha'", "missing", "'alpah'"}},
        Refusal{"MisspeltOptionalMaterialField", "\"type\": \"lambertian\", \"albedo\": 0.5",
                "\"type\": \"phong\", \"albedo\": 0.5, \"exponnt\": 10",
                {"'objects[0].material.exponnt'", "is not a field of a phong material", "did you mean 'exponent'",
                 "the fields of a phong material: type, albedo, exponent"}},
        Refusal{"DielectricEtaOne", "\"type\": \"lambertian\", \"albedo\": 0.5",
                "\"type\": \"dielectric\", \"albedo\": 1, \"eta\": 1",
                {"'objects[0].material.eta'", "must not be 1", "invisible"}},
        Refusal{"DielectricEtaAboveRange", "\"type\": \"lambertian\", \"albedo\": 0.5",
                "\"type\": \"dielectric\", \"albedo\": 1, \"eta\": 5",
                {"'objects[0].material.eta'", "[0.25, 4]", "5"}},
        Refusal{"DielectricWithoutEta", "\"type\": \"lambertian\", \"albedo\": 0.5",
                "\"type\": \"dielectric\", \"albedo\": 1",
                {"'objects[0].material.eta'", "missing"}},
        Refusal{"DielectricAlphaBelowGgxRange", "\"type\": \"lambertian\", \"albedo\": 0.5",
                "\"type\": \"dielectric\", \"albedo\": 1, \"eta\": 1.5, \"alpha\": 1e-4",
                {"'objects[0].material.alpha'", "must be 0 (smooth) or in [0.001, 1]"}},
        Refusal{"ExponentOnDielectric", "\"type\": \"lambertian\", \"albedo\": 0.5",
                "\"type\": \"dielectric\", \"albedo\": 1, \"eta\": 1.5, \"exponent\": 3",
                {"'objects[0].material.exponent'", "is a field of a phong material, not of a dielectric material", "the fields of a dielectric material: type, albedo, eta, alpha, shadowing"}},
        Refusal{"GgxFresnelZeroIndex", "\"type\": \"lambertian\", \"albedo\": 0.5",
                "\"type\": \"ggx\", \"albedo\": 1, \"alpha\": 0.3, \"fresnel\": {\"eta\": 0, \"k\": 0}",
                {"'objects[0].material.fresnel.k'", "must be above 0 when eta is 0"}},
        Refusal{"GgxFresnelUnknownField", "\"type\": \"lambertian\", \"albedo\": 0.5",
                "\"type\": \"ggx\", \"albedo\": 1, \"alpha\": 0.3, \"fresnel\": {\"eta\": 1, \"k\": 2, \"n\": 3}",
                {"'objects[0].material.fresnel.n'", "is not a known field"}},
        Refusal{"GgxFresnelNotAnObject", "\"type\": \"lambertian\", \"albedo\": 0.5",
                "\"type\": \"ggx\", \"albedo\": 1, \"alpha\": 0.3, \"fresnel\": 1.5",
                {"'objects[0].material.fresnel'", "must be an object"}},
        Refusal{"GgxFresnelWithoutK", "\"type\": \"lambertian\", \"albedo\": 0.5",
                "\"type\": \"ggx\", \"albedo\": 1, \"alpha\": 0.3, \"fresnel\": {\"eta\": 1}",
                {"'objects[0].material.fresnel.k'", "missing"}},
        Refusal{"GgxFresnelNegativeK", "\"type\": \"lambertian\", \"albedo\": 0.5",
                "\"type\": \"ggx\", \"albedo\": 1, \"alpha\": 0.3, \"fresnel\": {\"eta\": 1, \"k\": -1}",
                {"'objects[0].material.fresnel.k'", "[0, 100]"}},
        Refusal{"GgxWithoutAlpha", "\"type\": \"lambertian\"", "\"type\": \"ggx\"",
                {"'objects[0].material.alpha'", "missing"}},
        Refusal{"GgxUnknownShadowing", "\"type\": \"lambertian\", \"albedo\": 0.5",
                "\"type\": \"ggx\", \"albedo\": 0.5, \"alpha\": 0.1, \"shadowing\": \"smith\"",
                {"'objects[0].material.shadowing'", "separable, height_correlated", "\"smith\""}},
        Refusal{"GgxShadowingNotString", "\"type\": \"lambertian\", \"albedo\": 0.5",
                "\"type\": \"ggx\", \"albedo\": 0.5, \"alpha\": 0.1, \"shadowing\": 1",
                {"'objects[0].material.shadowing'", "string"}},
        Refusal{"GgxMisspeltShadowing", "\"type\": \"lambertian\", \"albedo\": 0.5",
                "\"type\": \"ggx\", \"albedo\": 0.5, \"alpha\": 0.1, \"shadowng\": \"separable\"",
                {"'objects[0].material.shadowng'", "did you mean 'shadowing'"}},
        Refusal{"MisspeltRequiredField", "\"shape\": {\"type\": \"disk\"", "\"shap\": {\"type\": \"disk\"",
                {"'objects[1].shape'", "missing", "'shap'"}},
        Refusal{"DuplicatedField", "\"albedo\": 0.5", "\"albedo\": 0.5, \"albedo\": 0.7",
                {"'objects[0].material.albedo'", "twice"}},
        // Numbers beyond double range (nlohmann's out_of_range, not a parse_error).
        Refusal{"EmissionBeyondDouble", "\"emission\": 3", "\"emission\": 1e309",
                {"'objects[1].emission'", "beyond the range of double", "1e309"}},
        Refusal{"NegativeBeyondDouble", "[0.5, 0, 1]", "[0.5, -1e309, 1]", {"'point_lights[0].position[1]'", "-1e309"}},
        Refusal{"ResolutionBeyondDouble", "[8, 4]", "[8, 1e400]", {"'camera.resolution[1]'"}},
        Refusal{"ResolutionBeyondUint64", "[8, 4]", "[8, 99999999999999999999]", {"'camera.resolution'"}},
        Refusal{"FractionalResolution", "[8, 4]", "[8, 4.5]", {"'camera.resolution'", "[8,4.5]"}},
        Refusal{"NegativeResolution", "[8, 4]", "[8, -4]", {"'camera.resolution'", "[8,-4]"}},
        Refusal{"NaNLiteral", "\"emission\": 3", "\"emission\": NaN", {"not valid JSON", "'objects[1].emission'"}},
        Refusal{"NaNString", "\"emission\": 3", "\"emission\": \"nan\"", {"'objects[1].emission'", "\"nan\""}},
        // Coordinates Embree's float rays cannot take.
        Refusal{"CameraFarAway", "\"center\": [0, 0, 0.5]", "\"center\": [0, 0, 1e19]", {"'camera.center'", "1e+19"}},
        Refusal{"CameraHuge", "\"size\": [4, 2]", "\"size\": [1e300, 1e300]", {"'camera.size'", "1e+300"}},
        // Wrong types and shapes of values.
        Refusal{"ShortSize", "\"size\": [4, 2]", "\"size\": [4]", {"'camera.size'", "[4]"}},
        Refusal{"LongVector", "[0.5, 0, 1]", "[0.5, 0, 1, 2]", {"'point_lights[0].position'", "[0.5,0,1,2]"}},
        Refusal{"ObjectForNumber", "\"emission\": 3", "\"emission\": {}", {"'objects[1].emission'", "{}"}},
        Refusal{"NumberForObject", "\"environment\": {\"radiance\": 0.25}", "\"environment\": 5", {"'environment'"}},
        Refusal{"StringForBool", "\"emission\": 3", "\"emission\": 3, \"two_sided\": \"yes\"",
                {"'objects[1].two_sided'", "\"yes\""}},
        Refusal{"NumberForName", "\"name\": \"t\"", "\"name\": 7", {"'name'", "7"}},
        Refusal{"ObjectsNotArray", "\"objects\": [", "\"objects\": 3, \"x\": [", {"'objects'"}},
        // Geometry degenerate within round-off.
        Refusal{"ZeroCameraSize", "\"size\": [4, 2]", "\"size\": [0, 2]", {"'camera.size'", "width of 0"}},
        Refusal{"ForwardParallelToUp", "\"up\": [0, 1, 0]", "\"up\": [0, 0, 3]", {"'camera.up'", "parallel"}},
        Refusal{"ZeroRadius", "\"radius\": 0.5", "\"radius\": 0", {"'objects[1].shape.radius'", "radius of 0"}},
        Refusal{"ZeroNormal", "\"normal\": [0, 0, -2]", "\"normal\": [0, 0, 0]", {"'objects[1].shape.normal'", "[0,0,0]"}},
        Refusal{"ZeroEdge", "\"edge_v\": [0, 2, 0]", "\"edge_v\": [0, 0, 0]", {"'objects[0].shape.edge_v'", "length 0"}},
        Refusal{"ParallelEdges", "\"edge_v\": [0, 2, 0]", "\"edge_v\": [-8, 0, 0]", {"'objects[0].shape.edge_v'", "parallel"}},
        Refusal{"CollinearTriangle", "{\"type\": \"disk\", \"center\": [0, 0, 2], \"normal\": [0, 0, -2], \"radius\": 0.5}",
                "{\"type\": \"triangle\", \"p0\": [0, 0, 2], \"p1\": [1, 1, 2], \"p2\": [3, 3, 2]}",
                {"'objects[1].shape.p2'", "collinear"}},
        Refusal{"PointLightOnSurface", "[0.5, 0, 1]", "[0.5, 0, 0]", {"'point_lights[0].position'", "'floor'"}},
        Refusal{"PointLightOnSphere", "\"emission\": 3}", "\"emission\": 3}, {\"shape\": {\"type\": \"sphere\", "
                "\"center\": [0.5, 0, 0.5], \"radius\": 0.5}}",
                {"'point_lights[0].position'", "objects[2]"}},
        Refusal{"DenormalRadius", "\"radius\": 0.5", "\"radius\": 1e-320", {"'objects[1].shape.radius'"}},
        Refusal{"Truncated", "\"emission\": 3}\n  ]\n}", "\"emission\": 3", {"not valid JSON", "byte"}}),
    [](const testing::TestParamInfo<Refusal>& info) { return info.param.name; });

TEST(SceneSchema, BaseSceneIsValid) { EXPECT_EQ(rejection(kBase), ""); }

// The error of a misspelt name suggests the closest known field even when
// the typo is in the middle of a long name.
TEST(SceneSchema, SuggestsTheClosestName) {
  const std::string message = rejection(with("\"radiance\": 0.25", "\"radiance\": 0.25, \"mpa\": \"x.exr\""));
  EXPECT_NE(message.find("did you mean 'map'"), std::string::npos) << message;
}

// ---------------------------------------------------------------------------
// Every built-in scene is valid, and stays valid under the transforms of the
// integration stability tests (scale 1e-4 … 1e4, moved 2e3 from the origin)
// and near the edge of the coordinate range (scaled by 1e3, moved 5e5).

using nlohmann::json;

json read_scene(const std::filesystem::path& path) {
  std::ifstream in(path);
  return json::parse(in);
}

// p ↦ s·p + offset, v ↦ s·v for edges and lengths, directions unchanged.
json transformed(json scene, double scale, double offset) {
  const auto point = [&](json& p) {
    for (auto& x : p) x = scale * x.get<double>() + offset;
  };
  const auto vector = [&](json& v) {
    for (auto& x : v) x = scale * x.get<double>();
  };
  point(scene["camera"]["center"]);
  vector(scene["camera"]["size"]);
  for (auto& o : scene["objects"]) {
    json& s = o["shape"];
    for (const char* key : {"center", "corner", "p0", "p1", "p2"})
      if (s.contains(key)) point(s[key]);
    for (const char* key : {"edge_u", "edge_v"})
      if (s.contains(key)) vector(s[key]);
    if (s.contains("radius")) s["radius"] = scale * s["radius"].get<double>();
  }
  if (scene.contains("point_lights"))
    for (auto& l : scene["point_lights"]) point(l["position"]);
  return scene;
}

std::vector<std::filesystem::path> builtin_scenes() {
  std::vector<std::filesystem::path> paths;
  for (const auto& entry : std::filesystem::directory_iterator(FURNACE_SCENE_DIR))
    if (entry.path().extension() == ".json") paths.push_back(entry.path());
  std::sort(paths.begin(), paths.end());
  return paths;
}

// Hard-case scenes placed on purpose at the edge of the accepted ranges
// (lights and occluders 1e-5 above a receiver, lights of 1e-8 sr): scaling
// them down or moving them far pushes their smallest lengths out of range,
// which is the schema doing its job. They are checked as they are.
const std::set<std::string> kSceneAtTheRangeEdge = {"near_contact.json", "tiny_lights.json"};

TEST(SceneSchema, EveryBuiltinSceneIsValidAtEveryStabilityScale) {
  const auto paths = builtin_scenes();
  ASSERT_GE(paths.size(), 19u);
  for (const auto& path : paths) {
    EXPECT_NO_THROW(load_scene(path)) << path;
    if (kSceneAtTheRangeEdge.count(path.filename().string()) > 0) continue;
    const json scene = read_scene(path);
    for (const auto& [scale, offset] : std::vector<std::pair<double, double>>{
             {1e-4, 0}, {1e-2, 0}, {1e2, 0}, {1e4, 0}, {1, 2e3}, {1e-3, 10}, {1e3, 5e5}}) {
      // Written next to the original so that environment maps resolve.
      const std::string text = transformed(scene, scale, offset).dump();
      try {
        parse_scene(text, path.string());
      } catch (const Error& e) {
        ADD_FAILURE() << path << " scaled " << scale << ", moved " << offset << ": " << e.what();
      }
    }
  }
}

}  // namespace
}  // namespace furnace
