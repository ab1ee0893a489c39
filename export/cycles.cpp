// Blender Cycles export. The facts it relies on, each measured with Blender
// 3.4.1 from Debian 12 (K = 16 renders of 128 spp checked by `furnace check`
// unless stated; tests/export/cycles_peer_test.cpp repeats the scene
// and control measurements):
//
// | fact | how it was measured |
// |---|---|
// | ORTHO camera, ortho_scale = the image plane's width with sensor_fit HORIZONTAL (its height with VERTICAL when taller in pixel-aspect units), pixel aspect = furnace's pixel width : height | every exportable scene passes, among them grazing_emitters (pixel aspect 1 : 12.5, VERTICAL) and enclosure_sphere (tilted camera) |
// | a Blackman-Harris filter of width 0.01 px keeps samples within 0.01 px of the pixel centre; a Box filter covers the whole pixel whatever its width | a half-plane emitter at distance d from a pixel centre, 4096 spp: lit fraction 36 % at d = 0.001 px, 1.3 % at 0.006, 0.07 % at 0.008, 0 from 0.01 to 10 px; Box of width 0.01: 0.5 − d (49 % at 0.01, 20 % at 0.3, 0 from 0.5); Blender's default 1.5 px filter fails mirror_disk (worst pixel abs t 166) |
// | view transform Standard, look None, exposure 0, gamma 1, 32-bit float EXR (ZIP): R = G = B = linear radiance | the scenes pass; the +1 % emission control fails (image-mean t 67) |
// | the Emission shader of strength Le, colour 1, is radiance Le; the Background shader of strength L is radiance L | same |
// | max_bounces B traces B + 2 path segments; roulette stays unbiased | enclosure_box_rho5 at B = 2 passes the 4-segment reference (t −0.78) and fails the 3- and 5-segment ones (t 1032, −517); the enclosures pass at B = 1024 |
// | emission is two-sided in 3.4; mixing the Emission shader with nothing by Geometry Backfacing makes it one-sided | back_facing_emitters passes; exported two-sided it is 87 % too bright (t 5748) |
// | Diffuse BSDF colour ρ, roughness 0, is Lambertian ρ; Glossy BSDF SHARP colour ρ is an ideal mirror of reflectance ρ | the scenes pass; mirror_disk passes (detectable bias 0.006 %) |
// | mesh triangles face cross(v1 − v0, v2 − v0), as furnace's | back_facing_emitters and the one-sided lights pass |
// | Sobol-Burley (SOBOL) with distinct seeds gives independent renders; the same seed gives the same pixels in one Blender process or several, on 1 or 2 threads | renders compared pixel by pixel (max difference 0 for the same seed, 2e-3 between seeds) |
// | the default clamp is 10 for indirect light, adaptive sampling and denoising are on, the light threshold is 0.01: all switched off | Blender's factory settings (bl_rna defaults) |
// | Cycles 3.4 has no emission-side setting, no light tree, path guiding off by default | Blender's Python API (bpy.types.CyclesRenderSettings) |
// | Glossy BSDF distribution GGX is Trowbridge-Reitz with α = roughness² and the separable Smith G2, no Fresnel, Color multiplying f | ggx_sky_strips and ggx_disk_occluder (albedo 0.8, normal view) and the oblique sphere-light scenes made all-separable pass (K = 16, 128 spp); the oblique sky scenes fail by −7e-5 at 2048 spp, a bias of Cycles 3.4's sampler (docs/findings.md); roughness = α instead of √α fails (+7.5 %) |
// | Cycles 3.4 has no height-correlated Smith form: a height-correlated surface is exported only where the forms agree (seen only along its normal) | the height-correlated strips of the oblique scenes are refused; the separable oblique scenes rendered and checked as height-correlated fail |
// | world.cycles.sampling_method NONE leaves the environment's light to BSDF sampling alone, with the same expected radiance | the oblique sky scenes rendered that way (docs/findings.md) |
// | Multiscatter GGX (MULTI_GGX) is the Heitz et al. 2016 random walk, not furnace's single-scattering GGX; only its energy conservation has an exact answer here | the energy-conserving variant under a constant sky, checked against L_env·ρ (docs/findings.md) |
// | the Glass BSDF SHARP of IOR η, Color ρ, is a delta reflection of weight ρ·F and a delta refraction of weight ρ·max(1e-4, 1 − F), F the exact Fresnel at the shading normal, 1/IOR on back faces, no 1/η² (furnace's `none` convention); Blender 3.x creates it Beckmann, IOR 1.45 | kernel/svm/closure.h and closure/bsdf_refraction.h as shipped with Blender 3.4.1 (scripts/addons/cycles/source); glass_smooth_outside_60, _inside_60, _inside_30 pass in `none` (image-mean t −0.93, −0.61, 0.68); outside_60 checked in `radiance` fails (t 13121); IOR 1.45 checked as 1.5 fails |
// | every scattering event counts against max_bounces B, reflections against glossy, refractions against transmission; the event reaching a limit still traces its ray to the world but ends at the next surface (kernel/integrator/path_state.h, with the host adding 1 to each limit): the smooth glass sphere keeps K = min(B − 1, glossy) internal reflections, furnace's (B + 2)-segment reference 1 − T·R^(K+1) | glass_sphere at B = 2 passes --max-depth 4 (t 1.09) and fails 3 (t 310) and 5 (t −33.5); B = 1024 with glossy 1 gives the same pixels; transmission 1 suffices at unlimited depth, 0 fails |
// | a mesh shaded smooth with custom normals gets at each point the normalised barycentric blend of its vertex normals: a sphere's radial normals at the vertices give the sphere's normal through every mesh point | glass_sphere at --max-depth 4 passes so; flat facets fail its silhouette pixels (0.51 against 0.86) |
// | Cycles 3.4 has no exact complex-index conductor Fresnel (fresnel_conductor, an approximation, is used by no 3.4 shader node) and its rough Glass BSDF is not Walter et al.'s (Fresnel at the shading normal as closure weights, separable Smith G2, approximate visible-normal sampling): both refused | kernel sources as above; the rough-glass difference is measured in docs/findings.md |
// | the default pattern, progressive multi-jitter, also gives seed-dependent renders (disk_occluder passes with it: t 1.10, detectable 0.12 %); Sobol-Burley is kept for its documented Owen scrambling | rendered |
#include "export/cycles.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>
#include <variant>

