// The `furnace` command line: render, verify (the default verification run).
// Every user error is one sentence on stderr and a non-zero exit.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <filesystem>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "core/error.h"
#include "core/scene.h"
#include "renderer/exr_io.h"
#include "renderer/render.h"
#include "verify/analytic_query.h"
#include "verify/check.h"
#include "verify/harness.h"
#include "verify/report.h"
#include "verify/statistics.h"

namespace {

using namespace furnace;

int run_render(const std::string& scene_path, const std::string& strategy, const std::string& defect,
               int spp, uint64_t seed, int threads, int max_depth, int roulette_depth, const std::string& output,
               const std::string& light_selection) {
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
  write_exr(output, image);
  const double samples = double(image.width) * image.height * spp;
  fmt::print("rendered {} ({}x{}, {} spp, strategy {}) in {:.3f} s, {:.3g} samples/s, {} non-finite samples -> {}\n",
             scene.name, image.width, image.height, spp, strategy, image.seconds, samples / image.seconds,
             image.nonfinite_samples, output);
  return 0;
}

int run_verify(std::vector<std::string> scenes, std::vector<std::string> strategies, const std::string& defect,
               int spp, uint64_t seed, int threads, double alpha, int max_depth, const std::string& light_selection) {
  // Empty: the built-in suite's own choice per case (it runs some scenes
  // under both), uniform for --scene files.
  const LightSelection selection =
      light_selection.empty() ? LightSelection::kUniform : parse_light_selection(light_selection);
  std::vector<verify::Case> cases;
  if (scenes.empty()) {
    for (verify::Case c : verify::default_suite(spp, seed, threads)) {
      c.options.defect = parse_defect(defect);
      if (!light_selection.empty()) c.options.light_selection = selection;
      const bool selected = strategies.empty() ||
                            std::find(strategies.begin(), strategies.end(), strategy_name(c.options.strategy)) !=
                                strategies.end();
      if (selected) cases.push_back(c);
    }
    for (const std::string& name : strategies) parse_strategy(name);  // reject unknown names
  }
  const bool all_direct = strategies.empty();
  if (!scenes.empty() && strategies.empty())
    for (Strategy s : all_strategies()) strategies.push_back(strategy_name(s));
  for (const std::string& path : scenes) {
    const Scene scene = load_scene(path);  // fail fast on a bad file, before any rendering
    for (const std::string& name : strategies) {
      // By default, skip the strategies that cannot see the scene's point lights.
      if (all_direct && !scene.point_lights.empty() && !strategy_sees_delta_lights(parse_strategy(name))) continue;
      verify::Case c;
      c.options.light_selection = selection;
      c.scene_path = path;
      c.options.strategy = parse_strategy(name);
      c.options.defect = parse_defect(defect);
      c.options.spp = spp;
      c.options.seed = seed;
      c.options.threads = threads;
      c.options.max_depth = max_depth;
      cases.push_back(c);
    }
  }
  // Šidák: the cases share the family-wise α equally.
  if (cases.empty()) throw Error("no verification case matches the given --scene and --strategy options.");
  const double per_case_alpha = stats::sidak_alpha(alpha, cases.size());
  std::vector<verify::Verdict> verdicts;
  for (const verify::Case& c : cases) verdicts.push_back(verify::run_case(c, per_case_alpha));
  std::fputs(verify::format_table(verdicts, alpha).c_str(), stdout);
  bool all_pass = true;
  for (const auto& v : verdicts) all_pass = all_pass && v.pass;
  std::puts(all_pass ? "verdict: PASS" : "verdict: FAIL");
  return all_pass ? 0 : 1;
}

int run_report(const std::vector<std::string>& strategies, int min_spp, int max_spp, uint64_t seed, int threads,
               const std::string& dir, const std::string& command_line) {
  if (min_spp > max_spp)
    throw Error(fmt::format("--min-spp ({}) must not exceed --max-spp ({}).", min_spp, max_spp));
  for (const std::string& name : strategies) parse_strategy(name);
  std::vector<verify::ConvergenceSeries> series;
  for (const verify::Case& c : verify::default_suite(max_spp, seed, threads)) {
    const bool selected = strategies.empty() || std::find(strategies.begin(), strategies.end(),
                                                          strategy_name(c.options.strategy)) != strategies.end();
    if (!selected) continue;
    series.push_back(verify::measure_convergence(c, min_spp, max_spp));
    const auto& s = series.back();
    fmt::print("{:<16} {:<22} slope {:>7.3f}  rel. RMSE {:.3e} at {} spp in {:.3f} s\n", s.scene, s.strategy, s.slope,
               s.points.back().relative_rmse, s.points.back().spp, s.points.back().seconds);
  }
  verify::write_convergence_report(series, dir, command_line);
  fmt::print("wrote {}/convergence.md and {}/convergence.csv\n", dir, dir);
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
  fmt::print("false-alarm sweep: {} cases x {} seeds at {} spp, per-case alpha {}\n", cases.size(), seeds, spp,
             case_alpha);
  fmt::print("{:<22} {:<24} {:>10} {:>8} {:>19} {:>10}\n", "scene", "strategy", "rejected", "rate", "95% CI",
             "binom p");
  size_t total_rejections = 0, total_trials = 0;
  bool calibrated = true;
  for (const verify::Case& base : cases) {
    std::string scene_name, strategy;
    const stats::RejectionRate rate = stats::measure_rejection_rate(
        [&](uint64_t seed) {
          verify::Case c = base;
          c.options.seed = seed;
          const verify::Verdict v = verify::run_case(c, case_alpha);
          scene_name = v.scene;
          strategy = v.strategy;
          return !v.pass;
        },
        size_t(seeds), case_alpha, 1);
    total_rejections += rate.rejections;
    total_trials += rate.trials;
    // Too many false alarms is the failure that matters (one-sided reading of
    // the two-sided exact test): a significant excess at 1 %.
    const bool excess = rate.rate > case_alpha && rate.binomial_p_value < 0.01;
    calibrated = calibrated && !excess;
    fmt::print("{:<22} {:<24} {:>5}/{:<4} {:>8.4f} [{:.4f}, {:.4f}] {:>10.3g}{}\n", scene_name, strategy,
               rate.rejections, rate.trials, rate.rate, rate.ci_low, rate.ci_high, rate.binomial_p_value,
               excess ? "  EXCESS" : "");
  }
  const double p_all = stats::binomial_two_sided_p_value(total_rejections, total_trials, case_alpha);
  fmt::print("all cases: {}/{} rejected, rate {:.4f} against alpha {} (binomial p {:.3g})\n", total_rejections,
             total_trials, double(total_rejections) / double(total_trials), case_alpha, p_all);
  std::puts(calibrated ? "calibration: OK (no case rejects significantly more often than alpha)"
                       : "calibration: FAIL (some case rejects significantly more often than alpha)");
  return calibrated ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"furnace: deterministic verification of Monte Carlo rendering against exact references"};
  app.require_subcommand(1);

