// Progress of a long run (verify, report, sweep) on stderr: "verify: 12/58
// cases, 41 s elapsed, ~2.7 min left", one line updated in place, and only
// when stderr is a terminal: redirected output (tests, CI logs) is unchanged.
#pragma once

#include <chrono>
#include <cstddef>
#include <string>

namespace furnace::verify {

class Progress {
 public:
  // `total` units of work (cases, case × seed runs) named `label`.
  Progress(std::string label, size_t total);
  ~Progress();
  // One more unit done: redraw the line.
  void step();
  // Erase the line (before printing a result row to stdout); step() redraws it.
  void clear();
  // Erase the line for good.
  void finish();

  // The line's text after `done` of `total` units in `elapsed_seconds`.
  static std::string line(const std::string& label, size_t done, size_t total, double elapsed_seconds);

 private:
  std::string label_;
  size_t total_ = 0;
  size_t done_ = 0;
  bool enabled_ = false;  // stderr is a terminal
  bool shown_ = false;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace furnace::verify
