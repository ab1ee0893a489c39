// Iterative unidirectional path tracers.
//
//  - naive: BSDF sampling only, emission (and the environment) counted where
//    a path hits it;
//  - NEE + MIS: at every non-delta vertex one light sample (LightStrategy,
//    solid-angle sampling) plus the BSDF continuation; emission found by the
//    continuation is weighted against the light density by the power
//    heuristic, emission found by light sampling against the BSDF density.
// Russian roulette from RenderOptions::roulette_depth with survival
// probability min(1, throughput/η-scale), survivors reweighted by 1/p (the
// η-scale is the product of the radiance convention's 1/η′² factors in the
// throughput, as pbrt-v4's etaScale); paths end at
// RenderOptions::max_depth segments (the camera segment is segment 1). A
// path of a scene whose expected length has no bound (core/path_length.h)
// throws furnace::Error at kOpenScenePathSegmentCap segments.
// Sample weights follow estimator.h (weight = f·cos θ/pdf).
#pragma once

#include <optional>

#include "renderer/direct_strategies.h"
#include "renderer/render_options.h"

namespace furnace {

class PathTracer {
 public:
  PathTracer(const EmbreeScene& scene, const LightSet& lights, const RenderOptions& options);
  // Radiance along the camera ray (origin, direction) whose first hit is
  // `first_hit` (traced once per pixel by the caller). `setups`, when bound
  // to the first hit's shading point, keeps the light strategy's per-emitter
  // set-up there between samples (EmitterSetups; same results).
  double radiance(const Vec3& direction, const std::optional<SurfaceHit>& first_hit, Rng& rng,
                  TraceCounters& counters, EmitterSetups* setups = nullptr) const;

 private:
  const EmbreeScene& scene_;
  bool next_event_;
  int max_depth_;
  int roulette_depth_;
  int segment_cap_;  // kOpenScenePathSegmentCap, or max_depth_ when the scene's bound needs no cap
  Defect defect_;  // DEFECT(roulette_no_reweight), DEFECT(double_count_emission) in path_tracer.cpp
  TransportConvention convention_;
  LightStrategy light_;
  BsdfStrategy bsdf_;
};

}  // namespace furnace
