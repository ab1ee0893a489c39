#include "cli/progress.h"

#include <unistd.h>

#include <cstdio>

#include <fmt/format.h>

namespace furnace::verify {

namespace {

std::string duration_text(double seconds) {
  if (seconds < 90) return fmt::format("{:.0f} s", seconds);
  if (seconds < 5400) return fmt::format("{:.1f} min", seconds / 60);
  return fmt::format("{:.1f} h", seconds / 3600);
}

}  // namespace

Progress::Progress(std::string label, size_t total)
    : label_(std::move(label)), total_(total), enabled_(::isatty(2) == 1), start_(std::chrono::steady_clock::now()) {}

Progress::~Progress() { finish(); }

std::string Progress::line(const std::string& label, size_t done, size_t total, double elapsed_seconds) {
  std::string text = fmt::format("{}: {}/{} done, {} elapsed", label, done, total, duration_text(elapsed_seconds));
  // The remaining time at the mean pace so far (cases differ in cost, so it is rough).
  if (done > 0 && done < total)
    text += fmt::format(", ~{} left", duration_text(elapsed_seconds / double(done) * double(total - done)));
  return text;
}

void Progress::step() {
  ++done_;
  if (!enabled_) return;
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  // \r and erase-to-end-of-line: the line is rewritten in place.
  std::fprintf(stderr, "\r%s\033[K", line(label_, done_, total_, elapsed).c_str());
  std::fflush(stderr);
  shown_ = true;
}

void Progress::clear() {
  if (!enabled_ || !shown_) return;
  std::fputs("\r\033[K", stderr);
  std::fflush(stderr);
  shown_ = false;
}

void Progress::finish() { clear(); }

}  // namespace furnace::verify
