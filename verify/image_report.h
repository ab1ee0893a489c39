// What the reports of `furnace check` (verify/check_report.h) and `furnace
// compare` (verify/compare_report.h) write alike: the --json file (or
// stdout), its BAD INPUT form, non-finite numbers as JSON null, and the
// per-pixel t map (--zmap) as an OpenEXR file.
#pragma once

#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace furnace::verify {

// A relative number as a percentage ("1.23%"), "inf" when not finite.
std::string percent_text(double relative);

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
