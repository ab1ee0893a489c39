// Provenance of furnace's own renders: string attributes in the header of
// every EXR `furnace render` writes, saying what the image is a render of, so
// that `furnace check` can warn when an image belongs to another scene.
//
//   furnace.scene            the scene's name (Scene::name)
//   furnace.scene_hash       "fnv1a64:" + 16 lowercase hex digits: the 64-bit
//                            FNV-1a hash (offset basis 0xcbf29ce484222325, prime
//                            0x100000001b3; Fowler, Noll & Vo) of the scene
//                            file's bytes exactly as stored (files it refers to,
//                            like an environment map, are not included)
//   furnace.strategy         strategy name, as the CLI spells it
//   furnace.spp              samples per pixel (decimal)
//   furnace.seed             random seed (decimal)
//   furnace.max_depth        longest path in segments (the camera segment counts
//                            as 1), decimal, or "unlimited"
//   furnace.light_selection  "uniform" or "power"
//   furnace.defect           negative-control defect, "none" for the renderer
//   furnace.convention       "radiance" or "none": how radiance crossing a
//                            dielectric was transported (--convention)
//   furnace.version          furnace's version (the CMake project VERSION)
// An image from another renderer has none of these; every field is then empty.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <string_view>

#include "core/strategy.h"

namespace furnace {

// FNV-1a, 64 bits, of the bytes.
uint64_t fnv1a_64(std::string_view bytes);
// "fnv1a64:" + 16 hex digits of the file's bytes. Throws furnace::Error
// naming the file when it cannot be read.
std::string file_content_hash(const std::filesystem::path& path);

// The furnace version this binary was built as (CMake's PROJECT_VERSION).
std::string furnace_version();

struct ImageProvenance {
  std::string scene, scene_hash, strategy, spp, seed, max_depth, light_selection, defect, convention, version;

  bool empty() const { return scene.empty() && scene_hash.empty(); }
  // The header attributes above (fields left empty are omitted).
  std::map<std::string, std::string> attributes() const;
  // Reads the attributes above; absent ones stay empty.
  static ImageProvenance from_attributes(const std::map<std::string, std::string>& attributes);
};

}  // namespace furnace
