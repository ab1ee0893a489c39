// The pbrt-v4 exporter without pbrt: which scenes it refuses and why, the
// facts it writes (depth mapping, scale = Le, constant spectra, camera
// orientation, disk rotations), and that its output appears atomically.
#include "tests/command.h"
#include "export/pbrt_v4.h"
#include "tests/export/exported_cameras.h"

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "core/error.h"
#include "core/scene.h"
#include "export/scene_facts.h"
#include "tests/export/material_coverage.h"

namespace furnace::exporter {
namespace {

namespace fs = std::filesystem;

Scene builtin(const std::string& name) { return load_scene(fs::path(FURNACE_SCENE_DIR) / (name + ".json")); }

std::string refusal_of(const Scene& scene) { return pbrt_v4_refusal(scene).value_or(""); }

Object& named_object(Scene& scene, const std::string& name) {
  for (Object& o : scene.objects)
    if (o.name == name) return o;
  throw std::runtime_error("no object '" + name + "' in scene '" + scene.name + "'");
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// A scene with a mirror floor seen straight down by the camera, and a light.
Scene mirror_scene() {
  return parse_scene(R"({
    "name": "mirror_test",
    "camera": {"type": "orthographic", "center": [0, 0, 1], "forward": [0, 0, -1], "up": [0, 1, 0],
               "size": [1, 1], "resolution": [4, 4]},
    "objects": [
      {"name": "floor", "shape": {"type": "rectangle", "corner": [-1, -1, 0], "edge_u": [2, 0, 0], "edge_v": [0, 2, 0]},
       "material": {"type": "mirror", "albedo": 0.8}},
      {"name": "lamp", "shape": {"type": "disk", "center": [0, 0, 2], "normal": [0, 0, -1], "radius": 0.5},
       "emission": 3.0}
    ]})",
                     "mirror_test.json");
}

TEST(PbrtV4Export, RefusesExactlyTheImageEnvironmentsAndGlossyScenesAmongTheBuiltInScenes) {
  std::set<std::string> refused;
  for (const auto& entry : fs::directory_iterator(FURNACE_SCENE_DIR)) {
    if (entry.path().extension() != ".json") continue;
    const Scene scene = load_scene(entry.path());
    if (pbrt_v4_refusal(scene)) refused.insert(scene.name);
  }
  EXPECT_EQ(refused, (std::set<std::string>{"environment_map", "environment_map_tilted",
                                            // a sky on one side: an image environment
                                            "glass_sky_outside_60", "glass_sky_inside_30", "glossy_environment",
                                            "glossy_sphere_light", "ggx_sky_strips", "ggx_disk_occluder", "ggx_oblique_sky_60",
                                            "ggx_oblique_sky_78", "ggx_oblique_sphere_60", "ggx_oblique_sphere_78",
                                            // a separable strip seen obliquely beside the height-correlated ones
                                            "glass_rough_disk_inside", "glass_rough_inside_45",
                                            "glass_rough_outside_60", "conductor_fresnel_sky_60",
                                            "conductor_fresnel_sphere_60"}));
}

TEST(PbrtV4Export, ImageEnvironmentRefusalNamesSceneAndFeature) {
  const Scene scene = builtin("environment_map");
  const std::string reason = refusal_of(scene);
  EXPECT_TRUE(contains(reason, "scene 'environment_map'")) << reason;
  EXPECT_TRUE(contains(reason, "environment map")) << reason;
  EXPECT_TRUE(contains(reason, "octahedral")) << reason;
  try {
    export_pbrt_v4(scene, {});
    ADD_FAILURE() << "export_pbrt_v4 accepted an image environment";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), reason);
  }
}

TEST(PbrtV4Export, RefusesPhong) {
  Scene scene = builtin("disk_occluder");
  scene.objects[0].material = {0.5, Phong{10}};
  const std::string reason = refusal_of(scene);
  EXPECT_TRUE(contains(reason, "'receiver'")) << reason;
  EXPECT_TRUE(contains(reason, "Phong")) << reason;
}

TEST(PbrtV4Export, BlackPhongIsBlackDiffuse) {
  Scene scene = builtin("disk_occluder");
  scene.objects[2].material = {0, Phong{10}};
  EXPECT_FALSE(pbrt_v4_refusal(scene));
}

TEST(PbrtV4Export, PhongRefusalNamesSceneObjectFieldAndValue) {
  Scene scene = builtin("disk_occluder");
  scene.objects[0].material = {0.5, Phong{10}};
  const std::string reason = refusal_of(scene);
  EXPECT_EQ(reason, "scene 'disk_occluder' (" + scene.source + ") cannot be exported to pbrt-v4: the object 'receiver' "
                    "(objects[0].material.type \"phong\", albedo 0.5, exponent 10) has a normalised Phong BSDF, "
                    "which pbrt-v4 does not have.");
  try {
    export_pbrt_v4(scene, {});
    ADD_FAILURE() << "export_pbrt_v4 accepted a Phong reflector";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), reason);
  }
}

