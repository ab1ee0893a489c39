#include "verify/check_report.h"

#include <cmath>

#include <fmt/format.h>

#include "core/provenance.h"
#include "core/strategy.h"
#include "stats/test_design.h"
#include "verify/image_report.h"
#include "verify/image_statistics.h"

namespace furnace::verify {

namespace {

using nlohmann::json;

bool is_path_tracer_name(const std::string& name) {
  for (Strategy s : path_tracing_strategies())
    if (strategy_name(s) == name) return true;
  return false;
}

std::string dof_text(double dof) { return std::isfinite(dof) ? fmt::format("{:g} d.o.f.", dof) : "normal"; }

std::string advice_text(const CheckResult& r) {
  const CheckAdvice& a = r.advice;
  const std::string target = percent_text(r.max_detectable_bias);
  auto spp = [&](double factor) {
    return a.current_spp > 0 ? fmt::format(" ({:.3g} spp)", std::ceil(factor * a.current_spp)) : std::string();
  };
  std::string text = fmt::format("to detect {} with power {}: ", target, stats::kReportedPower);
  const std::string current = a.current_spp > 0 ? fmt::format("{:g} spp", a.current_spp) : "the current spp";
  text += a.images_at_current_spp > 0 ? fmt::format("{} images at {}", a.images_at_current_spp, current)
                                      : fmt::format("more than {} images at {}", 1000000, current);
  if (a.advised_images != r.images)
    text += fmt::format(", or {} images at {:.3g}x the spp{}", a.advised_images, a.spp_factor_at_advised_images,
                        spp(a.spp_factor_at_advised_images));
  text += fmt::format(", or these {} image(s) at {:.3g}x the spp{}", r.images, a.spp_factor_at_current_images,
                      spp(a.spp_factor_at_current_images));
  text += "; assumes the true spread of an image's mean is the observed one and falls as 1/sqrt(spp) (independent "
          "samples), and that the check of K images bounds it from K - 1 d.o.f. as this one does\n";
  return text;
}

std::string spp_text(double spp) { return spp > 0 ? fmt::format("{:.6g} spp", spp) : "the EXR's N"; }

// The rare-event guard's line: what it took, and the worst test it held.
std::string guard_text(const CheckResult& r) {
  const CheckGuard& g = r.guard;
  if (g.guard_images == 0) {
    if (r.rejected_below_unguarded)
      return "note: a test rejected below the reference; a rare contribution that no sample of these images met "
             "looks the same, and only renders of the same renderer at a higher spp tell them apart: --guard "
             "IMAGE ... (docs/checking.md)\n";
    return "";
  }
  std::string text = fmt::format("rare-event guard: {} guard image(s) at {}, these images at {}; below the "
                                 "reference each test's variance is floored at the guard's per sample (its {} "
                                 "lower confidence bound)",
                                 g.guard_images, spp_text(g.guard_spp), spp_text(g.checked_spp), kSpreadConfidence);
  if (!g.assumption.empty()) text += fmt::format("; {}", g.assumption);
  text += "\n";
  if (g.worst_held.empty()) return text + "  held: none\n";
  std::string families;
  for (const std::string& f : g.held) families += (families.empty() ? "" : ", ") + f;
  text += fmt::format("  held ({}): worst {}{}: t {:.3g}, guarded t {:.3g} (critical {:.3g}); these images at {:.3g}x "
                      "their spp would find a bias of that size with power {}\n",
                      families, g.worst_held, r.channels.size() > 1 ? " [" + g.worst_held_channel + "]" : "",
                      g.worst_held_t, g.worst_held_guarded_t, g.worst_held_threshold, g.worst_held_spp_factor,
                      stats::kReportedPower);
  return text;
}

}  // namespace

std::vector<std::string> provenance_warnings(const Scene& scene, const std::string& scene_hash,
                                             const std::vector<ForeignImage>& images, const CheckReference& reference) {
  std::vector<std::string> warnings;
  for (const ForeignImage& img : images) {
    const ImageProvenance& p = img.provenance;
    if (!p.scene.empty() && p.scene != scene.name)
      warnings.push_back(fmt::format("image '{}' says it is a render of scene '{}', not of '{}' ({}).", img.path,
                                     p.scene, scene.name, scene.source));
    else if (!p.scene_hash.empty() && p.scene_hash != scene_hash)
      warnings.push_back(fmt::format("image '{}' was rendered from a scene file with hash {}, but '{}' now hashes to "
                                     "{} (the file changed since).",
                                     img.path, p.scene_hash, scene.source, scene_hash));
    if (!p.defect.empty() && p.defect != "none")
      warnings.push_back(fmt::format("image '{}' says it was rendered with the negative-control defect '{}'.",
                                     img.path, p.defect));
    if (!p.convention.empty() && !reference.convention.empty() && p.convention != reference.convention)
      warnings.push_back(fmt::format("image '{}' was rendered in the '{}' transport convention, but the reference is "
                                     "checked in '{}' (--convention).",
                                     img.path, p.convention, reference.convention));
    if (is_path_tracer_name(p.strategy) && !p.max_depth.empty() && p.max_depth != depth_name(reference.max_segments))
      warnings.push_back(fmt::format("image '{}' was rendered by {} with max depth {}, but the reference is {}.",
                                     img.path, p.strategy, p.max_depth, reference.description));
  }
  return warnings;
}

std::string format_check(const Scene& scene, const CheckReference& reference, const CheckResult& r) {
  std::string out;
  const size_t channels = r.channels.size();
  out += fmt::format("scene {} ({}): {} image(s), {} pixels, channels {}\n", scene.name, scene.source, r.images,
                     r.pixels, channels == 1 ? r.channels[0].channel : "R, G, B separately");
  out += fmt::format("reference: {}\n", reference.description);
  if (!reference.note.empty()) out += fmt::format("  (no global answer: {})\n", reference.note);
  out += fmt::format("method: {}; family-wise alpha {}: {} to the image mean{}, {} shared by {} pixel tests (Sidak)\n",
                     r.method, r.alpha, r.alpha * kImageMeanAlphaShare, channels > 1 ? "s" : "",
                     r.alpha * (1 - kImageMeanAlphaShare), size_t(r.pixels) * channels);
  out += fmt::format("detectable bias: found with power {} (noncentral t), the spread taken at its {} upper "
                     "confidence bound\n",
                     stats::kReportedPower, kSpreadConfidence);
  const std::string statistic = r.method == "furnace variance" ? "z" : "t";
  if (r.method == "furnace variance")
    out += "note: one image: its pixel t-tests have no skewness correction (the EXR stores no third moment), so for "
           "strongly skewed estimators (path tracing in enclosures) they reject somewhat more often than alpha; K >= 2 "
           "renders avoid this\n";
  for (const ChannelCheck& c : r.channels) {
    const std::string label = channels > 1 ? fmt::format(" [{}]", c.channel) : "";
    const bool power = c.detectable_relative_bias <= r.max_detectable_bias;
    out += fmt::format("image mean{}: {:.6g}, reference {:.6g}, {} {:.3f} (critical {:.3f}, {}): {}; detectable bias "
                       "{}: {}\n",
                       label, c.image_mean, c.reference_mean, statistic, c.statistic, c.threshold, dof_text(c.dof),
                       c.image_mean_held ? fmt::format("held (guarded {} {:.3f})", statistic, c.guarded_statistic)
                                         : (c.image_mean_pass ? "agrees" : "REJECTED"),
                       percent_text(c.detectable_relative_bias),
                       power ? fmt::format("has power (<= {})", percent_text(r.max_detectable_bias))
                             : fmt::format("LOW POWER (> {})", percent_text(r.max_detectable_bias)));
    const bool pixel_power = c.median_pixel_detectable_relative_bias <= r.max_detectable_bias;
    std::string untested =
        c.pixels_untested > 0 ? fmt::format(", {} untested (constant yet off the reference)", c.pixels_untested) : "";
    if (c.pixels_held > 0) untested += fmt::format(", {} held (rare-event guard)", c.pixels_held);
    if (c.pixels_few_values > 0)
      untested += fmt::format(", {} untested (their {} values take at most {} distinct values, {}: the spread does "
                              "not estimate their error)",
                              c.pixels_few_values, r.images, r.images / kFewValuesDivisor,
                              repeated_values_reason(r.half_float));
    out += fmt::format("pixels{}: {}/{} fail{} (critical |t| {:.3g}, {}), median detectable pixel bias {}: {}; "
                       "relative RMSE {:.3e}\n",
                       label, c.pixel_failures, r.pixels, untested, c.pixel_threshold, dof_text(c.pixel_dof),
                       percent_text(c.median_pixel_detectable_relative_bias),
                       pixel_power ? "have power"
                                   : fmt::format("low power (only local errors above {} are caught)",
                                                 percent_text(c.median_pixel_detectable_relative_bias)),
                       c.relative_rmse);
  }
  if (r.negative.values > 0)
    out += negative_values_text("the images", r.negative, r.images) +
           "  (the reference is non-negative: the tests above include them; many or large ones are a bias they may "
           "find)\n";
  out += "worst pixels (x, y, channel: value, reference, t):\n";
  for (const WorstPixel& w : r.worst_pixels)
    out += fmt::format("  ({}, {}) {}: {:.6g}, {:.6g}, {:.3g}{}\n", w.x, w.y, w.channel, w.value, w.reference, w.t,
                       w.untested ? " (untested)" : (w.held ? " (held)" : ""));
  out += guard_text(r);
  if (r.advice.needed) out += advice_text(r);
  out += fmt::format("verdict: {}\n", verdict_name(r.verdict));
  return out;
}

json check_json(const Scene& scene, const std::string& scene_hash, const CheckReference& reference,
                const std::vector<ForeignImage>& images, const CheckResult& r, const std::vector<std::string>& warnings,
                ChannelMode channels_mode, const std::string& zmap_path, const std::vector<ForeignImage>& guard) {
  json j;
  j["command"] = "check";
  j["scene"] = {{"name", scene.name}, {"file", scene.source}, {"hash", scene_hash}};
  j["reference"] = {{"kind", reference.global ? "global" : "direct"},
                    {"max_depth", depth_name(reference.max_segments)},
                    {"description", reference.description},
                    {"note", reference.note}};
  json image_list = json::array();
  for (const ForeignImage& img : images) {
    json p = json::object();
    for (const auto& [name, value] : img.provenance.attributes()) p[name] = value;
    image_list.push_back({{"path", img.path},
                          {"has_variance", img.has_variance()},
                          {"provenance", p},
                          {"stated_spp", img.stated_spp.empty() ? json(nullptr) : json(std::stoll(img.stated_spp))},
                          {"half_float", img.half_float},
                          {"negative_values", img.negative_values}});
  }
  j["images"] = image_list;
  j["image_count"] = r.images;
  j["negative_values"] = negative_values_json(r.negative);
  j["half_float"] = r.half_float;
  j["pixels"] = r.pixels;
  j["pixel_tests"] = r.pixels * int(r.channels.size());
  j["channels_mode"] = channel_mode_name(channels_mode);
  j["method"] = r.method;
  j["alpha"] = r.alpha;
  j["image_mean_alpha_share"] = kImageMeanAlphaShare;
  j["power"] = stats::kReportedPower;
  j["spread_confidence"] = kSpreadConfidence;
  j["max_detectable_bias"] = r.max_detectable_bias;
  json channels = json::array();
  for (const ChannelCheck& c : r.channels)
    channels.push_back({{"channel", c.channel},
                        {"image_mean", json_number(c.image_mean)},
                        {"reference_mean", json_number(c.reference_mean)},
                        {"standard_error", json_number(c.standard_error)},
                        {"statistic", json_number(c.statistic)},
                        {"threshold", json_number(c.threshold)},
                        {"dof", json_number(c.dof)},
                        {"alpha", c.alpha},
                        {"detectable_relative_bias", json_number(c.detectable_relative_bias)},
                        {"image_mean_pass", c.image_mean_pass},
                        {"image_mean_held", c.image_mean_held},
                        {"guarded_statistic", json_number(c.guarded_statistic)},
                        {"pixels_held", c.pixels_held},
                        {"pixel_failures", c.pixel_failures},
                        {"pixels_untested", c.pixels_untested},
                        {"pixels_few_values", c.pixels_few_values},
                        {"pixel_alpha", c.pixel_alpha},
                        {"pixel_threshold", json_number(c.pixel_threshold)},
                        {"pixel_dof", json_number(c.pixel_dof)},
                        {"median_pixel_detectable_relative_bias", json_number(c.median_pixel_detectable_relative_bias)},
                        {"relative_rmse", json_number(c.relative_rmse)}});
  j["channels"] = channels;
  j["detectable_relative_bias"] = json_number(r.detectable_relative_bias);
  j["image_mean_has_power"] = r.image_mean_has_power;
  j["pixels_have_power"] = r.pixels_have_power;
  json worst = json::array();
  for (const WorstPixel& w : r.worst_pixels)
    worst.push_back({{"x", w.x}, {"y", w.y}, {"channel", w.channel}, {"value", json_number(w.value)},
                     {"reference", json_number(w.reference)}, {"t", json_number(w.t)}, {"untested", w.untested},
                     {"held", w.held}});
  j["worst_pixels"] = worst;
  if (r.guard.guard_images > 0) {
    const CheckGuard& g = r.guard;
    json paths = json::array();
    for (const ForeignImage& img : guard) paths.push_back(img.path);
    j["rare_event_guard"] = {
        {"images", paths},
        {"guard_spp", g.guard_spp > 0 ? json(g.guard_spp) : json(nullptr)},
        {"checked_spp", g.checked_spp > 0 ? json(g.checked_spp) : json(nullptr)},
        {"assumption", g.assumption},
        {"held", g.held},
        {"worst_held", g.worst_held.empty()
                           ? json(nullptr)
                           : json({{"test", g.worst_held},
                                   {"channel", g.worst_held_channel},
                                   {"t", json_number(g.worst_held_t)},
                                   {"guarded_t", json_number(g.worst_held_guarded_t)},
                                   {"threshold", json_number(g.worst_held_threshold)},
                                   {"spp_factor", json_number(g.worst_held_spp_factor)}})}};
  } else {
    j["rare_event_guard"] = nullptr;
  }
  j["rejected_below_unguarded"] = r.rejected_below_unguarded;
  if (r.advice.needed)
    j["advice"] = {{"images_at_current_spp", r.advice.images_at_current_spp},
                   {"spp_factor_at_current_images", json_number(r.advice.spp_factor_at_current_images)},
                   {"advised_images", r.advice.advised_images},
                   {"spp_factor_at_advised_images", json_number(r.advice.spp_factor_at_advised_images)},
                   {"current_spp", r.advice.current_spp > 0 ? json(r.advice.current_spp) : json(nullptr)}};
  else
    j["advice"] = nullptr;
  add_outcome(j, warnings, zmap_path, verdict_name(r.verdict), exit_code(r.verdict));
  return j;
}

void write_zmap(const std::string& path, const Scene& scene, const CheckResult& r) {
  std::vector<std::string> channels;
  std::vector<double> critical_t;
  for (const ChannelCheck& c : r.channels) {
    channels.push_back(c.channel);
    critical_t.push_back(c.pixel_threshold);
  }
  write_t_map(path, scene.camera.width_px, scene.camera.height_px, channels, r.pixel_t, critical_t,
              "furnace.check.",
              {{"scene", scene.name}, {"method", r.method}, {"verdict", verdict_name(r.verdict)}});
}

}  // namespace furnace::verify