#include <fmt/format.h>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/overloaded.h"
#include "export/cycles_scene.h"
#include "export/scene_facts.h"
#include "export/text.h"

namespace furnace::exporter {

namespace {

std::string tuple(const Vec3& p) { return fmt::format("({}, {}, {})", num(p.x), num(p.y), num(p.z)); }
// A Python string literal holding `text` (repr-style escapes).
std::string python_string(const std::string& text) {
  std::string out = "'";
  for (unsigned char c : text) {
    if (c == '\\' || c == '\'') out += '\\', out += char(c);
    else if (c < 0x20 || c == 0x7f) out += fmt::format("\\x{:02x}", c);
    else out += char(c);
  }
  return out + "'";
}

// Blender's property limits (bl_rna hard_min / hard_max, Blender 3.4.1).
constexpr int kCyclesMaxSpp = 16777216;
constexpr int64_t kCyclesMaxSeed = 2147483647;
constexpr double kBlenderMaxPixelAspect = 200;
constexpr double kBlenderMinClipStart = 1e-6;
// The camera sits clip_start behind furnace's image plane along forward, so
// its rays start on the plane: the smallest clip_start Blender takes, scaled
// with the camera's coordinates so that float keeps it (2^-20 relative).
double clip_start(const Camera& c) {
  const double scale = std::max({std::fabs(c.center.x), std::fabs(c.center.y), std::fabs(c.center.z), c.width,
                                 c.height, 1.0});
  return std::max(kBlenderMinClipStart, 0x1p-20 * scale);
}
// Far enough for any scene within scene_limits (coordinates up to 1e6).
constexpr double kClipEnd = 1e10;
// Bounds of the tessellation options: 20·4^7 = 327 680 triangles per sphere,
// 2·256² = 131 072 per emitting rectangle keep the script below ~20 MB.
constexpr int kMaxSphereSubdivisions = 7;
constexpr int kMaxEmitterGrid = 256;
// Blackman-Harris at Blender's smallest width: samples within 0.01 px of the
// pixel centre (Cycles widens a Box filter to 1 px whatever its width).
constexpr const char* kFilterType = "BLACKMAN_HARRIS";
constexpr double kFilterWidth = 0.01;

double triangle_area(const Vec3& a, const Vec3& b, const Vec3& c) { return 0.5 * length(cross(b - a, c - a)); }

void finish_area(CyclesMesh& mesh) {
  mesh.mesh_area = 0;
  for (const auto& t : mesh.triangles)
    mesh.mesh_area += triangle_area(mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]);
}

// Triangles of the parallelogram corner + s·u + t·v, cut into grid² cells.
CyclesMesh parallelogram(const Vec3& corner, const Vec3& u, const Vec3& v, int grid) {
  CyclesMesh mesh;
  for (int j = 0; j <= grid; ++j)
    for (int i = 0; i <= grid; ++i) mesh.vertices.push_back(corner + u * (double(i) / grid) + v * (double(j) / grid));
  auto index = [grid](int i, int j) { return j * (grid + 1) + i; };
  for (int j = 0; j < grid; ++j)
    for (int i = 0; i < grid; ++i) {
      // cross(u, v) orientation: (i,j) → (i+1,j) → (i+1,j+1) and (i,j) → (i+1,j+1) → (i,j+1).
      mesh.triangles.push_back({index(i, j), index(i + 1, j), index(i + 1, j + 1)});
      mesh.triangles.push_back({index(i, j), index(i + 1, j + 1), index(i, j + 1)});
    }
  return mesh;
}

// The triangle p0 p1 p2 cut into grid² congruent triangles (each edge in grid parts).
CyclesMesh triangle_grid(const Triangle& tri, int grid) {
  CyclesMesh mesh;
  const Vec3 e1 = tri.p1 - tri.p0, e2 = tri.p2 - tri.p0;
  std::map<std::pair<int, int>, int> index;
  for (int j = 0; j <= grid; ++j)
    for (int i = 0; i + j <= grid; ++i) {
      index[{i, j}] = int(mesh.vertices.size());
      mesh.vertices.push_back(tri.p0 + e1 * (double(i) / grid) + e2 * (double(j) / grid));
    }
  for (int j = 0; j < grid; ++j)
    for (int i = 0; i + j < grid; ++i) {
      mesh.triangles.push_back({index[{i, j}], index[{i + 1, j}], index[{i, j + 1}]});
      if (i + j + 1 < grid) mesh.triangles.push_back({index[{i + 1, j}], index[{i + 1, j + 1}], index[{i, j + 1}]});
    }
  return mesh;
}

// A regular N-gon of the disk's area, fanned from the centre: circumradius
// R' = R·sqrt(2π / (N·sin(2π/N))). Its vertices lie R' − R outside the
// circle and its edge midpoints R − R'·cos(π/N) inside.
CyclesMesh disk_mesh(const Disk& d) {
  constexpr int n = kCyclesDiskVertices;
  CyclesMesh mesh;
  const double step = 2 * kPi / n;
  const double circumradius = d.radius * std::sqrt(2 * kPi / (n * std::sin(step)));
  const Frame f = Frame::from_normal(normalize(d.normal));
  FURNACE_CHECK(dot(cross(f.s, f.t), f.n) > 0);  // right-handed: the fan faces the disk's normal
  mesh.vertices.push_back(d.center);
  for (int k = 0; k < n; ++k)
    mesh.vertices.push_back(d.center + f.s * (circumradius * std::cos(k * step)) +
                            f.t * (circumradius * std::sin(k * step)));
  for (int k = 0; k < n; ++k) mesh.triangles.push_back({0, 1 + k, 1 + (k + 1) % n});
  mesh.construction = fmt::format("regular {}-gon of the disk's area, R' = R*sqrt(2*pi/(N*sin(2*pi/N))), "
                                  "{} triangles fanned from the centre",
                                  n, n);
  mesh.exact_area = d.area();
  mesh.max_distance_outside = circumradius - d.radius;
  mesh.max_distance_inside = d.radius - circumradius * std::cos(step / 2);
  return mesh;
}

// An icosahedron subdivided `levels` times (each triangle into four), its
// vertices on a sphere of radius R' chosen so that the polyhedron's area is
// the sphere's 4πR². Vertices lie R' − R outside the sphere; the face point
// nearest the centre, the foot of the perpendicular (inside every face of
// this acute mesh, checked), lies R − min_face_distance inside.
CyclesMesh sphere_mesh(const Sphere& sp, int subdivisions) {
  const double g = (1 + std::sqrt(5.0)) / 2;
  std::vector<Vec3> unit = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
                            {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  for (Vec3& v : unit) v = normalize(v);
  std::vector<std::array<int, 3>> faces = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                           {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                           {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                           {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int level = 0; level < subdivisions; ++level) {
    std::map<std::pair<int, int>, int> midpoint;
    auto middle = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      const auto found = midpoint.find(key);
      if (found != midpoint.end()) return found->second;
      unit.push_back(normalize(unit[a] + unit[b]));
      return midpoint[key] = int(unit.size()) - 1;
    };
    std::vector<std::array<int, 3>> finer;
    for (const auto& f : faces) {
      const int ab = middle(f[0], f[1]), bc = middle(f[1], f[2]), ca = middle(f[2], f[0]);
      finer.push_back({f[0], ab, ca});
      finer.push_back({f[1], bc, ab});
      finer.push_back({f[2], ca, bc});
      finer.push_back({ab, bc, ca});
    }
    faces = std::move(finer);
  }
  double unit_area = 0;
  for (const auto& f : faces) unit_area += triangle_area(unit[f[0]], unit[f[1]], unit[f[2]]);
  const double circumradius = sp.radius * std::sqrt(4 * kPi / unit_area);
  CyclesMesh mesh;
  double min_face_distance = circumradius;
  for (const Vec3& v : unit) mesh.vertices.push_back(sp.center + v * circumradius);
  for (auto f : faces) {
    const Vec3 a = unit[f[0]], b = unit[f[1]], c = unit[f[2]];
    Vec3 n = cross(b - a, c - a);
    if (dot(n, a + b + c) < 0) std::swap(f[1], f[2]), n = -n;  // face outward
    n = normalize(n);
    // The foot of the perpendicular from the centre, in barycentric terms, must be inside the face.
    const Vec3 foot = n * dot(n, a);
    const double total = length(cross(b - a, c - a));
    const double wa = dot(cross(b - foot, c - foot), n) / total, wb = dot(cross(c - foot, a - foot), n) / total;
    FURNACE_CHECK(wa > 0 && wb > 0 && wa + wb < 1);
    min_face_distance = std::min(min_face_distance, circumradius * dot(n, a));
    mesh.triangles.push_back(f);
  }
  mesh.construction = fmt::format("icosahedron subdivided {} times ({} triangles, {} vertices), vertices at the "
                                  "radius R' that gives it the sphere's area",
                                  subdivisions, faces.size(), unit.size());
  mesh.exact_area = sp.area();
  mesh.max_distance_outside = circumradius - sp.radius;
  mesh.max_distance_inside = sp.radius - min_face_distance;
  return mesh;
}

// How the exported script renders one object's material, or the reason it
// cannot (without the scene's name). The Cycles export's only branch on the
// material type: one case per alternative of BsdfParameters, no catch-all
// (core/overloaded.h). The script's builder
// (cycles_scene.py) decides nothing: it makes a Glossy SHARP BSDF where
// `mirror` is true and a Diffuse BSDF otherwise.
struct CyclesMaterial {
  bool mirror = false;                  // Glossy BSDF, distribution SHARP: an ideal mirror of reflectance ρ
  std::optional<std::string> refusal;   // set when refused
  // Glossy BSDF of distribution `ggx_distribution` ("GGX" or "MULTI_GGX"),
  // roughness √α, colour ρ; empty for the other BSDFs.
  std::optional<std::string> ggx_distribution;
  double ggx_roughness = 0;
  // Glass BSDF of distribution SHARP, IOR = the dielectric's η, colour ρ;
  // empty for the other BSDFs.
  std::optional<double> glass_ior;
};
CyclesMaterial diffuse_bsdf() { return {false, std::nullopt, std::nullopt, 0, std::nullopt}; }  // Diffuse BSDF of colour ρ, roughness 0
CyclesMaterial glossy_sharp() { return {true, std::nullopt, std::nullopt, 0, std::nullopt}; }
CyclesMaterial refused(std::string reason) { return {false, std::move(reason), std::nullopt, 0, std::nullopt}; }
CyclesMaterial glass_sharp(double ior) { return {false, std::nullopt, std::nullopt, 0, ior}; }

// A GGX surface as Cycles 3.4's Glossy BSDF: distribution GGX (Trowbridge-Reitz
// with the separable Smith G2, no Fresnel term), roughness r with α = r², so
// r = √α; Color = albedo multiplies f. The energy-conserving variant writes
// Multiscatter GGX instead (reference only: see CyclesOptions).
CyclesMaterial ggx_glossy(const Scene& scene, size_t index, const Ggx& ggx, const CyclesOptions& options) {
  const std::string what = object_material_text(scene, index);
  if (options.energy_conserving_ggx) {
    if (auto reason = energy_conserving_ggx_refusal(scene))
      return refused(fmt::format("the energy-conserving GGX variant is only checked where an energy-conserving "
                                 "BSDF's answer is L_env * albedo, and {}",
                                 *reason));
    return {false, std::nullopt, std::string("MULTI_GGX"), std::sqrt(ggx.alpha), std::nullopt};
  }
  switch (ggx.shadowing) {
    case MicrofacetShadowing::kSeparable:
      break;
    case MicrofacetShadowing::kHeightCorrelated:
      // The forms agree where every path leaves the surface along its normal.
      if (auto reason = not_seen_only_along_normal(scene, index))
        return refused(fmt::format("the GGX object {} uses the height-correlated Smith form, which Cycles 3.4 does "
                                   "not implement (its G2 is separable), and the forms differ here: {}",
                                   what, *reason));
      break;
  }
  return {false, std::nullopt, std::string("GGX"), std::sqrt(ggx.alpha), std::nullopt};
}

// Why a glass sphere, which Cycles renders as the flat facets of its mesh,
// cannot be exported in `scene`; empty where the facets cannot change the
// answer at unlimited depth: clear (albedo 1) smooth glass alone in a
// constant environment, no light, where every path returns L_env whatever
// the closed surface's shape. (With a depth limit the facets do change the
// truncated paths' weights: the peer test traces the exported mesh and
// states that change beside the check's detectable bias.)
std::optional<std::string> faceted_glass_reason(const Scene& scene, size_t index) {
  const std::string what = object_material_text(scene, index);
  const std::string facets = fmt::format(
      "the glass object {} is a sphere, which Cycles renders as a polyhedron whose flat facets refract along other "
      "directions than the sphere; it is exported only where that cannot change the answer (clear smooth glass "
      "alone in a constant environment, no light: every path returns L_env), and ",
      what);
  if (scene.environment.map || !(scene.environment.radiance > 0))
    return facets + "the scene has no constant environment";
  if (!scene.point_lights.empty()) return facets + fmt::format("the scene has the point light '{}'", scene.point_lights[0].name);
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    const Object& o = scene.objects[i];
    if (o.is_emitter()) return facets + fmt::format("the object '{}' emits", o.name);
    const Dielectric* d = o.material.as<Dielectric>();
    if (!d || !d->smooth() || o.material.albedo != 1)
      return facets + fmt::format("the object {} is not clear smooth glass", object_material_text(scene, i));
  }
  return std::nullopt;
}

// A smooth dielectric as Cycles 3.4's Glass BSDF: distribution SHARP (the
// Blender 3.x node's default is Beckmann), IOR = η (inside over outside:
// Cycles uses 1/IOR on back faces, furnace's outside), Color = albedo. The
// node's closures are a reflection of weight Color·F and a refraction of
// weight Color·max(1e-4, 1 − F), F the exact dielectric Fresnel at the
// shading normal (kernel/svm/closure.h), so smooth glass is furnace's
// dielectric in the none convention. Rough glass is not: refused.
CyclesMaterial glass_bsdf(const Scene& scene, size_t index, const Dielectric& d) {
  const std::string what = object_material_text(scene, index);
  if (!d.smooth())
    return refused(fmt::format(
        "the object {} is a rough dielectric, which Cycles 3.4's Glass BSDF does not render as Walter et al. "
        "2007's model that furnace checks: it weights a GGX reflection closure by the Fresnel reflectance at the "
        "shading normal and a GGX refraction closure by one minus it (not per microfacet), with the separable "
        "Smith G2 and an approximate visible-normal sampler (docs/findings.md measures the difference)",
        what));
  if (is_planar(scene.objects[index].shape)) return glass_sharp(d.eta);
  if (auto reason = faceted_glass_reason(scene, index)) return refused(*reason);
  return glass_sharp(d.eta);
}

CyclesMaterial cycles_material(const Scene& scene, size_t index, const CyclesOptions& options) {
  const Object& o = scene.objects[index];
  // Black, whatever the type (reflects() decides it per type): the builder's
  // black Diffuse BSDF reflects nothing either.
  if (!reflects(o.material)) return diffuse_bsdf();
  return std::visit(
      overloaded{[&](const Lambertian&) { return diffuse_bsdf(); },
                 [&](const Mirror&) {
                   if (!is_planar(o.shape))
                     return refused(fmt::format("the mirror {} is a sphere, which Cycles would render as a faceted "
                                                "polyhedron whose flat facets reflect along other directions than "
                                                "the sphere",
                                                object_material_text(scene, index)));
                   return glossy_sharp();
                 },
                 [&](const Phong&) {
                   return refused(fmt::format("the object {} has a normalised Phong BSDF, which Cycles does not have",
                                              object_material_text(scene, index)));
                 },
                 [&](const Ggx& ggx) {
                   if (ggx.fresnel)
                     return refused(fmt::format(
                         "the object {} is a GGX conductor with the exact Fresnel reflectance of a complex index, "
                         "which Cycles 3.4 cannot express: its Glossy BSDF has no Fresnel term, a Color or "
                         "Fresnel-node factor is evaluated at the shading normal instead of each microfacet's, and "
                         "its kernel's only conductor Fresnel (fresnel_conductor, used by no 3.4 shader node) is an "
                         "approximation",
                         object_material_text(scene, index)));
                   return ggx_glossy(scene, index, ggx, options);
                 },
                 [&](const Dielectric& d) { return glass_bsdf(scene, index, d); }},
      o.material.bsdf);
}

// The reason Cycles (as exported here) cannot express `scene`, without the scene's name.
std::optional<std::string> refusal_reason(const Scene& scene, const CyclesOptions& options) {
  if (scene.environment.map)
    return fmt::format("its environment map '{}' would need Cycles' equirectangular lookup (orientation, texel "
                       "centres, interpolation) matched to furnace's nearest-texel z-up map, which this export has "
                       "not measured",
                       scene.environment.map_file);
  if (!scene.point_lights.empty())
    return fmt::format("its point light '{}' would need Blender's watts-to-intensity convention for point lamps, "
                       "which this export has not measured",
                       scene.point_lights.front().name);
  for (size_t i = 0; i < scene.objects.size(); ++i)
    if (auto refusal = cycles_material(scene, i, options).refusal) return refusal;
  return std::nullopt;
}

std::string error_lines(const Object& o, const CyclesMesh& mesh) {
  if (mesh.exact)
    return fmt::format("#   {}: {}; exact (the triangles are the shape).\n", comment_text(o.name), mesh.construction);
  const double size = std::visit(
      overloaded{[](const Disk& d) { return d.radius; }, [](const Sphere& s) { return s.radius; },
                 [](const Rectangle&) { return 1.0; }, [](const Triangle&) { return 1.0; }},
      o.shape);
  return fmt::format(
      "#   {}:\n"
      "#     {}.\n"
      "#     area: exact {:.17g}, triangles summed in double {:.17g}\n"
      "#     (relative difference {:.3g}: equal by construction, the difference is round-off);\n"
      "#     farthest mesh point outside the exact surface {:.3g} ({:.3g} R),\n"
      "#     farthest exact-surface point not covered {:.3g} ({:.3g} R).\n",
      comment_text(o.name), mesh.construction, mesh.exact_area, mesh.mesh_area,
      (mesh.mesh_area - mesh.exact_area) / mesh.exact_area, mesh.max_distance_outside,
      mesh.max_distance_outside / size, mesh.max_distance_inside, mesh.max_distance_inside / size);
}

std::string header(const Scene& scene, const CyclesOptions& options, const std::vector<CyclesMesh>& meshes) {
  const int check_depth = check_max_depth(scene, options.max_segments);
  const std::string depth_words = options.max_segments == kUnlimitedDepth
                                      ? fmt::format("unlimited depth (max_bounces {}: a path of more segments carries\n# "
                                                    "a fraction rho^{} of the light, nothing at these albedos)",
                                                    kCyclesMaxBounces, kCyclesMaxBounces + 2)
                                      : fmt::format("{} path segments", options.max_segments);
  std::string text = fmt::format(
      "# Scene '{}' ({}) exported by `furnace export --format cycles` for Blender 3.4 Cycles\n"
      "# (facts measured with Blender 3.4.1 from Debian 12). Render K >= 2 times with distinct seeds in one\n"
      "# Blender process, then test the images against the exact reference:\n"
      "#   blender -b --factory-startup --python-exit-code 1 --python this.py -- --seeds 1-16 --output render_{{seed}}.exr\n"
      "#   furnace check --scene {} --max-depth {} --image render_1.exr --image render_2.exr ...\n"
      "# (one image: -- --seed S --output image.exr; also --spp N, --threads T). Exit 0 when every image is\n"
      "# written, 2 on bad arguments, 1 when Blender fails. Cycles' answer is furnace's global illumination at\n"
      "# {}{}.\n"
      "# Facts this script relies on (Blender 3.4.1), each with how it was measured:\n"
      "# - Camera ORTHO, ortho_scale = the image plane's width with sensor_fit HORIZONTAL (its height with\n"
      "#   VERTICAL when taller), resolution percentage 100, pixel aspect = furnace's pixel width : height.\n"
      "#   The camera sits clip_start behind furnace's image plane, so its rays start on that plane.\n"
      "#   Measured: every exportable built-in scene passes, grazing_emitters (pixel aspect 1 : 12.5) included.\n"
      "# - Pixel centres: Cycles' Box filter is always 1 px wide whatever its width, so samples spread over the\n"
      "#   pixel; a Blackman-Harris filter of width 0.01 px keeps every sample within 0.01 px of the centre.\n"
      "#   Measured: an emitter edge d px from a pixel centre got 0.5 - d of 4096 Box samples, and of the\n"
      "#   Blackman-Harris ones 0.07 % at d = 0.008 and none from 0.01 to 10 px; the default 1.5 px filter fails.\n"
      "# - Film: view transform Standard, look None, exposure 0, gamma 1, Cycles film exposure 1: the 32-bit\n"
      "#   float EXR is linear radiance (R = G = B; furnace check reads their mean). Measured: the scenes pass\n"
      "#   and a light 1 % too bright fails (image-mean t 67).\n"
      "# - CPU, fixed seed (scene.cycles.seed, not animated), adaptive sampling off, denoising off, no clamping\n"
      "#   (the default indirect clamp is 10), light threshold 0, filter glossy 0, caustics allowed (suppressing\n"
      "#   them would drop light furnace's reference counts), path guiding off. Read from Blender's defaults.\n"
      "# - Sampling pattern Sobol-Burley (identifier SOBOL), Owen-scrambled by the seed: distinct seeds give\n"
      "#   independent renders, the same seed the same pixels (compared: alone or in a batch, on 1 or 2\n"
      "#   threads). Cycles 3.4's default, progressive multi-jitter, also gave seed-dependent renders that\n"
      "#   pass disk_occluder; Sobol-Burley is kept for its documented scrambling. QMC makes some pixels take\n"
      "#   few distinct values over the renders; furnace check reports such pixels as untested.\n"
      "# - max_bounces B traces B + 2 path segments (the camera's included), diffuse and glossy bounces the\n"
      "#   same: here {}{}.\n"
      "#   Russian roulette stays unbiased. Measured: enclosure_box_rho5 at B = 2\n"
      "#   passes the 4-segment reference and fails the 3- and 5-segment ones; the enclosures pass at 1024.\n"
      "# - Emission: the Emission shader of strength Le (colour 1) gives radiance Le. It emits on both sides in\n"
      "#   Blender 3.4; a one-sided emitter mixes it with nothing by the Geometry node's Backfacing output.\n"
      "#   Measured: back_facing_emitters passes; exported two-sided it is 87 % too bright.\n"
      "# - Diffuse BSDF of colour rho, roughness 0, is Lambertian rho; Glossy BSDF SHARP of colour rho is an\n"
      "#   ideal mirror of reflectance rho at every angle; the Background shader of strength L is radiance L.\n"
      "#   Measured: the scenes pass, mirror_disk and environment_blocker among them.\n"
      "# - Triangles face cross(v1 - v0, v2 - v0), furnace's front; flat shading (the geometric normal).\n"
      "# - Debian's Blender links the same libembree3 and libOpenEXR as furnace (ldd): a bug in those libraries\n"
      "#   would affect both.\n"
      "# - Cycles 3.4 defects furnace found (docs/checking_cycles.md): a large triangle light renders too dark\n"
      "#   (hence the emitter grid), a sphere light of many triangles too dark, blockers within about 1e-4 of\n"
      "#   the scene's size from a surface let light through, and rare camera samples cross curved silhouettes.\n"
      "# Tessellation (Cycles renders triangles; each shape's error below is computed from its construction):\n",
      comment_text(scene.name), comment_text(scene.source), comment_text(scene.source), depth_name(check_depth),
      depth_words, direct_lighting_clause(scene, options.max_segments),
      cycles_max_bounces(options.max_segments),
      options.max_segments == kUnlimitedDepth ? std::string(" for unlimited depth (Blender's largest)") : std::string());
  for (size_t i = 0; i < scene.objects.size(); ++i) text += error_lines(scene.objects[i], meshes[i]);
  return text;
}

// The header's lines about GGX surfaces and the diagnostic options.
std::string ggx_lines(const Scene& scene, const CyclesOptions& options) {
  std::string text;
  bool any = false;
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    const Object& o = scene.objects[i];
    const Ggx* g = o.material.as<Ggx>();
    if (!g || !reflects(o.material)) continue;
    any = true;
    text += fmt::format("# - The GGX object '{}' (alpha {}, shadowing {}, albedo {}): Glossy BSDF {}, roughness\n"
                        "#   sqrt(alpha) = {}, Color {}.\n",
                        comment_text(o.name), g->alpha, microfacet_shadowing_name(g->shadowing), o.material.albedo,
                        options.energy_conserving_ggx ? "MULTI_GGX" : "GGX", num(std::sqrt(g->alpha)),
                        num(o.material.albedo));
    if (!options.energy_conserving_ggx && g->shadowing == MicrofacetShadowing::kHeightCorrelated)
      text += "#   The scene asks for the height-correlated form; light leaves this surface towards the eye only\n"
              "#   along its normal, where it equals Cycles 3.4's separable form (Lambda(n) = 0).\n";
  }
  if (!any) return text;
  std::string facts =
      "# GGX (Blender 3.4.1): distribution GGX is Trowbridge-Reitz with alpha = roughness^2 (clamped to <= 1), no\n"
      "#   Fresnel term, Color multiplying f, and the separable Smith G2 = G1(wo) G1(wi). Measured: the\n"
      "#   separable GGX peer scenes pass, but under a sky at oblique view Cycles 3.4 renders about 7e-5\n"
      "#   too dark (its approximate visible-normal sampler; docs/findings.md); roughness = alpha instead of\n"
      "#   sqrt(alpha) fails (tests/export/cycles_peer_test.cpp). Reflective caustics stay on and Filter Glossy is 0: off,\n"
      "#   caustics would drop diffuse-to-glossy paths and Filter Glossy would blur glossy bounces after\n"
      "#   the first (Blender's manual; the GGX scenes' glossy bounce is the camera's first, so they do not\n"
      "#   exercise either setting).\n";
  if (options.energy_conserving_ggx)
    facts +=
        "# ENERGY-CONSERVING GGX VARIANT (reference only): every GGX surface is Cycles' Multiscatter GGX, which\n"
        "#   furnace does not model. Here each surface sees a constant sky alone, where an energy-conserving BSDF\n"
        "#   of albedo rho reflects L = L_env * rho: check the renders against the same scene with each GGX\n"
        "#   surface replaced by a Lambertian one of the same albedo, whose exact answer that is.\n";
  if (!options.world_light_sampling)
    facts += "# DIAGNOSTIC: the world is not sampled as a light (sampling_method NONE): the BSDF sampler alone\n"
             "#   carries the environment's light, so a biased BSDF sampler shows in the image.\n";
  return facts + text;
}

// The header's lines about glass (smooth dielectrics): what the Glass BSDF
// is, how the depth limit truncates glass paths, the convention to check in.
std::string glass_lines(const Scene& scene) {
  std::string text;
  bool sphere = false;
  for (const Object& o : scene.objects) {
    const Dielectric* d = o.material.as<Dielectric>();
    if (!d || !reflects(o.material)) continue;
    sphere = sphere || std::holds_alternative<Sphere>(o.shape);
    text += fmt::format("# - The glass object '{}' (eta {}, albedo {}): Glass BSDF SHARP, IOR {}, Color {}.\n",
                        comment_text(o.name), num(d->eta), num(o.material.albedo), num(d->eta),
                        num(o.material.albedo));
  }
  if (text.empty()) return text;
  std::string facts =
      "# Glass (Blender 3.4.1, kernel/svm/closure.h): the Glass BSDF of IOR eta (1/eta on back faces) is a\n"
      "#   reflection closure of weight Color*F and a refraction closure of weight Color*max(1e-4, 1 - F), F the\n"
      "#   exact dielectric Fresnel reflectance at the shading normal; SHARP makes both ideal (delta) lobes,\n"
      "#   furnace's smooth dielectric. Distribution and IOR are set explicitly (Blender 3.x creates the node as\n"
      "#   Beckmann, IOR 1.45). Cycles never divides radiance by eta^2: check with --convention none.\n"
      "#   Measured: glass_smooth_outside_60, _inside_60 (total internal reflection), _inside_30 pass in the\n"
      "#   none convention; outside_60 checked in the radiance convention and IOR 1.45 checked as 1.5 fail.\n"
      "# - Depth: Cycles counts every scattering event (delta ones too) against max_bounces and each\n"
      "#   reflection against glossy_bounces, each refraction against transmission_bounces; the ray leaving\n"
      "#   the event that reaches a limit still sees the world but ends at the next surface. With all limits\n"
      "#   B = segments - 2, a camera path has at most B + 1 events, furnace's B + 2 segments; a glass sphere's\n"
      "#   pixel keeps paths of K <= min(B - 1, glossy) internal reflections, 1 - T*R^(B) = furnace's\n"
      "#   (B + 2)-segment reference. Measured: glass_sphere at B = 2 passes --max-depth 4 and fails 3 and 5;\n"
      "#   B = 1024 with glossy 1 renders the same pixels (K = 1). Filter Glossy 0, both caustics on and no\n"
      "#   clamping keep every glass path.\n";
  if (sphere)
    facts +=
        "# - A glass sphere is the mesh below shaded smooth, each vertex's normal the sphere's own (custom split\n"
        "#   normals): Cycles' normalised barycentric interpolation then gives at each mesh point the sphere's\n"
        "#   normal through that point, so only the hit points (within the distances above) differ from the\n"
        "#   sphere. Clear glass alone in a constant world returns L_env at unlimited depth whatever its shape.\n"
        "#   Measured: glass_sphere at --max-depth 4 passes; flat facets fail it (silhouette pixels 0.51\n"
        "#   against 0.86).\n";
  return facts + text;
}

}  // namespace

