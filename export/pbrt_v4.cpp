// pbrt-v4 export. The facts it relies on, each measured with pbrt-v4 5f7a6068
// (the peer binary of tests/export/pbrt_peer_test.cpp; K = 16 renders
// of 256 spp checked by `furnace check`) or read where stated:
//
// | fact | how it was measured |
// |---|---|
// | `Option "disablepixeljitter" true` puts every camera ray through its pixel's centre, furnace's one ray per pixel | point_light (a hard shadow) passes with it; without it 39 of 1024 pixels fail |
// | a box filter of radius 0 makes every pixel NaN (reported, written as 0); radius 0.5 is harmless once jitter is off | rendered |
// | Film "rgb", "savefp16" false, sensor "cie1931", iso 100, shutter [0, 1]: a float EXR whose pixel value is radiance | every exportable built-in scene passes |
// | a light with no spectrum emits the colour space's illuminant (D65 for sRGB) divided by its luminance, so "float scale" X gives R = G = B = X, for area, point and infinite lights alike | the scenes pass, the +1 % radiance control fails; source (lights.cpp) |
// | reflectance as the constant spectrum [300 ρ 900 ρ] reflects ρ at every wavelength | the scenes pass, the albedo 0.49-for-0.5 control fails |
// | for gray values "rgb L" [c c c] and "rgb reflectance" [ρ ρ ρ] render pixel-identical images to the two forms above; the spectrum forms are kept because their meaning does not rest on the RGB-to-spectrum tables | disk_occluder rendered both ways |
// | integrator "path" with maxdepth M traces M + 1 path segments (the camera's included); its Russian roulette divides by the survival probability | enclosure_box_rho5 at maxdepth 2 passes the 3-segment reference and fails the 2- and 4-segment ones; enclosure_box_rho99 (mean path length 100) passes at unlimited depth |
// | disks face +z and emit on their front only; a disk's hit normal flips under a handedness-swapping transform but its sampled normal does not, so disks are placed by proper rotations only | source (shapes.h); disk lights facing -z pass |
// | triangles face cross(p1 − p0, p2 − p0), spheres outward, as in furnace | one-sided rectangle lights and enclosure walls pass |
// | `Scale -1 1 1` before `LookAt` makes image right = cross(forward, up) (LookAt alone gives cross(up, forward)); an orthographic camera's rays start on the plane through the eye, as furnace's do | asymmetric scenes pass, the mirrored-image control fails |
// | no per-object camera visibility: the camera sees every shape, as furnace's camera does | same camera placement as furnace |
// | a conductor with "reflectance" r and roughness 0 is a smooth mirror whose Fresnel reflectance is r at normal incidence only (eta 1, k = 2√r/√(1−r), r clamped to 0.9999) | source (materials.h); mirror_disk passes |
// | environment maps only as equal-area octahedral square images | documentation |
// | a conductor with "spectrum eta" [300 0 900 0] and "spectrum k" [300 1 900 1] reflects F ≡ 1 at every angle and wavelength (η + ik = i: \|r∥\| = \|r⊥\| = 1 in its complex Fresnel); "rgb reflectance" [1 1 1] leaves 1 − F between 1e-4 and 5e-3 | the GGX peer scenes (albedo 1) pass; the albedo-0.99 control fails; source (FrComplex, util/scattering.h) |
// | "float roughness" is α itself with "bool remaproughness" false; true (the default) takes α = √roughness | the GGX peer scenes pass; the same export with remaproughness true fails |
// | pbrt-v4's GGX is Trowbridge-Reitz D with the height-correlated Smith G2 = 1/(1 + Λ(ωo) + Λ(ωi)) and exact visible-normal sampling (Heitz 2018); no separable form | the height-correlated oblique peer scenes pass at cos θo 0.5 and 0.2; source (TrowbridgeReitzDistribution, util/scattering.h) |
// | α is clamped to ≥ 1e-4 and a distribution with α < 1e-3 (float) is rendered as a perfect mirror | source (EffectivelySmooth); furnace's α ≥ 1e-3 never reaches it, the export refuses it anyway |
// | a GGX surface whose light reaches the eye only along its normal (planar, facing the orthographic camera, every other object black or in its plane) has equal separable and height-correlated G2 (Λ(n) = 0) | ggx_sky_strips and ggx_disk_occluder (both forms) pass exported with pbrt's height-correlated G2 |
// | the independent sampler's numbers depend only on (pixel, seed); a seed in the file overrides `pbrt --seed` | equal seeds give pixel-identical renders, distinct ones differ; source (samplers.cpp) |
// | "dielectric" with "float eta" η is a constant index (no dispersion), η = index behind the normal / index in front (furnace's eta, same fronts); roughness 0 is smooth (exact Fresnel chooses R or T), else Walter 2007 with F at the microfacet, height-correlated G2 and exact visible-normal sampling; transmitted radiance divided by η′² (furnace's radiance convention) | glass_sphere, the smooth interface from both sides and the rough-glass scenes (height-correlated) pass with --convention radiance; the same render checked with --convention none fails; η 1.45 for 1.5 fails; source (DielectricBxDF, bxdfs.cpp) |
// | maxdepth M allows M − 2 internal reflections in a closed smooth object: a --max-depth S export renders furnace's S-segment reference | glass_sphere exported at 4 segments passes the 4-segment check and fails the 3- and 5-segment ones |
// | light sampling and MIS through rough transmission are right in 5f7a6068 (the 2021 fix dfa11074 of f and pdf both missing η′²) | glass_rough_disk_inside (height-correlated: a disk light inside the glass) passes |
// | a conductor with constant spectra "spectrum eta" [300 n 900 n], "spectrum k" [300 k 900 k] reflects pbrt's exact FrComplex(ωo·m, n + ik), furnace's conductor Fresnel | conductor_fresnel_sky_60 and _sphere_60 (height-correlated) pass; the gold strips rendered with F ≡ 1 fail |
#include "export/pbrt_v4.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <variant>

