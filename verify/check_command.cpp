#include "verify/check_command.h"

#include <cmath>
#include <cstdio>
#include <exception>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/exr.h"
#include "core/provenance.h"
#include "renderer/render.h"
#include "verify/harness.h"

namespace furnace::verify {

namespace {

using nlohmann::json;

bool is_path_tracer_name(const std::string& name) {
  for (Strategy s : path_tracing_strategies())
    if (strategy_name(s) == name) return true;
  return false;
}

std::string percent(double relative) { return std::isfinite(relative) ? fmt::format("{:.3g}%", 100 * relative) : "inf"; }

std::string dof_text(double dof) { return std::isfinite(dof) ? fmt::format("{:g} d.o.f.", dof) : "normal"; }

// Non-finite numbers are null in the JSON (the contract in check_command.h).
json number(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

std::string advice_text(const CheckResult& r) {
  const CheckAdvice& a = r.advice;
  const std::string target = percent(r.max_detectable_bias);
  auto spp = [&](double factor) {
    return a.current_spp > 0 ? fmt::format(" ({:.3g} spp)", std::ceil(factor * a.current_spp)) : std::string();
  };
  std::string text = fmt::format("to detect {} with power {}: ", target, kReportedPower);
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

json check_json(const Scene& scene, const std::string& scene_hash, const CheckReference& reference,
                const std::vector<ForeignImage>& images, const CheckResult& r, const std::vector<std::string>& warnings,
                const CheckOptions& options) {
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
    image_list.push_back({{"path", img.path}, {"has_variance", img.has_variance()}, {"provenance", p}});
  }
  j["images"] = image_list;
  j["image_count"] = r.images;
  j["pixels"] = r.pixels;
  j["pixel_tests"] = r.pixels * int(r.channels.size());
  j["channels_mode"] = channel_mode_name(options.channels);
  j["method"] = r.method;
  j["alpha"] = r.alpha;
  j["image_mean_alpha_share"] = kImageMeanAlphaShare;
  j["power"] = kReportedPower;
  j["spread_confidence"] = kSpreadConfidence;
  j["max_detectable_bias"] = r.max_detectable_bias;
  json channels = json::array();
  for (const ChannelCheck& c : r.channels)
    channels.push_back({{"channel", c.channel},
                        {"image_mean", number(c.image_mean)},
                        {"reference_mean", number(c.reference_mean)},
                        {"standard_error", number(c.standard_error)},
                        {"statistic", number(c.statistic)},
                        {"threshold", number(c.threshold)},
                        {"dof", number(c.dof)},
                        {"alpha", c.alpha},
                        {"detectable_relative_bias", number(c.detectable_relative_bias)},
                        {"image_mean_pass", c.image_mean_pass},
                        {"pixel_failures", c.pixel_failures},
                        {"pixels_untested", c.pixels_untested},
                        {"pixels_few_values", c.pixels_few_values},
                        {"pixel_alpha", c.pixel_alpha},
                        {"pixel_threshold", number(c.pixel_threshold)},
                        {"pixel_dof", number(c.pixel_dof)},
                        {"median_pixel_detectable_relative_bias", number(c.median_pixel_detectable_relative_bias)},
                        {"relative_rmse", number(c.relative_rmse)}});
  j["channels"] = channels;
  j["detectable_relative_bias"] = number(r.detectable_relative_bias);
  j["image_mean_has_power"] = r.image_mean_has_power;
  j["pixels_have_power"] = r.pixels_have_power;
  json worst = json::array();
  for (const WorstPixel& w : r.worst_pixels)
    worst.push_back({{"x", w.x}, {"y", w.y}, {"channel", w.channel}, {"value", number(w.value)},
                     {"reference", number(w.reference)}, {"t", number(w.t)}, {"untested", w.untested}});
  j["worst_pixels"] = worst;
  if (r.advice.needed)
    j["advice"] = {{"images_at_current_spp", r.advice.images_at_current_spp},
                   {"spp_factor_at_current_images", number(r.advice.spp_factor_at_current_images)},
                   {"advised_images", r.advice.advised_images},
                   {"spp_factor_at_advised_images", number(r.advice.spp_factor_at_advised_images)},
                   {"current_spp", r.advice.current_spp > 0 ? json(r.advice.current_spp) : json(nullptr)}};
  else
    j["advice"] = nullptr;
  j["warnings"] = warnings;
  j["zmap"] = options.zmap_path.empty() ? json(nullptr) : json(options.zmap_path);
  j["verdict"] = verdict_name(r.verdict);
  j["exit_code"] = exit_code(r.verdict);
  return j;
}

}  // namespace

void emit_json(const std::string& path, const json& j) {
  const std::string text = j.dump(2) + "\n";
  if (path == "-")
    std::fputs(text.c_str(), stdout);
  else
    write_text_file_atomically(path, text, "JSON file");
}

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
                     kReportedPower, kSpreadConfidence);
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
                       c.image_mean_pass ? "agrees" : "REJECTED", percent(c.detectable_relative_bias),
                       power ? fmt::format("has power (<= {})", percent(r.max_detectable_bias))
                             : fmt::format("LOW POWER (> {})", percent(r.max_detectable_bias)));
    const bool pixel_power = c.median_pixel_detectable_relative_bias <= r.max_detectable_bias;
    std::string untested =
        c.pixels_untested > 0 ? fmt::format(", {} untested (constant yet off the reference)", c.pixels_untested) : "";
    if (c.pixels_few_values > 0)
      untested += fmt::format(", {} untested (their {} values take at most {} distinct values, as a quasi-Monte Carlo "
                              "or quantised render gives: the spread does not estimate their error)",
                              c.pixels_few_values, r.images, r.images / kFewValuesDivisor);
    out += fmt::format("pixels{}: {}/{} fail{} (critical |t| {:.3g}, {}), median detectable pixel bias {}: {}; "
                       "relative RMSE {:.3e}\n",
                       label, c.pixel_failures, r.pixels, untested, c.pixel_threshold, dof_text(c.pixel_dof),
                       percent(c.median_pixel_detectable_relative_bias),
                       pixel_power ? "have power"
                                   : fmt::format("low power (only local errors above {} are caught)",
                                                 percent(c.median_pixel_detectable_relative_bias)),
                       c.relative_rmse);
  }
  out += "worst pixels (x, y, channel: value, reference, t):\n";
  for (const WorstPixel& w : r.worst_pixels)
    out += fmt::format("  ({}, {}) {}: {:.6g}, {:.6g}, {:.3g}{}\n", w.x, w.y, w.channel, w.value, w.reference, w.t,
                       w.untested ? " (untested)" : "");
  if (r.advice.needed) out += advice_text(r);
  out += fmt::format("verdict: {}\n", verdict_name(r.verdict));
  return out;
}

