// The verify verdict table's machine-readable and browsable twins:
// `furnace verify --json FILE` (every number the text table shows, at full
// precision) and `furnace verify --html DIR` (DIR/index.html: the same table,
// failing cases first, self-contained, no script, no network).
//
// JSON: {"generator", "family_alpha", "power", "pass", "cases": [...],
// "variance_skipped_cases", "weakest_mean_tests", "weakest_variance_tests"};
// each case holds the Verdict's fields under the same names, its
// "relative_rmse" and "verdict" ("pass", "FAIL biased", "FAIL variance") and
// "table", the row's cells as the text table prints them. A number that is
// not finite (the detectable error of an exact case, the |t| of a failing
// zero-variance pixel) is null.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "verify/harness.h"
#include "verify/verdict_table.h"

namespace furnace::verify {

// The cells of one verdict row, (column, text), formatted as the text table
// (format_table) formats them, without padding.
std::vector<std::pair<std::string, std::string>> verdict_cells(const Verdict& v);

std::string verdicts_json(const std::vector<Verdict>& verdicts, double family_alpha);
std::string verdicts_html(const std::vector<Verdict>& verdicts, double family_alpha, const std::string& command_line);

// Write them atomically: FILE, and DIR/index.html (DIR created if needed).
void write_verdicts_json(const std::vector<Verdict>& verdicts, double family_alpha, const std::string& path);
void write_verdicts_html(const std::vector<Verdict>& verdicts, double family_alpha, const std::string& command_line,
                         const std::string& dir);

}  // namespace furnace::verify