  std::string scene_path, strategy = "light_area", defect = "none", output = "out.exr";
  int spp = 64, threads = 0;
  uint64_t seed = 1;
  auto* render_cmd = app.add_subcommand("render", "Render a scene with one strategy to an OpenEXR image");
  render_cmd->add_option("--scene", scene_path, "Scene file (JSON)")->required();
  render_cmd->add_option("--strategy", strategy, "Sampling strategy")->capture_default_str();
  std::string light_selection = "uniform";
  render_cmd->add_option("--light-selection", light_selection, "Light selection pmf: uniform or power")->capture_default_str();
  render_cmd->add_option("--defect", defect, "Negative-control defect to inject (tests only)")->capture_default_str();
  render_cmd->add_option("--spp", spp, "Samples per pixel")->capture_default_str()->check(CLI::Range(1, 1 << 24));
  render_cmd->add_option("--seed", seed, "Random seed")->capture_default_str();
  render_cmd->add_option("--threads", threads, "Worker threads (0: all)")->capture_default_str()->check(CLI::Range(0, 1024));
  render_cmd->add_option("--output,-o", output, "Output EXR path")->capture_default_str();
  int max_depth = std::numeric_limits<int>::max(), roulette_depth = 3;
  render_cmd->add_option("--max-depth", max_depth, "Path tracers: longest path in segments (default unlimited)")
      ->check(CLI::Range(1, std::numeric_limits<int>::max()));
  render_cmd->add_option("--roulette-depth", roulette_depth, "Path tracers: depth at which Russian roulette starts")
      ->capture_default_str()->check(CLI::Range(1, std::numeric_limits<int>::max()));

