#include "cli/report_command.h"

#include <cstdio>

#include <fmt/format.h>

#include "cli/cases.h"
#include "cli/cli_options.h"
#include "cli/progress.h"
#include "core/error.h"
#include "core/path_length.h"
#include "core/scene.h"
#include "verify/report.h"
#include "verify/report_html.h"
#include "verify/seed_figure.h"

namespace furnace::cli {

CLI::App* add_report_command(CLI::App& app, ReportCommandOptions& o) {
  CLI::App* command = app.add_subcommand("report", "Write convergence reports (error against spp and time, plots, "
                                         "images; HTML, Markdown, CSV) for the built-in suite or the given scenes");
  CLI::Option* scene = command->add_option("--scene", o.scenes, "Scene file(s); default: the built-in suite");
  add_suite_option(command, o.suite)->excludes(scene);
  add_strategies_option(command, o.strategies);
  command->add_option("--min-spp", o.min_spp, "Smallest spp (doubled up to --max-spp)")
      ->capture_default_str()->transform(integer_in(2, kMaxSpp));
  command->add_option("--max-spp", o.max_spp, "Largest spp")->capture_default_str()->transform(integer_in(2, kMaxSpp));
  add_seed_option(command, o.seed);
  add_threads_option(command, o.threads);
  command->add_option("--output-dir", o.output_dir, "Directory for index.html, its PNG files, report.json, "
                      "convergence.md and convergence.csv (created before any rendering)")
      ->capture_default_str()->check(output_directory());
  command->add_flag("--no-html", o.no_html, "Write only convergence.md and convergence.csv: no plots, images, "
                    "report.json or index.html (and no Python needed)");
  set_contract_footer(command, "report needs Python 3 with matplotlib (Debian: python3-matplotlib) for its plots and "
                      "images: without it, it exits 2 before rendering anything (--no-html does without).");
  return command;
}

namespace {

// The report's cases: the built-in suite, or each --scene file with the
// chosen strategies (default: every direct strategy that sees its lights).
std::vector<verify::Case> report_cases(const ReportCommandOptions& o) {
  if (o.scenes.empty()) return suite_cases(verify::builtin_suite(o.suite, o.max_spp, o.seed, o.threads), o.strategies);
  std::vector<verify::Case> cases = scene_file_cases(o.scenes, o.strategies);
  for (verify::Case& c : cases) {
    c.options.spp = o.max_spp;
    c.options.seed = o.seed;
    c.options.threads = o.threads;
  }
  return cases;
}

void print_seed_figure(const verify::SeedFigure& f) {
  fmt::print("seed figure ({}, {}x{}): {} at {} spp rel. RMSE {:.3g} in {:.3f} s, {} at {} spp rel. RMSE {:.3g} in "
             "{:.3f} s; pixel variance ratio predicted {:.3g}, measured {:.3g} (MSE ratio {:.3g})\n",
             f.scene, f.width, f.height, f.hemisphere.strategy, f.hemisphere.spp, f.hemisphere.relative_rmse,
             f.hemisphere.seconds, f.light.strategy, f.light.spp, f.light.relative_rmse, f.light.seconds,
             f.predicted_variance_ratio, f.measured_variance_ratio, f.measured_mse_ratio);
}

}  // namespace

int run_report(const ReportCommandOptions& o) {
  if (o.min_spp > o.max_spp)
    throw Error(fmt::format("--min-spp ({}) must not exceed --max-spp ({}).", o.min_spp, o.max_spp));
  const bool html = !o.no_html;
  const std::string& dir = o.output_dir;
  // Everything the HTML report needs is found, and where it goes is settled,
  // before any rendering.
  const verify::PlotTools tools = html ? verify::find_plot_tools() : verify::PlotTools{};
  const std::vector<verify::Case> cases = report_cases(o);
  if (cases.empty()) throw Error("no report case matches the given --scene and --strategy options.");
  // A path tracer's scene whose answer is infinite or whose paths would be
  // about endless is refused before the output directory is touched.
  for (const verify::Case& c : cases)
    if (is_path_tracer(c.options.strategy))
      require_bounded_paths(load_scene(c.scene_path), c.options.max_depth, c.options.roulette_depth);
  create_output_directory(dir, "--output-dir");
  verify::Progress progress("report", cases.size() + (html ? 1 : 0));
  const std::vector<verify::ReportCase> measured =
      verify::measure_report(cases, o.min_spp, o.max_spp, [&](const verify::ReportCase& rc) {
        progress.clear();
        const verify::ConvergenceSeries& s = rc.series;
        fmt::print("{:<16} {:<22} slope {:>7.3f}  rel. RMSE {:.3e} at {} spp in {:.3f} s\n", s.scene, s.strategy,
                   s.slope, s.points.back().relative_rmse, s.points.back().spp, s.points.back().seconds);
        progress.step();
      });
  std::vector<verify::ConvergenceSeries> series;
  for (const verify::ReportCase& rc : measured) series.push_back(rc.series);
  if (!html) {
    progress.finish();
    verify::write_convergence_report(series, dir, o.command_line);
    fmt::print("wrote {}/convergence.md and {}/convergence.csv (--no-html: no plots, images or index.html)\n", dir,
               dir);
    return kExitPass;
  }
  const verify::SeedFigure figure = verify::measure_seed_figure(o.seed, o.threads);
  progress.step();
  progress.finish();
  print_seed_figure(figure);
  verify::write_convergence_report(series, dir, o.command_line);
  verify::write_report_json(measured, figure, {o.command_line, o.min_spp, o.max_spp, o.seed}, dir);
  const int status = verify::run_plot_script(tools, dir);
  if (status != 0) {
    std::fprintf(stderr, "furnace: error: %s %s failed (exit %d); %s has convergence.md, convergence.csv and "
                 "report.json but no new index.html.\n", tools.python.c_str(), tools.script.c_str(), status,
                 dir.c_str());
    return kExitFail;
  }
  fmt::print("wrote {}/index.html (plots and images), {}/convergence.md, {}/convergence.csv, {}/report.json\n", dir,
             dir, dir, dir);
  return kExitPass;
}

}  // namespace furnace::cli
