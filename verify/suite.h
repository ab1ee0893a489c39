// The cases `furnace verify` runs: a scene file with render options, the
// label every output names a case by, and the built-in suite.
#pragma once

#include <cstdint>
#include <map>
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

// The built-in suites. `default` is what `furnace verify` runs when no scene
// is given: one scene per class of case (each light and occluder kind, each
// BSDF family, the enclosures, the hard cases) and every defect's catching
// case, sized to run in under 90 s on 2 cores. `extended` holds the second
// views of classes the default already covers (an unoccluded variant, a
// second light selection, a second view angle or depth limit, the costliest
// references); `all` is both. The default ctest run tests every case of
// `all` (tests/integration/strategy_verification_test.cpp).
enum class Suite { kDefault, kExtended, kAll };
const char* suite_name(Suite suite);
// "default", "extended", "all" (the --suite option's accepted values).
const std::map<std::string, Suite>& suite_names();

// Each built-in scene of `suite` with the strategies whose reference it has
// (direct-lighting strategies against analytic::reference_image, path tracers
// against analytic::global_reference_image), at `spp` samples per pixel.
std::vector<Case> builtin_suite(Suite suite, int spp, uint64_t seed, int threads);
// builtin_suite(Suite::kDefault, ...).
std::vector<Case> default_suite(int spp, uint64_t seed, int threads);

}  // namespace furnace::verify
