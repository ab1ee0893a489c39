// `furnace analytic`: the exact answers at one receiver point of a scene.
// A Lambertian receiver (or none): the irradiance, the radiance of a
// Lambertian receiver there, and for each single-sample estimator of the
// irradiance its second moment and variance. A glossy receiver (Phong, GGX):
// the radiance its own BSDF reflects toward a view direction, and each direct
// strategy's single-sample estimator of that radiance: its second moment and
// variance. A dielectric receiver in a glass scene (analytic/glass.h), seen
// from either side: its radiance toward the view in the query's transport
// convention and the bsdf estimator's moments. A mirror receiver is refused
// (a delta lobe has no reference at a point).
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
  // Unit direction from the point toward the viewer, for a glossy receiver:
  // default the scene camera's (orthographic: −forward). Must lie above the
  // receiver's horizon (n·view > 0).
  std::optional<Vec3> view;
  // Estimators whose second moment and variance to compute (names from
  // kStrategyTable); empty: every strategy with its own variance model (a
  // glossy receiver: every direct strategy).
  std::vector<Strategy> estimators;
  // A dielectric receiver's transport convention (what it transmits depends on it).
  TransportConvention convention = TransportConvention::kRadiance;
};

// Runs the query and formats the answer (17 significant digits) as text or
// JSON. Every value carries an error bound: |value|·(the relative error the
// quadratures behind it reported + kRoundoffUlps·ε) (analytic/error_ledger.h),
// and for a variance m2 − E² the bound of m2 plus 2|E| times that of E.
// Throws furnace::Error for configurations analytic/ does not solve.
std::string answer_analytic_query(const Scene& scene, const AnalyticQuery& q, bool json);

}  // namespace furnace::verify