  std::vector<std::string> v_scenes, v_strategies;
  std::string v_defect = "none";
  int v_spp = 4096, v_threads = 0;
  uint64_t v_seed = 20261125;
  double v_alpha = verify::kDefaultFamilyAlpha;
  int v_max_depth = std::numeric_limits<int>::max();
  auto* verify_cmd = app.add_subcommand("verify", "Render the analytic scenes and test them against their exact references");
  verify_cmd->add_option("--scene", v_scenes, "Scene file(s); default: the built-in suite");
  verify_cmd->add_option("--strategy", v_strategies, "Strategy name(s); default: all");
  std::string v_light_selection;
  verify_cmd->add_option("--light-selection", v_light_selection,
                         "Light selection pmf, uniform or power, for every case (default: the built-in suite's own "
                         "choice per case, uniform for --scene files)");
  verify_cmd->add_option("--defect", v_defect, "Inject a negative-control defect (the run must then fail)")->capture_default_str();
  verify_cmd->add_option("--spp", v_spp, "Samples per pixel")->capture_default_str()->check(CLI::Range(2, 1 << 24));
  verify_cmd->add_option("--seed", v_seed, "Random seed")->capture_default_str();
  verify_cmd->add_option("--threads", v_threads, "Worker threads (0: all)")->capture_default_str()->check(CLI::Range(0, 1024));
  verify_cmd->add_option("--alpha", v_alpha, "Family-wise false-alarm probability of the whole run")
      ->capture_default_str()->check(CLI::Range(1e-12, 0.5));
  verify_cmd->add_option("--max-depth", v_max_depth, "Path tracers with --scene: longest path in segments (default unlimited)")
      ->check(CLI::Range(1, std::numeric_limits<int>::max()));

  std::vector<std::string> r_strategies;
  int r_min_spp = 4, r_max_spp = 1024, r_threads = 0;
  uint64_t r_seed = 20261125;
  std::string r_dir = "reports/generated";
  auto* report_cmd = app.add_subcommand("report", "Write convergence reports (error against spp and time) for the built-in suite");
  report_cmd->add_option("--strategy", r_strategies, "Strategy name(s); default: all");
  report_cmd->add_option("--min-spp", r_min_spp, "Smallest spp (doubled up to --max-spp)")->capture_default_str()->check(CLI::Range(2, 1 << 24));
  report_cmd->add_option("--max-spp", r_max_spp, "Largest spp")->capture_default_str()->check(CLI::Range(2, 1 << 24));
  report_cmd->add_option("--seed", r_seed, "Random seed")->capture_default_str();
  report_cmd->add_option("--threads", r_threads, "Worker threads (0: all)")->capture_default_str()->check(CLI::Range(0, 1024));
  report_cmd->add_option("--output-dir", r_dir, "Directory for convergence.md and convergence.csv")->capture_default_str();

  std::string a_scene, a_point, a_normal;
  double a_albedo = -1;
  bool a_json = false;
  auto* analytic_cmd = app.add_subcommand("analytic", "Print the exact irradiance, radiance and estimator moments at a point");
  analytic_cmd->add_option("--scene", a_scene, "Scene file (JSON)")->required();
  analytic_cmd->add_option("--point", a_point, "Receiver point x,y,z")->required();
  analytic_cmd->add_option("--normal", a_normal, "Receiver normal x,y,z (normalised)")->required();
  analytic_cmd->add_option("--albedo", a_albedo, "Lambertian albedo for the radiance (default: the receiver's)")
      ->check(CLI::Range(0.0, 1.0));
  analytic_cmd->add_flag("--json", a_json, "Print JSON");

