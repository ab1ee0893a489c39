// `furnace compare`: two sets of OpenEXR renders of any scene, from any
// renderer, tested for the same expected image (verify/compare_command.h
// runs it and states its contract: exit 0 SAME, 1 DIFFERENT, 2 bad input,
// 3 INCONCLUSIVE).
#pragma once

#include <CLI/CLI.hpp>

#include "verify/compare_command.h"

namespace furnace::cli {

// Adds `compare` to `app`, its options bound to `options` (verify::run_compare
// runs it).
CLI::App* add_compare_command(CLI::App& app, verify::CompareOptions& options);

}  // namespace furnace::cli
