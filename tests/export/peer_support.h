// What the peer tests (pbrt_peer_test.cpp, cycles_peer_test.cpp) share:
// finding a peer renderer's binary, running commands, `furnace check` on K
// renders with the numbers of its JSON report, and the built-in scenes an
// exporter can express. Needs FURNACE_SCENE_DIR and FURNACE_CLI defined.
#pragma once

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/scene.h"
#include "core/strategy.h"
#include "tests/command.h"

namespace furnace::exporter::peer {

namespace fs = std::filesystem;

inline bool is_executable_file(const fs::path& p) { return fs::is_regular_file(p) && ::access(p.c_str(), X_OK) == 0; }

// The first executable `name` in a directory of PATH.
inline std::optional<fs::path> find_on_path(const std::string& name) {
  const char* path = std::getenv("PATH");
  const std::string dirs = path ? path : "";
  for (size_t start = 0; start <= dirs.size();) {
    const size_t end = std::min(dirs.find(':', start), dirs.size());
    const fs::path candidate = fs::path(dirs.substr(start, end - start)) / name;
    if (end > start && is_executable_file(candidate)) return candidate;
    start = end + 1;
  }
  return std::nullopt;
}

// `command` with its stdout and stderr captured.
inline testing_support::CommandResult run(const std::string& command) {
  return testing_support::run_command(command + " 2>&1");
}

inline std::string quoted(const fs::path& p) { return "'" + p.string() + "'"; }

inline std::string read_text(const fs::path& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// The numbers of check's JSON report a peer line prints: the largest |t|
// over the pixels, the image-mean t and relative error, the detectable
// relative bias and the failed pixels (NaN or −1 when the report has none).
struct Diagnostics {
  double worst_pixel_t = NAN;
  double image_mean_t = NAN;
  double image_mean_relative_error = NAN;
  double detectable_relative_bias = NAN;
  int failed_pixels = -1;
};

inline Diagnostics diagnostics(const std::string& check_json) {
  Diagnostics d;
  const nlohmann::json j = nlohmann::json::parse(check_json, nullptr, false);
  if (j.is_discarded() || !j.contains("channels")) return d;
  auto number = [](const nlohmann::json& v) { return v.is_number() ? v.get<double>() : NAN; };
  if (!j["worst_pixels"].empty()) d.worst_pixel_t = std::fabs(number(j["worst_pixels"][0]["t"]));
  if (!j["channels"].empty()) {
    const nlohmann::json& c = j["channels"][0];
    d.image_mean_t = number(c["statistic"]);
    d.image_mean_relative_error = number(c["image_mean"]) / number(c["reference_mean"]) - 1;
    if (c["pixel_failures"].is_number_integer()) d.failed_pixels = c["pixel_failures"].get<int>();
  }
  d.detectable_relative_bias = number(j["detectable_relative_bias"]);
  return d;
}

// One `furnace check` of renders against a scene file's reference.
struct CheckRun {
  int exit_code = -1;
  std::string output;  // check's report
  Diagnostics numbers;
};

// Runs `furnace check --scene scene_file --max-depth check_depth
// --convention convention` on `images`, its JSON report written to
// `json_file`. The convention matters only for scenes with dielectrics:
// pbrt-v4 renders the radiance convention, Cycles none.
inline CheckRun check_renders(const fs::path& scene_file, int check_depth, const std::vector<fs::path>& images,
                              const fs::path& json_file,
                              TransportConvention convention = TransportConvention::kRadiance) {
  std::string image_args;
  for (const fs::path& image : images) image_args += " --image " + quoted(image);
  const testing_support::CommandResult check =
      run(fmt::format("{} check --scene {} --max-depth {} --convention {} --json {}{}", FURNACE_CLI,
                      quoted(scene_file), depth_name(check_depth), transport_convention_name(convention),
                      quoted(json_file), image_args));
  return {check.exit_code, check.output, diagnostics(read_text(json_file))};
}

inline fs::path scene_file(const std::string& name) { return fs::path(FURNACE_SCENE_DIR) / (name + ".json"); }

// The built-in scenes `exportable` accepts, sorted: the `costly` ones when
// `costly_binary`, else the rest (the costly scenes run under label slow).
inline std::vector<std::string> exportable_scenes(const std::function<bool(const Scene&)>& exportable,
                                                  const std::set<std::string>& costly, bool costly_binary) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(FURNACE_SCENE_DIR)) {
    const std::string name = entry.path().stem().string();
    if (entry.path().extension() != ".json" || (costly.count(name) > 0) != costly_binary) continue;
    if (exportable(load_scene(entry.path()))) names.push_back(name);
  }
  std::sort(names.begin(), names.end());
  return names;
}

