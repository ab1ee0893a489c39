// `furnace check`: another renderer's OpenEXR images of a scene against the
// scene's exact reference (verify/check_command.h runs it and states its
// contract: exit 0 PASS, 1 FAIL, 2 bad input, 3 INCONCLUSIVE).
#pragma once

#include <CLI/CLI.hpp>

#include "verify/check_command.h"

namespace furnace::cli {

// Adds `check` to `app`, its options bound to `options` (verify::run_check
// runs it).
CLI::App* add_check_command(CLI::App& app, verify::CheckOptions& options);

}  // namespace furnace::cli
