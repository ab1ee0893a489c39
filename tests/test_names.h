// Names of the instances of value-parameterised suites (the fourth argument
// of INSTANTIATE_TEST_SUITE_P). GoogleTest accepts letters, digits and
// underscores; furnace's names are CamelCase without underscores, and CTest
// registers them verbatim (tests/CMakeLists.txt), so a name is built from the
// case's words and integers, never from a printed double or an address.
// Each parameter type also has a PrintTo that prints the case's name, so
// GoogleTest's test list and failure messages show the case, not its bytes.
#pragma once

#include <cctype>
#include <string>
#include <string_view>

namespace furnace::testing_support {

// "light_solid_angle" -> "LightSolidAngle", "enclosure_box_rho5" ->
// "EnclosureBoxRho5": every character other than a letter or digit ends a
// word and is dropped, and each word starts with a capital.
inline std::string camel_case(std::string_view words) {
  std::string name;
  bool word_start = true;
  for (const char ch : words) {
    const auto c = static_cast<unsigned char>(ch);
    if (!std::isalnum(c)) {
      word_start = true;
      continue;
    }
    name += word_start ? static_cast<char>(std::toupper(c)) : ch;
    word_start = false;
  }
  return name;
}

}  // namespace furnace::testing_support
