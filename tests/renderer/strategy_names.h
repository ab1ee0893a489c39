// How tests print and name the renderer's enums: GoogleTest prints a
// Strategy, Defect or LightSelection parameter by its CLI name
// ("light_solid_angle"), and a suite parameterised by Strategy alone names its
// instances by that name in CamelCase ("LightSolidAngle").
#pragma once

#include <ostream>
#include <string>

#include <gtest/gtest.h>

#include "renderer/render.h"
#include "tests/test_names.h"

namespace furnace {

// GoogleTest finds PrintTo by argument-dependent lookup, so these are in the
// enums' namespace; without them a value prints as its object bytes.
inline void PrintTo(Strategy s, std::ostream* os) { *os << strategy_name(s); }
inline void PrintTo(Defect d, std::ostream* os) { *os << defect_name(d); }
inline void PrintTo(LightSelection s, std::ostream* os) { *os << light_selection_name(s); }

namespace testing_support {

// Name generator of a suite whose parameter is a Strategy.
inline std::string strategy_param_name(const ::testing::TestParamInfo<Strategy>& info) {
  return camel_case(strategy_name(info.param));
}

}  // namespace testing_support
}  // namespace furnace
