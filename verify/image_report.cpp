#include "verify/image_report.h"

#include <cmath>
#include <cstdio>
#include <utility>

#include <fmt/format.h>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/exr.h"

namespace furnace::verify {

std::string percent_text(double relative) {
  return std::isfinite(relative) ? fmt::format("{:.3g}%", 100 * relative) : "inf";
}

std::string repeated_values_reason(bool half_float) {
  return half_float ? "the images store 16-bit half floats, whose rounding (11 significant bits) is coarser than "
                      "these pixels' noise: half-float rounding, not a quasi-Monte Carlo pattern"
                    : "as a quasi-Monte Carlo or quantised (discrete) render gives";
}

std::string negative_values_text(const std::string& what, const NegativeValues& n, int images) {
  if (n.values == 0) return "";
  return fmt::format("negative values ({}): {} in {} of {} image(s), the most negative {:.6g} in channel '{}' at "
                     "pixel ({}, {}) of '{}'; finite, so used as is (a spectral renderer's RGB film makes small ones)\n",
                     what, n.values, n.images, images, n.most_negative, n.channel, n.x, n.y, n.path);
}

nlohmann::json negative_values_json(const NegativeValues& n) {
  const bool any = n.values > 0;
  return {{"values", n.values},
          {"images", n.images},
          {"most_negative", any ? nlohmann::json(n.most_negative) : nlohmann::json(nullptr)},
          {"path", any ? nlohmann::json(n.path) : nlohmann::json(nullptr)},
          {"channel", any ? nlohmann::json(n.channel) : nlohmann::json(nullptr)},
          {"x", any ? nlohmann::json(n.x) : nlohmann::json(nullptr)},
          {"y", any ? nlohmann::json(n.y) : nlohmann::json(nullptr)}};
}

nlohmann::json json_number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

void add_outcome(nlohmann::json& j, const std::vector<std::string>& warnings, const std::string& zmap_path,
                 const std::string& verdict, int exit_code) {
  j["warnings"] = warnings;
  j["zmap"] = zmap_path.empty() ? nlohmann::json(nullptr) : nlohmann::json(zmap_path);
  j["verdict"] = verdict;
  j["exit_code"] = exit_code;
}

void emit_json(const std::string& path, const nlohmann::json& j) {
  const std::string text = j.dump(2) + "\n";
  if (path == "-")
    std::fputs(text.c_str(), stdout);
  else
    write_text_file_atomically(path, text, "JSON file");
}

void emit_bad_input_json(const std::string& path, const std::string& command, const std::string& message) {
  try {
    emit_json(path, {{"command", command}, {"verdict", "BAD INPUT"}, {"exit_code", 2}, {"error", message}});
  } catch (const Error& json_error) {
    std::fprintf(stderr, "furnace: error: %s\n", json_error.what());
  }
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

}  // namespace furnace::verify
