// The report of `furnace compare` (verify/compare.h): its warnings from the
// renders' provenance, its text, its JSON twin, its per-pixel t map and its
// HTML page. The command (cli/compare_command.h) states where each goes and
// the exit codes.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "verify/check_image.h"
#include "verify/compare.h"
#include "verify/report_html.h"

namespace furnace::verify {

// Warnings from the images' provenance: the two sides name different scenes,
// or different spp (the variance test then compares different noise levels).
std::vector<std::string> compare_warnings(const CompareSide& a, const CompareSide& b);

// The human-readable report (ends with "verdict: SAME|DIFFERENT|INCONCLUSIVE").
std::string format_compare(const CompareResult& r);

// The JSON twin of format_compare: every number the text shows (non-finite
// ones null), both sides' files, the warnings, `zmap_path` (null when
// empty), the verdict and its exit code.
nlohmann::json compare_json(const CompareSide& a, const CompareSide& b, const CompareResult& r,
                            const std::vector<std::string>& warnings, ChannelMode channels_mode,
                            const std::string& zmap_path);

// The per-pixel Welch t of A − B of every tested channel as an OpenEXR file
// (channel Y for gray, R, G, B for rgb), atomically.
void write_compare_zmap(const std::string& path, const CompareResult& r);

// Before any work, for --html DIR: the Python with matplotlib and
// scripts/plot_compare.py, the report's plotting script's sibling (it imports
// that script's helpers), and DIR created. Throws furnace::Error (bad input)
// naming what is missing or why DIR cannot be created.
PlotTools prepare_compare_html(const std::string& dir);

// DIR/compare.json (`report`, compare_json's, plus every pixel the page
// draws) and the page plot_compare.py makes of it: DIR/index.html with
// DIR/compare_<channel>.png. Throws furnace::Error when the script fails.
void write_compare_html(const PlotTools& tools, const std::string& dir, nlohmann::json report,
                        const CompareResult& r);

}  // namespace furnace::verify
