#include "cli/export_command.h"

#include <array>
#include <filesystem>
#include <vector>

#include <fmt/format.h>

#include "cli/cli_options.h"
#include "core/error.h"
#include "core/path_length.h"
#include "core/scene.h"
#include "export/cycles.h"
#include "export/pbrt_v4.h"
#include "renderer/render_options.h"

namespace furnace::cli {

namespace {

void write_pbrt_v4_file(const Scene& scene, const ExportCommandOptions& o) {
  exporter::PbrtV4Options options;
  if (o.spp) options.spp = *o.spp;
  options.seed = o.seed;
  options.max_segments = o.max_segments;
  options.image_filename = std::filesystem::path(o.output).stem().string() + ".exr";
  exporter::write_pbrt_v4(scene, options, o.output);
}

void write_cycles_file(const Scene& scene, const ExportCommandOptions& o) {
  exporter::CyclesOptions options;
  if (o.spp) options.spp = *o.spp;
  options.max_segments = o.max_segments;
  if (o.emitter_grid) options.emitter_grid = *o.emitter_grid;
  if (o.sphere_subdivisions) options.sphere_subdivisions = *o.sphere_subdivisions;
  exporter::write_cycles(scene, options, o.output);
}

// Whether each option that only some formats take was given: --seed,
// --emitter-grid, --sphere-subdivisions (the others, --scene, --format,
// --spp, --max-depth and --output, every format takes).
using OptionGiven = bool (*)(const ExportCommandOptions& options);
constexpr std::array<OptionGiven, 3> kFormatOptions = {{
    [](const ExportCommandOptions& o) { return o.seed.has_value(); },
    [](const ExportCommandOptions& o) { return o.emitter_grid.has_value(); },
    [](const ExportCommandOptions& o) { return o.sphere_subdivisions.has_value(); },
}};

struct ExportFormatInfo {
  ExportFormat format;
  const char* name;  // --format's value
  void (*write)(const Scene& scene, const ExportCommandOptions& options);
  // Its decision on each option of kFormatOptions, in that order: nullptr
  // where it takes the option, else the sentence that refuses it.
  std::array<const char*, kFormatOptions.size()> refusal;
};

constexpr const char* kMeshOptionsRefusal =
    "options --emitter-grid and --sphere-subdivisions apply to --format cycles only (pbrt-v4 renders rectangles and "
    "spheres exactly).";

// In the order --help lists them.
constexpr std::array<ExportFormatInfo, 2> kExportFormats = {{
    {ExportFormat::kPbrtV4, "pbrt-v4", write_pbrt_v4_file, {nullptr, kMeshOptionsRefusal, kMeshOptionsRefusal}},
    {ExportFormat::kCycles, "cycles", write_cycles_file,
     {"option --seed is not written into a Cycles script: pass it to the script (-- --seed S or --seeds A-B).",
      nullptr, nullptr}},
}};

// Refuses the first option of `o` (in kFormatOptions' order) that its format
// does not take.
void refuse_other_formats_options(const ExportFormatInfo& format, const ExportCommandOptions& o) {
  for (size_t i = 0; i < kFormatOptions.size(); ++i)
    if (format.refusal[i] && kFormatOptions[i](o)) throw Error(format.refusal[i]);
}

// Every enumerator 0 … kExportFormats.size() − 1 has exactly one row.
constexpr bool every_format_has_one_row() {
  for (size_t v = 0; v < kExportFormats.size(); ++v) {
    int rows = 0;
    for (const ExportFormatInfo& info : kExportFormats) rows += info.format == ExportFormat(v);
    if (rows != 1) return false;
  }
  return true;
}
static_assert(every_format_has_one_row(), "kExportFormats needs one row per ExportFormat");

const ExportFormatInfo& format_info(ExportFormat format) {
  for (const ExportFormatInfo& info : kExportFormats)
    if (info.format == format) return info;
  check_failed("every ExportFormat has a row in kExportFormats", __FILE__, __LINE__);  // the static_assert above
}

}  // namespace

CLI::App* add_export_command(CLI::App& app, ExportCommandOptions& o) {
  CLI::App* command = app.add_subcommand("export", "Write a scene in another renderer's format (refused, exit 2, "
                                         "when that format cannot express it exactly)");
  command->add_option("--scene", o.scene_path, "Scene file (JSON)")->required();
  std::vector<std::pair<std::string, ExportFormat>> formats;
  for (const ExportFormatInfo& info : kExportFormats) formats.emplace_back(info.name, info.format);
  command->add_option("--format", o.format, "Target format")
      ->required()->transform(enum_by_name(formats))->type_name("TEXT");
  command->add_option_function<int>("--spp", [&o](const int& spp) { o.spp = spp; },
                                    "Samples per pixel (pbrt-v4 default 256, cycles default 128)")
      ->transform(integer_in(1, kMaxSpp));
  command->add_option_function<uint64_t>("--seed", [&o](const uint64_t& seed) { o.seed = seed; },
                                         "pbrt-v4: seed written into the file (default: none, the renderer's own "
                                         "--seed chooses)")
      ->transform(seed_value());
  max_depth_option(command->add_option("--max-depth", o.max_segments, "Longest path in segments, the camera's "
                                       "included, or 'unlimited' (default unlimited); the file names the matching "
                                       "furnace check --max-depth"));
  command->add_option_function<int>("--emitter-grid", [&o](const int& n) { o.emitter_grid = n; },
                                    "cycles: cut each emitting rectangle or triangle into a grid of N x N cells")
      ->default_str(std::to_string(exporter::CyclesOptions{}.emitter_grid))->transform(integer_in(1, 256));
  command->add_option_function<int>("--sphere-subdivisions", [&o](const int& level) { o.sphere_subdivisions = level; },
                                    "cycles: icosphere level of each sphere (20*4^L triangles)")
      ->default_str(std::to_string(exporter::CyclesOptions{}.sphere_subdivisions))->transform(integer_in(0, 7));
  command->add_option("--output,-o", o.output, "Output file")->required()->check(output_file());
  set_contract_footer(command);
  return command;
}

int run_export(const ExportCommandOptions& o) {
  const Scene scene = load_scene(o.scene_path);
  const ExportFormatInfo& format = format_info(o.format);
  // A scene whose answer is infinite at the requested depth, or whose paths
  // would be about endless, is refused as furnace's own render refuses it
  // (core/path_length.h, with furnace's default roulette depth): another
  // renderer would render it forever too.
  require_bounded_paths(scene, o.max_segments, RenderOptions{}.roulette_depth);
  refuse_other_formats_options(format, o);
  format.write(scene, o);
  fmt::print("exported {} ({}) for {} -> {}\n", scene.name, scene.source, format.name, o.output);
  return kExitPass;
}

}  // namespace furnace::cli