#include <fmt/format.h>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/overloaded.h"
#include "export/scene_facts.h"
#include "export/text.h"

namespace furnace::exporter {

namespace {

// A mirror must face the camera this exactly: at an angle θ off normal
// incidence pbrt's conductor reflects r + O(θ²), and 1 − cos θ ≤ 1e-9 keeps
// θ below 5e-5 rad, an error far below any Monte Carlo test's resolution.
constexpr double kMirrorNormalIncidenceTolerance = 1e-9;
// pbrt clamps a conductor's "reflectance" to this value.
constexpr double kPbrtMaxConductorReflectance = 0.9999;
// pbrt-v4 treats a Trowbridge-Reitz distribution with max(αx, αy) < 1e-3
// (in float) as effectively smooth: a perfect specular conductor
// (TrowbridgeReitzDistribution::EffectivelySmooth, util/scattering.h).
constexpr float kPbrtMinRoughAlpha = 1e-3f;

// Whether light crosses a dielectric in `scene`: its check needs the
// transport convention pbrt-v4 renders.
bool has_dielectric(const Scene& scene) {
  return std::any_of(scene.objects.begin(), scene.objects.end(),
                     [](const Object& o) { return reflects(o.material) && o.material.as<Dielectric>(); });
}

std::string point(const Vec3& p) { return fmt::format("{} {} {}", num(p.x), num(p.y), num(p.z)); }
std::string constant_spectrum(double value) { return fmt::format("[300 {0} 900 {0}]", value); }

// Whether `o` reflects as a mirror (pbrt_material() writes it as a conductor
// or refuses it); any other reflector would light a mirror at oblique
// incidence.
bool is_reflecting_mirror(const Object& o) { return reflects(o.material) && o.material.as<Mirror>(); }

// Why the mirror scene.objects[index] is not met only at normal incidence,
// where pbrt's conductor reflects exactly its reflectance; empty when it is.
std::optional<std::string> mirror_refusal(const Scene& scene, size_t index) {
  const Object& mirror = scene.objects[index];
  const std::string what = object_material_text(scene, index);
  if (!is_planar(mirror.shape))
    return fmt::format("the mirror {} is a sphere, which camera rays meet at oblique incidence", what);
  if (mirror.material.albedo > kPbrtMaxConductorReflectance)
    return fmt::format("the mirror {} has a reflectance above the {} to which pbrt clamps a conductor", what,
                       kPbrtMaxConductorReflectance);
  const Vec3 n = shape_normal(mirror.shape, Vec3{});
  const double cos_incidence = std::fabs(dot(n, normalize(scene.camera.forward)));
  if (1 - cos_incidence > kMirrorNormalIncidenceTolerance)
    return fmt::format("the mirror {} is not perpendicular to the camera's forward direction, so camera rays "
                       "meet it at oblique incidence",
                       what);
  for (const Object& o : scene.objects)
    if (reflects(o.material) && !is_reflecting_mirror(o))
      return fmt::format("the object '{}' reflects light onto the mirror '{}' at oblique incidence", o.name,
                         mirror.name);
  return std::nullopt;
}

// How pbrt-v4 renders one object's material: its Material statement, or the
// reason pbrt-v4 cannot (without the scene's name). The pbrt-v4 export's only
// branch on the material type: one case per alternative of BsdfParameters, no
// catch-all (core/overloaded.h).
struct PbrtMaterial {
  std::string statement;                // the Material statement, when accepted
  std::optional<std::string> refusal;   // set when refused
  bool normal_incidence_mirror = false;  // a conductor standing for an ideal mirror (the header says why it is exact)
};

PbrtMaterial diffuse(double albedo) {
  return {fmt::format("Material \"diffuse\" \"spectrum reflectance\" {}\n", constant_spectrum(albedo)), std::nullopt};
}
PbrtMaterial refused(std::string reason) { return {"", std::move(reason)}; }

// Why pbrt-v4, whose microfacet distribution is height-correlated only,
// cannot render the object scene.objects[index] with `shadowing`; empty when
// it can (the separable form is written as height-correlated only where the
// forms agree: every path leaves the surface towards the eye along its
// normal).
std::optional<std::string> shadowing_refusal(const Scene& scene, size_t index, MicrofacetShadowing shadowing) {
  switch (shadowing) {
    case MicrofacetShadowing::kHeightCorrelated:
      return std::nullopt;
    case MicrofacetShadowing::kSeparable:
      if (auto reason = not_seen_only_along_normal(scene, index))
        return fmt::format("the object {} uses the separable Smith form, which pbrt-v4 does not implement (its G2 "
                           "is height-correlated), and the forms differ here: {}",
                           object_material_text(scene, index), *reason);
      return std::nullopt;
  }
  FURNACE_CHECK(false);
  return std::nullopt;
}

// Why pbrt-v4 would not render the microfacet object scene.objects[index]
// of roughness α as rough; empty when it does.
std::optional<std::string> alpha_refusal(const Scene& scene, size_t index, double alpha) {
  if (static_cast<float>(alpha) >= kPbrtMinRoughAlpha) return std::nullopt;
  return fmt::format("the object {} has alpha {}, and pbrt-v4 renders a microfacet surface with alpha below {} as "
                     "perfectly smooth",
                     object_material_text(scene, index), alpha, kPbrtMinRoughAlpha);
}

// A GGX surface as pbrt-v4's rough conductor, α written as itself
// (remaproughness false), with the scene's complex index n + ik as constant
// spectra when it has Fresnel, else η + ik = i (both polarisations reflect
// fully at every angle: F ≡ 1). pbrt-v4 implements the height-correlated
// Smith form only, and its conductor has no constant factor on f.
PbrtMaterial ggx_conductor(const Scene& scene, size_t index, const Ggx& ggx) {
  const Material& m = scene.objects[index].material;
  const std::string what = object_material_text(scene, index);
  if (m.albedo != 1)
    return refused(fmt::format("the GGX object {} has albedo {}, and pbrt-v4's conductor has no constant factor "
                               "on its reflection (the export is exact for albedo 1 only)",
                               what, m.albedo));
  if (auto reason = alpha_refusal(scene, index, ggx.alpha)) return refused(*reason);
  if (auto reason = shadowing_refusal(scene, index, ggx.shadowing)) return refused(*reason);
  const double eta = ggx.fresnel ? ggx.fresnel->eta : 0;
  const double k = ggx.fresnel ? ggx.fresnel->k : 1;
  return {fmt::format("Material \"conductor\" \"spectrum eta\" {} \"spectrum k\" {} \"float roughness\" {} "
                      "\"bool remaproughness\" false\n",
                      constant_spectrum(eta), constant_spectrum(k), num(ggx.alpha)),
          std::nullopt};
}

// A dielectric as pbrt-v4's "dielectric": "float eta" (a constant index, so
// no wavelength is terminated for dispersion) is the index behind the
// surface normal relative to the one in front, furnace's eta with the same
// fronts; a rough one is Walter et al. 2007 with pbrt's height-correlated
// GGX, α as itself. pbrt-v4 transports radiance (1/η′² on transmission).
PbrtMaterial dielectric(const Scene& scene, size_t index, const Dielectric& d) {
  const Material& m = scene.objects[index].material;
  const std::string what = object_material_text(scene, index);
  if (m.albedo != 1)
    return refused(fmt::format("the dielectric {} has albedo {}, and pbrt-v4's dielectric has no constant factor "
                               "on its reflection and transmission (the export is exact for albedo 1 only)",
                               what, m.albedo));
  if (d.smooth())
    return {fmt::format("Material \"dielectric\" \"float eta\" {} \"float roughness\" 0\n", num(d.eta)),
            std::nullopt};
  if (auto reason = alpha_refusal(scene, index, d.alpha)) return refused(*reason);
  if (auto reason = shadowing_refusal(scene, index, d.shadowing)) return refused(*reason);
  return {fmt::format("Material \"dielectric\" \"float eta\" {} \"float roughness\" {} "
                      "\"bool remaproughness\" false\n",
                      num(d.eta), num(d.alpha)),
          std::nullopt};
}

PbrtMaterial pbrt_material(const Scene& scene, size_t index) {
  const Material& m = scene.objects[index].material;
  // Black, whatever the type (reflects() decides it per type): a black
  // diffuse surface reflects nothing either.
  if (!reflects(m)) return diffuse(0);
  return std::visit(
      overloaded{[&](const Lambertian&) { return diffuse(m.albedo); },
                 [&](const Mirror&) {
                   // pbrt's only smooth mirror is a conductor whose Fresnel
                   // reflectance equals ρ at normal incidence only; export it
                   // only where every path meets it there.
                   if (auto reason = mirror_refusal(scene, index))
                     return refused("pbrt-v4 has no ideal mirror (its smooth conductor of reflectance r reflects r "
                                    "at normal incidence only) and " + *reason);
                   return PbrtMaterial{fmt::format("Material \"conductor\" \"spectrum reflectance\" {} "
                                                   "\"float roughness\" 0\n",
                                                   constant_spectrum(m.albedo)),
                                       std::nullopt, true};
                 },
                 [&](const Phong&) {
                   return refused(fmt::format("the object {} has a normalised Phong BSDF, which pbrt-v4 does not "
                                              "have",
                                              object_material_text(scene, index)));
                 },
                 [&](const Ggx& ggx) { return ggx_conductor(scene, index, ggx); },
                 [&](const Dielectric& d) { return dielectric(scene, index, d); }},
      m.bsdf);
}

// The reason pbrt-v4 cannot express `scene`, without the scene's name.
std::optional<std::string> refusal_reason(const Scene& scene) {
  if (scene.environment.map)
    return fmt::format("its environment map '{}' is a latitude-longitude image, and pbrt-v4 takes image "
                       "environments only as equal-area octahedral square images (resampling would change the "
                       "radiance the exact reference integrates)",
                       scene.environment.map_file);
  for (size_t i = 0; i < scene.objects.size(); ++i)
    if (auto refusal = pbrt_material(scene, i).refusal) return refusal;
  return std::nullopt;
}

std::string triangle_mesh(std::initializer_list<Vec3> vertices, const std::string& indices) {
  std::string p;
  for (const Vec3& v : vertices) p += (p.empty() ? "" : "  ") + point(v);
  return fmt::format("Shape \"trianglemesh\" \"point3 P\" [{}] \"integer indices\" [{}]\n", p, indices);
}

// The shape in world space. Triangle meshes need no transform (they face
// cross(p1 − p0, p2 − p0), as furnace's do); a disk is placed by a proper
// rotation taking +z to its normal; a sphere by a translation.
std::string shape(const Shape& s) {
  struct Visitor {
    std::string operator()(const Rectangle& r) const {
      return triangle_mesh({r.corner, r.corner + r.edge_u, r.corner + r.edge_u + r.edge_v, r.corner + r.edge_v},
                           "0 1 2  0 2 3");
    }
    std::string operator()(const Triangle& t) const { return triangle_mesh({t.p0, t.p1, t.p2}, "0 1 2"); }
    std::string operator()(const Sphere& sp) const {
      return fmt::format("Translate {}\nShape \"sphere\" \"float radius\" {}\n", point(sp.center), sp.radius);
    }
    std::string operator()(const Disk& d) const {
      const Frame f = Frame::from_normal(normalize(d.normal));
      FURNACE_CHECK(dot(cross(f.s, f.t), f.n) > 0);  // right-handed: a rotation, not a reflection
      // pbrt reads the 16 numbers column by column: the columns are the images
      // of the object's x, y, z axes and its origin.
      return fmt::format("Transform [{} 0  {} 0  {} 0  {} 1]\nShape \"disk\" \"float radius\" {}\n", point(f.s),
                         point(f.t), point(f.n), point(d.center), d.radius);
    }
  };
  return std::visit(Visitor{}, s);
}

std::string object(const Scene& scene, size_t index) {
  const Object& o = scene.objects[index];
  std::string text = fmt::format("# {}\nAttributeBegin\n", comment_text(o.name));
  text += pbrt_material(scene, index).statement;
  if (o.is_emitter())
    text += fmt::format("AreaLightSource \"diffuse\" \"float scale\" {}{}\n", num(o.emitted_radiance),
                        o.two_sided ? " \"bool twosided\" true" : "");
  text += shape(o.shape);
  return text + "AttributeEnd\n";
}

std::string header(const Scene& scene, const PbrtV4Options& options) {
  const int max_depth = pbrt_max_depth(options.max_segments);
  const std::string depth_words = options.max_segments == kUnlimitedDepth
                                      ? std::string("unlimited depth")
                                      : fmt::format("{} path segments", options.max_segments);
  std::string text = fmt::format(
      "# Scene '{}' ({}) exported by `furnace export --format pbrt-v4` for pbrt-v4 (facts measured with 5f7a6068).\n"
      "# Render K >= 2 times with distinct seeds, then test the images against the exact reference:\n"
      "#   pbrt --seed S --outfile render_S.exr this.pbrt\n"
      "#   furnace check --scene {} --max-depth {}{} --image render_1.exr --image render_2.exr ...\n"
      "# pbrt's answer is furnace's global illumination at {}{}.\n"
      "# Facts this file relies on:\n"
      "# - Option \"disablepixeljitter\": every camera ray passes through its pixel's centre, as furnace's one ray\n"
      "#   per pixel centre; the box filter keeps radius 0.5 (radius 0 makes every pixel NaN).\n"
      "# - Film \"rgb\" with \"savefp16\" false, sensor \"cie1931\", iso 100, shutter [0, 1]: the float EXR pixel is\n"
      "#   radiance. pbrt renders spectrally, so R, G and B carry different noise; their mean is the gray value.\n"
      "# - No light names a spectrum: each then emits the colour space's illuminant (D65) divided by its luminance,\n"
      "#   so \"float scale\" X gives R = G = B = X (furnace's gray radiance Le, intensity I or environment L).\n"
      "# - Reflectances are constant spectra [300 r 900 r]: r at every wavelength, whatever pbrt's RGB-to-spectrum\n"
      "#   tables (a gray \"rgb\" reflectance or \"rgb L\" renders identically with 5f7a6068).\n"
      "# - Integrator \"path\" maxdepth M traces M + 1 path segments, the camera's included: maxdepth {}\n"
      "#   is {}. Russian roulette ends the paths, unbiased (it divides by the survival probability).\n"
      "# - Disks face +z and are placed by proper rotations; triangles face cross(p1 - p0, p2 - p0); spheres face\n"
      "#   outward; an area light emits on its front only unless \"twosided\". furnace's fronts are the same.\n"
      "# - Scale -1 1 1 before LookAt makes image right = cross(forward, up), furnace's; pixel (0, 0) is top-left.\n"
      "#   The orthographic rays start on the plane through the eye, as furnace's start on its image plane, and\n"
      "#   see every shape, as furnace's camera does.\n"
      "# - {}\n",
      comment_text(scene.name), comment_text(scene.source), comment_text(scene.source),
      depth_name(check_max_depth(scene, options)), has_dielectric(scene) ? " --convention radiance" : "", depth_words, direct_lighting_clause(scene, options.max_segments),
      max_depth, depth_words,
      options.seed ? fmt::format("\"integer seed\" {} is fixed here and overrides `pbrt --seed`.", *options.seed)
                   : std::string("No seed is set here: `pbrt --seed S` chooses the independent sampler's numbers,\n"
                                 "#   which depend only on (pixel, seed)."));
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    if (!pbrt_material(scene, i).normal_incidence_mirror) continue;
    const Object& o = scene.objects[i];
    text += fmt::format(
        "# - The mirror '{}' (reflectance {}) is a smooth conductor whose Fresnel reflectance is {} at normal\n"
        "#   incidence only; every path meets it there (it is perpendicular to the camera and nothing else\n"
        "#   reflects), so this export is exact.\n",
        comment_text(o.name), o.material.albedo, o.material.albedo);
  }
  std::string ggx;
  std::string glass;
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    const Object& o = scene.objects[i];
    if (!reflects(o.material)) continue;
    const auto separable_note = [](MicrofacetShadowing s) {
      return s == MicrofacetShadowing::kSeparable
                 ? "#     The scene asks for the separable form: light leaves this surface towards the eye only along\n"
                   "#     its normal (it faces the orthographic camera; every other object is black or in its plane),\n"
                   "#     where the two forms are equal (Lambda(n) = 0), so pbrt's height-correlated G2 is exact here.\n"
                 : "";
    };
    if (const Ggx* g = o.material.as<Ggx>()) {
      ggx += fmt::format("#   '{}' (alpha {}, shadowing {}): \"float roughness\" {}, {}.\n", comment_text(o.name),
                         g->alpha, microfacet_shadowing_name(g->shadowing), num(g->alpha),
                         g->fresnel ? fmt::format("exact Fresnel of n + ik = {} + {}i", g->fresnel->eta, g->fresnel->k)
                                    : std::string("F = 1 (eta + ik = i)"));
      ggx += separable_note(g->shadowing);
    }
    if (const Dielectric* d = o.material.as<Dielectric>()) {
      glass += fmt::format("#   '{}' (eta {}{}).\n", comment_text(o.name), d->eta,
                           d->smooth() ? std::string(", smooth")
                                       : fmt::format(", alpha {}, shadowing {}", d->alpha,
                                                     microfacet_shadowing_name(d->shadowing)));
      if (!d->smooth()) glass += separable_note(d->shadowing);
    }
  }
  if (!ggx.empty())
    text +=
        "# - GGX objects are rough conductors with constant spectra \"spectrum eta\" [300 n 900 n] and \"spectrum k\"\n"
        "#   [300 k 900 k]: pbrt's exact complex Fresnel (FrComplex at wo.m) of n + ik at every wavelength. A GGX\n"
        "#   object without Fresnel has n + ik = i, which reflects both polarisations fully at every angle, so\n"
        "#   F = 1 exactly (every GGX albedo here is 1; \"rgb reflectance\" [1 1 1] would leave 1 - F up to 5e-3).\n"
        "#   \"bool remaproughness\" false makes \"roughness\" alpha itself\n"
        "#   (left true, pbrt takes alpha = sqrt(roughness)). pbrt's Trowbridge-Reitz D, height-correlated Smith G2\n"
        "#   and exact visible-normal sampler (Heitz 2018) are furnace's. Measured: the GGX and conductor-Fresnel\n"
        "#   peer scenes pass; remaproughness true and albedo 0.99 for 1 fail (tests/export/pbrt_peer_test.cpp).\n" +
        ggx;
  if (!glass.empty())
    text +=
        "# - Dielectrics are pbrt's \"dielectric\" with \"float eta\": a constant index (a spectrum eta would be\n"
        "#   dispersive), the index behind the surface normal relative to the one in front, as furnace's eta\n"
        "#   (triangles face cross(p1 - p0, p2 - p0), spheres outward). Smooth ones have roughness 0; rough ones\n"
        "#   \"float roughness\" alpha with \"bool remaproughness\" false: Walter et al. 2007 with Fresnel at the\n"
        "#   microfacet normal, height-correlated Smith G2 and exact visible-normal sampling, furnace's model.\n"
        "#   pbrt-v4 transports radiance (transmitted radiance divided by eta'^2), furnace's radiance convention:\n"
        "#   check with --convention radiance. maxdepth M allows M - 2 internal reflections in a closed object.\n" +
        glass;
  return text + "\n";
}

}  // namespace

