// The verdict table `furnace verify` prints, and the cells its JSON and
// HTML twins (verdict_export.h) share with it.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "verify/harness.h"

namespace furnace::verify {

// The verdict table's cells that its JSON and HTML twins (verdict_export.h)
// print too, so the three cannot drift apart:
// the verdict column: "pass", "FAIL biased" or "FAIL variance";
const char* verdict_label(VerdictKind kind);
// the strategy column: the strategy, with "+defect" when one is injected;
std::string strategy_label(const Verdict& v);
// the "var detect" column: "-" when not tested, "exact" for a zero predicted
// variance (tested for exact agreement), else the detectable error in %;
std::string variance_detect_cell(const Verdict& v);
// the "weakest" lines: the `count` verdicts with the largest finite `detect`
// among those `applies` selects, largest first (an exact case, tested for
// exact agreement, quotes no relative error and is left out).
std::vector<const Verdict*> weakest_cases(const std::vector<Verdict>& verdicts, double Verdict::*detect,
                                          bool (*applies)(const Verdict&), size_t count);

// How many of the least powerful cases the table's summary names, per test.
inline constexpr size_t kWeakestCasesListed = 5;

// Formats the verdict table: one row per case with the smallest relative bias
// its image-mean test detects (`detect`), the median of the same per pixel
// (`px detect`) and the smallest relative error of the summed variance its
// variance test detects (`var detect`; "-" when not tested, "exact" when the
// predicted variance is 0 and the test is one of exact agreement), each at power
// kReportedPower; a line per failed case saying which kind of failure it is;
// and a summary naming the kWeakestCasesListed cases with the largest
// `detect` and `var detect`.
std::string format_table(const std::vector<Verdict>& verdicts, double family_alpha);

}  // namespace furnace::verify
