// Export of a furnace scene to Blender Cycles: a Blender Python script that
// builds the scene in an empty Blender file and renders it with Cycles, so
// that `furnace check` can test Blender's images against the exact reference.
//
// Run the written script as
//   blender -b --factory-startup --python-exit-code 1 --python scene.py -- --seed S --output image.exr
// or, to pay Blender's start-up (2.2 s of wall time, 1.3 CPU-s, measured on a
// loaded 2-core machine) once for several renders,
//   ... -- --seeds 1-16 --output render_{seed}.exr
// (`--spp N` overrides the samples per pixel, `--threads T` fixes Cycles'
// thread count). The script exits 0 after writing every image, 2 on bad
// arguments (nothing rendered), 1 when Blender or Cycles fails.
//
// What the export means: Cycles' max_bounces B traces B + 2 path segments
// (the camera's included), so a furnace depth of D segments is B = D − 2;
// unlimited depth is B = 1024, Blender's largest, beyond which Russian
// roulette has ended every path that matters. check_max_depth() of
// export/scene_facts.h names the `furnace check --max-depth` whose reference
// Cycles renders (direct lighting where light bounces at most once).
//
// Cycles renders triangle meshes: disks and spheres are tessellated (equal
// area), and emitting rectangles and triangles are cut into a grid of
// smaller triangles. Each exported shape's tessellation error, computed
// exactly from the construction, is written into the script's header. The
// facts about Cycles the export relies on, and how each was measured, open
// cycles.cpp and every exported script. The Blender program the script
// ends with is export/cycles_scene.py, embedded at build time.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/scene.h"
#include "core/strategy.h"
#include "export/scene_facts.h"

namespace furnace::exporter {

// Vertices of a disk's equal-area regular polygon.
inline constexpr int kCyclesDiskVertices = 4096;
// Subdivision level of a sphere's icosphere: 20·4^level triangles (level 4:
// 5120, which passes; level 6, 81 920 triangles, renders a sphere light too
// dark: see docs/checking_cycles.md).
inline constexpr int kCyclesSphereSubdivisions = 4;
// An emitting rectangle is cut into grid² cells of two triangles, an
// emitting triangle into grid² triangles (16 passes; 1, the exact two
// triangles of a rectangle light, renders too dark).
inline constexpr int kCyclesEmitterGrid = 16;

struct CyclesOptions {
  int spp = 128;                      // scene.cycles.samples; the script's --spp overrides it
  int max_segments = kUnlimitedDepth;  // furnace's depth convention, >= 2
  int sphere_subdivisions = kCyclesSphereSubdivisions;  // in [0, 7]
  int emitter_grid = kCyclesEmitterGrid;                // in [1, 256]
  // Diagnostics and reference-only variants, off in a plain export:
  //  - world_light_sampling false: the world is not sampled as a light
  //    (world.cycles.sampling_method NONE), so the BSDF sampler alone carries
  //    the environment's light; the rendered radiance is the same.
  //  - energy_conserving_ggx: every GGX surface as Cycles' Multiscatter GGX
  //    (Heitz et al. 2016's random walk), which is not the BSDF furnace
  //    models: furnace has no reference for it, except where each surface
  //    sees a constant sky alone (energy_conserving_ggx_refusal()), where an
  //    energy-conserving BSDF of albedo ρ reflects L = L_env·ρ, the radiance
  //    of the same scene with each GGX surface Lambertian of albedo ρ.
  bool world_light_sampling = true;
  bool energy_conserving_ggx = false;
};
// Blender's largest max_bounces; the export's "unlimited".
inline constexpr int kCyclesMaxBounces = 1024;

// Cycles' max_bounces for a path of `max_segments` (>= 2) segments.
int cycles_max_bounces(int max_segments);

// A shape as Cycles renders it: triangles (vertex indices) facing
// cross(v1 − v0, v2 − v0), with what the tessellation changed.
struct CyclesMesh {
  std::vector<Vec3> vertices;
  std::vector<std::array<int, 3>> triangles;
  std::string construction;     // e.g. "regular 4096-gon of equal area, fanned from its centre"
  double exact_area = 0;        // the furnace shape's area
  double mesh_area = 0;         // sum of the triangles' areas (double arithmetic)
  double max_distance_outside = 0;  // largest distance of a mesh point outside the exact shape
  double max_distance_inside = 0;   // largest distance of an exact-surface point the mesh leaves uncovered
                                    // (disk: in its plane; sphere: radially)
  bool exact = false;           // the triangles are the shape itself (rectangles, triangles)
};

// The triangles Cycles renders for `object` (emitters get the grid).
CyclesMesh cycles_mesh(const Object& object, const CyclesOptions& options = {});

// Empty when the export can express the scene; otherwise the reason, one
// sentence naming the scene, the object and its field (e.g.
// objects[0].material.type "phong") or the feature. Every material type is
// decided explicitly: written, or refused with its reason.
std::optional<std::string> cycles_refusal(const Scene& scene, const CyclesOptions& options = {});

// Why `scene` is no scene whose energy-conserving-GGX render has a known
// answer, L = L_env·ρ at every pixel; empty when it is: a constant
// environment, no other light, and only reflecting GGX surfaces, each seen
// only along its normal and seeing nothing but the sky (export/scene_facts.h,
// not_seen_only_along_normal()).
std::optional<std::string> energy_conserving_ggx_refusal(const Scene& scene);

// The scene as a Blender Python script, opening with comments that state the
// facts it relies on and each shape's tessellation error. Throws
// furnace::Error (the refusal sentence) when the scene cannot be exported,
// or naming the option when an option is out of range.
std::string export_cycles(const Scene& scene, const CyclesOptions& options);

// export_cycles() written atomically to `path` (nothing is written on error).
void write_cycles(const Scene& scene, const CyclesOptions& options, const std::filesystem::path& path);

}  // namespace furnace::exporter
