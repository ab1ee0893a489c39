// `verify --json` and `verify --html` (verify/verdict_export.h) say what the
// text table says: every cell of every row, formatted from the JSON's own
// numbers, appears in that row of format_table's text, in the JSON's "table"
// object and in the HTML row; the HTML lists failing cases first; the
// "weakest" lists match. Three real cases of disk_occluder: light_area
// (passes), light_area with skip_shadow_ray (FAIL biased: the negative
// control that makes the failing-first order observable) and light_area at
// 64 spp (variance test skipped).
#include <gtest/gtest.h>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <string>
#include <vector>

#include "core/strategy.h"
#include "verify/harness.h"
#include "verify/verdict_table.h"
#include "verify/verdict_export.h"

namespace furnace::verify {
namespace {

constexpr double kAlpha = 0.01;
constexpr uint64_t kExportTestSeed = 20261202;

Case disk_case(Defect defect, int spp) {
  Case c;
  c.scene_path = std::string(FURNACE_SCENE_DIR) + "/disk_occluder.json";
  c.options.strategy = Strategy::kLightArea;
  c.options.defect = defect;
  c.options.spp = spp;
  c.options.seed = kExportTestSeed;
  return c;
}

const std::vector<Verdict>& verdicts() {
  static const std::vector<Verdict> v = [] {
    const double per_case = 1 - std::pow(1 - kAlpha, 1.0 / 3);
    return std::vector<Verdict>{run_case(disk_case(Defect::kNone, 256), per_case),
                                run_case(disk_case(Defect::kSkipShadowRay, 256), per_case),
                                run_case(disk_case(Defect::kNone, 64), per_case)};
  }();
  return v;
}

// The lines of `table` that belong to row `index` (its row and the indented
// lines under it).
std::string table_block(const std::string& table, size_t index) {
  std::vector<std::string> lines;
  size_t start = 0;
  while (start < table.size()) {
    const size_t end = table.find('\n', start);
    lines.push_back(table.substr(start, end - start));
    start = end + 1;
  }
  // lines[0]: alpha line, lines[1]: header, then rows with indented details.
  size_t row = 0;
  std::string block;
  for (size_t i = 2; i < lines.size(); ++i) {
    const bool detail = lines[i].rfind("    ", 0) == 0;
    if (!detail) ++row;
    if (row == index + 1 && (detail || block.empty())) block += lines[i] + "\n";
    if (row > index + 1) break;
  }
  return block;
}

TEST(VerdictExport, TheCasesAreWhatTheTestNeeds) {
  ASSERT_EQ(verdicts().size(), 3u);
  EXPECT_TRUE(verdicts()[0].pass);
  EXPECT_EQ(verdict_kind(verdicts()[1]), VerdictKind::kBiased);
  EXPECT_FALSE(verdicts()[2].variance_skipped.empty());
}

TEST(VerdictExport, JsonNumbersFormatToTheTableCells) {
  const std::string table = format_table(verdicts(), kAlpha);
  const nlohmann::json j = nlohmann::json::parse(verdicts_json(verdicts(), kAlpha));
  ASSERT_EQ(j["cases"].size(), verdicts().size());
  EXPECT_EQ(j["pass"], false);
  EXPECT_EQ(j["variance_skipped_cases"], 1);
  for (size_t i = 0; i < verdicts().size(); ++i) {
    const nlohmann::json& c = j["cases"][i];
    const std::string block = table_block(table, i);
    SCOPED_TRACE(block);
    // Every cell, as verdict_cells formats it, is in the table's row and in the JSON.
    for (const auto& [column, text] : verdict_cells(verdicts()[i])) {
      if (column.rfind("var ", 0) == 0 && text == "-") continue;  // the table shows nothing for untested variance
      EXPECT_NE(block.find(text), std::string::npos) << column << " = " << text;
      EXPECT_EQ(c["table"][column], text) << column;
    }
    // The JSON's numbers reproduce the cells.
    const auto cell = [&](const char* column) { return c["table"][column].get<std::string>(); };
    EXPECT_EQ(fmt::format("{:.6g}", c["image_mean"].get<double>()), cell("mean"));
    EXPECT_EQ(fmt::format("{:.6g}", c["reference_mean"].get<double>()), cell("reference"));
    EXPECT_EQ(fmt::format("{:.3f}", c["z"].get<double>()), cell("z"));
    EXPECT_EQ(fmt::format("{:.2f}", c["threshold"].get<double>()), cell("z crit"));
    EXPECT_EQ(fmt::format("{}/{}", c["pixel_failures"].get<int>(), c["pixels"].get<int>()), cell("px fail"));
    EXPECT_EQ(fmt::format("{}", c["pixels_untested"].get<int>()), cell("px skip"));
    EXPECT_EQ(fmt::format("{:.3g}", c["relative_rmse"].get<double>()), cell("rel RMSE"));
    EXPECT_EQ(fmt::format("{:.3g}%", 100 * c["detectable_rel_bias"].get<double>()), cell("detect"));
    EXPECT_EQ(fmt::format("{:.3g}%", 100 * c["median_pixel_detectable_rel_bias"].get<double>()), cell("px detect"));
    EXPECT_EQ(fmt::format("{:.3f}", c["seconds"].get<double>()), cell("time s"));
    EXPECT_EQ(fmt::format("{:.3g}", c["samples_per_second"].get<double>() / 1e6), cell("Msamples/s"));
    EXPECT_EQ(c["verdict"].get<std::string>(), cell("verdict"));
    if (c["variance_tested"].get<bool>()) {
      EXPECT_EQ(fmt::format("{:.6g}", c["measured_variance"].get<double>()), cell("var measured"));
      EXPECT_EQ(fmt::format("{:.6g}", c["predicted_variance"].get<double>()), cell("var predicted"));
      EXPECT_EQ(fmt::format("{:.3f}", c["variance_z"].get<double>()), cell("var z"));
      EXPECT_EQ(fmt::format("{:.3g}%", 100 * c["variance_detectable_rel_error"].get<double>()), cell("var detect"));
    } else {
      EXPECT_NE(block.find("variance: skipped (" + c["variance_skipped"].get<std::string>() + ")"),
                std::string::npos);
    }
    if (c["verdict"] == "FAIL biased") {
      const auto& w = c["worst_pixel"];
      EXPECT_NE(block.find(fmt::format("worst pixel ({}, {}): mean {:.6g}, reference {:.6g}", w["x"].get<int>(),
                                       w["y"].get<int>(), w["mean"].get<double>(), w["reference"].get<double>())),
                std::string::npos);
    }
  }
  // The weakest lists name the cases the table names, in its order.
  for (const char* key : {"weakest_mean_tests", "weakest_variance_tests"}) {
    std::string line;
    for (const auto& w : j[key])
      line += fmt::format("{}{} {:.3g}%", line.empty() ? "" : ", ", w["case"].get<std::string>(),
                          100 * w["detectable"].get<double>());
    EXPECT_NE(table.find(line + "\n"), std::string::npos) << key << ": " << line;
  }
}

TEST(VerdictExport, HtmlShowsEveryCellWithFailingCasesFirst) {
  const std::string page = verdicts_html(verdicts(), kAlpha, "furnace verify (test)");
  EXPECT_EQ(page.rfind("<!DOCTYPE html>", 0), 0u);
  EXPECT_EQ(page.find("<script"), std::string::npos);
  EXPECT_EQ(page.find("http"), std::string::npos);  // nothing fetched from a network
  // The failing case's row comes first although it is second in the table;
  // the passing ones follow in table order.
  size_t row = 0;
  for (size_t i : {size_t(1), size_t(0), size_t(2)}) {
    row = page.find("<tr class=", row + 1);
    ASSERT_NE(row, std::string::npos);
    const std::string html_row = page.substr(row, page.find("</tr>", row) - row);
    EXPECT_EQ(html_row.rfind(verdicts()[i].pass ? "<tr class=\"pass\">" : "<tr class=\"fail\">", 0), 0u);
    for (const auto& [column, text] : verdict_cells(verdicts()[i]))
      EXPECT_NE(html_row.find(">" + text + "</td>"), std::string::npos) << column << " = " << text;
  }
}

}  // namespace
}  // namespace furnace::verify
