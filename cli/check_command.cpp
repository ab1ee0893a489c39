#include "cli/check_command.h"

#include <cstddef>
#include <cstdio>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include "cli/cli_options.h"
#include "core/error.h"
#include "core/provenance.h"
#include "core/scene.h"
#include "verify/analytic_cache.h"
#include "verify/check_report.h"
#include "verify/image_report.h"

namespace furnace::cli {

CLI::App* add_check_command(CLI::App& app, CheckCommandOptions& o) {
  CLI::App* command =
      app.add_subcommand("check", "Test another renderer's OpenEXR images of a scene against its exact reference");
  command->add_option("--scene", o.scene_path, "Scene file the images are renders of")->required();
  command->add_option("--image", o.image_paths,
                      "OpenEXR image(s): K >= 2 independent renders (different seeds), or one furnace EXR (with "
                      "variance.R/G/B and N channels)")->required();
  command->add_option("--guard", o.guard_paths,
                      "Rare-event guard: OpenEXR renders of the same renderer and settings at a high spp (K >= 2 "
                      "other seeds, or one furnace EXR). A test below the reference that rejects only because the "
                      "images' spread is smaller than these renders' spread per sample predicts (a rare contribution "
                      "no sample met) is held, not failed: INCONCLUSIVE, with the spp that would judge it")
      ->type_name("IMAGE ...");
  command->add_option("--alpha", o.alpha, "Family-wise false-alarm probability")
      ->capture_default_str()->check(family_alpha());
  command->add_option("--max-detectable-bias", o.max_detectable_bias,
                      "PASS needs the image-mean test to detect a relative bias this large with power 0.9 "
                      "(else INCONCLUSIVE)")
      ->capture_default_str()->check(number_in(0, 1, End::kOpen));
  max_depth_option(command->add_option_function<int>(
      "--max-depth", [&o](const int& segments) { o.max_depth = segments; },
      "The reference's path length, as for render (default: unlimited where the scene has a closed-form global "
      "answer, else direct lighting; 2 is direct lighting)"));
  add_convention_option(command, o.convention);
  const std::map<std::string, verify::ChannelMode> channel_modes{{"gray", verify::ChannelMode::kGray},
                                                                 {"rgb", verify::ChannelMode::kRgb}};
  command->add_option("--channels", o.channels, "gray: test the mean of R, G, B (or Y); rgb: test R, G and B separately")
      ->transform(CLI::CheckedTransformer(channel_modes, CLI::ignore_case).description(""))
      ->type_name("gray|rgb")->default_str("gray");
  command->add_option("--zmap", o.zmap_path, "Write the per-pixel t statistic to this OpenEXR file")
      ->check(output_file().description(""))->type_name("FILE");
  command->add_option("--json", o.json_path, "Write every number of the report as JSON to FILE ('-': stdout, "
                      "the text report then goes to stderr)")
      ->check(output_file(true).description(""))->type_name("FILE");
  command->footer(
      "Reference: a scene with a closed-form global-illumination answer (closed enclosures, white furnaces, scenes "
      "whose light bounces at most once, mirrors in front of these) is checked against the full answer at unlimited "
      "depth, what a path tracer without a depth limit computes; any other scene against direct lighting "
      "(emission + one bounce, --max-depth 2), the only exact answer it has.\n"
      "Verdict: PASS (exit 0) when no test rejects and the image-mean test detects a bias of --max-detectable-bias "
      "with power 0.9; FAIL (exit 1) when any test rejects, whatever the power; bad input (exit 2, one sentence on "
      "stderr); INCONCLUSIVE (exit 3) when nothing rejects but the test lacks that power (the report says how many "
      "images or samples would give it, or --guard held a test).\n"
      "Finite negative values are used as is in the tests and counted in the report and the JSON (the reference is "
      "non-negative); NaN or infinite radiance is bad input.\n" + std::string(kExitContract));
  return command;
}

int run_check(const CheckCommandOptions& options) {
  try {
    const Scene scene = load_scene(options.scene_path);
    const std::string scene_hash = file_content_hash(options.scene_path);
    const verify::CheckReference reference = verify::check_reference(scene, options.max_depth, options.convention);
    verify::require_finite_reference(reference.values, scene);
    // The checked images, then the guard's: a guard image that copies a
    // checked one (or another guard image) is not an independent render.
    std::vector<verify::ForeignImage> images;
    for (const std::vector<std::string>* paths : {&options.image_paths, &options.guard_paths})
      for (const std::string& path : *paths) images.push_back(verify::read_foreign_image(path, scene, options.channels));
    verify::reject_identical_images(images, reference.values);
    const auto first_guard = images.begin() + std::ptrdiff_t(options.image_paths.size());
    const std::vector<verify::ForeignImage> guard(std::make_move_iterator(first_guard),
                                                  std::make_move_iterator(images.end()));
    images.erase(first_guard, images.end());
    const verify::CheckResult r =
        verify::check_images(images, reference.values, options.alpha, options.max_detectable_bias, guard);
    const std::vector<std::string> warnings = verify::provenance_warnings(scene, scene_hash, images, reference);
    for (const std::string& w : warnings) std::fprintf(stderr, "furnace: warning: %s\n", w.c_str());
    if (!options.zmap_path.empty()) verify::write_zmap(options.zmap_path, scene, r);
    const std::string text = verify::format_check(scene, reference, r);
    std::fputs(text.c_str(), options.json_path == "-" ? stderr : stdout);
    if (!options.json_path.empty())
      verify::emit_json(options.json_path, verify::check_json(scene, scene_hash, reference, images, r, warnings,
                                                              options.channels, options.zmap_path, guard));
    return verify::exit_code(r.verdict);
  } catch (const Error& e) {
    if (!options.json_path.empty()) verify::emit_bad_input_json(options.json_path, "check", e.what());
    throw;
  }
}

}  // namespace furnace::cli
