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
// measured to stay within its stated α, per strategy: `furnace sweep
// --strategy NAME` found no case rejecting significantly more often than its
// per-case α there and at every larger spp measured (README "Low spp" gives
// the counts). Below it the per-pixel tests' normal approximations (Hall's
// statistic, Cochran's rule, the fourth-moment standard error of s²) are not
// calibrated for that strategy's most skewed cases: verify and sweep still
// run but print low_spp_warning().
int min_calibrated_spp(Strategy strategy);
// The smallest and largest min_calibrated_spp over all strategies (--help).
int lowest_min_calibrated_spp();
int highest_min_calibrated_spp();

// One sentence naming each strategy among `cases` whose case spp is below its
// min_calibrated_spp, with that spp; empty when every case is at or above its
// strategy's.
std::string low_spp_warning(const std::vector<Case>& cases);

}  // namespace furnace::verify
