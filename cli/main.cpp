// The `furnace` command line: render, verify (the default verification run).
// Every user error is one sentence on stderr and a non-zero exit.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "analytic/global.h"
#include "core/error.h"
#include "core/provenance.h"
#include "core/scene.h"
#include "renderer/exr_io.h"
#include "renderer/render.h"
#include "verify/analytic_query.h"
#include "verify/check.h"
#include "verify/check_command.h"
#include "cli/cli_options.h"
#include "export/cycles.h"
#include "export/pbrt_v4.h"
#include "verify/harness.h"
#include "verify/verdict_table.h"
#include "cli/progress.h"
#include "verify/report.h"
#include "verify/report_html.h"
#include "verify/seed_figure.h"
#include "verify/verdict_export.h"
#include "stats/statistics.h"

namespace {

using namespace furnace;

int run_render(const std::string& scene_path, const std::string& strategy, const std::string& defect,
               int spp, uint64_t seed, int threads, int max_depth, int roulette_depth, const std::string& output,
               const std::string& light_selection, bool allow_nonfinite) {
  const Scene scene = load_scene(scene_path);
  RenderOptions options;
  options.light_selection = parse_light_selection(light_selection);
  options.strategy = parse_strategy(strategy);
  options.defect = parse_defect(defect);
  options.spp = spp;
  options.seed = seed;
  options.threads = threads;
  options.max_depth = max_depth;
  options.roulette_depth = roulette_depth;
  const Image image = render(scene, options);
  write_exr(output, image, render_provenance(scene_path, scene, options));
  const double samples = double(image.width) * image.height * spp;
  fmt::print("rendered {} ({}x{}, {} spp, strategy {}) in {:.3f} s, {:.3g} samples/s, {} non-finite samples -> {}\n",
             scene.name, image.width, image.height, spp, strategy, image.seconds, samples / image.seconds,
             image.nonfinite_samples, output);
  // Non-finite samples are dropped from the image, so its mean is not the
  // estimator's: a failure unless the user accepts it.
  if (image.nonfinite_samples > 0 && !allow_nonfinite) {
    std::fprintf(stderr,
                 "furnace: FAIL: %llu of %.0f samples were not finite (NaN or Inf, dropped from %s); "
                 "--allow-nonfinite accepts them.\n",
                 static_cast<unsigned long long>(image.nonfinite_samples), samples, output.c_str());
    return cli::kExitFail;
  }
  return cli::kExitPass;
}

// The built-in suite's cases whose strategy is among `strategies` (all of
// them when none is named); an unknown name is refused.
std::vector<verify::Case> suite_cases(const std::vector<verify::Case>& suite, const std::vector<std::string>& strategies) {
  for (const std::string& name : strategies) parse_strategy(name);
  std::vector<verify::Case> cases;
  for (const verify::Case& c : suite)
    if (strategies.empty() ||
        std::find(strategies.begin(), strategies.end(), strategy_name(c.options.strategy)) != strategies.end())
      cases.push_back(c);
  return cases;
}

// The cases of --scene files: each file with the named strategies, or by
// default every direct strategy that can see its lights (none that misses its
// point lights). Each file is loaded first, so a bad one fails before any
// rendering. Options other than the strategy are the caller's to set.
std::vector<verify::Case> scene_file_cases(const std::vector<std::string>& scenes,
                                           std::vector<std::string> strategies) {
  const bool all_direct = strategies.empty();
  if (all_direct)
    for (Strategy s : direct_strategies()) strategies.push_back(strategy_name(s));
  std::vector<verify::Case> cases;
  for (const std::string& path : scenes) {
    const Scene scene = load_scene(path);
    for (const std::string& name : strategies) {
      const Strategy strategy = parse_strategy(name);
      if (all_direct && !scene.point_lights.empty() && !strategy_sees_delta_lights(strategy)) continue;
      verify::Case c;
      c.scene_path = path;
      c.options.strategy = strategy;
      cases.push_back(c);
    }
  }
  return cases;
}

// Where `verify` writes its JSON and HTML twins of the table (empty: not asked for).
struct VerifyOutputs {
  std::string json_path, html_dir, command_line;
};

int run_verify(std::vector<std::string> scenes, std::vector<std::string> strategies, const std::string& defect,
               int spp, uint64_t seed, int threads, double alpha, int max_depth, const std::string& light_selection,
               const VerifyOutputs& outputs) {
  // Empty: the built-in suite's own choice per case (it runs some scenes
  // under both), uniform for --scene files.
  const LightSelection selection =
      light_selection.empty() ? LightSelection::kUniform : parse_light_selection(light_selection);
  std::vector<verify::Case> cases;
  if (scenes.empty())
    for (verify::Case c : suite_cases(verify::default_suite(spp, seed, threads), strategies)) {
      c.options.defect = parse_defect(defect);
      if (!light_selection.empty()) c.options.light_selection = selection;
      cases.push_back(c);
    }
  for (verify::Case c : scene_file_cases(scenes, strategies)) {
    c.options.light_selection = selection;
    c.options.defect = parse_defect(defect);
    c.options.spp = spp;
    c.options.seed = seed;
    c.options.threads = threads;
    c.options.max_depth = max_depth;
    cases.push_back(c);
  }
  // Šidák: the cases share the family-wise α equally.
  if (cases.empty()) throw Error("no verification case matches the given --scene and --strategy options.");
  const double per_case_alpha = stats::sidak_alpha(alpha, cases.size());
  if (!outputs.html_dir.empty()) cli::create_output_directory(outputs.html_dir, "--html");
  const std::string warning = verify::low_spp_warning(cases);
  if (!warning.empty()) std::fprintf(stderr, "furnace: warning: %s\n", warning.c_str());
  verify::Progress progress("verify", cases.size());
  const std::vector<verify::Verdict> verdicts =
      verify::run_cases(cases, per_case_alpha, threads, [&] { progress.step(); });
  progress.finish();
  std::fputs(verify::format_table(verdicts, alpha).c_str(), stdout);
  if (!outputs.json_path.empty()) verify::write_verdicts_json(verdicts, alpha, outputs.json_path);
  if (!outputs.html_dir.empty()) verify::write_verdicts_html(verdicts, alpha, outputs.command_line, outputs.html_dir);
  bool all_pass = true;
  for (const auto& v : verdicts) all_pass = all_pass && v.pass;
  std::puts(all_pass ? "verdict: PASS" : "verdict: FAIL");
  return all_pass ? 0 : 1;
}

// The report's cases: the built-in suite, or each --scene file with the
// chosen strategies (default: every direct strategy that sees its lights).
std::vector<verify::Case> report_cases(const std::vector<std::string>& scenes, const std::vector<std::string>& strategies,
                                       int max_spp, uint64_t seed, int threads) {
  if (scenes.empty()) return suite_cases(verify::default_suite(max_spp, seed, threads), strategies);
  std::vector<verify::Case> cases = scene_file_cases(scenes, strategies);
  for (verify::Case& c : cases) {
    c.options.spp = max_spp;
    c.options.seed = seed;
    c.options.threads = threads;
  }
  return cases;
}

int run_report(const std::vector<std::string>& scenes, const std::vector<std::string>& strategies, int min_spp,
               int max_spp, uint64_t seed, int threads, const std::string& dir, const std::string& command_line,
               bool html) {
  if (min_spp > max_spp)
    throw Error(fmt::format("--min-spp ({}) must not exceed --max-spp ({}).", min_spp, max_spp));
  // Everything the HTML report needs is found, and where it goes is settled,
  // before any rendering.
  const verify::PlotTools tools = html ? verify::find_plot_tools() : verify::PlotTools{};
  const std::vector<verify::Case> cases = report_cases(scenes, strategies, max_spp, seed, threads);
  if (cases.empty()) throw Error("no report case matches the given --scene and --strategy options.");
  cli::create_output_directory(dir, "--output-dir");
  verify::Progress progress("report", cases.size() + (html ? 1 : 0));
  const std::vector<verify::ReportCase> measured =
      verify::measure_report(cases, min_spp, max_spp, [&](const verify::ReportCase& rc) {
        progress.clear();
        const auto& s = rc.series;
        fmt::print("{:<16} {:<22} slope {:>7.3f}  rel. RMSE {:.3e} at {} spp in {:.3f} s\n", s.scene, s.strategy,
                   s.slope, s.points.back().relative_rmse, s.points.back().spp, s.points.back().seconds);
        progress.step();
      });
  std::vector<verify::ConvergenceSeries> series;
  for (const verify::ReportCase& rc : measured) series.push_back(rc.series);
  if (!html) {
    progress.finish();
    verify::write_convergence_report(series, dir, command_line);
    fmt::print("wrote {}/convergence.md and {}/convergence.csv (--no-html: no plots, images or index.html)\n", dir,
               dir);
    return 0;
  }
  const verify::SeedFigure figure = verify::measure_seed_figure(seed, threads);
  progress.step();
  progress.finish();
  fmt::print("seed figure ({}, {}x{}): {} at {} spp rel. RMSE {:.3g} in {:.3f} s, {} at {} spp rel. RMSE {:.3g} in "
             "{:.3f} s; pixel variance ratio predicted {:.3g}, measured {:.3g} (MSE ratio {:.3g})\n",
             figure.scene, figure.width, figure.height, figure.hemisphere.strategy, figure.hemisphere.spp,
             figure.hemisphere.relative_rmse, figure.hemisphere.seconds, figure.light.strategy, figure.light.spp,
             figure.light.relative_rmse, figure.light.seconds, figure.predicted_variance_ratio,
             figure.measured_variance_ratio, figure.measured_mse_ratio);
  verify::write_convergence_report(series, dir, command_line);
  verify::write_report_json(measured, figure, {command_line, min_spp, max_spp, seed}, dir);
  const int status = verify::run_plot_script(tools, dir);
  if (status != 0) {
    std::fprintf(stderr, "furnace: error: %s %s failed (exit %d); %s has convergence.md, convergence.csv and "
                 "report.json but no new index.html.\n", tools.python.c_str(), tools.script.c_str(), status,
                 dir.c_str());
    return cli::kExitFail;
  }
  fmt::print("wrote {}/index.html (plots and images), {}/convergence.md, {}/convergence.csv, {}/report.json\n", dir,
             dir, dir, dir);
  return 0;
}

// The false-alarm sweep: every selected case of the built-in suite rerun over
// `seeds` seeds at the per-case level `case_alpha`; the observed rejection
// rate of each case is compared with case_alpha by an exact binomial test.
// The per-case tests are Šidák-corrected over pixels and partly positively
// correlated, so the true rate may sit below case_alpha but must not exceed it.
int run_sweep(const std::vector<std::string>& strategies, int seeds, int spp, double case_alpha, int threads) {
  for (const std::string& name : strategies) parse_strategy(name);
  std::vector<verify::Case> cases;
  for (const verify::Case& c : verify::default_suite(spp, 0, threads)) {
    const bool selected = strategies.empty() || std::find(strategies.begin(), strategies.end(),
                                                          strategy_name(c.options.strategy)) != strategies.end();
    if (selected) cases.push_back(c);
  }
  if (cases.empty()) throw Error("no sweep case matches the given --strategy options.");
  const std::string warning = verify::low_spp_warning(cases);
  if (!warning.empty()) std::fprintf(stderr, "furnace: warning: %s\n", warning.c_str());
  fmt::print("false-alarm sweep: {} cases x {} seeds at {} spp, per-case alpha {}\n", cases.size(), seeds, spp,
             case_alpha);
  fmt::print("{:<22} {:<24} {:>10} {:>8} {:>19} {:>10}\n", "scene", "strategy", "rejected", "rate", "95% CI",
             "binom p");
  size_t total_rejections = 0, total_trials = 0;
  bool calibrated = true;
  verify::Progress progress("sweep", cases.size() * size_t(seeds));
  for (const verify::Case& base : cases) {
    // The case at seeds 1 … seeds, run together (run_cases: the analytic
    // values once for all seeds, several seeds at a time).
    std::vector<verify::Case> runs(size_t(seeds), base);
    for (size_t i = 0; i < runs.size(); ++i) runs[i].options.seed = 1 + i;
    const std::vector<verify::Verdict> verdicts =
        verify::run_cases(runs, case_alpha, threads, [&] { progress.step(); });
    const std::string& scene_name = verdicts.front().scene;
    const std::string& strategy = verdicts.front().strategy;
    const stats::RejectionRate rate = stats::measure_rejection_rate(
        [&](uint64_t seed) { return !verdicts[seed - 1].pass; }, size_t(seeds), case_alpha, 1);
    total_rejections += rate.rejections;
    total_trials += rate.trials;
    // Too many false alarms is the failure that matters (one-sided reading of
    // the two-sided exact test): a significant excess at 1 %.
    const bool excess = rate.rate > case_alpha && rate.binomial_p_value < 0.01;
    calibrated = calibrated && !excess;
    progress.clear();
    fmt::print("{:<22} {:<24} {:>5}/{:<4} {:>8.4f} [{:.4f}, {:.4f}] {:>10.3g}{}\n", scene_name, strategy,
               rate.rejections, rate.trials, rate.rate, rate.ci_low, rate.ci_high, rate.binomial_p_value,
               excess ? "  EXCESS" : "");
  }
  progress.finish();
  const double p_all = stats::binomial_two_sided_p_value(total_rejections, total_trials, case_alpha);
  fmt::print("all cases: {}/{} rejected, rate {:.4f} against alpha {} (binomial p {:.3g})\n", total_rejections,
             total_trials, double(total_rejections) / double(total_trials), case_alpha, p_all);
  std::puts(calibrated ? "calibration: OK (no case rejects significantly more often than alpha)"
                       : "calibration: FAIL (some case rejects significantly more often than alpha)");
  return calibrated ? 0 : 1;
}

// "uniform_hemisphere 128, cosine_hemisphere 128, ...": each strategy's
// verify::min_calibrated_spp, in table order, for --help.
std::string calibrated_spp_list() {
  std::vector<std::string> items;
  for (const StrategyInfo& info : kStrategyTable)
    items.push_back(fmt::format("{} {}", info.name, verify::min_calibrated_spp(info.strategy)));
  return fmt::format("{}", fmt::join(items, ", "));
}

// The accepted names of each vocabulary, in table order, for CLI11's
// IsMember validator (which also lists them in --help).
std::vector<std::string> strategy_choices() {
  std::vector<std::string> out;
  for (const StrategyInfo& info : kStrategyTable) out.push_back(info.name);
  return out;
}
std::vector<std::string> defect_choices() {
  std::vector<std::string> out;
  for (const DefectInfo& info : kDefectTable) out.push_back(info.name);
  return out;
}
std::vector<std::string> light_selection_choices() {
  std::vector<std::string> out;
  for (const auto& [name, selection] : light_selection_names()) out.push_back(name);
  return out;
}

// --max-depth, the same for render, verify and check: the longest path in
// segments (the camera segment counts as 1; 2 is direct lighting), a number
// >= 1 or the word "unlimited" (kUnlimitedDepth).
CLI::Option* add_max_depth_option(CLI::App* command, int& segments, const std::string& description) {
  const std::map<std::string, int> words{{"unlimited", kUnlimitedDepth}};
  return command->add_option("--max-depth", segments, description)
      ->transform(CLI::Transformer(words, CLI::ignore_case).description(""))
      ->check(cli::integer_in(1, kUnlimitedDepth).description(""))
      ->type_name("SEGMENTS|unlimited");
}

// Upper bounds of the integer options: 2^24 spp keeps spp × pixels × path
// length far inside 64-bit counters; 1024 threads is beyond any machine the
// tests run on while still catching a mistyped number.
constexpr int kMaxSpp = 1 << 24;
constexpr int kMaxThreads = 1024;
// α of a whole run, at most 0.5; at least 1e-12 so that its Šidák share of
// one test among ~10⁵ (cases × pixels) is still a representable level.
const CLI::Validator alpha_range = cli::number_in(1e-12, 0.5);

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"furnace: deterministic verification of Monte Carlo rendering against exact references"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "furnace " + furnace_version());
  app.footer(cli::kExitContract);
  // Every option's numbers go through cli_options.h's validators (finite,
  // in range, decimal); each subcommand's --help ends with the contract too.
  const auto with_contract = [](CLI::App* command, const std::string& footer = "") {
    command->footer(footer.empty() ? std::string(cli::kExitContract) : footer + "\n" + cli::kExitContract);
  };
  const std::string spp_help = fmt::format(
      "Samples per pixel (the variance test needs >= {}; the stated alpha is calibrated from {} to {} spp, "
      "depending on the strategy)",
      stats::kMinVarianceTestSamples, verify::lowest_min_calibrated_spp(), verify::highest_min_calibrated_spp());

  std::string scene_path, strategy = "light_area", defect = "none", output = "out.exr";
  int spp = 64, threads = 0;
  uint64_t seed = 1;
  auto* render_cmd = app.add_subcommand("render", "Render a scene with one strategy to an OpenEXR image");
  render_cmd->add_option("--scene", scene_path, "Scene file (JSON)")->required();
  render_cmd->add_option("--strategy", strategy, "Sampling strategy")->capture_default_str()->check(CLI::IsMember(strategy_choices()));
  std::string light_selection = "uniform";
  render_cmd->add_option("--light-selection", light_selection, "Light selection pmf")->capture_default_str()->check(CLI::IsMember(light_selection_choices()));
  render_cmd->add_option("--defect", defect, "Negative-control defect to inject (tests only)")->capture_default_str()->check(CLI::IsMember(defect_choices()));
  render_cmd->add_option("--spp", spp, "Samples per pixel")->capture_default_str()->check(cli::integer_in(1, kMaxSpp));
  render_cmd->add_option("--seed", seed, "Random seed")->capture_default_str()->check(cli::seed_value());
  render_cmd->add_option("--threads", threads, "Worker threads (0: all)")->capture_default_str()->check(cli::integer_in(0, kMaxThreads));
  render_cmd->add_option("--output,-o", output, "Output EXR path")->capture_default_str()->check(cli::output_file());
  bool allow_nonfinite = false;
  render_cmd->add_flag("--allow-nonfinite", allow_nonfinite,
                       "Exit 0 even if some samples were NaN or Inf (dropped and counted; default: exit 1)");
  with_contract(render_cmd, "render exits 1 when any sample is not finite (NaN or Inf), unless --allow-nonfinite.");
  int max_depth = kUnlimitedDepth, roulette_depth = 3;
  add_max_depth_option(render_cmd, max_depth, "Path tracers: longest path in segments, camera segment included, or "
                       "'unlimited' (default unlimited)");
  render_cmd->add_option("--roulette-depth", roulette_depth, "Path tracers: depth at which Russian roulette starts")
      ->capture_default_str()->check(cli::integer_in(1, std::numeric_limits<int>::max()));

  std::vector<std::string> v_scenes, v_strategies;
  std::string v_defect = "none";
  int v_spp = 4096, v_threads = 0;
  uint64_t v_seed = 20261125;
  double v_alpha = verify::kDefaultFamilyAlpha;
  int v_max_depth = kUnlimitedDepth;
  auto* verify_cmd = app.add_subcommand("verify", "Render the analytic scenes and test them against their exact references");
  verify_cmd->add_option("--scene", v_scenes, "Scene file(s); default: the built-in suite");
  verify_cmd->add_option("--strategy", v_strategies, "Strategy name(s); default: all")->check(CLI::IsMember(strategy_choices()));
  std::string v_light_selection;
  verify_cmd->add_option("--light-selection", v_light_selection,
                         "Light selection pmf, uniform or power, for every case (default: the built-in suite's own "
                         "choice per case, uniform for --scene files)")
      ->check(CLI::IsMember(light_selection_choices()));
  verify_cmd->add_option("--defect", v_defect, "Inject a negative-control defect (the run must then fail)")->capture_default_str()->check(CLI::IsMember(defect_choices()));
  auto* v_scene_opt = verify_cmd->get_option("--scene");
  verify_cmd->add_option("--spp", v_spp, spp_help)->capture_default_str()->check(cli::integer_in(2, kMaxSpp));
  verify_cmd->add_option("--seed", v_seed, "Random seed")->capture_default_str()->check(cli::seed_value());
  verify_cmd->add_option("--threads", v_threads, "Worker threads (0: all)")->capture_default_str()->check(cli::integer_in(0, kMaxThreads));
  verify_cmd->add_option("--alpha", v_alpha, "Family-wise false-alarm probability of the whole run")
      ->capture_default_str()->check(alpha_range);
  add_max_depth_option(verify_cmd, v_max_depth, "Path tracers with --scene: longest path in segments, camera segment "
                       "included, or 'unlimited' (default unlimited; the built-in suite sets its own)")
      ->needs(v_scene_opt);
  with_contract(verify_cmd, fmt::format("A test that cannot run (the variance test below {} spp) is skipped and "
                                        "named, never failed; below a strategy's calibrated spp ({}) a warning "
                                        "says alpha is not calibrated.",
                                        stats::kMinVarianceTestSamples, calibrated_spp_list()));

  std::string v_json, v_html;
  verify_cmd->add_option("--json", v_json, "Also write every number of the verdict table as JSON to FILE")
      ->check(cli::output_file().description(""))->type_name("FILE");
  verify_cmd->add_option("--html", v_html, "Also write the verdict table as DIR/index.html (failing cases first)")
      ->check(cli::output_directory().description(""))->type_name("DIR");

  std::vector<std::string> r_scenes, r_strategies;
  int r_min_spp = 4, r_max_spp = 1024, r_threads = 0;
  uint64_t r_seed = 20261125;
  std::string r_dir = "reports/generated";
  auto* report_cmd = app.add_subcommand("report", "Write convergence reports (error against spp and time, plots, "
                                        "images; HTML, Markdown, CSV) for the built-in suite or the given scenes");
  report_cmd->add_option("--scene", r_scenes, "Scene file(s); default: the built-in suite");
  report_cmd->add_option("--strategy", r_strategies, "Strategy name(s); default: all")->check(CLI::IsMember(strategy_choices()));
  report_cmd->add_option("--min-spp", r_min_spp, "Smallest spp (doubled up to --max-spp)")->capture_default_str()->check(cli::integer_in(2, kMaxSpp));
  report_cmd->add_option("--max-spp", r_max_spp, "Largest spp")->capture_default_str()->check(cli::integer_in(2, kMaxSpp));
  report_cmd->add_option("--seed", r_seed, "Random seed")->capture_default_str()->check(cli::seed_value());
  report_cmd->add_option("--threads", r_threads, "Worker threads (0: all)")->capture_default_str()->check(cli::integer_in(0, kMaxThreads));
  report_cmd->add_option("--output-dir", r_dir, "Directory for index.html, its PNG files, report.json, "
                         "convergence.md and convergence.csv (created before any rendering)")
      ->capture_default_str()->check(cli::output_directory());
  bool r_no_html = false;
  report_cmd->add_flag("--no-html", r_no_html, "Write only convergence.md and convergence.csv: no plots, images, "
                       "report.json or index.html (and no Python needed)");
  with_contract(report_cmd, "report needs Python 3 with matplotlib (Debian: python3-matplotlib) for its plots and "
                "images: without it, it exits 2 before rendering anything (--no-html does without).");

  std::string a_scene;
  std::array<double, 3> a_point{}, a_normal{};
  std::vector<std::string> a_estimators;
  double a_albedo = 0;
  bool a_json = false;
  auto* analytic_cmd = app.add_subcommand("analytic", "Print the exact irradiance, radiance and estimator moments at a point");
  analytic_cmd->add_option("--scene", a_scene, "Scene file (JSON)")->required();
  analytic_cmd->add_option("--point", a_point, "Receiver point x,y,z")
      ->required()->delimiter(',')->check(cli::finite_number().description(""))->type_name("X,Y,Z");
  analytic_cmd->add_option("--normal", a_normal, "Receiver normal x,y,z (normalised)")
      ->required()->delimiter(',')->check(cli::finite_number().description(""))->type_name("X,Y,Z");
  auto* a_albedo_opt = analytic_cmd->add_option("--albedo", a_albedo, "Lambertian albedo for the radiance (default: the receiver's)")
      ->check(cli::number_in(0.0, 1.0));
  analytic_cmd->add_option("--estimator", a_estimators,
                           "Estimator(s) whose second moment and variance to compute (repeatable; default: every "
                           "strategy with its own variance model)")
      ->check(CLI::IsMember(strategy_choices()));
  with_contract(analytic_cmd);
  analytic_cmd->add_flag("--json", a_json, "Print JSON");

  verify::CheckOptions c_options;
  int c_max_depth = kUnlimitedDepth;
  auto* check_cmd = app.add_subcommand("check", "Test another renderer's OpenEXR images of a scene against its exact reference");
  check_cmd->add_option("--scene", c_options.scene_path, "Scene file the images are renders of")->required();
  check_cmd->add_option("--image", c_options.image_paths,
                        "OpenEXR image(s): K >= 2 independent renders (different seeds), or one furnace EXR (with "
                        "variance.R/G/B and N channels)")->required();
  c_options.alpha = verify::kDefaultFamilyAlpha;
  check_cmd->add_option("--alpha", c_options.alpha, "Family-wise false-alarm probability")
      ->capture_default_str()->check(alpha_range);
  check_cmd->add_option("--max-detectable-bias", c_options.max_detectable_bias,
                        "PASS needs the image-mean test to detect a relative bias this large with power 0.9 "
                        "(else INCONCLUSIVE)")
      ->capture_default_str()->check(cli::number_in(0, 1, cli::End::kOpen));
  auto* c_depth = add_max_depth_option(
      check_cmd, c_max_depth,
      "The reference's path length, as for render (default: unlimited where the scene has a closed-form global "
      "answer, else direct lighting; 2 is direct lighting)");
  const std::map<std::string, verify::ChannelMode> channel_modes{{"gray", verify::ChannelMode::kGray},
                                                                 {"rgb", verify::ChannelMode::kRgb}};
  check_cmd->add_option("--channels", c_options.channels,
                        "gray: test the mean of R, G, B (or Y); rgb: test R, G and B separately")
      ->transform(CLI::CheckedTransformer(channel_modes, CLI::ignore_case).description(""))
      ->type_name("gray|rgb")->default_str("gray");
  check_cmd->add_option("--zmap", c_options.zmap_path, "Write the per-pixel t statistic to this OpenEXR file")
      ->check(cli::output_file().description(""))->type_name("FILE");
  check_cmd->add_option("--json", c_options.json_path, "Write every number of the report as JSON to FILE ('-': stdout, "
                        "the text report then goes to stderr)")
      ->check(cli::output_file(true).description(""))->type_name("FILE");
  check_cmd->footer(
      "Reference: a scene with a closed-form global-illumination answer (closed enclosures, white furnaces, scenes "
      "whose light bounces at most once, mirrors in front of these) is checked against the full answer at unlimited "
      "depth, what a path tracer without a depth limit computes; any other scene against direct lighting "
      "(emission + one bounce, --max-depth 2), the only exact answer it has.\n"
      "Verdict: PASS (exit 0) when no test rejects and the image-mean test detects a bias of --max-detectable-bias "
      "with power 0.9; FAIL (exit 1) when any test rejects, whatever the power; bad input (exit 2, one sentence on "
      "stderr); INCONCLUSIVE (exit 3) when nothing rejects but the test lacks that power (the report says how many "
      "images or samples would give it).\n" + std::string(cli::kExitContract));

  std::string e_scene, e_format, e_output;
  exporter::PbrtV4Options e_options;
  uint64_t e_seed = 0;
  auto* export_cmd = app.add_subcommand("export", "Write a scene in another renderer's format (refused, exit 2, "
                                        "when that format cannot express it exactly)");
  export_cmd->add_option("--scene", e_scene, "Scene file (JSON)")->required();
  export_cmd->add_option("--format", e_format, "Target format")->required()->check(CLI::IsMember({"pbrt-v4", "cycles"}));
  auto* e_spp_opt = export_cmd->add_option("--spp", e_options.spp, "Samples per pixel (pbrt-v4 default 256, cycles "
                                           "default 128)")->check(cli::integer_in(1, kMaxSpp));
  auto* e_seed_opt = export_cmd->add_option("--seed", e_seed, "pbrt-v4: seed written into the file (default: "
                                            "none, the renderer's own --seed chooses)")->check(cli::seed_value());
  add_max_depth_option(export_cmd, e_options.max_segments, "Longest path in segments, the camera's included, or "
                       "'unlimited' (default unlimited); the file names the matching furnace check --max-depth");
  exporter::CyclesOptions e_cycles;
  auto* e_grid_opt = export_cmd->add_option("--emitter-grid", e_cycles.emitter_grid, "cycles: cut each emitting rectangle or triangle "
                         "into a grid of N x N cells")->capture_default_str()->check(cli::integer_in(1, 256));
  auto* e_sphere_opt = export_cmd->add_option("--sphere-subdivisions", e_cycles.sphere_subdivisions, "cycles: icosphere level of each "
                         "sphere (20*4^L triangles)")->capture_default_str()->check(cli::integer_in(0, 7));
  export_cmd->add_option("--output,-o", e_output, "Output file")->required()->check(cli::output_file());
  with_contract(export_cmd);

  std::vector<std::string> s_strategies;
  int s_seeds = 50, s_spp = 1024, s_threads = 0;
  double s_alpha = 0.05;
  auto* sweep_cmd = app.add_subcommand("sweep", "Measure the false-alarm rate of the verification over many seeds (slow)");
  sweep_cmd->add_option("--strategy", s_strategies, "Strategy name(s); default: all")->check(CLI::IsMember(strategy_choices()));
  sweep_cmd->add_option("--seeds", s_seeds, "Seeds per case")->capture_default_str()->check(cli::integer_in(1, 100000));
  sweep_cmd->add_option("--spp", s_spp, spp_help)->capture_default_str()->check(cli::integer_in(2, kMaxSpp));
  sweep_cmd->add_option("--case-alpha", s_alpha, "False-alarm level of each case")->capture_default_str()->check(cli::number_in(1e-6, 0.5));
  sweep_cmd->add_option("--threads", s_threads, "Worker threads (0: all)")->capture_default_str()->check(cli::integer_in(0, kMaxThreads));
  with_contract(sweep_cmd, "sweep exits 1 when some case rejects significantly more often than --case-alpha.");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version exit 0; every argument error is bad input (2),
    // one line on stderr, whatever CLI11's own code for it.
    if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return app.exit(e);
    std::fprintf(stderr, "furnace: error: %s\n", cli::parse_error_message(app, e).c_str());
    return cli::kExitBadInput;
  }
  try {
    if (*render_cmd) return run_render(scene_path, strategy, defect, spp, seed, threads, max_depth, roulette_depth, output, light_selection, allow_nonfinite);
    if (*analytic_cmd) {
      const Scene scene = load_scene(a_scene);
      verify::AnalyticQuery q;
      q.point = {a_point[0], a_point[1], a_point[2]};
      const Vec3 n{a_normal[0], a_normal[1], a_normal[2]};
      if (!(length(n) > 0) || !std::isfinite(length(n)))
        throw Error(fmt::format("option --normal must be a non-zero finite direction, got {},{},{}.", n.x, n.y, n.z));
      q.normal = normalize(n);
      if (a_albedo_opt->count() > 0) q.albedo = a_albedo;
      for (const std::string& name : a_estimators) q.estimators.push_back(parse_strategy(name));
      std::fputs(verify::answer_analytic_query(scene, q, a_json).c_str(), stdout);
      return 0;
    }
    if (*check_cmd) {
      if (c_depth->count() > 0) c_options.max_depth = c_max_depth;
      return verify::run_check(c_options);
    }
    if (*export_cmd) {
      const Scene scene = load_scene(e_scene);
      if (e_format == "cycles") {
        if (*e_seed_opt)
          throw Error("option --seed is not written into a Cycles script: pass it to the script (-- --seed S or "
                      "--seeds A-B).");
        exporter::CyclesOptions cycles_options = e_cycles;
        if (*e_spp_opt) cycles_options.spp = e_options.spp;
        cycles_options.max_segments = e_options.max_segments;
        exporter::write_cycles(scene, cycles_options, e_output);
        fmt::print("exported {} ({}) for {} -> {}\n", scene.name, scene.source, e_format, e_output);
        return 0;
      }
      if (*e_grid_opt || *e_sphere_opt)
        throw Error("options --emitter-grid and --sphere-subdivisions apply to --format cycles only (pbrt-v4 "
                    "renders rectangles and spheres exactly).");
      if (*e_seed_opt) e_options.seed = e_seed;
      e_options.image_filename = std::filesystem::path(e_output).stem().string() + ".exr";
      exporter::write_pbrt_v4(scene, e_options, e_output);
      fmt::print("exported {} ({}) for {} -> {}\n", scene.name, scene.source, e_format, e_output);
      return 0;
    }
    if (*sweep_cmd) return run_sweep(s_strategies, s_seeds, s_spp, s_alpha, s_threads);
    if (*report_cmd) {
      std::string command_line = "furnace";
      for (int i = 1; i < argc; ++i) command_line += std::string(" ") + argv[i];
      return run_report(r_scenes, r_strategies, r_min_spp, r_max_spp, r_seed, r_threads, r_dir, command_line,
                        !r_no_html);
    }
    if (*verify_cmd) {
      std::string command_line = "furnace";
      for (int i = 1; i < argc; ++i) command_line += std::string(" ") + argv[i];
      return run_verify(v_scenes, v_strategies, v_defect, v_spp, v_seed, v_threads, v_alpha, v_max_depth,
                        v_light_selection, {v_json, v_html, command_line});
    }
  } catch (const furnace::Error& e) {
    std::fprintf(stderr, "furnace: error: %s\n", e.what());
    return cli::kExitBadInput;
  }
  return cli::kExitPass;
}
