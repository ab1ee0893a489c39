#include "cli/analytic_command.h"

#include <cmath>
#include <cstdio>

#include <fmt/format.h>

#include "cli/cli_options.h"
#include "core/error.h"
#include "core/scene.h"
#include "verify/analytic_query.h"

namespace furnace::cli {

CLI::App* add_analytic_command(CLI::App& app, AnalyticCommandOptions& o) {
  CLI::App* command =
      app.add_subcommand("analytic", "Print the exact irradiance, radiance and estimator moments at a point");
  command->add_option("--scene", o.scene_path, "Scene file (JSON)")->required();
  command->add_option("--point", o.point, "Receiver point x,y,z")
      ->required()->delimiter(',')->check(finite_number().description(""))->type_name("X,Y,Z");
  command->add_option("--normal", o.normal, "Receiver normal x,y,z (normalised)")
      ->required()->delimiter(',')->check(finite_number().description(""))->type_name("X,Y,Z");
  command
      ->add_option_function<std::vector<double>>(
          "--view", [&o](const std::vector<double>& v) { o.view = std::array<double, 3>{v[0], v[1], v[2]}; },
          "Direction from the point toward the viewer x,y,z, for a glossy (phong, ggx) or dielectric receiver (a "
          "dielectric's from either side; default: toward the scene's camera, -forward)")
      ->expected(3)->delimiter(',')->check(finite_number().description(""))->type_name("X,Y,Z");
  command
      ->add_option_function<double>(
          "--albedo", [&o](const double& albedo) { o.albedo = albedo; },
          "The receiver's albedo for the radiance (default: the receiver's; for a glossy receiver the factor on f)")
      ->check(number_in(0.0, 1.0));
  command->add_option("--estimator", o.estimators,
                      "Estimator(s) whose second moment and variance to compute (repeatable; default: every "
                      "strategy with its own variance model)")
      ->transform(strategy_by_name())->type_name("TEXT");
  add_convention_option(command, o.convention);
  set_contract_footer(command);
  command->add_flag("--json", o.json, "Print JSON");
  return command;
}

int run_analytic(const AnalyticCommandOptions& o) {
  const Scene scene = load_scene(o.scene_path);
  verify::AnalyticQuery q;
  q.point = {o.point[0], o.point[1], o.point[2]};
  const Vec3 n{o.normal[0], o.normal[1], o.normal[2]};
  if (!(length(n) > 0) || !std::isfinite(length(n)))
    throw Error(fmt::format("option --normal must be a non-zero finite direction, got {},{},{}.", n.x, n.y, n.z));
  q.normal = normalize(n);
  q.albedo = o.albedo;
  if (o.view) {
    const Vec3 v{(*o.view)[0], (*o.view)[1], (*o.view)[2]};
    if (!(length(v) > 0) || !std::isfinite(length(v)))
      throw Error(fmt::format("option --view must be a non-zero finite direction, got {},{},{}.", v.x, v.y, v.z));
    q.view = normalize(v);
  }
  q.estimators = o.estimators;
  q.convention = o.convention;
  std::fputs(verify::answer_analytic_query(scene, q, o.json).c_str(), stdout);
  return kExitPass;
}

}  // namespace furnace::cli
