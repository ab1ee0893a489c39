// The design of the suite's hypothesis tests, stated once: the family-wise
// false-alarm probability a run starts from and the power at which every
// report quotes its detectable bias. `furnace verify`, `check` and `compare`
// take their defaults from here.
#pragma once

namespace furnace::stats {

// The family-wise false-alarm probability of one `furnace verify` run (all
// scenes × strategies × pixels together). Stated once; every test's own
// level is derived from it by the Šidák correction.
inline constexpr double kDefaultFamilyAlpha = 0.01;
// Power at which the minimum detectable bias is quoted: the bias the test
// would catch with probability 1 − β. 0.9 is the usual design power.
inline constexpr double kReportedPower = 0.9;

}  // namespace furnace::stats
