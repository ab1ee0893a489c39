// The report of `furnace check` (verify/check.h): its warnings from the
// images' provenance, its text, its JSON twin and its per-pixel t map. The
// command (cli/check_command.h) states where each goes and the exit codes.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/scene.h"
#include "verify/check.h"
#include "verify/check_image.h"

namespace furnace::verify {

// Warnings from the images' provenance (core/provenance.h) against the scene
// file and the reference: another scene name or scene-file hash, a defect,
// a path tracer's max depth differing from the reference's.
std::vector<std::string> provenance_warnings(const Scene& scene, const std::string& scene_hash,
                                             const std::vector<ForeignImage>& images, const CheckReference& reference);

// The human-readable report (ends with "verdict: PASS|FAIL|INCONCLUSIVE").
std::string format_check(const Scene& scene, const CheckReference& reference, const CheckResult& r);

// The JSON twin of format_check: every number the text shows (non-finite
// ones null), the images with their provenance, the warnings, `zmap_path`
// (null when empty), the rare-event guard's images and what it held (null
// without `guard`), the verdict and its exit code.
nlohmann::json check_json(const Scene& scene, const std::string& scene_hash, const CheckReference& reference,
                          const std::vector<ForeignImage>& images, const CheckResult& r,
                          const std::vector<std::string>& warnings, ChannelMode channels_mode,
                          const std::string& zmap_path, const std::vector<ForeignImage>& guard = {});

// The per-pixel t of every tested channel as an OpenEXR file (channel Y for
// gray, R, G, B for rgb; ±inf where a zero-spread pixel misses), atomically.
void write_zmap(const std::string& path, const Scene& scene, const CheckResult& r);

}  // namespace furnace::verify
