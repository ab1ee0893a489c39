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

std::string scene_dir() {
  const fs::path data = installed_data_dir();
  std::error_code ec;
  if (!data.empty() && fs::is_directory(data / "scenes", ec)) return (data / "scenes").string();
  if (fs::is_directory(kSourceSceneDir, ec)) return kSourceSceneDir;
  throw Error(fmt::format("furnace cannot find its built-in scenes: neither '{}' (installed) nor '{}' (source tree) "
                          "is a directory.",
                          data.empty() ? std::string("<executable>/../share/furnace/scenes")
                                       : (data / "scenes").string(),
                          kSourceSceneDir));
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
  const fs::path data = installed_data_dir();
  if (!data.empty() && fs::is_regular_file(data / "plot_report.py", ec)) return (data / "plot_report.py").string();
  if (fs::is_regular_file(kSourceReportScript, ec)) return kSourceReportScript;
  throw Error(fmt::format("report needs its plotting script, and neither '{}' (installed) nor '{}' (source tree) is a "
                          "file (set FURNACE_REPORT_SCRIPT).",
                          data.empty() ? std::string("<executable>/../share/furnace/plot_report.py")
                                       : (data / "plot_report.py").string(),
                          kSourceReportScript));
}

}  // namespace furnace::verify
