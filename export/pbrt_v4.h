// Export of a furnace scene to pbrt-v4's scene format, so that pbrt renders
// the image `furnace check` tests against the scene's exact reference.
//
// What the export means: pbrt's integrator "path" with maxdepth
// max_segments − 1 renders the radiance that furnace's global-illumination
// reference gives at max_segments path segments (the camera's segment
// included): `furnace check --max-depth <max_segments>`. The default,
// unlimited depth, is the complete light transport. Where light reaches the
// eye after at most one bounce (a single planar Lambertian reflector, every
// other object black) that is also the direct-lighting reference,
// `furnace check --max-depth 2`; check_max_depth() names the one to use.
//
// The facts about pbrt-v4 the export relies on, and how each was measured,
// open pbrt_v4.cpp and every exported file.
#pragma once

#include <cstdint>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>

#include "core/scene.h"
#include "core/strategy.h"
#include "export/scene_facts.h"

namespace furnace::exporter {

struct PbrtV4Options {
  int spp = 256;                  // Sampler "pixelsamples"; pbrt --spp overrides it
  std::optional<uint64_t> seed;   // empty: the file sets none and `pbrt --seed S` chooses
  int max_segments = kUnlimitedDepth;  // furnace's depth convention, >= 1
  std::string image_filename = "pbrt.exr";    // Film "filename"; pbrt --outfile overrides it
};

// pbrt's "maxdepth" for a path of `max_segments` segments: pbrt's maxdepth M
// traces M + 1 segments. Unlimited maps to M = INT_MAX − 1, which pbrt never
// reaches: Russian roulette ends its paths.
int pbrt_max_depth(int max_segments);

// The `furnace check --max-depth` value whose reference is what pbrt renders
// from this export: check_max_depth(scene, options.max_segments) of
// export/scene_facts.h (which also holds direct_lighting_is_complete()).
int check_max_depth(const Scene& scene, const PbrtV4Options& options);

// Empty when pbrt-v4 can express the scene exactly; otherwise the reason,
// one sentence naming the scene, the object and its field (e.g.
// objects[0].material.type "phong") or the feature pbrt-v4 lacks. Every
// material type is decided explicitly: written, or refused with its reason.
std::optional<std::string> pbrt_v4_refusal(const Scene& scene);

// The scene as pbrt-v4 text, opening with comments that state the facts it
// relies on. Throws furnace::Error (the refusal sentence) when pbrt-v4 cannot
// express the scene, or naming the option when an option is out of range.
std::string export_pbrt_v4(const Scene& scene, const PbrtV4Options& options);

// export_pbrt_v4() written atomically to `path` (nothing is written on error).
void write_pbrt_v4(const Scene& scene, const PbrtV4Options& options, const std::filesystem::path& path);

}  // namespace furnace::exporter
