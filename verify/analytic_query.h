// `furnace analytic`: the exact answers at one receiver point of a scene:
// irradiance, the radiance of a Lambertian receiver there, and for each
// single-sample estimator its second moment and variance.
#pragma once

#include <optional>
#include <string>

#include "core/scene.h"

namespace furnace::verify {

struct AnalyticQuery {
  Vec3 point;
  Vec3 normal;                   // unit
  std::optional<double> albedo;  // default: the receiver object's albedo, or 1 with no receiver
};

// Runs the query and formats the answer (17 significant digits) as text or
// JSON. Throws furnace::Error for configurations analytic/ does not solve.
std::string answer_analytic_query(const Scene& scene, const AnalyticQuery& q, bool json);

}  // namespace furnace::verify
