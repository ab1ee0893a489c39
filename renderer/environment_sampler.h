// Importance sampling of an image-based environment (core/environment_map.h):
// a piecewise-constant 2-D distribution over the lat-long map's texels,
// sampled by inversion of its CDFs.
//
// Method: texel (i, j) of value L_ij covers θ ∈ [θ_i, θ_{i+1}], φ ∈ [φ_j, φ_{j+1}]
// and the solid angle Ω_ij = Δφ·(cos θ_i − cos θ_{i+1}) (the sin θ Jacobian
// integrated exactly over the row). A row is chosen with probability
// ∝ Σ_j L_ij·Ω_ij, a column within it ∝ L_ij, and a direction inside the texel
// uniform in φ and in cos θ (uniform in solid angle over the texel). The
// density in solid angle is therefore exactly
//   p(ω) = L_ij / Σ_kl L_kl·Ω_kl   (sr⁻¹) for ω in texel (i, j),
// 0 on black texels, which are never sampled. Directions are world-space (the
// map's z-up convention); whether they lie above a receiver's horizon is the
// caller's concern (LightStrategy gives those below it weight 0).
//
// NEGATIVE CONTROL: DEFECT(env_missing_sin_theta) is implemented here: rows
// chosen ∝ Σ_j L_ij·Δφ·Δθ (the sin θ Jacobian forgotten) while pdf() still
// states the density above.
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "core/environment_map.h"
#include "core/strategy.h"
#include "core/vec3.h"

namespace furnace {

struct EnvironmentSample {
  Vec3 wi_world;
  double pdf_solid_angle = 0;  // pdf_solid_angle(wi_world), the stated density
};

class EnvironmentSampler {
 public:
  explicit EnvironmentSampler(std::shared_ptr<const LatLongMap> map);

  // False for a map that is black everywhere (nothing to sample).
  bool has_power() const { return total_ > 0; }
  // Σ_kl L_kl·Ω_kl: the map's integral over the sphere (sr, times map units).
  double integral() const { return total_; }

  // A direction from (u1, u2) ∈ [0,1)²: u1 chooses the row and, rescaled,
  // cos θ inside it; u2 the column and φ. Empty when the map has no power.
  // `defect` other than kEnvMissingSinTheta has no effect.
  std::optional<EnvironmentSample> sample(double u1, double u2, Defect defect = Defect::kNone) const;
  // Density in solid angle (sr⁻¹) of sample() for world direction wi (unit).
  double pdf_solid_angle(const Vec3& wi_world) const;

 private:
  // THE density helper sample() and pdf_solid_angle() share: L_ij / Σ L·Ω.
  double texel_pdf_solid_angle(int i, int j) const;

  std::shared_ptr<const LatLongMap> map_;
  std::vector<double> cos_edge_;     // cos θ_i at row edges i = 0..H (1 → −1)
  std::vector<double> row_cdf_;      // H entries, cumulative, last = 1
  std::vector<double> row_cdf_missing_sin_theta_;  // DEFECT(env_missing_sin_theta) only
  std::vector<double> column_cdf_;   // H×W, cumulative within each row, last of a non-black row = 1
  double total_ = 0;
};

}  // namespace furnace