// The Material statement pbrt-v4 must get for `m`, stated here independently
// of the exporter; empty when the material is refused. One case per BsdfType
// and no default: a new type fails this test's build (-Werror=switch) until
// the test says what the export must do with it.
std::optional<std::string> expected_material(const Material& m) {
  const auto diffuse = [](double rho) {
    return fmt::format("Material \"diffuse\" \"spectrum reflectance\" [300 {0} 900 {0}]", rho);
  };
  switch (m.type()) {
    case BsdfType::kLambertian:
      return diffuse(m.albedo);
    case BsdfType::kMirror:  // in scenes where every path meets it at normal incidence; refused elsewhere
      if (m.albedo == 0) return diffuse(0);
      return fmt::format("Material \"conductor\" \"spectrum reflectance\" [300 {0} 900 {0}] \"float roughness\" 0",
                         m.albedo);
    case BsdfType::kPhong:
      if (m.albedo == 0) return diffuse(0);  // a black glossy surface is black
      return std::nullopt;
    case BsdfType::kGgx:  // albedo 1 only, in a scene whose Smith form pbrt has (refused elsewhere)
      if (m.albedo == 0) return diffuse(0);
      if (m.albedo != 1) return std::nullopt;
      if (const auto& f = std::get<Ggx>(m.bsdf).fresnel)  // exact complex Fresnel, constant over wavelength
        return fmt::format("Material \"conductor\" \"spectrum eta\" [300 {0} 900 {0}] \"spectrum k\" [300 {1} 900 "
                           "{1}] \"float roughness\" {2} \"bool remaproughness\" false",
                           f->eta, f->k, std::get<Ggx>(m.bsdf).alpha);
      return fmt::format("Material \"conductor\" \"spectrum eta\" [300 0 900 0] \"spectrum k\" [300 1 900 1] "
                         "\"float roughness\" {} \"bool remaproughness\" false",
                         std::get<Ggx>(m.bsdf).alpha);
    case BsdfType::kDielectric: {  // albedo 1 only (a black one is a black diffuse surface)
      if (m.albedo == 0) return diffuse(0);
      if (m.albedo != 1) return std::nullopt;
      const Dielectric& d = std::get<Dielectric>(m.bsdf);
      if (d.smooth()) return fmt::format("Material \"dielectric\" \"float eta\" {} \"float roughness\" 0", d.eta);
      return fmt::format("Material \"dielectric\" \"float eta\" {} \"float roughness\" {} \"bool remaproughness\" "
                         "false",
                         d.eta, d.alpha);
    }
  }
  return std::nullopt;
}

// The Material line of each object block ("# name\nAttributeBegin\nMaterial ...") in order.
std::vector<std::pair<std::string, std::string>> written_materials(const std::string& text) {
  std::vector<std::pair<std::string, std::string>> materials;
  const std::regex block("# ([^\n]*)\nAttributeBegin\n(Material [^\n]*)\n");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), block); it != std::sregex_iterator(); ++it)
    materials.emplace_back((*it)[1].str(), (*it)[2].str());
  return materials;
}

TEST(PbrtV4Export, EveryMaterialOfTheBuiltInScenesIsExportedAsItselfOrRefusedNamingIt) {
  MaterialCoverage coverage;
  for (const auto& entry : fs::directory_iterator(FURNACE_SCENE_DIR)) {
    if (entry.path().extension() != ".json") continue;
    const Scene scene = load_scene(entry.path());
    if (const auto refusal = pbrt_v4_refusal(scene)) {
      coverage.count_refusal(scene, *refusal);
      continue;
    }
    const auto materials = written_materials(export_pbrt_v4(scene, {}));
    ASSERT_EQ(materials.size(), scene.objects.size()) << scene.name;
    for (size_t i = 0; i < scene.objects.size(); ++i) {
      const Object& o = scene.objects[i];
      EXPECT_EQ(materials[i].first, o.name) << scene.name;
      const std::optional<std::string> expected = expected_material(o.material);
      ASSERT_TRUE(expected) << scene.name << ": " << o.name << " is written although its material cannot be";
      EXPECT_EQ(materials[i].second, *expected) << scene.name << ": " << o.name;
      coverage.count_written(o);
    }
  }
  coverage.expect_built_in_coverage("pbrt-v4");
}

// Negative control of the test above: a mirror written as a diffuse surface
// (what the exporter did for any unknown type before the allow-list) does
// not match what the test expects.
TEST(PbrtV4Export, ADiffuseMirrorWouldNotPassTheMaterialTest) {
  const Scene scene = builtin("mirror_disk");
  const auto materials = written_materials(export_pbrt_v4(scene, {}));
  ASSERT_EQ(materials.size(), 2u);
  Material as_diffuse = scene.objects[0].material;
  as_diffuse.bsdf = Lambertian{};
  EXPECT_NE(materials[0].second, *expected_material(as_diffuse));
  EXPECT_EQ(materials[0].second, *expected_material(scene.objects[0].material));
}