void write_t_map(const std::string& path, int width, int height, const std::vector<std::string>& channels,
                 const std::vector<std::vector<double>>& pixel_t, const std::vector<double>& critical_t,
                 const std::string& attribute_prefix, std::map<std::string, std::string> attributes) {
  exr::Image image;
  image.width = width;
  image.height = height;
  for (size_t c = 0; c < channels.size(); ++c) {
    const std::string name = channels[c] == "gray" ? "Y" : channels[c];
    image.floats[name].assign(pixel_t[c].begin(), pixel_t[c].end());
    image.attributes[attribute_prefix + "critical_t." + name] = fmt::format("{:.6g}", critical_t[c]);
  }
  for (auto& [key, value] : attributes) image.attributes[attribute_prefix + key] = std::move(value);
  exr::write(path, image, "t map");
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

int run_check(const CheckOptions& options) {
  try {
    const Scene scene = load_scene(options.scene_path);
    const std::string scene_hash = file_content_hash(options.scene_path);
    const CheckReference reference = check_reference(scene, options.max_depth);
    require_finite_reference(reference.values, scene);
    std::vector<ForeignImage> images;
    for (const std::string& path : options.image_paths)
      images.push_back(read_foreign_image(path, scene, options.channels));
    reject_identical_images(images, reference.values);
    const CheckResult r = check_images(images, reference.values, options.alpha, options.max_detectable_bias);
    const std::vector<std::string> warnings = provenance_warnings(scene, scene_hash, images, reference);
    for (const std::string& w : warnings) std::fprintf(stderr, "furnace: warning: %s\n", w.c_str());
    if (!options.zmap_path.empty()) write_zmap(options.zmap_path, scene, r);
    const std::string text = format_check(scene, reference, r);
    std::fputs(text.c_str(), options.json_path == "-" ? stderr : stdout);
    if (!options.json_path.empty())
      emit_json(options.json_path, check_json(scene, scene_hash, reference, images, r, warnings, options));
    return exit_code(r.verdict);
  } catch (const Error& e) {
    if (!options.json_path.empty()) {
      try {
        emit_json(options.json_path,
                  {{"command", "check"}, {"verdict", "BAD INPUT"}, {"exit_code", 2}, {"error", e.what()}});
      } catch (const Error& json_error) {  // the input error stays the one reported
        std::fprintf(stderr, "furnace: error: %s\n", json_error.what());
      }
    }
    throw;
  }
}

}  // namespace furnace::verify
