// The cases `furnace verify` runs: a scene file with render options, the
// label every output names a case by, and the built-in suite.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "renderer/render.h"
#include "verify/resources.h"  // scene_dir(), where the suite's scenes are

namespace furnace::verify {

struct Case {
  std::string scene_path;
  RenderOptions options;
};

// The one label of a case's strategy, used by the verdict table, its JSON and
// HTML twins, the convergence report and the tests: the strategy's name,
// "/inf" or "/d<N>" for a path tracer's depth, "@power" under power light
// selection (e.g. "path_mis/d4", "light_area@power").
std::string case_label(const RenderOptions& options);

// The built-in suite `furnace verify` runs when no scene is given: each
// built-in scene with the strategies whose reference it has (direct-lighting
// strategies against analytic::reference_image, path tracers against
// analytic::global_reference_image), at `spp` samples per pixel.
std::vector<Case> default_suite(int spp, uint64_t seed, int threads);

}  // namespace furnace::verify