// A built-in GGX scene with every GGX object's albedo (and, when given,
// Smith form) replaced.
Scene ggx_variant(const std::string& name, double albedo, std::optional<MicrofacetShadowing> shadowing = {}) {
  Scene scene = builtin(name);
  for (Object& o : scene.objects) {
    Ggx* ggx = std::get_if<Ggx>(&o.material.bsdf);
    if (!ggx) continue;
    o.material.albedo = albedo;
    if (shadowing) ggx->shadowing = *shadowing;
  }
  return scene;
}

TEST(PbrtV4Export, GgxIsAConductorWithFresnelOneAndAlphaUnremapped) {
  for (const char* name : {"ggx_oblique_sky_60", "ggx_oblique_sphere_78", "ggx_sky_strips", "ggx_disk_occluder"}) {
    const Scene scene = ggx_variant(name, 1, MicrofacetShadowing::kHeightCorrelated);
    ASSERT_FALSE(pbrt_v4_refusal(scene)) << refusal_of(scene);
    const std::string text = export_pbrt_v4(scene, {});
    const auto materials = written_materials(text);
    ASSERT_EQ(materials.size(), scene.objects.size()) << name;
    int ggx = 0;
    for (size_t i = 0; i < scene.objects.size(); ++i) {
      EXPECT_EQ(materials[i].second, *expected_material(scene.objects[i].material)) << name;
      if (scene.objects[i].material.as<Ggx>()) ++ggx;
    }
    EXPECT_GE(ggx, 1) << name;
    EXPECT_TRUE(contains(text, "\"float roughness\" 0.3 \"bool remaproughness\" false") ||
                contains(text, "\"float roughness\" 0.5 \"bool remaproughness\" false"))
        << name;
    EXPECT_TRUE(contains(text, "F = 1 exactly")) << text.substr(0, 4000);
    EXPECT_TRUE(contains(text, "(left true, pbrt takes alpha = sqrt(roughness))")) << text.substr(0, 4000);
  }
}

TEST(PbrtV4Export, GgxRefusesAnAlbedoOtherThanOneNamingTheObject) {
  const Scene scene = builtin("ggx_sky_strips");  // albedo 0.8
  EXPECT_EQ(refusal_of(scene),
            "scene 'ggx_sky_strips' (" + scene.source + ") cannot be exported to pbrt-v4: the GGX object 'ggx_a1' "
            "(objects[0].material.type \"ggx\", albedo 0.8, alpha 1, shadowing \"height_correlated\") has albedo "
            "0.8, and pbrt-v4's conductor has no constant factor on its reflection (the export is exact for albedo 1 "
            "only).");
  EXPECT_TRUE(pbrt_v4_refusal(ggx_variant("ggx_sky_strips", 0.99)));
  EXPECT_FALSE(pbrt_v4_refusal(ggx_variant("ggx_sky_strips", 1)));
}

// furnace's scene files stop at α = 1e-3, pbrt's mirror threshold; a Scene
// built in memory below it is refused, and 1e-3 itself is written.
TEST(PbrtV4Export, GgxRefusesAnAlphaPbrtWouldRenderAsAMirror) {
  Scene scene = ggx_variant("ggx_sky_strips", 1);
  std::get<Ggx>(scene.objects[4].material.bsdf).alpha = 1e-3;
  EXPECT_FALSE(pbrt_v4_refusal(scene)) << refusal_of(scene);
  std::get<Ggx>(scene.objects[4].material.bsdf).alpha = 9.9e-4;
  const std::string reason = refusal_of(scene);
  EXPECT_TRUE(contains(reason, "'ggx_a0.05'") && contains(reason, "as perfectly smooth")) << reason;
}

TEST(PbrtV4Export, GgxRefusesTheSeparableFormWhereItDiffersFromPbrtsHeightCorrelatedOne) {
  // Oblique view: the separable strips are refused, the height-correlated ones are not.
  const Scene oblique = ggx_variant("ggx_oblique_sky_60", 1);
  const std::string reason = refusal_of(oblique);
  EXPECT_TRUE(contains(reason, "'ggx_a1_sep' (objects[0].material.type \"ggx\", albedo 1, alpha 1, shadowing "
                               "\"separable\") uses the separable Smith form, which pbrt-v4 does not implement"))
      << reason;
  EXPECT_TRUE(contains(reason, "not perpendicular to the camera's forward direction")) << reason;
  EXPECT_FALSE(pbrt_v4_refusal(ggx_variant("ggx_oblique_sky_60", 1, MicrofacetShadowing::kHeightCorrelated)));
  // Normal view but another object reflects light that left the GGX surface obliquely.
  Scene lit = ggx_variant("ggx_disk_occluder", 1);
  ASSERT_FALSE(pbrt_v4_refusal(lit)) << refusal_of(lit);
  named_object(lit, "occluder").material.albedo = 0.5;
  const std::string reflected = refusal_of(lit);
  EXPECT_TRUE(contains(reflected, "'ggx_a0.5'") && contains(reflected, "the object 'occluder' reflects light"))
      << reflected;
  std::get<Ggx>(named_object(lit, "ggx_a0.5").material.bsdf).shadowing = MicrofacetShadowing::kHeightCorrelated;
  EXPECT_FALSE(pbrt_v4_refusal(lit)) << refusal_of(lit);
}