int cycles_max_bounces(int max_segments) {
  FURNACE_CHECK(max_segments >= 2);
  return max_segments == kUnlimitedDepth ? kCyclesMaxBounces : max_segments - 2;
}

CyclesMesh cycles_mesh(const Object& object, const CyclesOptions& options) {
  const int grid = object.is_emitter() ? options.emitter_grid : 1;
  return std::visit(
      overloaded{[&](const Rectangle& r) {
                   CyclesMesh mesh = parallelogram(r.corner, r.edge_u, r.edge_v, grid);
                   mesh.construction = grid == 1 ? std::string("two triangles")
                                                 : fmt::format("{0}x{0} grid of cells, two triangles each "
                                                               "({1} triangles)",
                                                               grid, 2 * grid * grid);
                   mesh.exact = true;
                   mesh.exact_area = r.area();
                   finish_area(mesh);
                   return mesh;
                 },
                 [&](const Triangle& t) {
                   CyclesMesh mesh = triangle_grid(t, grid);
                   mesh.construction = grid == 1 ? std::string("one triangle")
                                                 : fmt::format("{} congruent triangles ({} along each edge)",
                                                               grid * grid, grid);
                   mesh.exact = true;
                   mesh.exact_area = t.area();
                   finish_area(mesh);
                   return mesh;
                 },
                 [](const Disk& d) {
                   CyclesMesh mesh = disk_mesh(d);
                   finish_area(mesh);
                   return mesh;
                 },
                 [&](const Sphere& s) {
                   CyclesMesh mesh = sphere_mesh(s, options.sphere_subdivisions);
                   finish_area(mesh);
                   return mesh;
                 }},
      object.shape);
}