  std::string c_scene;
  std::vector<std::string> c_images;
  double c_alpha = verify::kDefaultFamilyAlpha;
  int c_max_depth = 0;
  auto* check_cmd = app.add_subcommand("check", "Test another renderer's OpenEXR images of a scene against its exact reference");
  check_cmd->add_option("--scene", c_scene, "Scene file the images are renders of")->required();
  check_cmd->add_option("--image", c_images, "OpenEXR image(s): K >= 2 independent renders, or one furnace EXR")->required();
  check_cmd->add_option("--alpha", c_alpha, "Family-wise false-alarm probability")->capture_default_str()->check(CLI::Range(1e-12, 0.5));
  check_cmd->add_option("--max-depth", c_max_depth, "Compare with the global-illumination answer at this path depth "
                        "(segments; 0: direct lighting)")->capture_default_str()->check(CLI::Range(0, std::numeric_limits<int>::max()));

  std::vector<std::string> s_strategies;
  int s_seeds = 50, s_spp = 1024, s_threads = 0;
  double s_alpha = 0.05;
  auto* sweep_cmd = app.add_subcommand("sweep", "Measure the false-alarm rate of the verification over many seeds (slow)");
  sweep_cmd->add_option("--strategy", s_strategies, "Strategy name(s); default: all");
  sweep_cmd->add_option("--seeds", s_seeds, "Seeds per case")->capture_default_str()->check(CLI::Range(1, 100000));
  sweep_cmd->add_option("--spp", s_spp, "Samples per pixel")->capture_default_str()->check(CLI::Range(2, 1 << 24));
  sweep_cmd->add_option("--case-alpha", s_alpha, "False-alarm level of each case")->capture_default_str()->check(CLI::Range(1e-6, 0.5));
  sweep_cmd->add_option("--threads", s_threads, "Worker threads (0: all)")->capture_default_str()->check(CLI::Range(0, 1024));

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    if (*render_cmd) return run_render(scene_path, strategy, defect, spp, seed, threads, max_depth, roulette_depth, output, light_selection);
    if (*analytic_cmd) {
      const Scene scene = load_scene(a_scene);
      verify::AnalyticQuery q;
      q.point = verify::parse_vec3_option(a_point, "--point");
      const Vec3 n = verify::parse_vec3_option(a_normal, "--normal");
      if (!(length(n) > 0)) throw Error(fmt::format("option --normal must be a non-zero direction, got \"{}\".", a_normal));
      q.normal = normalize(n);
      if (a_albedo >= 0) q.albedo = a_albedo;
      std::fputs(verify::answer_analytic_query(scene, q, a_json).c_str(), stdout);
      return 0;
    }
    if (*check_cmd) {
      const Scene scene = load_scene(c_scene);
      std::vector<verify::ForeignImage> images;
      for (const std::string& path : c_images) images.push_back(verify::read_foreign_image(path, scene));
      const verify::CheckResult r = verify::check_images(scene, images, c_alpha, c_max_depth);
      std::fputs(verify::format_check(scene, r, c_alpha).c_str(), stdout);
      return r.pass ? 0 : 1;
    }
    if (*sweep_cmd) return run_sweep(s_strategies, s_seeds, s_spp, s_alpha, s_threads);
    if (*report_cmd) {
      std::string command_line = "furnace";
      for (int i = 1; i < argc; ++i) command_line += std::string(" ") + argv[i];
      return run_report(r_strategies, r_min_spp, r_max_spp, r_seed, r_threads, r_dir, command_line);
    }
    if (*verify_cmd) return run_verify(v_scenes, v_strategies, v_defect, v_spp, v_seed, v_threads, v_alpha, v_max_depth, v_light_selection);
  } catch (const furnace::Error& e) {
    std::fprintf(stderr, "furnace: error: %s\n", e.what());
    return 2;
  }
  return 0;
}