TEST(PbrtV4Export, GgxSeparableAtNormalViewIsWrittenAndTheFileSaysWhyItIsExact) {
  const Scene scene = ggx_variant("ggx_sky_strips", 1);  // separable and height-correlated strips
  ASSERT_FALSE(pbrt_v4_refusal(scene)) << refusal_of(scene);
  const std::string text = export_pbrt_v4(scene, {});
  EXPECT_TRUE(contains(text, "#   'ggx_a0.5' (alpha 0.5, shadowing separable): \"float roughness\" 0.5, F = 1 (eta + "
                             "ik = i).\n"
                             "#     The scene asks for the separable form")) << text;
  EXPECT_TRUE(contains(text, "#     where the two forms are equal (Lambda(n) = 0)")) << text;
  // The height-correlated strips get no such note.
  EXPECT_TRUE(contains(text, "#   'ggx_a1' (alpha 1, shadowing height_correlated): \"float roughness\" 1, F = 1 (eta + "
                             "ik = i).\n#   'ggx_a0.5'"))
      << text;
}

// Every microfacet material (GGX and rough dielectric) of a built-in scene
// set to the height-correlated form, which pbrt-v4 has.
Scene height_correlated(const std::string& name) {
  Scene scene = builtin(name);
  for (Object& o : scene.objects) {
    if (Ggx* g = std::get_if<Ggx>(&o.material.bsdf)) g->shadowing = MicrofacetShadowing::kHeightCorrelated;
    if (Dielectric* d = std::get_if<Dielectric>(&o.material.bsdf)) d->shadowing = MicrofacetShadowing::kHeightCorrelated;
  }
  return scene;
}

TEST(PbrtV4Export, ConductorFresnelIsTheComplexIndexAsConstantSpectra) {
  const Scene scene = height_correlated("conductor_fresnel_sky_60");
  ASSERT_FALSE(pbrt_v4_refusal(scene)) << refusal_of(scene);
  const std::string text = export_pbrt_v4(scene, {});
  EXPECT_TRUE(contains(text, "Material \"conductor\" \"spectrum eta\" [300 0.2 900 0.2] \"spectrum k\" [300 3.4 900 3.4] "
                             "\"float roughness\" 1 \"bool remaproughness\" false\n"))
      << text;
  EXPECT_TRUE(contains(text, "#   'lowk_a0.3_hc' (alpha 0.3, shadowing height_correlated): \"float roughness\" 0.3, "
                             "exact Fresnel of n + ik = 1.5 + 0.1i.\n"))
      << text;
  // No dielectric: the check line needs no convention.
  EXPECT_FALSE(contains(text, "--convention")) << text.substr(0, 600);
}

TEST(PbrtV4Export, DielectricsAreWrittenWithAConstantEtaAndAlphaUnremapped) {
  {
    const Scene smooth = builtin("glass_sphere");
    ASSERT_FALSE(pbrt_v4_refusal(smooth)) << refusal_of(smooth);
    const std::string text = export_pbrt_v4(smooth, {});
    EXPECT_TRUE(contains(text, "Material \"dielectric\" \"float eta\" 1.5 \"float roughness\" 0\n")) << text;
    EXPECT_TRUE(contains(text, "#   'glass_ball' (eta 1.5, smooth).\n")) << text;
    // pbrt-v4 renders the radiance convention, and the check line says so.
    EXPECT_TRUE(contains(text, "--max-depth unlimited --convention radiance --image")) << text.substr(0, 600);
    EXPECT_TRUE(contains(text, "maxdepth M allows M - 2 internal reflections in a closed object")) << text;
  }
  {
    const Scene rough = height_correlated("glass_rough_disk_inside");
    ASSERT_FALSE(pbrt_v4_refusal(rough)) << refusal_of(rough);
    const std::string text = export_pbrt_v4(rough, {});
    EXPECT_TRUE(contains(text, "Material \"dielectric\" \"float eta\" 1.5 \"float roughness\" 0.3 "
                               "\"bool remaproughness\" false\n"))
        << text;
    EXPECT_TRUE(contains(text, "#   'glass_a1' (eta 1.5, alpha 1, shadowing height_correlated).\n")) << text;
  }
  {
    // Eta below 1 (the denser medium in front of the normal) is written as it is.
    Scene inverted = builtin("glass_smooth_outside_60");
    std::get<Dielectric>(inverted.objects[0].material.bsdf).eta = 1 / 1.5;
    EXPECT_TRUE(contains(export_pbrt_v4(inverted, {}), fmt::format("\"float eta\" {} ", 1 / 1.5)));
  }
}

