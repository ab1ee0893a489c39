#include "cli/compare_command.h"

#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "cli/cli_options.h"
#include "core/error.h"
#include "verify/compare_report.h"
#include "verify/image_report.h"
#include "verify/report_html.h"

namespace furnace::cli {

CLI::App* add_compare_command(CLI::App& app, CompareCommandOptions& o) {
  CLI::App* command = app.add_subcommand(
      "compare", "Test whether two sets of OpenEXR renders of any scene have the same expected image");
  const std::string side_help =
      ": K >= 2 independent renders (different seeds), or one furnace EXR (with variance.R/G/B and N channels)";
  command->add_option("--a", o.a_paths, "OpenEXR renders of side A (e.g. after a change)" + side_help)
      ->required()->type_name("FILE");
  command->add_option("--b", o.b_paths, "OpenEXR renders of side B (e.g. the stored reference set; differences "
                      "are relative to B)" + side_help)
      ->required()->type_name("FILE");
  command->add_option("--alpha", o.alpha, "Family-wise false-alarm probability over every test")
      ->capture_default_str()->check(family_alpha());
  command->add_option("--max-detectable-difference", o.max_detectable_difference,
                      "SAME needs the image-mean test to detect a relative difference this large with power 0.9 "
                      "(else INCONCLUSIVE)")
      ->capture_default_str()->check(number_in(0, 1, End::kOpen));
  command->add_option("--tile", o.tile_size, "Tile size in pixels: the tile-mean tests use tile x tile blocks")
      ->capture_default_str()->transform(integer_in(1, 4096))->type_name("N");
  command->add_flag_function(
      "--no-variance-test", [&o](int64_t) { o.test_variance = false; },
      "Compare only the means (image, tiles, pixels), not the noise: for two renderers or samplers, whose variance "
      "legitimately differs");
  const std::map<std::string, verify::ChannelMode> channel_modes{{"gray", verify::ChannelMode::kGray},
                                                                 {"rgb", verify::ChannelMode::kRgb}};
  command->add_option("--channels", o.channels, "gray: test the mean of R, G, B (or Y); rgb: test R, G and B separately")
      ->transform(CLI::CheckedTransformer(channel_modes, CLI::ignore_case).description(""))
      ->type_name("gray|rgb")->default_str("gray");
  command->add_option("--zmap", o.zmap_path, "Write the per-pixel Welch t of A - B to this OpenEXR file")
      ->check(output_file().description(""))->type_name("FILE");
  command->add_option("--json", o.json_path, "Write every number of the report as JSON to FILE ('-': stdout, "
                      "the text report then goes to stderr)")
      ->check(output_file(true).description(""))->type_name("FILE");
  command->add_option("--html", o.html_dir, "Write DIR/index.html: both means, their difference, the pixel and tile "
                      "t maps (needs Python 3 with matplotlib)")
      ->check(output_directory().description(""))->type_name("DIR");
  command->footer(
      "Tests, each side's error bars from its K renders (or the furnace EXR's variance): Welch t of the image mean, "
      "of every tile mean and of every pixel, and a z-test of the ratio of the summed pixel variances; the family-wise "
      "alpha is shared by Sidak.\n"
      "Verdict: SAME (exit 0) when no test rejects and the image-mean test detects a relative difference of "
      "--max-detectable-difference with power 0.9; DIFFERENT (exit 1) when any test rejects, naming which (mean, "
      "tiles, pixels, variance); bad input (exit 2, one sentence on stderr: resolutions or channels that differ, "
      "NaN or infinite radiance, fewer than 2 renders on a side without variance channels, the same render on both "
      "sides); INCONCLUSIVE (exit 3) when nothing rejects but the test lacks that power (the report says how many "
      "renders or samples would give it).\n"
      "Finite negative values (a spectral renderer's RGB film) are data: used as is, counted per side in the report "
      "and the JSON.\n" + std::string(kExitContract));
  return command;
}

namespace {

verify::CompareSide read_side(const std::vector<std::string>& paths, verify::ChannelMode mode) {
  verify::CompareSide side;
  for (const std::string& path : paths) side.images.push_back(verify::read_foreign_image(path, mode));
  return side;
}

}  // namespace

int run_compare(const CompareCommandOptions& options) {
  try {
    verify::PlotTools tools;
    if (!options.html_dir.empty()) tools = verify::prepare_compare_html(options.html_dir);
    const verify::CompareSide a = read_side(options.a_paths, options.channels);
    const verify::CompareSide b = read_side(options.b_paths, options.channels);
    const verify::CompareResult r = verify::compare_renders(a, b, options.alpha, options.max_detectable_difference,
                                                            options.tile_size, options.test_variance);
    const std::vector<std::string> warnings = verify::compare_warnings(a, b);
    for (const std::string& w : warnings) std::fprintf(stderr, "furnace: warning: %s\n", w.c_str());
    if (!options.zmap_path.empty()) verify::write_compare_zmap(options.zmap_path, r);
    const std::string text = verify::format_compare(r);
    std::fputs(text.c_str(), options.json_path == "-" ? stderr : stdout);
    const auto report_json = [&] {
      return verify::compare_json(a, b, r, warnings, options.channels, options.zmap_path);
    };
    if (!options.json_path.empty()) verify::emit_json(options.json_path, report_json());
    if (!options.html_dir.empty()) verify::write_compare_html(tools, options.html_dir, report_json(), r);
    return verify::exit_code(r.verdict);
  } catch (const Error& e) {
    if (!options.json_path.empty()) verify::emit_bad_input_json(options.json_path, "compare", e.what());
    throw;
  }
}

}  // namespace furnace::cli
