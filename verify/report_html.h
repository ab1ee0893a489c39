// The HTML report: `furnace report` writes <dir>/report.json (every number
// and every pixel the page shows) and runs scripts/plot_report.py on it,
// which draws the plots and images with matplotlib (PNG files) and writes
// <dir>/index.html, a self-contained page (relative links only, no script,
// no network) that opens from disk.
//
// matplotlib was chosen over gnuplot because one library then does both the
// log-log plots and the images (tone-mapped renders, false-colour error and
// t maps with colour bars) and the same Python can decode the PNGs in the
// test; it is Debian's python3-matplotlib (scripts/setup.sh installs it).
//
// Python is looked up before any rendering: $FURNACE_PYTHON if set, else
// python3 on PATH, then /usr/bin/python3 (where Debian's python3-matplotlib
// lives when PATH has another Python first); the first that imports
// matplotlib is used. None: bad input (exit 2), one line naming what is
// missing. The script is found by verify/resources.h: $FURNACE_REPORT_SCRIPT
// if set, else the installed share/furnace/plot_report.py beside the
// executable, else the source tree's scripts/plot_report.py.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "verify/report.h"
#include "verify/seed_figure.h"

namespace furnace::verify {

struct PlotTools {
  std::string python;  // an interpreter that imports matplotlib
  std::string script;  // plot_report.py
};

// Finds both, or throws furnace::Error saying what is missing and how to get it.
PlotTools find_plot_tools();

struct ReportSettings {
  std::string command_line;
  int min_spp = 0, max_spp = 0;
  uint64_t seed = 0;
};

// Writes <dir>/report.json atomically.
void write_report_json(const std::vector<ReportCase>& cases, const SeedFigure& seed_figure,
                       const ReportSettings& settings, const std::string& dir);

// Runs the plotting script on <dir>; returns its exit code (0: index.html written).
int run_plot_script(const PlotTools& tools, const std::string& dir);

}  // namespace furnace::verify