TEST(PbrtV4Export, DielectricRefusalsNameTheObjectFieldAndValue) {
  {
    Scene tinted = builtin("glass_sphere");
    tinted.objects[0].material.albedo = 0.9;
    const std::string reason = refusal_of(tinted);
    EXPECT_TRUE(contains(reason, "'glass_ball' (objects[0].material.type \"dielectric\", albedo 0.9, eta 1.5") &&
                contains(reason, "has albedo 0.9, and pbrt-v4's dielectric has no constant factor"))
        << reason;
    tinted.objects[0].material.albedo = 0;  // black: a black diffuse surface
    EXPECT_FALSE(pbrt_v4_refusal(tinted)) << refusal_of(tinted);
  }
  {
    Scene nearly_smooth = builtin("glass_rough_normal");
    std::get<Dielectric>(nearly_smooth.objects[0].material.bsdf).alpha = 9.9e-4;
    const std::string reason = refusal_of(nearly_smooth);
    EXPECT_TRUE(contains(reason, "'glass_a0.1'") && contains(reason, "as perfectly smooth")) << reason;
  }
  {
    // At normal view the separable strip is written; at 60 degrees it is refused.
    EXPECT_FALSE(pbrt_v4_refusal(builtin("glass_rough_normal")));
    const std::string reason = refusal_of(builtin("glass_rough_outside_60"));
    EXPECT_TRUE(contains(reason, "'glass_a0.3_sep' (objects[2].material.type \"dielectric\", albedo 1, eta 1.5, "
                                 "alpha 0.3, shadowing \"separable\") uses the separable Smith form") &&
                contains(reason, "not perpendicular to the camera's forward direction"))
        << reason;
    EXPECT_FALSE(pbrt_v4_refusal(height_correlated("glass_rough_outside_60")));
  }
}

TEST(PbrtV4Export, AcceptsAMirrorMetOnlyAtNormalIncidenceAndSaysWhatItMeans) {
  const Scene scene = mirror_scene();
  ASSERT_FALSE(pbrt_v4_refusal(scene)) << refusal_of(scene);
  const std::string text = export_pbrt_v4(scene, {});
  EXPECT_TRUE(contains(text, "Material \"conductor\" \"spectrum reflectance\" [300 0.8 900 0.8] \"float roughness\" 0"))
      << text;
  EXPECT_TRUE(contains(text, "at normal\n#   incidence only")) << text;
}

TEST(PbrtV4Export, RefusesMirrorsMetAtObliqueIncidence) {
  {
    Scene tilted = mirror_scene();
    std::get<Rectangle>(tilted.objects[0].shape).edge_u = {2, 0, 0.2};
    const std::string reason = refusal_of(tilted);
    EXPECT_TRUE(contains(reason, "'floor'") && contains(reason, "not perpendicular")) << reason;
  }
  {
    Scene curved = mirror_scene();
    curved.objects[0].shape = Sphere{{0, 0, -1}, 0.5};
    const std::string reason = refusal_of(curved);
    EXPECT_TRUE(contains(reason, "'floor'") && contains(reason, "sphere")) << reason;
  }
  {
    Scene lit = mirror_scene();
    lit.objects[1].material.albedo = 0.5;  // the lamp reflects light onto the mirror obliquely
    const std::string reason = refusal_of(lit);
    EXPECT_TRUE(contains(reason, "'lamp'") && contains(reason, "oblique")) << reason;
  }
  {
    Scene white = mirror_scene();
    white.objects[0].material.albedo = 1.0;  // pbrt clamps a conductor's reflectance to 0.9999
    const std::string reason = refusal_of(white);
    EXPECT_TRUE(contains(reason, "'floor'") && contains(reason, "0.9999")) << reason;
  }
}

TEST(PbrtV4Export, MaxDepthIsSegmentsMinusOne) {
  EXPECT_EQ(pbrt_max_depth(1), 0);
  EXPECT_EQ(pbrt_max_depth(2), 1);
  EXPECT_EQ(pbrt_max_depth(6), 5);
  EXPECT_EQ(pbrt_max_depth(kUnlimitedDepth), kUnlimitedDepth - 1);
  const Scene scene = builtin("enclosure_box_rho5");
  PbrtV4Options options;
  options.max_segments = 6;
  const std::string text = export_pbrt_v4(scene, options);
  EXPECT_TRUE(contains(text, "Integrator \"path\" \"integer maxdepth\" 5\n")) << text;
  EXPECT_TRUE(contains(text, "--max-depth 6 ")) << text;
  const std::string unlimited = export_pbrt_v4(scene, {});
  EXPECT_TRUE(contains(unlimited, "Integrator \"path\" \"integer maxdepth\" 2147483646\n")) << unlimited;
  EXPECT_TRUE(contains(unlimited, "--max-depth unlimited ")) << unlimited;
  options.max_segments = 0;
  EXPECT_THROW(export_pbrt_v4(scene, options), Error);
}

