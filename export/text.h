// Text helpers every exporter's output uses, so that two formats write the
// same number the same way.
#pragma once

#include <algorithm>
#include <string>

#include <fmt/format.h>

namespace furnace::exporter {

// Shortest round-trip decimal (pbrt and Python read it back exactly); adding
// +0.0 writes -0 as 0.
inline std::string num(double x) { return fmt::format("{}", x + 0.0); }

// A name on one comment line: a line break in it would end the comment.
inline std::string comment_text(std::string name) {
  std::replace(name.begin(), name.end(), '\n', ' ');
  std::replace(name.begin(), name.end(), '\r', ' ');
  return name;
}

}  // namespace furnace::exporter
