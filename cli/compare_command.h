// `furnace compare`: two sets of OpenEXR renders of any scene, from any
// renderer, tested for the same expected image (verify/compare.h tests them,
// verify/compare_report.h writes the report). Its contract (the same as
// `furnace check`'s):
//   exit 0  SAME: no test rejects and the image-mean test has the stated power
//   exit 1  DIFFERENT: some test rejects (the report names which: mean,
//           tiles, pixels, variance); it wins over INCONCLUSIVE
//   exit 2  bad input: one sentence on stderr naming the file and value
//           (nothing but --json is written)
//   exit 3  INCONCLUSIVE: no test rejects, but the image-mean test cannot
//           detect a difference of --max-detectable-difference; the text says
//           how many renders or samples would
// The report goes to stdout (to stderr when the JSON goes to stdout);
// warnings (sides whose provenance names different scenes, or whose headers
// state different spp) go to stderr and into the JSON. Finite negative
// radiance is data, used as is and counted per side. --json FILE ("-": stdout) holds every number the
// text shows; non-finite numbers are null. --zmap FILE writes the per-pixel
// Welch t of A − B.
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "stats/test_design.h"
#include "verify/check_image.h"
#include "verify/compare.h"

namespace furnace::cli {

struct CompareCommandOptions {
  std::vector<std::string> a_paths, b_paths;
  double alpha = stats::kDefaultFamilyAlpha;
  double max_detectable_difference = verify::kDefaultMaxDetectableDifference;
  int tile_size = verify::kDefaultTileSize;
  bool test_variance = true;  // false: --no-variance-test
  verify::ChannelMode channels = verify::ChannelMode::kGray;
  std::string zmap_path;  // empty: none
  std::string json_path;  // empty: none; "-": stdout
  // empty: none; else DIR/compare.json (the JSON report with every pixel)
  // and DIR/index.html with DIR/compare_<channel>.png, drawn by
  // scripts/plot_compare.py with the report's plotting (verify/report_html.h
  // finds Python with matplotlib; none is bad input, found before any work).
  std::string html_dir;
};

// Adds `compare` to `app`, its options bound to `options`.
CLI::App* add_compare_command(CLI::App& app, CompareCommandOptions& options);

// Reads both sides, runs the comparison and prints its report; returns the
// exit code (0, 1, 3). Bad input throws furnace::Error (exit 2), after
// writing {"verdict": "BAD INPUT", "error": ...} to --json when given.
int run_compare(const CompareCommandOptions& options);

}  // namespace furnace::cli