// (export/scene_facts.h decides when direct lighting is complete; tests/export/scene_facts_test.cpp.)
TEST(PbrtV4Export, NamesTheCheckDepth) {
  PbrtV4Options options;
  EXPECT_EQ(check_max_depth(builtin("environment_blocker"), options), 2);
  EXPECT_EQ(check_max_depth(builtin("mirror_disk"), options), kUnlimitedDepth);
  options.max_segments = 1;  // emission only: not direct lighting
  EXPECT_EQ(check_max_depth(builtin("disk_occluder"), options), 1);
  const std::string text = export_pbrt_v4(builtin("environment_blocker"), {});
  EXPECT_TRUE(contains(text, "--max-depth 2 ")) << text;
  EXPECT_TRUE(contains(text, "which is direct lighting here")) << text;
  EXPECT_TRUE(contains(export_pbrt_v4(builtin("enclosure_box"), {}), "--max-depth unlimited ")) << text;
}

TEST(PbrtV4Export, EmittersAreScaledIlluminantsAndReflectancesConstantSpectra) {
  const std::string text = export_pbrt_v4(builtin("disk_occluder"), {});
  EXPECT_TRUE(contains(text, "AreaLightSource \"diffuse\" \"float scale\" 4\n")) << text;
  EXPECT_TRUE(contains(text, "Material \"diffuse\" \"spectrum reflectance\" [300 0.5 900 0.5]\n")) << text;
  EXPECT_TRUE(contains(text, "Material \"diffuse\" \"spectrum reflectance\" [300 0 900 0]\n")) << text;
  const std::string statements = text.substr(text.find("\nOption "));  // past the opening comments
  EXPECT_FALSE(contains(statements, "\"rgb L\"")) << text;
  EXPECT_FALSE(contains(statements, "\"rgb reflectance\"")) << text;

  const std::string point = export_pbrt_v4(builtin("point_light"), {});
  EXPECT_TRUE(contains(point, "LightSource \"point\" \"float scale\" 10 \"point3 from\" [0 0 2]\n")) << point;
  const std::string environment = export_pbrt_v4(builtin("environment_blocker"), {});
  EXPECT_TRUE(contains(environment, "LightSource \"infinite\" \"float scale\" 1.5\n")) << environment;
  const std::string enclosure = export_pbrt_v4(builtin("enclosure_sphere"), {});
  EXPECT_TRUE(contains(enclosure, "AreaLightSource \"diffuse\" \"float scale\" 1.5 \"bool twosided\" true\n"))
      << enclosure;
}

TEST(PbrtV4Export, FilmSamplerAndPixelCentres) {
  const std::string text = export_pbrt_v4(builtin("disk_occluder"), {});
  EXPECT_TRUE(contains(text, "Option \"disablepixeljitter\" true\n")) << text;
  EXPECT_TRUE(contains(text, "\"integer xresolution\" 32 \"integer yresolution\" 32 \"bool savefp16\" false")) << text;
  EXPECT_TRUE(contains(text, "\"string sensor\" \"cie1931\" \"float iso\" 100")) << text;
  EXPECT_TRUE(contains(text, "Sampler \"independent\" \"integer pixelsamples\" 256\n")) << text;
  EXPECT_FALSE(contains(text, "integer seed")) << "no seed unless asked for: pbrt --seed must choose";
  PbrtV4Options options;
  options.spp = 64;
  options.seed = 7;
  const std::string seeded = export_pbrt_v4(builtin("disk_occluder"), options);
  EXPECT_TRUE(contains(seeded, "Sampler \"independent\" \"integer pixelsamples\" 64 \"integer seed\" 7\n")) << seeded;
}

TEST(PbrtV4Export, CameraRightIsForwardCrossUp) {
  const std::string text = export_pbrt_v4(builtin("enclosure_sphere"), {});
  // furnace: center [0.1, -0.05, 0.3], forward ∝ [0.2, 0.1, -1], up [0, 1, 0], size 1.2 x 1.2.
  const size_t scale = text.find("\nScale -1 1 1\n");
  const size_t look_at = text.find("\nLookAt ");
  ASSERT_NE(scale, std::string::npos) << text;
  ASSERT_NE(look_at, std::string::npos) << text;
  EXPECT_LT(scale, look_at) << "the mirror Scale must precede LookAt to flip the camera's x axis";
  std::istringstream line(text.substr(look_at + 8));
  Vec3 eye, look, up;
  line >> eye.x >> eye.y >> eye.z >> look.x >> look.y >> look.z >> up.x >> up.y >> up.z;
  const Vec3 forward = normalize(Vec3{0.2, 0.1, -1});
  EXPECT_EQ(eye, (Vec3{0.1, -0.05, 0.3}));
  EXPECT_NEAR(length(look - eye - forward), 0, 1e-15);
  EXPECT_EQ(up, (Vec3{0, 1, 0}));
  EXPECT_TRUE(contains(text, "Camera \"orthographic\" \"float screenwindow\" [-0.6 0.6 -0.6 0.6]")) << text;
}

