#include "verify/verdict_export.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/atomic_file.h"
#include "core/provenance.h"
#include "stats/statistics.h"
#include "stats/test_design.h"

namespace furnace::verify {

namespace {

std::string case_label(const Verdict& v) { return v.scene + " " + strategy_label(v); }

// nlohmann writes a non-finite double as null; say so explicitly.
nlohmann::ordered_json number(double x) {
  return std::isfinite(x) ? nlohmann::ordered_json(x) : nlohmann::ordered_json(nullptr);
}

std::string escape_html(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

nlohmann::ordered_json weakest_json(const std::vector<const Verdict*>& cases, double Verdict::*detect) {
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (const Verdict* v : cases) out.push_back({{"case", case_label(*v)}, {"detectable", v->*detect}});
  return out;
}

bool every_case(const Verdict&) { return true; }
bool variance_case(const Verdict& v) { return v.variance_tested; }

}  // namespace

std::vector<std::pair<std::string, std::string>> verdict_cells(const Verdict& v) {
  std::vector<std::pair<std::string, std::string>> cells = {
      {"scene", v.scene},
      {"strategy", strategy_label(v)},
      {"spp", fmt::format("{}", v.spp)},
      {"mean", fmt::format("{:.6g}", v.image_mean)},
      {"reference", fmt::format("{:.6g}", v.reference_mean)},
      {"z", fmt::format("{:.3f}", v.z)},
      {"z crit", fmt::format("{:.2f}", v.threshold)},
      {"px fail", fmt::format("{}/{}", v.pixel_failures, v.pixels)},
      {"px skip", fmt::format("{}", v.pixels_untested)},
      {"rel RMSE", fmt::format("{:.3g}", v.reference_mean > 0 ? v.rmse / v.reference_mean : v.rmse)},
      {"detect", fmt::format("{:.3g}%", 100 * v.detectable_rel_bias)},
      {"px detect", fmt::format("{:.3g}%", 100 * v.median_pixel_detectable_rel_bias)},
      {"var detect", variance_detect_cell(v)},
      {"var measured", v.variance_tested ? fmt::format("{:.6g}", v.measured_variance) : "-"},
      {"var predicted", v.variance_tested ? fmt::format("{:.6g}", v.predicted_variance) : "-"},
      {"var z", v.variance_tested ? fmt::format("{:.3f}", v.variance_z) : "-"},
      {"var outliers", v.variance_tested ? fmt::format("{}", v.variance_pixel_failures) : "-"},
      {"time s", fmt::format("{:.3f}", v.seconds)},
      {"Msamples/s", fmt::format("{:.3g}", v.samples_per_second / 1e6)},
      {"verdict", verdict_label(verdict_kind(v))},
  };
  return cells;
}

std::string verdicts_json(const std::vector<Verdict>& verdicts, double family_alpha) {
  nlohmann::ordered_json j;
  j["generator"] = "furnace " + furnace_version();
  j["family_alpha"] = family_alpha;
  j["power"] = stats::kReportedPower;
  bool all_pass = true;
  size_t skipped = 0;
  j["cases"] = nlohmann::ordered_json::array();
  for (const Verdict& v : verdicts) {
    all_pass = all_pass && v.pass;
    skipped += v.variance_skipped.empty() ? 0 : 1;
    const VerdictKind kind = verdict_kind(v);
    nlohmann::ordered_json table;
    for (const auto& [column, text] : verdict_cells(v)) table[column] = text;
    j["cases"].push_back({
        {"scene", v.scene},
        {"strategy", v.strategy},
        {"defect", v.defect},
        {"spp", v.spp},
        {"pixels", v.pixels},
        {"image_mean", number(v.image_mean)},
        {"reference_mean", number(v.reference_mean)},
        {"z", number(v.z)},
        {"threshold", number(v.threshold)},
        {"detectable_rel_bias", number(v.detectable_rel_bias)},
        {"pixel_failures", v.pixel_failures},
        {"pixels_untested", v.pixels_untested},
        {"median_pixel_detectable_rel_bias", number(v.median_pixel_detectable_rel_bias)},
        {"worst_pixel", {{"x", v.worst_px}, {"y", v.worst_py}, {"t", number(v.worst_pixel_t)},
                         {"mean", number(v.worst_pixel_mean)}, {"reference", number(v.worst_pixel_reference)},
                         {"sample_variance", number(v.worst_pixel_sample_variance)}}},
        {"variance_tested", v.variance_tested},
        {"variance_skipped", v.variance_skipped},
        {"measured_variance", number(v.measured_variance)},
        {"predicted_variance", number(v.predicted_variance)},
        {"variance_z", number(v.variance_z)},
        {"variance_detectable_rel_error", number(v.variance_detectable_rel_error)},
        {"variance_pixel_failures", v.variance_pixel_failures},
        {"variance_pass", v.variance_pass},
        {"rmse", number(v.rmse)},
        {"relative_rmse", number(v.reference_mean > 0 ? v.rmse / v.reference_mean : v.rmse)},
        {"nonfinite_samples", v.nonfinite_samples},
        {"seconds", number(v.seconds)},
        {"samples_per_second", number(v.samples_per_second)},
        {"mean_pass", v.mean_pass},
        {"pass", v.pass},
        {"verdict", verdict_label(kind)},
        {"explanation", verdict_explanation(v)},
        {"exact_variance", v.exact_variance},
        {"calibrated_from_spp", v.calibrated_from_spp},
        {"table", table},
    });
  }
  j["pass"] = all_pass;
  j["verdict"] = run_outcome_word(run_outcome(verdicts));
  j["variance_skipped_cases"] = skipped;
  j["weakest_mean_tests"] = weakest_json(
      weakest_cases(verdicts, &Verdict::detectable_rel_bias, every_case, kWeakestCasesListed),
      &Verdict::detectable_rel_bias);
  j["weakest_variance_tests"] = weakest_json(
      weakest_cases(verdicts, &Verdict::variance_detectable_rel_error, variance_case, kWeakestCasesListed),
      &Verdict::variance_detectable_rel_error);
  return j.dump(2) + "\n";
}

std::string verdicts_html(const std::vector<Verdict>& verdicts, double family_alpha, const std::string& command_line) {
  // Failing cases first, each group in the table's order.
  std::vector<const Verdict*> rows;
  for (const Verdict& v : verdicts) rows.push_back(&v);
  std::stable_partition(rows.begin(), rows.end(), [](const Verdict* v) { return !v->pass; });
  const size_t failures = size_t(std::count_if(verdicts.begin(), verdicts.end(), [](const Verdict& v) { return !v.pass; }));

  std::string h;
  h += "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>furnace verify</title>\n<style>\n"
       "body{font-family:sans-serif;margin:1.5em;color:#222}table{border-collapse:collapse;font-size:12px}\n"
       "th,td{border:1px solid #ccc;padding:2px 6px;text-align:right;white-space:nowrap}\n"
       "td.l,th.l{text-align:left}tr.fail td{background:#fde0dc}tr.pass td.v{color:#1a7f37}\n"
       "tr.fail td.v{color:#b3261e;font-weight:bold}td.note{text-align:left;white-space:normal;color:#555;"
       "border-top:none;padding-left:2em}\n"
       "</style></head><body>\n";
  h += fmt::format("<h1>furnace verify: {}</h1>\n", run_outcome_word(run_outcome(verdicts)));
  h += fmt::format("<p>{} cases, {} failing (listed first). Family-wise &alpha; {} (&Scaron;id&aacute;k over the "
                   "cases, each over its pixels + image mean + variance test); detectable bias and variance error at "
                   "power {}. Generated by <code>{}</code> ({}).</p>\n",
                   verdicts.size(), failures, family_alpha, stats::kReportedPower, escape_html(command_line),
                   escape_html("furnace " + furnace_version()));
  h += "<p>z: image-mean statistic against z crit; px fail: pixels whose t test rejects / pixels; px skip: pixels "
       "too skewed to t-test at this spp; detect: smallest relative bias of the image mean found with that power; "
       "var z, var detect: the aggregate variance test against the analytic second moment (- where not modelled, "
       "exact where the predicted variance is 0).</p>\n<table>\n<tr>";
  const std::vector<std::pair<std::string, std::string>> header = verdict_cells(Verdict{});
  for (const auto& [column, text] : header)
    h += fmt::format("<th{}>{}</th>", column == "scene" || column == "strategy" ? " class=\"l\"" : "",
                     escape_html(column));
  h += "</tr>\n";
  for (const Verdict* v : rows) {
    const VerdictKind kind = verdict_kind(*v);
    h += fmt::format("<tr class=\"{}\">", v->pass ? "pass" : "fail");
    for (const auto& [column, text] : verdict_cells(*v)) {
      const char* cls = column == "scene" || column == "strategy" ? " class=\"l\"" : column == "verdict" ? " class=\"v\"" : "";
      h += fmt::format("<td{}>{}</td>", cls, escape_html(text));
    }
    std::string notes;
    if (!v->variance_skipped.empty()) notes += "variance: skipped (" + v->variance_skipped + "). ";
    if (v->nonfinite_samples > 0)
      notes += fmt::format("non-finite samples: {} (NaN or Inf, dropped from the image): the case fails. ",
                           v->nonfinite_samples);
    if (kind != VerdictKind::kPass) notes += verdict_explanation(*v) + ". ";
    if (kind == VerdictKind::kBiased || kind == VerdictKind::kInconclusive)
      notes += fmt::format("worst pixel ({}, {}): mean {:.6g}, reference {:.6g}, sample variance {:.3g}, |t| {:.3g}.",
                           v->worst_px, v->worst_py, v->worst_pixel_mean, v->worst_pixel_reference,
                           v->worst_pixel_sample_variance, v->worst_pixel_t);
    h += "</tr>\n";
    // Notes on a row of their own under the case, across the table.
    if (!notes.empty())
      h += fmt::format("<tr><td class=\"note\" colspan=\"{}\">{}</td></tr>\n", header.size(), escape_html(notes));
  }
  h += "</table>\n";
  const auto weakest_line = [&](double Verdict::*detect, bool (*applies)(const Verdict&)) {
    std::string out;
    for (const Verdict* v : weakest_cases(verdicts, detect, applies, kWeakestCasesListed))
      out += fmt::format("{}{} {:.3g}%", out.empty() ? "" : ", ", case_label(*v), 100 * (v->*detect));
    return out.empty() ? std::string("none") : out;
  };
  h += fmt::format("<p>Weakest mean tests (detect): {}<br>Weakest variance tests (var detect): {}</p>\n",
                   escape_html(weakest_line(&Verdict::detectable_rel_bias, every_case)),
                   escape_html(weakest_line(&Verdict::variance_detectable_rel_error, variance_case)));
  h += "</body></html>\n";
  return h;
}

void write_verdicts_json(const std::vector<Verdict>& verdicts, double family_alpha, const std::string& path) {
  write_text_file_atomically(path, verdicts_json(verdicts, family_alpha), "JSON file");
}

void write_verdicts_html(const std::vector<Verdict>& verdicts, double family_alpha, const std::string& command_line,
                         const std::string& dir) {
  std::filesystem::create_directories(dir);
  write_text_file_atomically(std::filesystem::path(dir) / "index.html",
                             verdicts_html(verdicts, family_alpha, command_line), "HTML file");
}

}  // namespace furnace::verify
