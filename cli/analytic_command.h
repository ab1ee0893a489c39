// `furnace analytic`: the exact irradiance, radiance and estimator moments at
// one receiver point (a glossy receiver's radiance toward a view), as text or
// JSON.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "core/strategy.h"

namespace furnace::cli {

struct AnalyticCommandOptions {
  std::string scene_path;
  std::array<double, 3> point{}, normal{};  // the normal is normalised by run_analytic
  std::optional<double> albedo;             // empty: the receiver's
  std::optional<std::array<double, 3>> view;  // empty: the camera's (glossy receivers)
  std::vector<Strategy> estimators;         // empty: every strategy with its own variance model
  TransportConvention convention = TransportConvention::kRadiance;  // a dielectric receiver's
  bool json = false;
};

// Adds `analytic` to `app`, its options bound to `options`.
CLI::App* add_analytic_command(CLI::App& app, AnalyticCommandOptions& options);

// Prints the answer; returns 0. Bad input (a zero normal, a bad scene)
// throws furnace::Error.
int run_analytic(const AnalyticCommandOptions& options);

}  // namespace furnace::cli