int check_max_depth(const Scene& scene, const PbrtV4Options& options) {
  return check_max_depth(scene, options.max_segments);
}

int pbrt_max_depth(int max_segments) {
  FURNACE_CHECK(max_segments >= 1);
  return max_segments == kUnlimitedDepth ? kUnlimitedDepth - 1 : max_segments - 1;
}

std::optional<std::string> pbrt_v4_refusal(const Scene& scene) {
  const std::optional<std::string> reason = refusal_reason(scene);
  if (!reason) return std::nullopt;
  return fmt::format("scene '{}' ({}) cannot be exported to pbrt-v4: {}.", scene.name, scene.source, *reason);
}

std::string export_pbrt_v4(const Scene& scene, const PbrtV4Options& options) {
  if (const auto refusal = pbrt_v4_refusal(scene)) throw Error(*refusal);
  if (options.spp < 1) throw Error(fmt::format("option --spp must be at least 1, got {}.", options.spp));
  if (options.max_segments < 1)
    throw Error(fmt::format("option --max-depth must be at least 1 path segment, got {}.", options.max_segments));
  if (options.image_filename.find_first_of("\"\n") != std::string::npos)
    throw Error(fmt::format("the image file name '{}' cannot be written in a pbrt string (it holds a quote or a "
                            "newline).",
                            options.image_filename));
  const Camera& c = scene.camera;
  std::string text = header(scene, options);
  text += "Option \"disablepixeljitter\" true\n";
  text += "Option \"rendercoordsys\" \"world\"\n";
  text += "Scale -1 1 1\n";
  text += fmt::format("LookAt {}  {}  {}\n", point(c.center), point(c.center + normalize(c.forward)), point(c.up));
  text += fmt::format(
      "Camera \"orthographic\" \"float screenwindow\" [{} {} {} {}] \"float shutteropen\" 0 \"float shutterclose\" 1\n",
      num(-c.width / 2), num(c.width / 2), num(-c.height / 2), num(c.height / 2));
  text += fmt::format("Sampler \"independent\" \"integer pixelsamples\" {}{}\n", options.spp,
                      options.seed ? fmt::format(" \"integer seed\" {}", *options.seed) : std::string());
  text += fmt::format("Integrator \"path\" \"integer maxdepth\" {}\n", pbrt_max_depth(options.max_segments));
  text += "PixelFilter \"box\" \"float xradius\" 0.5 \"float yradius\" 0.5\n";
  text += fmt::format(
      "Film \"rgb\" \"integer xresolution\" {} \"integer yresolution\" {} \"bool savefp16\" false\n"
      "  \"string sensor\" \"cie1931\" \"float iso\" 100 \"string filename\" \"{}\"\n",
      c.width_px, c.height_px, options.image_filename);
  text += "\nWorldBegin\n";
  if (scene.environment.radiance > 0)
    text += fmt::format("# constant environment\nLightSource \"infinite\" \"float scale\" {}\n",
                        num(scene.environment.radiance));
  for (const PointLight& light : scene.point_lights)
    text += fmt::format("# {}\nLightSource \"point\" \"float scale\" {} \"point3 from\" [{}]\n",
                        comment_text(light.name), num(light.intensity), point(light.position));
  for (size_t i = 0; i < scene.objects.size(); ++i) text += object(scene, i);
  return text;
}

void write_pbrt_v4(const Scene& scene, const PbrtV4Options& options, const std::filesystem::path& path) {
  write_text_file_atomically(path, export_pbrt_v4(scene, options), "pbrt-v4 scene file");
}

}  // namespace furnace::exporter
