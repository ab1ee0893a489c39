// `furnace analytic`: the exact answers at one receiver point of a scene:
// irradiance, the radiance of a Lambertian receiver there, and for each
// single-sample estimator its second moment and variance.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/scene.h"
#include "core/strategy.h"

namespace furnace::verify {

struct AnalyticQuery {
  Vec3 point;
  Vec3 normal;                   // unit
  std::optional<double> albedo;  // default: the receiver object's albedo, or 1 with no receiver
  // Estimators whose second moment and variance to compute (names from
  // kStrategyTable); empty: every strategy with its own variance model.
  std::vector<Strategy> estimators;
};

// Runs the query and formats the answer (17 significant digits) as text or
// JSON. Every value carries an error bound: |value|·(the relative error the
// quadratures behind it reported + kRoundoffUlps·ε) (analytic/error_ledger.h),
// and for a variance m2 − E² the bound of m2 plus 2|E| times that of E.
// Throws furnace::Error for configurations analytic/ does not solve.
std::string answer_analytic_query(const Scene& scene, const AnalyticQuery& q, bool json);

}  // namespace furnace::verify
