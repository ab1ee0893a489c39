// The components a 50-digit MIS reference integrates together on one set of
// nodes (glass_precision_test.cpp over the sphere of directions,
// glass_light_precision_test.cpp over a disk light), with h = f·|cos θi|,
// p_b the BSDF sampler's density and p_l the light sampler's: ∫h (the
// mean), ∫h²/p_b (bsdf), ∫h²/p_l (light alone), ∫h²/(c p_b + (1 − c) p_l)
// (one-sample MIS), and per heuristic exponent β = 1 (balance) and 2
// (power) the four pieces of multi-sample MIS: ∫w_b² h²/p_b, ∫w_l² h²/p_l,
// ∫w_b h, ∫w_l h, with w_b = p_b^β/(p_b^β + p_l^β), w_l = 1 − w_b.
#pragma once

#include <cstddef>

namespace furnace::analytic::mis_components {

enum Component : size_t {
  kMean,
  kBsdf,
  kLight,
  kOneSample,
  kBalanceBsdf,
  kBalanceLight,
  kBalanceWeightedBsdf,
  kBalanceWeightedLight,
  kPowerBsdf,
  kPowerLight,
  kPowerWeightedBsdf,
  kPowerWeightedLight,
  kComponents
};

}  // namespace furnace::analytic::mis_components
