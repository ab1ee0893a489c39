// Direct-lighting strategies: single-sample estimators of the reflected
// radiance ∫ f·Li·cos θi dωi at a shading point, Li the radiance emitted by
// the first surface along ωi (or the environment).
//
// Each strategy is a small struct whose sample() and pdf() compute the density
// through one shared helper; samples follow the return convention of
// estimator.h (weight = f·cos θi/pdf). The light strategies live in
// light_strategy.h; DirectLighting combines them (single strategy or MIS).
//
// NEGATIVE CONTROLS: the Defect values of core/strategy.h are implemented at lines
// marked "DEFECT(...)" (here, in light_strategy.cpp, estimator.h and
// path_tracer.cpp). With Defect::kNone none of them is active.
#pragma once

#include <array>
#include <optional>
#include <vector>

#include "core/strategy.h"
#include "renderer/estimator.h"
#include "renderer/light_strategy.h"
#include "renderer/lights.h"
#include "renderer/render_options.h"
#include "renderer/rng.h"

namespace furnace {

// Directions uniform on the hemisphere around the face-forwarded normal.
struct UniformHemisphereStrategy {
  Defect defect = Defect::kNone;
  std::optional<DirectionSample> sample(const ShadingContext& ctx, const Uniform3& u) const;
  // Density in solid angle (sr⁻¹) of world direction wi.
  double pdf(const ShadingContext& ctx, const Vec3& wi_world) const;
};

// Cosine-weighted directions around the face-forwarded normal.
struct CosineHemisphereStrategy {
  Defect defect = Defect::kNone;
  std::optional<DirectionSample> sample(const ShadingContext& ctx, const Uniform3& u) const;
  double pdf(const ShadingContext& ctx, const Vec3& wi_world) const;
};

// The surface's own BSDF sampling (may be a delta sample).
struct BsdfStrategy {
  Defect defect = Defect::kNone;
  std::optional<DirectionSample> sample(const ShadingContext& ctx, const Uniform3& u) const;
  double pdf(const ShadingContext& ctx, const Vec3& wi_world) const;
};

// The two strategies' densities (solid angle, sr⁻¹) of one direction, as MIS
// weighs them: p_bsdf from BsdfStrategy::pdf, p_light from the light strategy
// of mis_balance/mis_power (light_solid_angle) for the ray that found `hit`.
struct MisPdfs {
  double p_bsdf = 0;
  double p_light = 0;
};
// The MIS weights of the BSDF and the light sample of one direction under
// heuristic β (1 balance, 2 power): w_bsdf + w_light = 1 wherever either
// density is positive, except under DEFECT(mis_unnormalised_weight).
struct MisWeights {
  double w_bsdf = 0;
  double w_light = 0;
};
MisWeights mis_weights(const MisPdfs& pdfs, int beta, Defect defect);

// The single-sample estimate of ∫ f·Li·cos θi dωi at ctx by `strategy`
// (one of the direct-lighting strategies).
class DirectLighting {
 public:
  // The most strategies one DirectLighting estimates from shared samples.
  static constexpr size_t kMaxSharedEstimators = kMaxSharedStrategies;

  DirectLighting(const EmbreeScene& scene, const LightSet& lights, Strategy strategy, Defect defect);
  // Several strategies estimated from the same samples (render.h's
  // shares_samples holds for every pair; at most kMaxSharedEstimators):
  // estimate_shared() gives each one's value of every sample, each to the
  // bit what a DirectLighting of that strategy alone gives. Throws
  // furnace::Error for a list that does not share its samples.
  DirectLighting(const EmbreeScene& scene, const LightSet& lights, const std::vector<Strategy>& strategies,
                 Defect defect);
  // How many strategies this estimates (1 unless built from a list).
  size_t estimators() const { return n_estimators_; }
  // `setups`, when bound to ctx, keeps the light strategy's per-emitter set-up
  // between the samples of one shading point (EmitterSetups; same results).
  double estimate(const ShadingContext& ctx, Rng& rng, TraceCounters& counters,
                  EmitterSetups* setups = nullptr) const;
  // n ≤ kRayPacket samples at once: out[i] is estimate(ctx, rngs[i], …) to
  // the bit (each sample draws from its own stream in the same order), and
  // the samples' rays go to Embree as packets (EmbreeScene's batch queries).
  // (One estimator only: estimators() == 1.)
  void estimate(const ShadingContext& ctx, Rng* rngs, size_t n, TraceCounters& counters, EmitterSetups* setups,
                double* out) const;
  // The batch form for every estimator at once: out[e][i] is strategy e's
  // value of sample i, out[e] holding n values for each e < estimators().
  void estimate_shared(const ShadingContext& ctx, Rng* rngs, size_t n, TraceCounters& counters,
                       EmitterSetups* setups, double* const* out) const;
  // Both strategies' densities of wi_world at ctx (the ray along it found
  // `hit`), exactly as estimate_mis() weighs its samples. For tests of MIS.
  MisPdfs mis_pdfs(const ShadingContext& ctx, const Vec3& wi_world, const std::optional<SurfaceHit>& hit) const;

 private:
  // Each fills out[0..n) for the samples of rngs[0..n).
  template <typename DirectionStrategy>
  void estimate_direction(const DirectionStrategy& s, const ShadingContext& ctx, Rng* rngs, size_t n,
                          TraceCounters& counters, double* out) const;
  void estimate_light(const ShadingContext& ctx, Rng* rngs, size_t n, TraceCounters& counters,
                      EmitterSetups* setups, double* out) const;
  // Multi-sample MIS under the heuristic of each estimator (betas_): the
  // samples, rays and densities once, the weights per heuristic.
  void estimate_mis(const ShadingContext& ctx, Rng* rngs, size_t n, TraceCounters& counters,
                    EmitterSetups* setups, double* const* out) const;
  // mis_one_sample: Veach's one-sample model (1997, §9.2.4) with the balance
  // heuristic. Strategy i ∈ {bsdf, light} is chosen with probability c_i and
  // its sample X gives f(X)·Li(X)·cos θ / Σ_j c_j·p_j(X); a delta sample (a
  // mirror lobe, a point light) is covered by its own strategy only and gives
  // weight·Li/c_i. DEFECT(one_sample_no_selection_prob) drops the c_j.
  void estimate_one_sample(const ShadingContext& ctx, Rng* rngs, size_t n, TraceCounters& counters,
                           EmitterSetups* setups, double* out) const;

  const EmbreeScene& scene_;
  const LightSet& lights_;
  Strategy strategy_;  // the first estimator's
  Defect defect_;
  LightStrategy light_;
  size_t n_estimators_ = 1;
  std::array<int, kMaxSharedEstimators> betas_{};  // the MIS heuristic of each estimator (MIS strategies only)
};

}  // namespace furnace
