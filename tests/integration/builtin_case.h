// One case of a built-in scene through verify::run_case, the function
// `furnace verify` runs, with the integration controls' fixed budget: kSpp
// samples per pixel, the named seed kSeed, and kCaseAlpha shared by the case's
// pixel tests, image-mean test and (where modelled) variance test by the
// Šidák correction. The verdict row (z, detectable bias) is printed.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "renderer/image.h"
#include "verify/harness.h"
#include "verify/verdict_table.h"

namespace furnace::verify::test {

inline constexpr int kSpp = 4096;
inline constexpr uint64_t kSeed = 0x5eed2026;  // fixed: a pass today fails only when the code changes
inline constexpr double kCaseAlpha = 1e-3;

inline Verdict run_builtin_case(const std::string& scene_file, Strategy strategy, Defect defect) {
  Case c;
  c.scene_path = scene_dir() + "/" + scene_file;
  c.options.strategy = strategy;
  c.options.defect = defect;
  c.options.spp = kSpp;
  c.options.seed = kSeed;
  const Verdict v = run_case(c, kCaseAlpha);
  std::printf("%s", format_table({v}, kCaseAlpha).c_str());
  return v;
}

// How many pixels of two renders of one scene differ in mean or sample
// variance (0: bit-identical images, as a defect that cannot act leaves them).
inline size_t differing_pixels(const Image& a, const Image& b) {
  if (a.pixels.size() != b.pixels.size()) return std::max(a.pixels.size(), b.pixels.size());
  size_t differing = 0;
  for (size_t i = 0; i < a.pixels.size(); ++i)
    differing += a.pixels[i].mean != b.pixels[i].mean || a.pixels[i].sample_variance() != b.pixels[i].sample_variance();
  return differing;
}

}  // namespace furnace::verify::test
