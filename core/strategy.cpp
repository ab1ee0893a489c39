#include "core/strategy.h"

#include <fmt/format.h>

#include "core/error.h"

namespace furnace {

namespace {

// Finds the row of `value` in a table whose rows hold it in `field`.
template <class Table, class Value, class Field>
const typename Table::value_type& row_of(const Table& table, Value value, Field field) {
  for (const auto& row : table)
    if (row.*field == value) return row;
  FURNACE_CHECK(false && "every enumerator has a table row");
  return table.front();
}

// Parses `name` against a table's names; the error lists them all.
template <class Table, class Field, class NameField>
auto parse_in(const Table& table, const std::string& name, Field field, NameField name_field, const char* what) {
  std::string accepted;
  for (const auto& row : table) {
    if (name == row.*name_field) return row.*field;
    accepted += accepted.empty() ? row.*name_field : std::string(", ") + row.*name_field;
  }
  throw Error(fmt::format("unknown {} '{}'; the accepted names are {}.", what, name, accepted));
}

struct LightSelectionInfo {
  LightSelection selection;
  const char* name;
};
constexpr std::array<LightSelectionInfo, 2> kLightSelectionTable = {{
    {LightSelection::kUniform, "uniform"},
    {LightSelection::kPower, "power"},
}};

struct TransportConventionInfo {
  TransportConvention convention;
  const char* name;
};
constexpr std::array<TransportConventionInfo, 2> kTransportConventionTable = {{
    {TransportConvention::kRadiance, "radiance"},
    {TransportConvention::kNone, "none"},
}};

}  // namespace

Strategy parse_strategy(const std::string& name) {
  return parse_in(kStrategyTable, name, &StrategyInfo::strategy, &StrategyInfo::name, "strategy");
}

std::vector<Strategy> direct_strategies() {
  std::vector<Strategy> out;
  for (const StrategyInfo& info : kStrategyTable)
    if (info.kind == StrategyKind::kDirect) out.push_back(info.strategy);
  return out;
}

std::vector<Strategy> path_tracing_strategies() {
  std::vector<Strategy> out;
  for (const StrategyInfo& info : kStrategyTable)
    if (info.kind == StrategyKind::kPath) out.push_back(info.strategy);
  return out;
}

std::vector<Strategy> multi_sample_mis_strategies() {
  std::vector<Strategy> out;
  for (const StrategyInfo& info : kStrategyTable)
    if (is_multi_sample_mis(info.strategy)) out.push_back(info.strategy);
  return out;
}

std::map<std::string, Strategy> strategy_names() {
  std::map<std::string, Strategy> out;
  for (const StrategyInfo& info : kStrategyTable) out.emplace(info.name, info.strategy);
  return out;
}

std::string light_selection_name(LightSelection s) {
  return row_of(kLightSelectionTable, s, &LightSelectionInfo::selection).name;
}

LightSelection parse_light_selection(const std::string& name) {
  return parse_in(kLightSelectionTable, name, &LightSelectionInfo::selection, &LightSelectionInfo::name,
                  "light selection");
}

std::map<std::string, LightSelection> light_selection_names() {
  std::map<std::string, LightSelection> out;
  for (const LightSelectionInfo& info : kLightSelectionTable) out.emplace(info.name, info.selection);
  return out;
}

std::string transport_convention_name(TransportConvention c) {
  return row_of(kTransportConventionTable, c, &TransportConventionInfo::convention).name;
}

TransportConvention parse_transport_convention(const std::string& name) {
  return parse_in(kTransportConventionTable, name, &TransportConventionInfo::convention,
                  &TransportConventionInfo::name, "transport convention");
}

std::map<std::string, TransportConvention> transport_convention_names() {
  std::map<std::string, TransportConvention> out;
  for (const TransportConventionInfo& info : kTransportConventionTable) out.emplace(info.name, info.convention);
  return out;
}

std::string defect_name(Defect d) { return row_of(kDefectTable, d, &DefectInfo::defect).name; }

Defect parse_defect(const std::string& name) {
  return parse_in(kDefectTable, name, &DefectInfo::defect, &DefectInfo::name, "defect");
}

std::map<std::string, Defect> defect_names() {
  std::map<std::string, Defect> out;
  for (const DefectInfo& info : kDefectTable) out.emplace(info.name, info.defect);
  return out;
}

std::string depth_name(int max_depth) {
  return max_depth == kUnlimitedDepth ? std::string("unlimited") : std::to_string(max_depth);
}

}  // namespace furnace
