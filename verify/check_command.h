// `furnace check`: the command around verify/check.h. Its contract:
//   exit 0  PASS: no test rejects and the image-mean test has the stated power
//   exit 1  FAIL: some test rejects (it wins over INCONCLUSIVE)
//   exit 2  bad input: one sentence on stderr naming the file and, for a bad
//           pixel, the pixel, channel and value (nothing but --json is written)
//   exit 3  INCONCLUSIVE: no test rejects, but the image-mean test cannot
//           detect a bias of --max-detectable-bias; the text says how many
//           images or samples would
// The report goes to stdout (to stderr when the JSON goes to stdout);
// warnings (an image whose provenance names another scene, another scene-file
// hash, a defect, or another depth) go to stderr and into the JSON.
// --json FILE ("-": stdout) holds every number the text shows; non-finite
// numbers (a t of ±inf) are null. --zmap FILE writes the per-pixel t.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "verify/check.h"

namespace furnace::verify {

struct CheckOptions {
  std::string scene_path;
  std::vector<std::string> image_paths;
  double alpha = 0.01;
  double max_detectable_bias = kDefaultMaxDetectableBias;
  std::optional<int> max_depth;  // empty: check_reference()'s default
  ChannelMode channels = ChannelMode::kGray;
  std::string zmap_path;  // empty: none
  std::string json_path;  // empty: none; "-": stdout
};

// Runs the check and prints its report; returns the exit code (0, 1, 3).
// Bad input throws furnace::Error (exit 2), after writing {"verdict": "BAD
// INPUT", "error": ...} to --json when given.
int run_check(const CheckOptions& options);

// Warnings from the images' provenance (core/provenance.h) against the scene
// file and the reference: another scene name or scene-file hash, a defect,
// a path tracer's max depth differing from the reference's.
std::vector<std::string> provenance_warnings(const Scene& scene, const std::string& scene_hash,
                                             const std::vector<ForeignImage>& images, const CheckReference& reference);

// The human-readable report (ends with "verdict: PASS|FAIL|INCONCLUSIVE").
std::string format_check(const Scene& scene, const CheckReference& reference, const CheckResult& r);

// The per-pixel t of every tested channel as an OpenEXR file (channel Y for
// gray, R, G, B for rgb; ±inf where a zero-spread pixel misses), atomically.
void write_zmap(const std::string& path, const Scene& scene, const CheckResult& r);

// The per-pixel t of `channels` (channel "gray" is written as Y) as an
// OpenEXR file, atomically, with the attributes <prefix>critical_t.<channel>
// and <prefix><key> for each of `attributes` (write_zmap's and compare's).
void write_t_map(const std::string& path, int width, int height, const std::vector<std::string>& channels,
                 const std::vector<std::vector<double>>& pixel_t, const std::vector<double>& critical_t,
                 const std::string& attribute_prefix, std::map<std::string, std::string> attributes);

// Writes `j` (indented) to `path` atomically, or to stdout for "-" (the
// --json of check and compare).
void emit_json(const std::string& path, const nlohmann::json& j);

}  // namespace furnace::verify
