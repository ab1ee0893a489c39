#include "cli/cases.h"

#include <algorithm>
#include <map>
#include <utility>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "cli/cli_options.h"
#include "core/scene.h"
#include "stats/statistics.h"

namespace furnace::cli {

std::vector<verify::Case> suite_cases(const std::vector<verify::Case>& suite, const std::vector<Strategy>& strategies) {
  std::vector<verify::Case> cases;
  for (const verify::Case& c : suite)
    if (strategies.empty() || std::find(strategies.begin(), strategies.end(), c.options.strategy) != strategies.end())
      cases.push_back(c);
  return cases;
}

std::vector<verify::Case> scene_file_cases(const std::vector<std::string>& scenes,
                                           const std::vector<Strategy>& strategies) {
  const bool all_direct = strategies.empty();
  const std::vector<Strategy> chosen = all_direct ? direct_strategies() : strategies;
  std::vector<verify::Case> cases;
  for (const std::string& path : scenes) {
    const Scene scene = load_scene(path);
    for (const Strategy strategy : chosen) {
      if (all_direct && !scene.point_lights.empty() && !strategy_sees_delta_lights(strategy)) continue;
      verify::Case c;
      c.scene_path = path;
      c.options.strategy = strategy;
      cases.push_back(c);
    }
  }
  return cases;
}

std::string spp_help() {
  return fmt::format(
      "Samples per pixel (the variance test needs >= {}; the stated alpha is calibrated from {} to {} spp, "
      "depending on the strategy)",
      stats::kMinVarianceTestSamples, verify::lowest_min_calibrated_spp(), verify::highest_min_calibrated_spp());
}

std::string calibrated_spp_list() {
  std::vector<std::string> items;
  for (const StrategyInfo& info : kStrategyTable)
    items.push_back(fmt::format("{} {}", info.name, verify::min_calibrated_spp(info.strategy)));
  return fmt::format("{}", fmt::join(items, ", "));
}

CLI::Option* add_suite_option(CLI::App* command, verify::Suite& suite) {
  const std::map<std::string, verify::Suite>& by_name = verify::suite_names();
  return command
      ->add_option("--suite", suite,
                   "Built-in suite: default (one scene per class, under 90 s on 2 cores), extended (the classes' "
                   "second views: other light selections, view angles, depth limits) or all")
      ->transform(enum_by_name(std::vector<std::pair<std::string, verify::Suite>>(by_name.begin(), by_name.end())))
      ->type_name("default|extended|all")
      ->default_str(verify::suite_name(suite));
}

}  // namespace furnace::cli
