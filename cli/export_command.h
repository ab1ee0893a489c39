// `furnace export`: a scene in another renderer's format, for `furnace check`
// of that renderer's images. A format that cannot express the scene exactly
// refuses it (bad input, exit 2). The formats are one table (kExportFormats):
// a new exporter is one row, its writer and its enumerator.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "core/strategy.h"

namespace furnace::cli {

enum class ExportFormat { kPbrtV4, kCycles };

struct ExportCommandOptions {
  std::string scene_path;
  ExportFormat format = ExportFormat::kPbrtV4;
  std::optional<int> spp;        // empty: the format's default
  std::optional<uint64_t> seed;  // pbrt-v4 only; empty: none written
  int max_segments = kUnlimitedDepth;
  std::optional<int> emitter_grid, sphere_subdivisions;  // cycles only; empty: the exporter's defaults
  std::string output;
};

// Adds `export` to `app`, its options bound to `options`.
CLI::App* add_export_command(CLI::App& app, ExportCommandOptions& options);

// Writes the file; returns 0. A refused scene, an option the format does not
// take or a bad scene throws furnace::Error, and nothing is written.
int run_export(const ExportCommandOptions& options);

}  // namespace furnace::cli
