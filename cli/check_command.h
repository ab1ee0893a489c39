// `furnace check`: another renderer's OpenEXR images of a scene against the
// scene's exact reference (verify/check.h tests them, verify/check_report.h
// writes the report). Its contract:
//   exit 0  PASS: no test rejects and the image-mean test has the stated power
//   exit 1  FAIL: some test rejects (it wins over INCONCLUSIVE)
//   exit 2  bad input: one sentence on stderr naming the file and, for a bad
//           pixel, the pixel, channel and value (nothing but --json is written)
//   exit 3  INCONCLUSIVE: no test rejects, but the image-mean test cannot
//           detect a bias of --max-detectable-bias (the text says how many
//           images or samples would), or the rare-event guard (--guard) held
//           a test (the text says at what spp it would be judged)
// The report goes to stdout (to stderr when the JSON goes to stdout);
// warnings (an image whose provenance names another scene, another scene-file
// hash, a defect, or another depth) go to stderr and into the JSON.
// --json FILE ("-": stdout) holds every number the text shows; non-finite
// numbers (a t of ±inf) are null. --zmap FILE writes the per-pixel t.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "stats/test_design.h"
#include "verify/check.h"
#include "verify/check_image.h"

namespace furnace::cli {

struct CheckCommandOptions {
  std::string scene_path;
  std::vector<std::string> image_paths;
  std::vector<std::string> guard_paths;  // the rare-event guard's images (verify/check.h); empty: none
  double alpha = stats::kDefaultFamilyAlpha;
  double max_detectable_bias = verify::kDefaultMaxDetectableBias;
  std::optional<int> max_depth;  // empty: verify::check_reference()'s default
  TransportConvention convention = TransportConvention::kRadiance;  // the checked renderer's
  verify::ChannelMode channels = verify::ChannelMode::kGray;
  std::string zmap_path;  // empty: none
  std::string json_path;  // empty: none; "-": stdout
};

// Adds `check` to `app`, its options bound to `options`.
CLI::App* add_check_command(CLI::App& app, CheckCommandOptions& options);

// Runs the check and prints its report; returns the exit code (0, 1, 3).
// Bad input throws furnace::Error (exit 2), after writing {"verdict": "BAD
// INPUT", "error": ...} to --json when given.
int run_check(const CheckCommandOptions& options);

}  // namespace furnace::cli
