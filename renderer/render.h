// The renderer's public entry point: render a scene with one named strategy
// and return, per pixel, the running moments of the single-sample estimator.
#pragma once

#include <vector>

#include "core/scene.h"
#include "core/strategy.h"
#include "renderer/image.h"
#include "renderer/render_options.h"

namespace furnace {

// Renders the scene: one camera ray per pixel centre; the pixel estimator is
// Y = Le(x) + (ρ/π)·Ê(x) at the first hit x, Ê the strategy's single-sample
// irradiance estimate (the environment radiance on a miss). For non-Lambertian
// first hits the direct strategies estimate ∫ f·Li·cos dω with the BSDF's f:
// only `bsdf` and the MIS strategies see a mirror's delta lobe. Path tracers
// return their path's radiance. Throws furnace::Error if the scene has no
// emitter (nor environment) for light sampling, if it has point lights and the
// strategy cannot see them (strategy_sees_delta_lights), or on a bad option.
Image render(const Scene& scene, const RenderOptions& options);

// One render for every strategy of `strategies` (1 to kMaxSharedStrategies,
// each pair shares_samples; options.strategy is ignored): image e is render(scene, options with
// strategy = strategies[e]) to the bit (its rays are the same rays), but for
// `seconds`: the wall time of the one shared render. Throws furnace::Error as render() does, and for an empty
// list or strategies that do not share their samples.
std::vector<Image> render_sharing_samples(const Scene& scene, const RenderOptions& options,
                                          const std::vector<Strategy>& strategies);

}  // namespace furnace