// The camera pbrt-v4 reads from the file, each pixel's ray as its
// orthographic camera makes it: tests/export/exported_cameras.h.
using exported_camera::PbrtCamera;
using exported_camera::pbrt_pixel_origin;
using exported_camera::read_pbrt_camera;

TEST(PbrtV4Export, NonSquareCameraPutsEveryPixelCentreWhereFurnacesRayStarts) {
  // A wide image (3 x 1 scene units) on 24 x 4 pixels, tilted: the pixels
  // are 0.125 wide and 0.25 tall, so neither the image nor its pixels are square.
  const Scene scene = parse_scene(R"({
    "name": "wide_camera",
    "camera": {"type": "orthographic", "center": [0.2, -0.1, 1], "forward": [0.1, 0.2, -1], "up": [0.3, 1, 0],
               "size": [3, 1], "resolution": [24, 4]},
    "objects": [
      {"name": "floor", "shape": {"type": "rectangle", "corner": [-3, -3, 0], "edge_u": [6, 0, 0], "edge_v": [0, 6, 0]},
       "material": {"type": "lambertian", "albedo": 0.5}, "emission": 1}
    ]})",
                                  "wide_camera.json");
  const std::string text = export_pbrt_v4(scene, {});
  EXPECT_TRUE(contains(text, "\"float screenwindow\" [-1.5 1.5 -0.5 0.5]")) << text;
  const PbrtCamera c = read_pbrt_camera(text);
  ASSERT_EQ(c.xres, 24);
  ASSERT_EQ(c.yres, 4);
  double worst = 0, worst_swapped = 0;
  PbrtCamera swapped = c;  // the control: the window's x and y extents exchanged
  std::swap(swapped.window[0], swapped.window[2]);
  std::swap(swapped.window[1], swapped.window[3]);
  for (int py = 0; py < c.yres; ++py)
    for (int px = 0; px < c.xres; ++px) {
      const Camera::Ray ray = scene.camera.pixel_center_ray(px, py);
      EXPECT_NEAR(length(normalize(c.look - c.eye) - ray.direction), 0, 1e-15);
      worst = std::max(worst, length(pbrt_pixel_origin(c, px, py) - ray.origin));
      worst_swapped = std::max(worst_swapped, length(pbrt_pixel_origin(swapped, px, py) - ray.origin));
    }
  EXPECT_LT(worst, 1e-14) << "a pixel centre is off furnace's by " << worst;
  EXPECT_GT(worst_swapped, 0.1) << "the control (width and height exchanged) must be detected";
}

// The Transform of the first disk in `text`, as pbrt reads it: four columns.
std::vector<Vec3> disk_columns(const std::string& text) {
  const std::regex transform(R"(Transform \[([^\]]*)\]\nShape "disk")");
  std::smatch m;
  if (!std::regex_search(text, m, transform)) return {};
  std::istringstream numbers(m[1].str());
  std::vector<Vec3> columns(4);
  for (int i = 0; i < 4; ++i) {
    double w = -1;
    numbers >> columns[i].x >> columns[i].y >> columns[i].z >> w;
    if (!numbers || w != (i == 3 ? 1 : 0)) return {};
  }
  return columns;
}

TEST(PbrtV4Export, DisksArePlacedByProperRotationsTakingZToTheirNormal) {
  // enclosure_blockers' disk_blocker: normal ∝ (0.3, -0.2, 1), centre (0.4, 0.3, 0.1).
  const Scene scene = builtin("enclosure_blockers");
  const std::string text = export_pbrt_v4(scene, {});
  const std::vector<Vec3> c = disk_columns(text);
  ASSERT_EQ(c.size(), 4u) << text;
  const Vec3 normal = normalize(Vec3{0.3, -0.2, 1});
  EXPECT_NEAR(length(c[2] - normal), 0, 1e-15);
  EXPECT_NEAR(dot(cross(c[0], c[1]), c[2]), 1, 1e-15) << "determinant +1: a rotation, not a reflection";
  EXPECT_NEAR(dot(c[0], c[1]), 0, 1e-15);
  EXPECT_NEAR(length(c[0]), 1, 1e-15);
  EXPECT_EQ(c[3], (Vec3{0.4, 0.3, 0.1}));
  // disk_occluder's light faces -z.
  const std::vector<Vec3> light = disk_columns(export_pbrt_v4(builtin("disk_occluder"), {}));
  ASSERT_EQ(light.size(), 4u);
  EXPECT_EQ(light[2], (Vec3{0, 0, -1}));
  EXPECT_NEAR(dot(cross(light[0], light[1]), light[2]), 1, 1e-15);
}

