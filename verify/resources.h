// Where furnace finds the files it ships with: the built-in scenes and the
// HTML report's plotting script.
//
// Installed (`cmake --install build --prefix P`), the command is
// P/bin/furnace and its files are P/share/furnace/scenes/ and
// P/share/furnace/plot_report.py. Each is looked up relative to the running
// executable (/proc/self/exe): <executable's directory>/../share/furnace/.
// Nothing of the source or build tree is needed, and the prefix may be moved
// or copied anywhere.
//
// In the build tree there is no share/furnace beside build/bin (nor beside a
// test binary), so the source tree's scenes/ and scripts/plot_report.py,
// whose paths are compiled in, are used instead.
//
// $FURNACE_REPORT_SCRIPT, when set, names the plotting script and nothing
// else is tried.
#pragma once

#include <filesystem>
#include <string>

namespace furnace::verify {

// <directory of the running executable>/../share/furnace, normalised; empty
// when /proc/self/exe cannot be read.
std::filesystem::path installed_data_dir();

// The built-in scenes' directory: the installed one if it is a directory,
// else the source tree's. Throws furnace::Error naming both when neither is.
std::string scene_dir();

// The plotting script: $FURNACE_REPORT_SCRIPT if set, else the installed one
// if it is a file, else the source tree's. Throws furnace::Error naming what
// was tried when it is not a file.
std::string report_script();

}  // namespace furnace::verify
