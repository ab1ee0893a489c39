// `furnace render`: one scene, one strategy, an OpenEXR image with its
// provenance. Exits 1 when a sample is not finite, unless allowed.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

#include "renderer/render_options.h"

namespace furnace::cli {

struct RenderCommandOptions {
  std::string scene_path;
  RenderOptions render;  // strategy, defect, light selection, spp, seed, threads, depths
  std::string output = "out.exr";
  bool allow_nonfinite = false;
};

// Adds `render` to `app`, its options bound to `options`.
CLI::App* add_render_command(CLI::App& app, RenderCommandOptions& options);

// Renders and writes the image; returns the exit code (0, or 1 for dropped
// non-finite samples). Bad input throws furnace::Error.
int run_render(const RenderCommandOptions& options);

}  // namespace furnace::cli
