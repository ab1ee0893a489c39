#include "verify/report_html.h"

#include <spawn.h>
#include <sys/wait.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fcntl.h>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/provenance.h"
#include "verify/resources.h"

extern char** environ;

namespace furnace::verify {

namespace {

// Runs argv[0] (looked up on PATH) with `argv`; its output goes to /dev/null
// when `quiet`. Returns the exit status, or −errno when it could not start.
int run_process(const std::vector<std::string>& args, bool quiet) {
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  if (quiet) {
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
  }
  pid_t pid = 0;
  const int spawn_error = posix_spawnp(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawn_error != 0) return -spawn_error;
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return -errno;
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

std::string env_or_empty(const char* name) {
  const char* value = std::getenv(name);
  return value ? std::string(value) : std::string();
}

nlohmann::ordered_json pixels(const std::vector<double>& values) {
  // Seven significant digits (single precision, what an EXR would hold) keep
  // the file small: nlohmann prints the shortest text that reads back the same.
  std::vector<double> out;
  for (double v : values) out.push_back(std::strtod(fmt::format("{:.7g}", v).c_str(), nullptr));
  return out;
}

nlohmann::ordered_json render_json(const ReportRender& r) {
  return {{"spp", r.spp}, {"seconds", r.seconds}, {"mean", pixels(r.mean)}, {"variance", pixels(r.variance)}};
}

nlohmann::ordered_json seed_render_json(const SeedFigureRender& r) {
  return {{"strategy", r.strategy},
          {"spp", r.spp},
          {"seconds", r.seconds},
          {"rmse", r.rmse},
          {"relative_rmse", r.relative_rmse},
          {"mean_sample_variance", r.mean_sample_variance},
          {"mean_predicted_variance", r.mean_predicted_variance},
          {"mean", pixels(r.mean)}};
}

}  // namespace

PlotTools find_plot_tools() {
  PlotTools tools;
  const std::string forced = env_or_empty("FURNACE_PYTHON");
  const std::vector<std::string> candidates =
      forced.empty() ? std::vector<std::string>{"python3", "/usr/bin/python3"} : std::vector<std::string>{forced};
  std::string tried;
  for (const std::string& python : candidates) {
    const int status = run_process({python, "-c", "import matplotlib, numpy"}, true);
    if (status == 0) {
      tools.python = python;
      break;
    }
    tried += fmt::format("{}{} ({})", tried.empty() ? "" : ", ", python,
                         status < 0 ? std::strerror(-status) : "cannot import matplotlib");
  }
  if (tools.python.empty())
    throw Error(fmt::format("report needs Python 3 with matplotlib for its plots and images (Debian: apt-get install "
                            "python3-matplotlib; or set FURNACE_PYTHON); tried {}.",
                            tried));
  tools.script = report_script();
  return tools;
}

void write_report_json(const std::vector<ReportCase>& cases, const SeedFigure& f, const ReportSettings& settings,
                       const std::string& dir) {
  nlohmann::ordered_json j;
  j["generator"] = "furnace " + furnace_version();
  j["command_line"] = settings.command_line;
  j["min_spp"] = settings.min_spp;
  j["max_spp"] = settings.max_spp;
  j["seed"] = settings.seed;
  j["cases"] = nlohmann::ordered_json::array();
  for (const ReportCase& c : cases) {
    nlohmann::ordered_json points = nlohmann::ordered_json::array();
    for (const ConvergencePoint& p : c.series.points)
      points.push_back({{"spp", p.spp}, {"seconds", p.seconds}, {"rmse", p.rmse}, {"relative_rmse", p.relative_rmse}});
    j["cases"].push_back({{"scene", c.series.scene},
                          {"strategy", c.series.strategy},
                          {"slope", c.series.slope},
                          {"efficiency", c.series.efficiency},
                          {"seconds_to_one_percent", c.series.seconds_to_one_percent},
                          {"points", points},
                          {"width", c.width},
                          {"height", c.height},
                          {"time_budget", c.time_budget},
                          {"reference", pixels(c.reference)},
                          {"equal_spp", render_json(c.equal_spp)},
                          {"equal_time", render_json(c.equal_time)}});
  }
  j["seed_figure"] = {{"scene", f.scene},
                      {"width", f.width},
                      {"height", f.height},
                      {"reference_mean", f.reference_mean},
                      {"predicted_variance_ratio", f.predicted_variance_ratio},
                      {"measured_variance_ratio", f.measured_variance_ratio},
                      {"measured_mse_ratio", f.measured_mse_ratio},
                      {"reference", pixels(f.reference)},
                      {"hemisphere", seed_render_json(f.hemisphere)},
                      {"light", seed_render_json(f.light)}};
  write_text_file_atomically(std::filesystem::path(dir) / "report.json", j.dump(), "report file");
}

int run_plot_script(const PlotTools& tools, const std::string& dir) {
  const int status = run_process({tools.python, tools.script, dir}, false);
  return status;
}

}  // namespace furnace::verify
