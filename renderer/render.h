// The renderer's public entry point: render a scene with one named strategy
// and return, per pixel, the running moments of the single-sample estimator.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/running_moments.h"
#include "core/scene.h"

namespace furnace {

// Direct-lighting strategies (issue 2) and, later, path-tracing integrators.
// Names are the CLI's: strategy_name()/parse_strategy() convert.
enum class Strategy {
  kUniformHemisphere,  // "uniform_hemisphere": directions uniform on the hemisphere, pdf 1/(2π) sr⁻¹
  kCosineHemisphere,   // "cosine_hemisphere": pdf cos θ/π sr⁻¹
  kLightArea,          // "light_area": a point uniform on an emitter's area + shadow ray
  // Appended by the renderer work (issues 4 and 5); never renumber the above.
  kLightSolidAngle,    // "light_solid_angle": cone for spheres, spherical triangle (Arvo 1995) and
                       //   rectangle (Ureña et al. 2013); disks and sheared parallelograms fall
                       //   back to area sampling
  kBsdf,               // "bsdf": the surface's BSDF sampling (cosine for Lambertian, lobe for Phong, mirror)
  kMisBalance,         // "mis_balance": one BSDF + one light_solid_angle sample, balance heuristic
  kMisPower,           // "mis_power": the same with the power heuristic (β = 2)
  kPathNaive,          // "path_naive": iterative path tracer, BSDF sampling, emission on hit
  kPathMis,            // "path_mis": path tracer with next-event estimation + MIS (power heuristic)
  kMisOneSample,       // "mis_one_sample": with probability c = 1/2 one BSDF sample, else one
                       //   light_solid_angle sample; Veach's one-sample balance heuristic (§9.2.4)
};

// Deliberately wrong variants, for negative controls only. kNone is the
// renderer; every other value must make the verification fail.
enum class Defect {
  kNone,                // "none"
  kDropLightCosine,     // "drop_light_cosine": light_area forgets cos θ' (area→solid angle Jacobian)
  kPdfOffByConstant,    // "pdf_off_by_constant": the pdf used in the weight is 1.1× the true one
  kSkipShadowRay,       // "skip_shadow_ray": light_area treats every light sample as visible
  // Path-tracer and MIS controls (appended; never renumber the above).
  kRouletteNoReweight,  // "roulette_no_reweight": Russian roulette survivors not divided by the survival probability
  kDoubleCountEmission, // "double_count_emission": path_mis counts emission found by the BSDF continuation with
                        //   weight 1 as well as the light sample's MIS-weighted share (emission counted twice)
  kMisUnnormalisedWeight,  // "mis_unnormalised_weight": mis_balance/mis_power divide by the larger density
                           //   instead of the sum (weights p_a^β/max(p_a, p_b)^β sum to more than 1)
  // Point-light, light-selection and one-sample MIS controls (appended).
  kPointLightMisWeighted,     // "point_light_mis_weighted": MIS weighs a point-light (delta) sample like an
                              //   area sample, by pmf/(pmf + p_bsdf) < 1, although BSDF sampling never finds it
  kPowerSelectionUniformPmf,  // "power_selection_uniform_pmf": lights chosen by power, weights divided by
                              //   the uniform pmf 1/K
  kOneSampleNoSelectionProb,  // "one_sample_no_selection_prob": mis_one_sample divides by p_bsdf + p_light,
                              //   forgetting the selection probabilities c and 1 − c
  kEnvMissingSinTheta,  // "env_missing_sin_theta": environment-map sampling chooses rows ∝ Σ L·Δφ·Δθ (the sin θ
                        //   Jacobian forgotten) while its weight uses the stated density L/Σ L·Ω
};

// How light-sampling strategies choose one light among the scene's lights.
enum class LightSelection {
  kUniform,  // "uniform": pmf 1/K over the K lights
  kPower,    // "power": pmf proportional to each light's emitted power (lights.h states the powers)
};
std::string light_selection_name(LightSelection s);
// Throws furnace::Error naming the value and the accepted names.
LightSelection parse_light_selection(const std::string& name);

std::string strategy_name(Strategy s);
// Throws furnace::Error naming the value and the accepted names.
Strategy parse_strategy(const std::string& name);
// The direct-lighting strategies: the estimators of Y = Le + ∫ f·Li·cos dω with
// Li the radiance emitted by the first visible surface or the environment
// (the quantity analytic/ references). The path tracers are listed apart:
// they estimate full global illumination (equal to direct lighting only on
// scenes without interreflection, like the default disk-occluder scene).
std::vector<Strategy> all_strategies();
std::vector<Strategy> path_tracing_strategies();
// Whether the strategy can see delta (point) lights: only strategies that
// sample lights explicitly; render() refuses the others on scenes with point
// lights (their estimate would silently miss that light).
bool strategy_sees_delta_lights(Strategy s);
std::string defect_name(Defect d);
Defect parse_defect(const std::string& name);

struct RenderOptions {
  Strategy strategy = Strategy::kLightArea;
  Defect defect = Defect::kNone;
  LightSelection light_selection = LightSelection::kUniform;
  int spp = 64;
  uint64_t seed = 1;
  int threads = 0;  // 0: all hardware threads (tbb::global_control otherwise)
  // Path tracers only: the longest path (segments from the camera, the camera
  // segment counts as 1), and the depth from which Russian roulette starts
  // (survival probability min(1, throughput), reweighted by 1/p).
  int max_depth = 64;
  int roulette_depth = 3;
};

// Per-pixel central moments of the single-sample estimator Y, accumulated in
// sample order (so the result is independent of threading).
// Pixel index = py * width + px.
using PixelMoments = RunningMoments;

struct Image {
  int width = 0, height = 0;
  std::vector<PixelMoments> pixels;
  uint64_t nonfinite_samples = 0;  // NaN/Inf estimator values: dropped and counted (error tier 3)
  uint64_t rays = 0;               // rays traced (primary + secondary + shadow); the camera ray
                                   // is the same for every sample of a pixel and counted once
  double seconds = 0;              // wall time of render()
  const PixelMoments& at(int px, int py) const { return pixels[size_t(py) * width + px]; }
};

// Renders the scene: one camera ray per pixel centre; the pixel estimator is
// Y = Le(x) + (ρ/π)·Ê(x) at the first hit x, Ê the strategy's single-sample
// irradiance estimate (the environment radiance on a miss). For non-Lambertian
// first hits the direct strategies estimate ∫ f·Li·cos dω with the BSDF's f:
// only `bsdf` and the MIS strategies see a mirror's delta lobe. Path tracers
// return their path's radiance. Throws furnace::Error if the scene has no
// emitter (nor environment) for light sampling, if it has point lights and the
// strategy cannot see them (strategy_sees_delta_lights), or on a bad option.
Image render(const Scene& scene, const RenderOptions& options);

}  // namespace furnace
