#include "cli/render_command.h"

#include <cstdio>
#include <limits>

#include <fmt/format.h>

#include "cli/cli_options.h"
#include "core/path_length.h"
#include "core/provenance.h"
#include "core/scene.h"
#include "renderer/exr_io.h"
#include "renderer/render.h"

namespace furnace::cli {

CLI::App* add_render_command(CLI::App& app, RenderCommandOptions& o) {
  CLI::App* command = app.add_subcommand("render", "Render a scene with one strategy to an OpenEXR image");
  RenderOptions& r = o.render;
  command->add_option("--scene", o.scene_path, "Scene file (JSON)")->required();
  command->add_option("--strategy", r.strategy, "Sampling strategy")
      ->transform(strategy_by_name())->type_name("TEXT")->default_str(strategy_name(r.strategy));
  command->add_option("--light-selection", r.light_selection, "Light selection pmf")
      ->transform(light_selection_by_name())->type_name("TEXT")->default_str(light_selection_name(r.light_selection));
  add_convention_option(command, r.convention);
  command->add_option("--defect", r.defect, "Negative-control defect to inject (tests only)")
      ->transform(defect_by_name())->type_name("TEXT")->default_str(defect_name(r.defect));
  command->add_option("--spp", r.spp, "Samples per pixel")->capture_default_str()->transform(integer_in(1, kMaxSpp));
  add_seed_option(command, r.seed);
  add_threads_option(command, r.threads);
  command->add_option("--output,-o", o.output, "Output EXR path")->capture_default_str()->check(output_file());
  command->add_flag("--allow-nonfinite", o.allow_nonfinite,
                    "Exit 0 even if some samples were NaN or Inf (dropped and counted; default: exit 1)");
  set_contract_footer(command, "render exits 1 when any sample is not finite (NaN or Inf), unless --allow-nonfinite.");
  max_depth_option(command->add_option("--max-depth", r.max_depth, "Path tracers: longest path in segments, camera "
                                       "segment included, or 'unlimited' (default unlimited)"));
  command->add_option("--roulette-depth", r.roulette_depth, "Path tracers: depth at which Russian roulette starts")
      ->capture_default_str()->transform(integer_in(1, std::numeric_limits<int>::max()));
  return command;
}

int run_render(const RenderCommandOptions& o) {
  const Scene scene = load_scene(o.scene_path);
  // Said before the render starts: a path tracer's paths may be very long.
  if (is_path_tracer(o.render.strategy)) {
    require_bounded_paths(scene, o.render.max_depth, o.render.roulette_depth);
    if (const auto statement = path_length_statement(scene, o.render.max_depth, o.render.roulette_depth))
      std::fprintf(stderr, "furnace: warning: %s\n", statement->c_str());
  }
  const Image image = render(scene, o.render);
  write_exr(o.output, image, render_provenance(o.scene_path, scene, o.render));
  const double samples = double(image.width) * image.height * o.render.spp;
  fmt::print("rendered {} ({}x{}, {} spp, strategy {}) in {:.3f} s, {:.3g} samples/s, {} non-finite samples -> {}\n",
             scene.name, image.width, image.height, o.render.spp, strategy_name(o.render.strategy), image.seconds,
             samples / image.seconds, image.nonfinite_samples, o.output);
  // Non-finite samples are dropped from the image, so its mean is not the
  // estimator's: a failure unless the user accepts it.
  if (image.nonfinite_samples > 0 && !o.allow_nonfinite) {
    std::fprintf(stderr,
                 "furnace: FAIL: %llu of %.0f samples were not finite (NaN or Inf, dropped from %s); "
                 "--allow-nonfinite accepts them.\n",
                 static_cast<unsigned long long>(image.nonfinite_samples), samples, o.output.c_str());
    return kExitFail;
  }
  return kExitPass;
}

}  // namespace furnace::cli