TEST(PbrtV4Export, RectanglesKeepTheirFrontNormal) {
  // enclosure_box's ceiling: corner (-1,-1,1), edge_u (0,2,0), edge_v (2,0,0),
  // front normal cross(edge_u, edge_v) = -z; its triangles must keep it.
  const std::string text = export_pbrt_v4(builtin("enclosure_box"), {});
  const size_t ceiling = text.find("# ceiling\n");
  ASSERT_NE(ceiling, std::string::npos);
  const std::regex mesh(R"("point3 P" \[([^\]]*)\] "integer indices" \[0 1 2  0 2 3\])");
  std::smatch m;
  const std::string rest = text.substr(ceiling);
  ASSERT_TRUE(std::regex_search(rest, m, mesh)) << rest;
  std::istringstream numbers(m[1].str());
  Vec3 p[4];
  for (Vec3& v : p) numbers >> v.x >> v.y >> v.z;
  EXPECT_EQ(normalize(cross(p[1] - p[0], p[2] - p[0])), (Vec3{0, 0, -1}));
  EXPECT_EQ(normalize(cross(p[2] - p[0], p[3] - p[0])), (Vec3{0, 0, -1}));
}

TEST(PbrtV4Export, FileOpensWithTheFactsItReliesOn) {
  const std::string text = export_pbrt_v4(builtin("disk_occluder"), {});
  EXPECT_EQ(text.rfind("# Scene 'disk_occluder'", 0), 0u) << text;
  for (const char* fact : {"disablepixeljitter", "savefp16", "illuminant", "maxdepth M traces M + 1 path segments",
                           "Russian roulette", "Scale -1 1 1 before LookAt", "--seed"})
    EXPECT_TRUE(contains(text.substr(0, text.find("\nOption ")), fact)) << fact;
}

class PbrtV4ExportFile : public testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("furnace_export_test_" + std::to_string(::getpid()) + "_" +
            testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::vector<std::string> entries() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir_)) names.push_back(e.path().filename().string());
    return names;
  }
  fs::path dir_;
};

TEST_F(PbrtV4ExportFile, WritesTheWholeTextAndNoTemporaryFile) {
  const Scene scene = builtin("disk_occluder");
  const fs::path out = dir_ / "scene.pbrt";
  write_pbrt_v4(scene, {}, out);
  std::ifstream in(out);
  const std::string written((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(written, export_pbrt_v4(scene, {}));
  EXPECT_EQ(entries(), std::vector<std::string>{"scene.pbrt"});
}

TEST_F(PbrtV4ExportFile, RefusalLeavesAnExistingFileUntouched) {
  const fs::path out = dir_ / "scene.pbrt";
  std::ofstream(out) << "previous contents";
  EXPECT_THROW(write_pbrt_v4(builtin("environment_map"), {}, out), Error);
  std::ifstream in(out);
  const std::string kept((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(kept, "previous contents");
  EXPECT_EQ(entries(), std::vector<std::string>{"scene.pbrt"});
}

TEST_F(PbrtV4ExportFile, UnwritableDestinationThrowsNamingItAndLeavesNothing) {
  const fs::path out = dir_ / "missing_directory" / "scene.pbrt";
  try {
    write_pbrt_v4(builtin("disk_occluder"), {}, out);
    ADD_FAILURE() << "wrote into a missing directory";
  } catch (const Error& e) {
    EXPECT_TRUE(contains(e.what(), out.string())) << e.what();
  }
  EXPECT_TRUE(entries().empty());
}

using CliResult = testing_support::CommandResult;

CliResult run_cli(const std::string& args) {
  return testing_support::run_command(std::string(FURNACE_CLI) + " " + args + " 2>&1");
}

TEST_F(PbrtV4ExportFile, CliExportsAndRefusesWithExitTwo) {
  const std::string scenes = FURNACE_SCENE_DIR;
  const fs::path out = dir_ / "out.pbrt";
  const CliResult ok = run_cli("export --scene " + scenes + "/mirror_disk.json --format pbrt-v4 --spp 16 --seed 3 "
                               "--max-depth 9 -o " + out.string());
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
  std::ifstream in(out);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_TRUE(contains(text, "\"integer pixelsamples\" 16 \"integer seed\" 3\n")) << text;
  EXPECT_TRUE(contains(text, "\"integer maxdepth\" 8\n")) << text;
  EXPECT_TRUE(contains(text, "\"string filename\" \"out.exr\"")) << text;

  const CliResult unlimited =
      run_cli("export --scene " + scenes + "/enclosure_box.json --format pbrt-v4 --max-depth unlimited -o " +
              out.string());
  EXPECT_EQ(unlimited.exit_code, 0) << unlimited.output;

  const fs::path refused_out = dir_ / "refused.pbrt";
  const CliResult refused =
      run_cli("export --scene " + scenes + "/environment_map.json --format pbrt-v4 -o " + refused_out.string());
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_TRUE(contains(refused.output, "environment_map") && contains(refused.output, "octahedral")) << refused.output;
  EXPECT_FALSE(fs::exists(refused_out));

  const CliResult bad_format =
      run_cli("export --scene " + scenes + "/disk_occluder.json --format mitsuba -o " + refused_out.string());
  EXPECT_NE(bad_format.exit_code, 0) << bad_format.output;
  EXPECT_TRUE(contains(bad_format.output, "mitsuba")) << bad_format.output;
  EXPECT_FALSE(fs::exists(refused_out));
}

}  // namespace
}  // namespace furnace::exporter
