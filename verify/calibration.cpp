#include "verify/calibration.h"

#include <algorithm>
#include <array>
#include <limits>

#include <fmt/format.h>
#include <fmt/ranges.h>

namespace furnace::verify {

namespace {

// `furnace sweep --seeds 10 --spp N` over the default suite (198 cases), per-case
// α 0.05; a case is in excess when it rejects significantly more often than α
// (binomial p < 0.01: 4 or more of 10). Since the mean tests use the exact
// variance where the strategy's second moment is modelled (valid at any spp:
// those 112 cases rejected 1/1120 runs at 32 spp, 3/1120 at 128, no case in
// excess), a threshold here matters only for a strategy's cases without a
// model, whose rejections below it are INCONCLUSIVE (harness.h). It is the
// smallest spp measured (32, 128, 256, 512) whose sweep, and every larger
// one, had none of those cases in excess. Rejected runs per level are in
// docs/statistics.md.
struct Calibration {
  Strategy strategy;
  int min_spp;
};
constexpr std::array<Calibration, kStrategyTable.size()> kCalibrationTable = {{
    {Strategy::kUniformHemisphere, 32},  // its unmodelled case 0/10 at 32 … 512
    {Strategy::kCosineHemisphere, 32},   // every case modelled; 0/110 at 32 … 512
    {Strategy::kLightArea, 32},          // its unmodelled case 0/10 at 32 … 512
    {Strategy::kLightSolidAngle, 256},   // 128: sphere_occluder 4/10 (unmodelled)
    {Strategy::kBsdf, 32},               // every case modelled; at most 3/190 at 32 … 512
    {Strategy::kMisBalance, 256},        // 128: sphere_occluder 9/10, polygon_occluder 8/10
    {Strategy::kMisPower, 256},          // 128: sphere_occluder, polygon_occluder 5/10
    {Strategy::kMisOneSample, 32},       // unmodelled cases at most 3/120 at 32 … 512
    {Strategy::kPathNaive, 128},         // 32: glass_rough_outside_60 5/10, glass_rough_normal 4/10
    {Strategy::kPathMis, 256},           // 128: polygon_occluder 5/10, glass_rough_outside_60 5/10
}};

// Every strategy of core/strategy.h's table has exactly one calibration row:
// a new strategy fails the build here until its false-alarm rate is measured.
constexpr bool every_strategy_is_calibrated() {
  for (const StrategyInfo& info : kStrategyTable) {
    int rows = 0;
    for (const Calibration& c : kCalibrationTable) rows += c.strategy == info.strategy && c.min_spp > 0;
    if (rows != 1) return false;
  }
  return true;
}
static_assert(every_strategy_is_calibrated(), "kCalibrationTable needs one row per Strategy (run furnace sweep)");

}  // namespace

int min_calibrated_spp(Strategy strategy) {
  for (const Calibration& c : kCalibrationTable)
    if (c.strategy == strategy) return c.min_spp;
  return kCalibrationTable.front().min_spp;  // unreachable: the static_assert above
}

int lowest_min_calibrated_spp() {
  int lowest = std::numeric_limits<int>::max();
  for (const StrategyInfo& info : kStrategyTable) lowest = std::min(lowest, min_calibrated_spp(info.strategy));
  return lowest;
}

int highest_min_calibrated_spp() {
  int highest = 0;
  for (const StrategyInfo& info : kStrategyTable) highest = std::max(highest, min_calibrated_spp(info.strategy));
  return highest;
}

std::string low_spp_warning(const std::vector<Case>& cases) {
  // Each strategy once, in table order, at its smallest case spp.
  std::vector<std::string> below;
  int smallest_spp = std::numeric_limits<int>::max();
  for (const StrategyInfo& info : kStrategyTable) {
    int spp = std::numeric_limits<int>::max();
    for (const Case& c : cases)
      if (c.options.strategy == info.strategy) spp = std::min(spp, c.options.spp);
    if (spp >= min_calibrated_spp(info.strategy)) continue;
    below.push_back(fmt::format("{} ({})", info.name, min_calibrated_spp(info.strategy)));
    smallest_spp = std::min(smallest_spp, spp);
  }
  if (below.empty()) return "";
  return fmt::format("{} spp is below the smallest spp at which the suite's false-alarm rate was measured to stay "
                     "within alpha for {}; their cases without a modelled variance report a rejection as "
                     "INCONCLUSIVE, not FAIL.",
                     smallest_spp, fmt::join(below, ", "));
}


}  // namespace furnace::verify
