#include "verify/compare_report.h"

#include <cmath>
#include <filesystem>
#include <system_error>

#include <fmt/format.h>

#include "core/atomic_file.h"
#include "core/error.h"
#include "stats/statistics.h"
#include "stats/test_design.h"
#include "verify/image_report.h"
#include "verify/image_statistics.h"

namespace furnace::verify {

namespace {

using nlohmann::json;

std::string dof_text(double dof) { return std::isfinite(dof) ? fmt::format("{:.3g} d.o.f.", dof) : "normal"; }

std::string side_text(const char* name, int images, const std::string& method) {
  return method == "furnace variance" ? fmt::format("{}: one furnace EXR (its variance and N channels)", name)
                                      : fmt::format("{}: {} renders", name, images);
}

std::string joined(const std::vector<std::string>& words) {
  std::string out;
  for (const std::string& w : words) out += (out.empty() ? "" : ", ") + w;
  return out;
}

std::string advice_text(const CompareResult& r) {
  const CompareAdvice& a = r.advice;
  std::string text =
      fmt::format("to detect {} with power {}: ", percent_text(r.max_detectable_difference), stats::kReportedPower);
  text += a.renders_per_side > 0 ? fmt::format("{} renders per side at the current spp", a.renders_per_side)
                                 : fmt::format("more than {} renders per side at the current spp", 1000000);
  text += fmt::format(", or the current renders at {:.3g}x the spp", a.spp_factor);
  if (a.current_spp_a > 0 && a.current_spp_b > 0)
    text += fmt::format(" ({:.3g} and {:.3g} spp)", std::ceil(a.spp_factor * a.current_spp_a),
                        std::ceil(a.spp_factor * a.current_spp_b));
  text +=
      "; assumes each side's render-to-render spread of the image mean is the observed one and falls as "
      "1/sqrt(spp)\n";
  return text;
}

json estimate_json(const stats::MeanEstimate& e) {
  return {{"mean", json_number(e.mean)},
          {"standard_error", json_number(std::sqrt(e.variance_of_mean))},
          {"dof", json_number(e.dof)}};
}

PlotTools compare_plot_tools() {
  PlotTools tools = find_plot_tools();
  const std::filesystem::path script = std::filesystem::path(tools.script).parent_path() / "plot_compare.py";
  if (!std::filesystem::is_regular_file(script))
    throw Error(fmt::format("--html needs the plotting script '{}' beside '{}', and it is missing.", script.string(),
                            tools.script));
  tools.script = script.string();
  return tools;
}

void create_html_dir(const std::string& dir) {
  std::error_code error;
  std::filesystem::create_directories(dir, error);
  if (error || !std::filesystem::is_directory(dir))
    throw Error(fmt::format("--html directory '{}' cannot be created ({}).", dir,
                            error ? error.message() : "a file of that name exists"));
}

}  // namespace

std::vector<std::string> compare_warnings(const CompareSide& a, const CompareSide& b) {
  std::vector<std::string> warnings;
  const ImageProvenance& pa = a.images[0].provenance;
  const ImageProvenance& pb = b.images[0].provenance;
  if (!pa.scene.empty() && !pb.scene.empty() && pa.scene != pb.scene)
    warnings.push_back(fmt::format("image '{}' says it renders scene '{}' but '{}' says '{}'.", a.images[0].path,
                                   pa.scene, b.images[0].path, pb.scene));
  // The spp the headers state (furnace.spp, pbrt-v4's samplesPerPixel,
  // Blender's cycles.<layer>.samples): within a side, then across sides.
  const auto side_spp_warning = [&](const CompareSide& side, const char* name) {
    for (const ForeignImage& img : side.images)
      if (!img.stated_spp.empty() && !side.images[0].stated_spp.empty() && img.stated_spp != side.images[0].stated_spp)
        return fmt::format("side {} mixes spp: image '{}' states {} ({}) but '{}' states {} ({}); its renders are not "
                           "one distribution, so its spread is not their error.",
                           name, side.images[0].path, side.images[0].stated_spp, side.images[0].spp_attribute,
                           img.path, img.stated_spp, img.spp_attribute);
    return std::string();
  };
  for (const std::string& w : {side_spp_warning(a, "A"), side_spp_warning(b, "B")})
    if (!w.empty()) warnings.push_back(w);
  const ForeignImage& ia = a.images[0];
  const ForeignImage& ib = b.images[0];
  if (!ia.stated_spp.empty() && !ib.stated_spp.empty() && ia.stated_spp != ib.stated_spp)
    warnings.push_back(
        fmt::format("image '{}' states {} spp ({}) but '{}' states {} ({}); the means may still agree, but the "
                    "variance test compares the noise of one render, which differs with the spp (leave it out "
                    "with --no-variance-test).",
                    ia.path, ia.stated_spp, ia.spp_attribute, ib.path, ib.stated_spp, ib.spp_attribute));
  return warnings;
}

std::string format_compare(const CompareResult& r) {
  std::string out;
  const size_t channels = r.channels.size();
  out += fmt::format("{}; {}; {}x{} pixels, tiles of {}x{}, channels {}\n", side_text("A", r.images_a, r.method_a),
                     side_text("B", r.images_b, r.method_b), r.width, r.height, r.tile_size, r.tile_size,
                     channels == 1 ? r.channels[0].channel : "R, G, B separately");
  out += fmt::format(
      "family-wise alpha {} shared (Sidak) by {} families: image mean, tiles, pixels{}; "
      "Welch t with Welch-Satterthwaite d.o.f.\n",
      r.alpha, r.families, r.families == kCompareFamilies ? ", variance" : "");
  out += fmt::format(
      "detectable difference: relative to B, found with power {} (noncentral t), the spread at its {} "
      "upper confidence bound\n",
      stats::kReportedPower, kSpreadConfidence);
  for (size_t c = 0; c < channels; ++c) {
    const ChannelComparison& cc = r.channels[c];
    const std::string label = channels > 1 ? fmt::format(" [{}]", cc.channel) : "";
    const bool power = cc.detectable_relative_difference <= r.max_detectable_difference;
    out += fmt::format(
        "image mean{}: A {:.6g}, B {:.6g} ({:+.3g}%), t {:.3f} (critical {:.3f}, {}): {}; detectable "
        "difference {}: {}\n",
        label, cc.mean_a.mean, cc.mean_b.mean, 100 * (cc.mean_a.mean / cc.mean_b.mean - 1), cc.statistic, cc.threshold,
        dof_text(cc.dof), cc.image_mean_pass ? "same" : "DIFFERENT", percent_text(cc.detectable_relative_difference),
        power ? fmt::format("has power (<= {})", percent_text(r.max_detectable_difference))
              : fmt::format("LOW POWER (> {})", percent_text(r.max_detectable_difference)));
    out += fmt::format(
        "tiles{}: {}/{} differ (critical |t| {:.3g} for the median tile; worst t {:.3g} at tile ({}, {}), "
        "critical {:.3g} there), median detectable tile difference {}\n",
        label, cc.tile_failures, cc.tiles, cc.tile_threshold, cc.worst_tile_t, cc.worst_tile_x, cc.worst_tile_y,
        cc.worst_tile_threshold, percent_text(cc.median_tile_detectable_relative_difference));
    const std::string few =
        cc.pixels_few_values > 0
            ? fmt::format(", {} untested (their values repeat: {})", cc.pixels_few_values,
                          repeated_values_reason(r.half_float_a || r.half_float_b))
            : "";
    out += fmt::format(
        "pixels{}: {}/{} differ{} (critical |t| {:.3g} for the median pixel; worst t {:.3g} at ({}, "
        "{}), critical {:.3g} there), median detectable pixel difference {}\n",
        label, cc.pixel_failures, r.width * r.height, few, r.pixel_threshold[c], cc.worst_pixel_t, cc.worst_pixel_x,
        cc.worst_pixel_y, cc.worst_pixel_threshold, percent_text(cc.median_pixel_detectable_relative_difference));
    if (!cc.worst_held.empty())
      out += fmt::format(
          "rare-event guard{}: held {}{} tiles and {} pixels: Welch t rejects them, but the lower side's spread "
          "is below what the other side's noise per sample allows (as when its samples all missed a rare large "
          "contribution), so they are not judged; worst {}: t {:.3g}, guarded t {:.3g} (critical {:.3g}); both "
          "sides at {:.3g}x their spp would find a difference of that size with power 0.9\n",
          label, cc.image_mean_held ? "the image mean, " : "", cc.tiles_held, cc.pixels_held, cc.worst_held,
          cc.worst_held_t, cc.worst_held_guarded_t, cc.worst_held_threshold, cc.worst_held_spp_factor);
    if (!cc.variance_tested)
      out += fmt::format("variance{}: not tested (--no-variance-test)\n", label);
    else
      out += fmt::format(
          "variance{}: one render's summed pixel variance A/B = {:.4g}, z {:.3f} (critical {:.3f}): {}; "
          "detectable ratio {:.4g}\n",
          label, cc.variance_ratio, cc.variance_statistic, cc.variance_threshold,
          cc.variance_pass ? "same" : "DIFFERENT", cc.detectable_variance_ratio);
  }
  out += negative_values_text("side A", r.negative_a, r.images_a);
  out += negative_values_text("side B", r.negative_b, r.images_b);
  if (!r.rejected.empty()) out += fmt::format("different in: {}\n", joined(r.rejected));
  if (!r.held.empty()) {
    out += fmt::format("held by the rare-event guard, not judged: {}\n", joined(r.held));
    if (!r.guard_assumption.empty()) out += r.guard_assumption + "\n";
  }
  if (r.advice.needed) out += advice_text(r);
  if (r.verdict == CompareVerdict::kSame)
    out += fmt::format(
        "SAME means no difference of the stated size: none of {} or more of the image mean (found with power {}; "
        "this comparison detects {}), and none in a tile, pixel{} at its own level; a smaller difference may "
        "remain\n",
        percent_text(r.max_detectable_difference), stats::kReportedPower,
        percent_text(r.detectable_relative_difference), r.families == kCompareFamilies ? " or the variance" : "");
  out += fmt::format("verdict: {}\n", verdict_name(r.verdict));
  return out;
}

json compare_json(const CompareSide& a, const CompareSide& b, const CompareResult& r,
                  const std::vector<std::string>& warnings, ChannelMode channels_mode, const std::string& zmap_path) {
  json j;
  j["command"] = "compare";
  auto side = [](const CompareSide& s, const std::string& method, const NegativeValues& negative, bool half) {
    json paths = json::array(), spp = json::array();
    for (const ForeignImage& img : s.images) {
      paths.push_back(img.path);
      spp.push_back(img.stated_spp.empty() ? json(nullptr) : json(std::stoll(img.stated_spp)));
    }
    return json{{"images", paths},      {"image_count", s.images.size()}, {"method", method},
                {"stated_spp", spp},    {"half_float", half},             {"negative_values", negative_values_json(negative)}};
  };
  j["a"] = side(a, r.method_a, r.negative_a, r.half_float_a);
  j["b"] = side(b, r.method_b, r.negative_b, r.half_float_b);
  j["width"] = r.width;
  j["height"] = r.height;
  j["tile_size"] = r.tile_size;
  j["channels_mode"] = channel_mode_name(channels_mode);
  j["alpha"] = r.alpha;
  j["families"] = r.families;
  j["power"] = stats::kReportedPower;
  j["spread_confidence"] = kSpreadConfidence;
  j["max_detectable_difference"] = r.max_detectable_difference;
  json channels = json::array();
  for (size_t c = 0; c < r.channels.size(); ++c) {
    const ChannelComparison& cc = r.channels[c];
    channels.push_back(
        {{"channel", cc.channel},
         {"image_mean",
          {{"a", estimate_json(cc.mean_a)},
           {"b", estimate_json(cc.mean_b)},
           {"relative_difference", json_number(cc.mean_a.mean / cc.mean_b.mean - 1)},
           {"t", json_number(cc.statistic)},
           {"threshold", json_number(cc.threshold)},
           {"dof", json_number(cc.dof)},
           {"alpha", cc.alpha},
           {"detectable_relative_difference", json_number(cc.detectable_relative_difference)},
           {"guarded_t", json_number(cc.guarded_statistic)},
           {"held", cc.image_mean_held},
           {"pass", cc.image_mean_pass}}},
         {"tiles",
          {{"tiles", cc.tiles},
           {"failures", cc.tile_failures},
           {"held", cc.tiles_held},
           {"alpha", cc.tile_alpha},
           {"worst_t", json_number(cc.worst_tile_t)},
           {"worst_x", cc.worst_tile_x},
           {"worst_y", cc.worst_tile_y},
           {"worst_threshold", json_number(cc.worst_tile_threshold)},
           {"median_threshold", json_number(cc.tile_threshold)},
           {"median_detectable_relative_difference", json_number(cc.median_tile_detectable_relative_difference)}}},
         {"pixels",
          {{"failures", cc.pixel_failures},
           {"held", cc.pixels_held},
           {"few_values", cc.pixels_few_values},
           {"alpha", cc.pixel_alpha},
           {"median_threshold", json_number(r.pixel_threshold[c])},
           {"worst_t", json_number(cc.worst_pixel_t)},
           {"worst_x", cc.worst_pixel_x},
           {"worst_y", cc.worst_pixel_y},
           {"worst_threshold", json_number(cc.worst_pixel_threshold)},
           {"median_detectable_relative_difference", json_number(cc.median_pixel_detectable_relative_difference)}}},
         {"worst_held",
          cc.worst_held.empty() ? json(nullptr)
                                : json{{"test", cc.worst_held},
                                       {"t", json_number(cc.worst_held_t)},
                                       {"guarded_t", json_number(cc.worst_held_guarded_t)},
                                       {"threshold", json_number(cc.worst_held_threshold)},
                                       {"spp_factor", json_number(cc.worst_held_spp_factor)}}},
         {"variance",
          {{"tested", cc.variance_tested},
           {"sum_a", json_number(cc.sum_variance_a)},
           {"sum_b", json_number(cc.sum_variance_b)},
           {"ratio", json_number(cc.variance_ratio)},
           {"log_ratio_standard_error", json_number(cc.log_ratio_standard_error)},
           {"z", json_number(cc.variance_statistic)},
           {"threshold", json_number(cc.variance_threshold)},
           {"alpha", cc.variance_alpha},
           {"detectable_ratio", json_number(cc.detectable_variance_ratio)},
           {"pass", cc.variance_pass}}}});
  }
  j["channels"] = channels;
  j["detectable_relative_difference"] = json_number(r.detectable_relative_difference);
  j["image_mean_has_power"] = r.image_mean_has_power;
  j["rejected"] = r.rejected;
  j["held"] = r.held;
  j["rare_event_guard"] = {{"spp_a", r.guard_spp_a > 0 ? json(r.guard_spp_a) : json("N per pixel")},
                           {"spp_b", r.guard_spp_b > 0 ? json(r.guard_spp_b) : json("N per pixel")},
                           {"assumption", r.guard_assumption.empty() ? json(nullptr) : json(r.guard_assumption)}};
  if (r.advice.needed)
    j["advice"] = {{"renders_per_side", r.advice.renders_per_side},
                   {"spp_factor", json_number(r.advice.spp_factor)},
                   {"current_spp_a", r.advice.current_spp_a > 0 ? json(r.advice.current_spp_a) : json(nullptr)},
                   {"current_spp_b", r.advice.current_spp_b > 0 ? json(r.advice.current_spp_b) : json(nullptr)}};
  else
    j["advice"] = nullptr;
  add_outcome(j, warnings, zmap_path, verdict_name(r.verdict), exit_code(r.verdict));
  return j;
}

void write_compare_zmap(const std::string& path, const CompareResult& r) {
  std::vector<std::string> names;
  for (const ChannelComparison& cc : r.channels) names.push_back(cc.channel);
  write_t_map(path, r.width, r.height, names, r.pixel_t, r.pixel_threshold, "furnace.compare.",
              {{"verdict", verdict_name(r.verdict)}, {"difference", "A - B"}});
}

PlotTools prepare_compare_html(const std::string& dir) {
  PlotTools tools = compare_plot_tools();
  create_html_dir(dir);
  return tools;
}

void write_compare_html(const PlotTools& tools, const std::string& dir, json report, const CompareResult& r) {
  json images = json::array();
  for (size_t c = 0; c < r.channels.size(); ++c) {
    std::vector<json> t(r.pixel_t[c].size()), tile_t(r.tile_t[c].size());
    for (size_t i = 0; i < t.size(); ++i) t[i] = json_number(r.pixel_t[c][i]);
    for (size_t i = 0; i < tile_t.size(); ++i) tile_t[i] = json_number(r.tile_t[c][i]);
    images.push_back({{"channel", r.channels[c].channel},
                      {"mean_a", r.mean_a[c]},
                      {"mean_b", r.mean_b[c]},
                      {"pixel_t", t},
                      {"tile_t", tile_t}});
  }
  report["tiles_x"] = r.tiles_x;
  report["tiles_y"] = r.tiles_y;
  report["images"] = images;
  report["report_text"] = format_compare(r);
  write_text_file_atomically(std::filesystem::path(dir) / "compare.json", report.dump(), "compare JSON");
  const int status = run_plot_script(tools, dir);
  if (status != 0)
    throw Error(fmt::format("the plotting script '{}' failed (exit {}) on '{}'.", tools.script, status, dir));
}

}  // namespace furnace::verify
