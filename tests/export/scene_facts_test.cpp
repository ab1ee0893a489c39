// The scene facts every exporter shares (export/scene_facts.h): an object's
// material in a refusal sentence, which materials reflect, when direct
// lighting is the whole answer, and that a material type no exporter decided
// is an internal error, never a silently diffuse surface.
#include "export/scene_facts.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include <fmt/format.h>

#include "core/scene.h"
#include "core/strategy.h"

namespace furnace::exporter {
namespace {

namespace fs = std::filesystem;

Scene builtin(const std::string& name) { return load_scene(fs::path(FURNACE_SCENE_DIR) / (name + ".json")); }

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// A one-object scene whose material is {"type": type, "albedo": albedo}.
Scene scene_with_material(const std::string& type, double albedo) {
  return parse_scene(fmt::format(R"({{
    "name": "material_test",
    "camera": {{"type": "orthographic", "center": [0, 0, 1], "forward": [0, 0, -1], "up": [0, 1, 0],
               "size": [1, 1], "resolution": [4, 4]}},
    "objects": [
      {{"name": "floor", "shape": {{"type": "rectangle", "corner": [-1, -1, 0], "edge_u": [2, 0, 0], "edge_v": [0, 2, 0]}},
       "material": {{"type": "{}", "albedo": {}}}}}
    ]}})",
                                 type, albedo),
                     "material_test.json");
}

TEST(ExportSceneFacts, ObjectMaterialTextNamesObjectFieldAndValue) {
  const Scene scene = scene_with_material("phong", 0.25);
  EXPECT_EQ(object_material_text(scene, 0), "'floor' (objects[0].material.type \"phong\", albedo 0.25, exponent 1)");
}

TEST(ExportSceneFacts, ObjectMaterialTextOfGgxNamesAlphaAndSmithForm) {
  const Scene scene = builtin("ggx_oblique_sky_60");
  EXPECT_EQ(object_material_text(scene, 2), "'ggx_a0.3_sep' (objects[2].material.type \"ggx\", albedo 0.8, alpha "
                                            "0.3, shadowing \"separable\")");
}

// Light leaves a surface towards the eye only along its normal when the
// surface is planar, faces the orthographic camera and nothing else reflects.
TEST(ExportSceneFacts, SeenOnlyAlongTheNormalNeedsAPlanarSurfaceFacingTheCameraAndNoOtherReflector) {
  Scene strips = builtin("ggx_sky_strips");
  for (size_t i = 0; i < strips.objects.size(); ++i) EXPECT_FALSE(not_seen_only_along_normal(strips, i)) << i;
  // A camera tilted by 1e-3 rad (1 − cos = 5e-7 > 1e-9) sees every strip obliquely.
  strips.camera.forward = normalize(Vec3{0, 1e-3, -1});
  const auto tilted = not_seen_only_along_normal(strips, 0);
  ASSERT_TRUE(tilted);
  EXPECT_TRUE(contains(*tilted, "'ggx_a1' is not perpendicular")) << *tilted;
  // Within the tolerance: 1e-5 rad (1 − cos = 5e-11).
  strips.camera.forward = normalize(Vec3{0, 1e-5, -1});
  EXPECT_FALSE(not_seen_only_along_normal(strips, 0));
  // The strips all reflect but share one plane: none sees another. Lift
  // one strip by 0.01 and the others' oblique light can reach it.
  Scene lifted = builtin("ggx_sky_strips");
  std::get<Rectangle>(lifted.objects[4].shape).corner.z = 0.01;
  const auto raised = not_seen_only_along_normal(lifted, 0);
  ASSERT_TRUE(raised);
  EXPECT_TRUE(contains(*raised, "the object 'ggx_a0.05' reflects light that leaves 'ggx_a1'")) << *raised;
  EXPECT_TRUE(not_seen_only_along_normal(lifted, 4));
  // The disk scene: the black occluder reflects nothing; once it does, the
  // receivers' oblique light comes back.
  Scene disk = builtin("ggx_disk_occluder");
  EXPECT_FALSE(not_seen_only_along_normal(disk, 0));
  disk.objects[3].material.albedo = 0.5;
  const auto reflected = not_seen_only_along_normal(disk, 0);
  ASSERT_TRUE(reflected);
  EXPECT_TRUE(contains(*reflected, "'occluder' reflects")) << *reflected;
  // The oblique scenes' strips are seen at 60 degrees.
  EXPECT_TRUE(not_seen_only_along_normal(builtin("ggx_oblique_sky_60"), 0));
  // A sphere never qualifies.
  const Scene sphere = builtin("ggx_oblique_sphere_60");
  const auto round = not_seen_only_along_normal(sphere, 4);
  ASSERT_TRUE(round);
  EXPECT_TRUE(contains(*round, "'light' is a sphere")) << *round;
}

TEST(ExportSceneFacts, EveryTypeReflectsExactlyWhenItsAlbedoIsPositive) {
  for (const BsdfTypeInfo& info : kBsdfTypeTable) {
    ASSERT_TRUE(info.albedo_scales_reflection) << info.name << ": this test's premise";
    EXPECT_TRUE(reflects(Material{0.5, default_parameters(info.type)})) << info.name;
    EXPECT_TRUE(reflects(Material{1e-300, default_parameters(info.type)})) << info.name;
    EXPECT_FALSE(reflects(Material{0, default_parameters(info.type)})) << info.name;
  }
}

TEST(ExportSceneFacts, DirectLightingIsCompleteOnlyWithOnePlanarLambertianReflector) {
  for (const char* name : {"disk_occluder", "environment_blocker", "point_and_area", "three_lights", "sphere_light"})
    EXPECT_TRUE(direct_lighting_is_complete(builtin(name))) << name;
  for (const char* name : {"enclosure_box", "enclosure_sphere", "white_furnace", "convex_furnace", "mirror_disk"})
    EXPECT_FALSE(direct_lighting_is_complete(builtin(name))) << name;
  // The one reflector of disk_occluder (its receiver) as each other type.
  for (const BsdfType type : {BsdfType::kMirror, BsdfType::kPhong}) {
    Scene scene = builtin("disk_occluder");
    ASSERT_EQ(scene.objects[0].name, "receiver");
    scene.objects[0].material.bsdf = default_parameters(type);
    EXPECT_FALSE(direct_lighting_is_complete(scene)) << bsdf_type_name(type);
    scene.objects[0].material.albedo = 0;  // black whatever the type: nothing bounces
    EXPECT_TRUE(direct_lighting_is_complete(scene)) << bsdf_type_name(type);
  }
}

TEST(ExportSceneFacts, CheckDepthIsTwoWhereDirectLightingIsCompleteAndTheDepthAllowsABounce) {
  const Scene direct = builtin("environment_blocker");
  EXPECT_EQ(check_max_depth(direct, kUnlimitedDepth), 2);
  EXPECT_EQ(check_max_depth(direct, 5), 2);
  EXPECT_EQ(check_max_depth(direct, 1), 1);  // emission only: not direct lighting
  EXPECT_TRUE(contains(direct_lighting_clause(direct, kUnlimitedDepth), "which is direct lighting here"));
  EXPECT_EQ(direct_lighting_clause(direct, 2), "");  // the depth asked for already is direct lighting
  const Scene global = builtin("mirror_disk");
  EXPECT_EQ(check_max_depth(global, kUnlimitedDepth), kUnlimitedDepth);
  EXPECT_EQ(check_max_depth(global, 7), 7);
  EXPECT_EQ(direct_lighting_clause(global, kUnlimitedDepth), "");
}

}  // namespace
}  // namespace furnace::exporter
