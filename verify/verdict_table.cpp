#include "verify/verdict_table.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "stats/pixel_tests.h"
#include "stats/test_design.h"

namespace furnace::verify {

const char* verdict_label(VerdictKind kind) {
  switch (kind) {
    case VerdictKind::kPass: return "pass";
    case VerdictKind::kBiased: return "FAIL biased";
    case VerdictKind::kVarianceMismatch: return "FAIL variance";
    case VerdictKind::kInconclusive: return "INCONCLUSIVE";
  }
  return "";
}

std::string strategy_label(const Verdict& v) { return v.defect == "none" ? v.strategy : v.strategy + "+" + v.defect; }

std::string variance_detect_cell(const Verdict& v) {
  if (!v.variance_tested) return "-";
  return std::isfinite(v.variance_detectable_rel_error) ? fmt::format("{:.3g}%", 100 * v.variance_detectable_rel_error)
                                                         : std::string("exact");
}

std::vector<const Verdict*> weakest_cases(const std::vector<Verdict>& verdicts, double Verdict::*detect,
                                          bool (*applies)(const Verdict&), size_t count) {
  std::vector<const Verdict*> cases;
  for (const Verdict& v : verdicts)
    if (applies(v) && std::isfinite(v.*detect)) cases.push_back(&v);
  std::stable_sort(cases.begin(), cases.end(),
                   [&](const Verdict* a, const Verdict* b) { return a->*detect > b->*detect; });
  cases.resize(std::min(count, cases.size()));
  return cases;
}

namespace {

// "a 1.2%, b 0.9%, …", or "none".
std::string weakest(const std::vector<Verdict>& verdicts, double Verdict::*detect, bool (*applies)(const Verdict&),
                    size_t count) {
  std::string out;
  for (const Verdict* v : weakest_cases(verdicts, detect, applies, count))
    out += fmt::format("{}{} {} {:.3g}%", out.empty() ? "" : ", ", v->scene, strategy_label(*v), 100 * (v->*detect));
  return out.empty() ? "none" : out;
}

}  // namespace

std::string format_table(const std::vector<Verdict>& verdicts, double family_alpha) {
  std::string out;
  out += fmt::format("family-wise alpha {} (Sidak over {} cases, each over its pixels + image mean); "
                     "detectable bias and variance error at power {}\n",
                     family_alpha, verdicts.size(), stats::kReportedPower);
  out += fmt::format("{:<22} {:<24} {:>6} {:>10} {:>10} {:>7} {:>6} {:>9} {:>7} {:>9} {:>9} {:>9} {:>10} {:>7} {:>10}  {}\n",
                     "scene", "strategy", "spp", "mean", "reference", "z", "z crit", "px fail", "px skip", "rel RMSE",
                     "detect", "px detect", "var detect", "time s", "Msamples/s", "verdict");
  for (const Verdict& v : verdicts) {
    const std::string strategy = strategy_label(v);
    const VerdictKind kind = verdict_kind(v);
    const std::string variance_detect = variance_detect_cell(v);
    out += fmt::format("{:<22} {:<24} {:>6} {:>10.6g} {:>10.6g} {:>7.3f} {:>6.2f} {:>4}/{:<4} {:>7} {:>9.3g} {:>8.3g}% {:>8.3g}% {:>10} {:>7.3f} {:>10.3g}  {}\n",
                       v.scene, strategy, v.spp, v.image_mean, v.reference_mean, v.z, v.threshold,
                       v.pixel_failures, v.pixels, v.pixels_untested,
                       v.reference_mean > 0 ? v.rmse / v.reference_mean : v.rmse, 100 * v.detectable_rel_bias,
                       100 * v.median_pixel_detectable_rel_bias, variance_detect, v.seconds,
                       v.samples_per_second / 1e6, verdict_label(kind));
    if (v.variance_tested)
      out += fmt::format("    variance: measured {:.6g}, predicted {:.6g} (mean per pixel), z {:.3f}, {} pixel outliers (not in verdict), "
                         "detectable {:.3g}%\n",
                         v.measured_variance, v.predicted_variance, v.variance_z, v.variance_pixel_failures,
                         100 * v.variance_detectable_rel_error);
    if (!v.variance_skipped.empty()) out += fmt::format("    variance: skipped ({})\n", v.variance_skipped);
    if (v.nonfinite_samples > 0)
      out += fmt::format("    non-finite samples: {} (NaN or Inf, dropped from the image): the case fails\n",
                         v.nonfinite_samples);
    if (kind != VerdictKind::kPass) out += fmt::format("    {}\n", verdict_explanation(v));
    if (kind == VerdictKind::kBiased || kind == VerdictKind::kInconclusive)
      out += fmt::format("    worst pixel ({}, {}): mean {:.6g}, reference {:.6g}, sample variance {:.3g}, |t| {:.3g}\n",
                         v.worst_px, v.worst_py, v.worst_pixel_mean, v.worst_pixel_reference,
                         v.worst_pixel_sample_variance, v.worst_pixel_t);
  }
  const auto skipped = std::count_if(verdicts.begin(), verdicts.end(),
                                     [](const Verdict& v) { return !v.variance_skipped.empty(); });
  if (skipped > 0)
    out += fmt::format("skipped: the variance test of {} case(s), fewer than {} samples per pixel (the verdicts rest "
                       "on the mean tests)\n",
                       skipped, stats::kMinVarianceTestSamples);
  out += fmt::format("weakest mean tests (detect): {}\n",
                     weakest(verdicts, &Verdict::detectable_rel_bias, [](const Verdict&) { return true; },
                             kWeakestCasesListed));
  out += fmt::format("weakest variance tests (var detect): {}\n",
                     weakest(verdicts, &Verdict::variance_detectable_rel_error,
                             [](const Verdict& v) { return v.variance_tested; }, kWeakestCasesListed));
  return out;
}

}  // namespace furnace::verify