// A scene name as a test name: near_contact → NearContact.
inline std::string camel_case(const std::string& snake) {
  std::string out;
  bool upper = true;
  for (char c : snake) {
    if (c == '_') {
      upper = true;
      continue;
    }
    out += upper ? char(std::toupper(static_cast<unsigned char>(c))) : c;
    upper = false;
  }
  return out;
}

// A built-in GGX scene changed only in its GGX materials, written as
// `dir`/<name>.json so that `furnace check` computes the exact reference of
// the scene actually rendered: every GGX object's "shadowing" set to
// `shadowing` and/or its "albedo" to `albedo` (unchanged when empty). The
// file is the built-in one with those fields replaced and "name" set to
// `name`; nothing else differs, so the derived scene stays out of every
// built-in suite (verify's table, the exporters' scene lists).
inline fs::path derived_ggx_scene(const std::string& builtin, const std::string& name, const fs::path& dir,
                                  std::optional<std::string> shadowing, std::optional<double> albedo) {
  std::ifstream in(scene_file(builtin));
  nlohmann::json j = nlohmann::json::parse(in);
  j["name"] = name;
  int changed = 0;
  for (nlohmann::json& o : j["objects"]) {
    if (!o.contains("material") || o["material"].value("type", "") != "ggx") continue;
    if (shadowing) o["material"]["shadowing"] = *shadowing;
    if (albedo) o["material"]["albedo"] = *albedo;
    ++changed;
  }
  if (changed == 0) throw std::runtime_error("scene '" + builtin + "' has no GGX object to derive from");
  const fs::path out = dir / (name + ".json");
  std::ofstream(out) << j.dump(2) << "\n";
  return out;
}

// ggx_sky_strips with its five strips' α set to `alphas` (left to right)
// and albedo 1, written as `dir`/<name>.json: the near-specular end of
// furnace's α range under the sky at normal view.
inline fs::path derived_strips_with_alphas(const std::vector<double>& alphas, const std::string& name,
                                           const fs::path& dir) {
  std::ifstream in(scene_file("ggx_sky_strips"));
  nlohmann::json j = nlohmann::json::parse(in);
  j["name"] = name;
  if (j["objects"].size() != alphas.size()) throw std::runtime_error("ggx_sky_strips has another number of strips");
  for (size_t i = 0; i < alphas.size(); ++i) {
    j["objects"][i]["material"]["alpha"] = alphas[i];
    j["objects"][i]["material"]["albedo"] = 1.0;
    j["objects"][i]["name"] = fmt::format("ggx_a{}", alphas[i]);
  }
  const fs::path out = dir / (name + ".json");
  std::ofstream(out) << j.dump(2) << "\n";
  return out;
}

// A built-in scene with `edit` applied to the material of every object whose
// material type is `type`, written as `dir`/<name>.json with "name" set to
// `name` (nothing else differs, so the derived scene stays out of every
// built-in suite); throws when no object has that type.
inline fs::path derived_scene(const std::string& builtin, const std::string& name, const fs::path& dir,
                              const std::string& type, const std::function<void(nlohmann::json&)>& edit) {
  std::ifstream in(scene_file(builtin));
  nlohmann::json j = nlohmann::json::parse(in);
  j["name"] = name;
  int changed = 0;
  for (nlohmann::json& o : j["objects"]) {
    if (!o.contains("material") || o["material"].value("type", "") != type) continue;
    edit(o["material"]);
    ++changed;
  }
  if (changed == 0) throw std::runtime_error("scene '" + builtin + "' has no " + type + " object to derive from");
  const fs::path out = dir / (name + ".json");
  std::ofstream(out) << j.dump(2) << "\n";
  return out;
}

// A built-in GGX scene with every GGX material replaced by a Lambertian one
// of albedo `albedo`, written as `dir`/<name>.json: where each surface sees
// a constant sky alone, its exact answer L_env·albedo is also that of any
// energy-conserving BSDF of that albedo (the energy-conserving GGX check).
inline fs::path derived_lambertian_scene(const std::string& builtin, const std::string& name, const fs::path& dir,
                                         double albedo) {
  std::ifstream in(scene_file(builtin));
  nlohmann::json j = nlohmann::json::parse(in);
  j["name"] = name;
  for (nlohmann::json& o : j["objects"])
    if (o.contains("material") && o["material"].value("type", "") == "ggx")
      o["material"] = {{"type", "lambertian"}, {"albedo", albedo}};
  const fs::path out = dir / (name + ".json");
  std::ofstream(out) << j.dump(2) << "\n";
  return out;
}

inline Object& named(Scene& scene, const std::string& name) {
  for (Object& o : scene.objects)
    if (o.name == name) return o;
  throw std::runtime_error("no object '" + name + "' in scene '" + scene.name + "'");
}

}  // namespace furnace::exporter::peer