std::optional<std::string> energy_conserving_ggx_refusal(const Scene& scene) {
  if (scene.environment.map || !(scene.environment.radiance > 0))
    return std::string("the scene has no constant environment");
  if (!scene.point_lights.empty()) return fmt::format("the scene has the point light '{}'", scene.point_lights[0].name);
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    const Object& o = scene.objects[i];
    if (o.is_emitter()) return fmt::format("the object '{}' emits", o.name);
    if (!o.material.as<Ggx>() || !reflects(o.material))
      return fmt::format("the object {} is not a reflecting GGX surface", object_material_text(scene, i));
    if (auto reason = not_seen_only_along_normal(scene, i))
      return fmt::format("not every GGX surface sees the sky alone at normal view: {}", *reason);
  }
  return std::nullopt;
}

std::optional<std::string> cycles_refusal(const Scene& scene, const CyclesOptions& options) {
  const std::optional<std::string> reason = refusal_reason(scene, options);
  if (!reason) return std::nullopt;
  return fmt::format("scene '{}' ({}) cannot be exported to Cycles: {}.", scene.name, scene.source, *reason);
}

std::string export_cycles(const Scene& scene, const CyclesOptions& options) {
  if (const auto refusal = cycles_refusal(scene, options)) throw Error(*refusal);
  if (options.spp < 1 || options.spp > kCyclesMaxSpp)
    throw Error(fmt::format("option --spp must be in [1, {}] for Cycles, got {}.", kCyclesMaxSpp, options.spp));
  if (options.max_segments < 2 ||
      (options.max_segments != kUnlimitedDepth && options.max_segments - 2 > kCyclesMaxBounces))
    throw Error(fmt::format("option --max-depth must be 2 to {} path segments or unlimited for Cycles (its "
                            "max_bounces B traces B + 2 segments), got {}.",
                            kCyclesMaxBounces + 2, depth_name(options.max_segments)));
  const Camera& c = scene.camera;
  // Blender's pixel aspect: both factors >= 1, their ratio furnace's pixel width : height.
  const double pixel_ratio = (c.width / c.width_px) / (c.height / c.height_px);
  if (!(pixel_ratio >= 1.0 / kBlenderMaxPixelAspect && pixel_ratio <= kBlenderMaxPixelAspect))
    throw Error(fmt::format("scene '{}' ({}) cannot be exported to Cycles: its pixels' width : height {} is "
                            "beyond Blender's pixel aspect range 1/{} to {}.",
                            scene.name, scene.source, pixel_ratio, kBlenderMaxPixelAspect, kBlenderMaxPixelAspect));
  if (options.sphere_subdivisions < 0 || options.sphere_subdivisions > kMaxSphereSubdivisions)
    throw Error(fmt::format("the sphere subdivision level must be in [0, {}], got {}.", kMaxSphereSubdivisions,
                            options.sphere_subdivisions));
  if (options.emitter_grid < 1 || options.emitter_grid > kMaxEmitterGrid)
    throw Error(fmt::format("the emitter grid must be in [1, {}], got {}.", kMaxEmitterGrid, options.emitter_grid));
  std::vector<CyclesMesh> meshes;
  for (const Object& o : scene.objects) meshes.push_back(cycles_mesh(o, options));

  std::string text = header(scene, options, meshes) + ggx_lines(scene, options) + glass_lines(scene);
  text += "\nSCENE = {\n";
  text += fmt::format("    'name': {},\n    'spp': {},\n", python_string(scene.name), options.spp);
  text += fmt::format("    'resolution': ({}, {}),\n", c.width_px, c.height_px);
  text += fmt::format("    'pixel_aspect': ({}, {}),\n", num(std::max(pixel_ratio, 1.0)),
                      num(std::max(1 / pixel_ratio, 1.0)));
  // Camera axes: x = right = forward × up, y = the true up, z = −forward.
  const Vec3 forward = normalize(c.forward);
  const Vec3 right = normalize(cross(forward, c.up));
  const Vec3 up = cross(right, forward);
  const double width_px_aspect = c.width_px * std::max(pixel_ratio, 1.0);
  const double height_px_aspect = c.height_px * std::max(1 / pixel_ratio, 1.0);
  const bool horizontal = width_px_aspect >= height_px_aspect;
  // The camera sits clip_start behind the image plane: its rays start on it.
  const Vec3 eye = c.center - forward * clip_start(c);
  text += "    'camera': {\n";
  text += fmt::format("        'matrix': (({}, {}, {}, {}),\n", num(right.x), num(up.x), num(-forward.x), num(eye.x));
  text += fmt::format("                   ({}, {}, {}, {}),\n", num(right.y), num(up.y), num(-forward.y), num(eye.y));
  text += fmt::format("                   ({}, {}, {}, {}),\n", num(right.z), num(up.z), num(-forward.z), num(eye.z));
  text += "                   (0, 0, 0, 1)),\n";
  text += fmt::format("        'ortho_scale': {},\n        'sensor_fit': '{}',\n", num(horizontal ? c.width : c.height),
                      horizontal ? "HORIZONTAL" : "VERTICAL");
  text += fmt::format("        'clip_start': {},\n        'clip_end': {},\n    }},\n", num(clip_start(c)),
                      num(kClipEnd));
  text += fmt::format("    'environment': {},\n", num(scene.environment.radiance));
  text += fmt::format("    'world_light_sampling': {},\n", options.world_light_sampling ? "True" : "False");
  text += fmt::format("    'max_bounces': {},\n", cycles_max_bounces(options.max_segments));
  text += "    'objects': [\n";
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    const Object& o = scene.objects[i];
    const CyclesMesh& mesh = meshes[i];
    const CyclesMaterial material = cycles_material(scene, i, options);
    text += fmt::format("        {{'name': {}, 'albedo': {}, 'mirror': {}, 'ggx': {}, 'glass': {}, 'emission': {}, "
                        "'two_sided': {},\n",
                        python_string(o.name), num(o.material.albedo), material.mirror ? "True" : "False",
                        material.ggx_distribution
                            ? fmt::format("('{}', {})", *material.ggx_distribution, num(material.ggx_roughness))
                            : std::string("None"),
                        material.glass_ior ? fmt::format("('SHARP', {}, 0.0)", num(*material.glass_ior))
                                           : std::string("None"),
                        num(o.emitted_radiance), o.two_sided ? "True" : "False");
    // A glass sphere's mesh is shaded smooth with the sphere's own normals at its vertices.
    const Sphere* sphere = std::get_if<Sphere>(&o.shape);
    text += fmt::format("         'smooth_about': {},\n",
                        material.glass_ior && sphere ? tuple(sphere->center) : std::string("None"));
    text += "         'vertices': [";
    for (size_t k = 0; k < mesh.vertices.size(); ++k) text += (k ? ", " : "") + tuple(mesh.vertices[k]);
    text += "],\n         'triangles': [";
    for (size_t k = 0; k < mesh.triangles.size(); ++k)
      text += fmt::format("{}({}, {}, {})", k ? ", " : "", mesh.triangles[k][0], mesh.triangles[k][1],
                          mesh.triangles[k][2]);
    text += "]},\n";
  }
  text += "    ],\n}\n";
  text += fmt::format("FILTER = ('{}', {})\n", kFilterType, num(kFilterWidth));
  text += fmt::format("SEED_MAX = {}\nSPP_MAX = {}\n", kCyclesMaxSeed, kCyclesMaxSpp);
  return text + kCyclesScenePython;
}

void write_cycles(const Scene& scene, const CyclesOptions& options, const std::filesystem::path& path) {
  write_text_file_atomically(path, export_cycles(scene, options), "Cycles scene script");
}

}  // namespace furnace::exporter
