// Where the suite's stated false-alarm rate was measured to hold: the
// smallest calibrated spp per strategy (one table, with a completeness check:
// a new strategy fails the build until it has a row).
#pragma once

#include <string>
#include <vector>

#include "core/strategy.h"
#include "verify/suite.h"

namespace furnace::verify {

// The smallest spp at which the built-in suite's false-alarm rate has been
// measured to stay within its stated α, per strategy, for the cases whose
// variance is not modelled: `furnace sweep` found none of them rejecting
// significantly more often than its per-case α there and at every larger spp
// measured (docs/statistics.md "Low spp and calibration" gives the counts).
// Below it the sample-variance tests (Hall's statistic, Cochran's rule) are
// not calibrated for that strategy's most skewed cases: verify reports their
// rejections as INCONCLUSIVE and prints low_spp_warning(). Cases with a
// modelled variance are tested with it, valid at any spp.
int min_calibrated_spp(Strategy strategy);
// The smallest and largest min_calibrated_spp over all strategies (--help).
int lowest_min_calibrated_spp();
int highest_min_calibrated_spp();

// One sentence naming each strategy among `cases` whose case spp is below its
// min_calibrated_spp, with that spp; empty when every case is at or above its
// strategy's.
std::string low_spp_warning(const std::vector<Case>& cases);

}  // namespace furnace::verify
