#include "verify/resources.h"

#include <cstdlib>
#include <system_error>

#include <fmt/format.h>

#include "core/error.h"

namespace furnace::verify {

namespace fs = std::filesystem;

namespace {

// The source tree's copies, for executables run from the build tree
// (verify/CMakeLists.txt defines both).
constexpr const char* kSourceSceneDir = FURNACE_SOURCE_SCENE_DIR;
constexpr const char* kSourceReportScript = FURNACE_SOURCE_REPORT_SCRIPT;

}  // namespace

fs::path installed_data_dir() {
  std::error_code ec;
  const fs::path executable = fs::read_symlink("/proc/self/exe", ec);
  if (ec || executable.empty()) return {};
  return (executable.parent_path() / ".." / "share" / "furnace").lexically_normal();
}

namespace {

// share/furnace/<name> beside the executable when `exists` holds for it, else
// the source tree's copy when it does; else furnace::Error with `refusal`
// formatted with the two places tried (installed, then source).
template <class Exists>
std::string installed_or_source(const char* name, const char* source, Exists exists, const char* refusal) {
  const fs::path data = installed_data_dir();
  std::error_code ec;
  if (!data.empty() && exists(data / name, ec)) return (data / name).string();
  if (exists(fs::path(source), ec)) return source;
  const std::string installed =
      data.empty() ? std::string("<executable>/../share/furnace/") + name : (data / name).string();
  throw Error(fmt::format(fmt::runtime(refusal), installed, source));
}

}  // namespace

std::string scene_dir() {
  return installed_or_source(
      "scenes", kSourceSceneDir, [](const fs::path& p, std::error_code& ec) { return fs::is_directory(p, ec); },
      "furnace cannot find its built-in scenes: neither '{}' (installed) nor '{}' (source tree) is a directory.");
}

std::string report_script() {
  const char* forced = std::getenv("FURNACE_REPORT_SCRIPT");
  std::error_code ec;
  if (forced && *forced) {
    if (!fs::is_regular_file(forced, ec))
      throw Error(fmt::format("report needs its plotting script, and '{}' is not a file (set FURNACE_REPORT_SCRIPT).",
                              forced));
    return forced;
  }
  return installed_or_source(
      "plot_report.py", kSourceReportScript,
      [](const fs::path& p, std::error_code& ec) { return fs::is_regular_file(p, ec); },
      "report needs its plotting script, and neither '{}' (installed) nor '{}' (source tree) is a file (set "
      "FURNACE_REPORT_SCRIPT).");
}

}  // namespace furnace::verify
