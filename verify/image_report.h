// What the reports of `furnace check` (verify/check_report.h) and `furnace
// compare` (verify/compare_report.h) write alike: the --json file (or
// stdout), its BAD INPUT form, non-finite numbers as JSON null, and the
// per-pixel t map (--zmap) as an OpenEXR file.
#pragma once

#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "verify/check_image.h"

namespace furnace::verify {

// A relative number as a percentage ("1.23%"), "inf" when not finite.
std::string percent_text(double relative);

// Why K values of a pixel repeat, for the reports' untested pixels: 16-bit
// half-float rounding when the images store halves, else a quasi-Monte
// Carlo or quantised (discrete) render.
std::string repeated_values_reason(bool half_float);

// One line on a set of images' finite negative values ("" when none): how
// many, in how many images, the most negative and where, and that they are
// used as is. `what` names the set ("side A", "the images").
std::string negative_values_text(const std::string& what, const NegativeValues& n, int images);
// Their JSON: {"values", "images", "most_negative", "path", "channel", "x", "y"}
// (the last five null when there are none).
nlohmann::json negative_values_json(const NegativeValues& n);

// `v`, or null when it is not finite (a t of ±inf): the reports' JSON holds
// no non-finite numbers.
nlohmann::json json_number(double v);

// The fields a report's JSON ends with: its warnings, the --zmap path (null
// when none), the verdict and its exit code.
void add_outcome(nlohmann::json& j, const std::vector<std::string>& warnings, const std::string& zmap_path,
                 const std::string& verdict, int exit_code);

// Writes `j` (indented) to `path` atomically, or to stdout for "-" (the
// --json of check and compare).
void emit_json(const std::string& path, const nlohmann::json& j);

// Writes {"command": command, "verdict": "BAD INPUT", "exit_code": 2,
// "error": message} to `path` as emit_json does. When that write fails too,
// its error goes to stderr and the input error stays the one reported.
void emit_bad_input_json(const std::string& path, const std::string& command, const std::string& message);

// The per-pixel t of `channels` (channel "gray" is written as Y) as an
// OpenEXR file, atomically, with the attributes <prefix>critical_t.<channel>
// and <prefix><key> for each of `attributes` (check's and compare's --zmap).
void write_t_map(const std::string& path, int width, int height, const std::vector<std::string>& channels,
                 const std::vector<std::vector<double>>& pixel_t, const std::vector<double>& critical_t,
                 const std::string& attribute_prefix, std::map<std::string, std::string> attributes);

}  // namespace furnace::verify
