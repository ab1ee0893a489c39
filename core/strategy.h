// The vocabulary every layer shares: the sampling strategies and their
// properties (one table), how lights are selected, the negative-control
// defects, path depth ("unlimited" spelled once) and the constants of the
// renderer's sampling contract that analytic/ must model.
//
// renderer/ implements the strategies, analytic/ models their moments and
// verify/ decides which references and tests apply, all from this table: a
// new strategy is one row here plus every switch over Strategy that the
// compiler then names (-Werror=switch; docs/extending.md lists them).
#pragma once

#include <array>
#include <cstddef>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/error.h"

namespace furnace {

// Sampling strategies. Values are stable (never renumber); names are the CLI's.
enum class Strategy {
  kUniformHemisphere,
  kCosineHemisphere,
  kLightArea,
  kLightSolidAngle,
  kBsdf,
  kMisBalance,
  kMisPower,
  kPathNaive,
  kPathMis,
  kMisOneSample,
};

// What a strategy estimates. A direct strategy estimates Y = Le + ∫ f·Li·cos dω
// at the first hit, Li the radiance emitted by the first surface or the
// environment seen along ωi (the quantity analytic::reference_image gives); a
// path tracer estimates full global illumination (analytic::global_reference_image).
enum class StrategyKind { kDirect, kPath };

struct StrategyInfo {
  Strategy strategy;
  const char* name;
  StrategyKind kind;
  // Draws explicit light samples: needs a light (an emitter, a point light or
  // the environment) and is the only kind that finds delta (point) lights.
  bool samples_lights;
  // The strategy whose single-sample second moment analytic/moments.h models
  // for this one on a Lambertian receiver (bsdf sampling of a Lambertian
  // surface is cosine sampling), or none.
  std::optional<Strategy> variance_model;
  // MIS heuristic exponent β of w_s = p_s^β / Σ p^β (1 balance, 2 power);
  // 0 for strategies that are not multi-sample MIS.
  int mis_beta;
  // Draws directions on the viewer's side of the surface only (the
  // hemisphere strategies): blind to what a surface transmits, so render()
  // refuses it on a scene with a dielectric.
  bool viewer_side_only;
  // Draws directions from the surface's BSDF (alone, in MIS or along a
  // path): the only way to follow a delta lobe (a mirror, a smooth
  // dielectric), so render() refuses the others on a scene with a smooth
  // dielectric.
  bool samples_bsdf;
  const char* description;  // one line, for --help and the README
};

// The table, in the order the CLI lists and the suite runs the strategies.
inline constexpr std::array<StrategyInfo, 10> kStrategyTable = {{
    {Strategy::kUniformHemisphere, "uniform_hemisphere", StrategyKind::kDirect, false, Strategy::kUniformHemisphere, 0,
     true, false, "directions uniform on the hemisphere, pdf 1/(2π) per sr"},
    {Strategy::kCosineHemisphere, "cosine_hemisphere", StrategyKind::kDirect, false, Strategy::kCosineHemisphere, 0,
     true, false, "cosine-weighted directions, pdf cos θ/π per sr"},
    {Strategy::kLightArea, "light_area", StrategyKind::kDirect, true, Strategy::kLightArea, 0,
     false, false, "a point uniform on a chosen emitter's area, plus a shadow ray"},
    {Strategy::kLightSolidAngle, "light_solid_angle", StrategyKind::kDirect, true, Strategy::kLightSolidAngle, 0,
     false, false, "uniform in the solid angle of spheres (cone), triangles and rectangles; area sampling otherwise"},
    {Strategy::kBsdf, "bsdf", StrategyKind::kDirect, false, Strategy::kCosineHemisphere, 0,
     false, true, "the surface's BSDF sampling (cosine for Lambertian, lobe for Phong, the mirror direction)"},
    {Strategy::kMisBalance, "mis_balance", StrategyKind::kDirect, true, Strategy::kMisBalance, 1,
     false, true, "one BSDF and one light_solid_angle sample, balance heuristic"},
    {Strategy::kMisPower, "mis_power", StrategyKind::kDirect, true, Strategy::kMisPower, 2,
     false, true, "one BSDF and one light_solid_angle sample, power heuristic (β = 2)"},
    {Strategy::kMisOneSample, "mis_one_sample", StrategyKind::kDirect, true, Strategy::kMisOneSample, 0,
     false, true, "BSDF or light_solid_angle sampling chosen with probability 1/2, one-sample balance heuristic"},
    {Strategy::kPathNaive, "path_naive", StrategyKind::kPath, false, std::nullopt, 0,
     false, true, "path tracer: BSDF sampling, emission on hit, Russian roulette"},
    {Strategy::kPathMis, "path_mis", StrategyKind::kPath, true, std::nullopt, 2,
     false, true, "path tracer: next-event estimation with the power heuristic, Russian roulette"},
}};

// Every enumerator 0 … kStrategyTable.size() − 1 has exactly one row.
constexpr bool every_strategy_has_one_row() {
  for (size_t v = 0; v < kStrategyTable.size(); ++v) {
    int rows = 0;
    for (const StrategyInfo& info : kStrategyTable) rows += info.strategy == Strategy(v);
    if (rows != 1) return false;
  }
  return true;
}
static_assert(every_strategy_has_one_row(), "kStrategyTable needs one row per Strategy");

// The row of a strategy.
constexpr const StrategyInfo& strategy_info(Strategy s) {
  for (const StrategyInfo& info : kStrategyTable)
    if (info.strategy == s) return info;
  // An enumerator added without its row: the static_assert above checks the
  // values 0 … size − 1 only, so a value past the table ends here (a compile
  // error where evaluated at compile time).
  check_failed("every Strategy has a row in kStrategyTable", __FILE__, __LINE__);
}
inline std::string strategy_name(Strategy s) { return strategy_info(s).name; }
inline bool is_path_tracer(Strategy s) { return strategy_info(s).kind == StrategyKind::kPath; }
inline bool samples_lights(Strategy s) { return strategy_info(s).samples_lights; }
// Only strategies that sample lights explicitly see delta lights; render()
// refuses the others on scenes with point lights (their estimate would
// silently miss that light).
inline bool strategy_sees_delta_lights(Strategy s) { return samples_lights(s); }
inline bool has_variance_model(Strategy s) { return strategy_info(s).variance_model.has_value(); }
// Multi-sample MIS: a direct strategy that draws one sample of each technique
// and weighs them by the heuristic of exponent mis_beta (mis_balance,
// mis_power). Two such strategies draw the same samples and rays and differ
// only in the weights, so one render and one quadrature serve them all.
constexpr bool is_multi_sample_mis(Strategy s) {
  return strategy_info(s).kind == StrategyKind::kDirect && strategy_info(s).mis_beta > 0;
}
// The multi-sample MIS strategies, in table order, and how many there are.
std::vector<Strategy> multi_sample_mis_strategies();
constexpr size_t multi_sample_mis_count() {
  size_t n = 0;
  for (const StrategyInfo& info : kStrategyTable) n += is_multi_sample_mis(info.strategy) ? 1 : 0;
  return n;
}
// Throws furnace::Error naming the value and the accepted names.
Strategy parse_strategy(const std::string& name);
// The direct-lighting strategies and the path tracers, in table order.
std::vector<Strategy> direct_strategies();
std::vector<Strategy> path_tracing_strategies();
// Name → value, for CLI11's CheckedTransformer.
std::map<std::string, Strategy> strategy_names();

// How light-sampling strategies choose one light among the scene's lights.
enum class LightSelection {
  kUniform,  // "uniform": pmf 1/K over the K lights
  kPower,    // "power": pmf proportional to each light's emitted power
};
std::string light_selection_name(LightSelection s);
LightSelection parse_light_selection(const std::string& name);
std::map<std::string, LightSelection> light_selection_names();

// How radiance crossing a dielectric interface is transported (Veach 1997,
// ch. 5): "radiance" divides it by η′² = (η_t/η_i)² on entering the denser
// side (L/η² is what is conserved: pbrt-v4, Mitsuba 3), "none" transports it
// unscaled (Cycles). A camera outside a closed glass object sees the same in
// both (the factors cancel); a single interface, or a light or camera inside
// glass, tells them apart by η².
enum class TransportConvention { kRadiance, kNone };
std::string transport_convention_name(TransportConvention c);
TransportConvention parse_transport_convention(const std::string& name);
std::map<std::string, TransportConvention> transport_convention_names();

// Deliberately wrong variants, for negative controls only. kNone is the
// renderer; every other value must make the verification fail.
enum class Defect {
  kNone,
  kDropLightCosine,
  kPdfOffByConstant,
  kSkipShadowRay,
  kRouletteNoReweight,
  kDoubleCountEmission,
  kMisUnnormalisedWeight,
  kPointLightMisWeighted,
  kPowerSelectionUniformPmf,
  kOneSampleNoSelectionProb,
  kEnvMissingSinTheta,
  kPhongWrongNormalisation,
  kNanSample,
  kBackFaceEmits,
  kRayOffset1e4,
  kGrazingEmitterCosine,
  kConeSamplingFloat,
  kMisPowerExponent3,
  kGgxVndfPdfWithoutG1,
  kGgxSampleAlphaSquared,
  kGgxLambdaOtherAlpha,
  kGgxSeparableAsHeightCorrelated,
  kGgxDWithoutInvPi,
  kDielectricTransmissionWithoutEta2,
  kDielectricReflectionJacobian,
  kDielectricNoRadianceScaling,
  kDielectricMacroFresnel,
  kDielectricTirAbsorbs,
  kDielectricEtaNotInverted,
  kConductorFresnelApproximate,
};

struct DefectInfo {
  Defect defect;
  const char* name;
  const char* description;
};
inline constexpr std::array<DefectInfo, 30> kDefectTable = {{
    {Defect::kNone, "none", "the renderer as it is"},
    {Defect::kDropLightCosine, "drop_light_cosine", "light_area forgets cos θ' (the area to solid angle Jacobian)"},
    {Defect::kPdfOffByConstant, "pdf_off_by_constant", "the weight divides by 1.1 × the true pdf"},
    {Defect::kSkipShadowRay, "skip_shadow_ray", "light_area treats every light sample as visible"},
    {Defect::kRouletteNoReweight, "roulette_no_reweight",
     "Russian-roulette survivors not divided by the survival probability"},
    {Defect::kDoubleCountEmission, "double_count_emission",
     "path_mis counts emission found by BSDF continuation with weight 1 as well as the light sample's share"},
    {Defect::kMisUnnormalisedWeight, "mis_unnormalised_weight",
     "MIS weights divided by the larger density instead of the sum"},
    {Defect::kPointLightMisWeighted, "point_light_mis_weighted",
     "MIS weighs a point-light (delta) sample like an area sample, by pmf/(pmf + p_bsdf)"},
    {Defect::kPowerSelectionUniformPmf, "power_selection_uniform_pmf",
     "lights chosen by power, weights divided by the uniform pmf 1/K"},
    {Defect::kOneSampleNoSelectionProb, "one_sample_no_selection_prob",
     "mis_one_sample divides by p_bsdf + p_light, forgetting the selection probabilities c and 1 − c"},
    {Defect::kEnvMissingSinTheta, "env_missing_sin_theta",
     "environment-map rows chosen without the sin θ Jacobian while the weight uses the stated density"},
    {Defect::kPhongWrongNormalisation, "phong_wrong_normalisation",
     "Phong eval normalised by (n+1)/(2π), the sampling density's constant, instead of (n+2)/(2π)"},
    {Defect::kNanSample, "nan_sample", "one sample in 1024 runs away to NaN (counted, and a failure by default)"},
    {Defect::kBackFaceEmits, "back_face_emits", "one-sided emitters emit from both sides (every emitter taken as two_sided)"},
    {Defect::kRayOffset1e4, "ray_offset_1e4",
     "shadow and continuation rays start 1e-4 along the face-forwarded normal instead of at the surface point"},
    {Defect::kGrazingEmitterCosine, "grazing_emitter_cosine",
     "area sampling converts to solid angle with max(cos θ', 0.05), a firefly guard wrong only at grazing emission"},
    {Defect::kConeSamplingFloat, "cone_sampling_float",
     "the sphere cone's 1 − cos θmax computed in single precision by subtraction, 1 − sqrtf(1 − sin²θmax)"},
    {Defect::kMisPowerExponent3, "mis_power_exponent_3",
     "mis_power weighs with the power heuristic's β = 3 while claiming β = 2: unbiased, but another variance"},
    {Defect::kGgxVndfPdfWithoutG1, "ggx_vndf_pdf_without_g1",
     "GGX visible-normal density without its G1(ωo) factor, D·max(0, ωo·m)/cos θo (NVIDIA-RTX Donut #23)"},
    {Defect::kGgxSampleAlphaSquared, "ggx_sample_alpha_squared",
     "GGX sampler stretches by α² where eval and pdf use α (Falcor #212)"},
    {Defect::kGgxLambdaOtherAlpha, "ggx_lambda_other_alpha",
     "GGX Smith Λ computed with α² while D uses α (OloEngineBase #904)"},
    {Defect::kGgxSeparableAsHeightCorrelated, "ggx_separable_as_height_correlated",
     "GGX evaluates the separable G1·G1 for a material that says height_correlated"},
    {Defect::kGgxDWithoutInvPi, "ggx_d_without_inv_pi", "GGX D(m) without its 1/π"},
    {Defect::kDielectricTransmissionWithoutEta2, "dielectric_transmission_without_eta2",
     "rough dielectric transmission f and pdf both without the Jacobian's η_i² (pbrt-v4 before dfa11074): "
     "BSDF-sampled weights stay right"},
    {Defect::kDielectricReflectionJacobian, "dielectric_reflection_jacobian",
     "rough dielectric transmission f and pdf with the reflection Jacobian 1/(4|ωi·m|)"},
    {Defect::kDielectricNoRadianceScaling, "dielectric_no_radiance_scaling",
     "the radiance convention's 1/η′² on transmission dropped (the none convention rendered for radiance)"},
    {Defect::kDielectricMacroFresnel, "dielectric_macro_fresnel",
     "rough dielectric Fresnel taken at the macro normal instead of the microfacet normal (Cycles <= 3.5)"},
    {Defect::kDielectricTirAbsorbs, "dielectric_tir_absorbs",
     "total internal reflection treated as absorption: the reflection lobe weighted 1 − T without TIR"},
    {Defect::kDielectricEtaNotInverted, "dielectric_eta_not_inverted",
     "a dielectric seen from inside uses η instead of 1/η"},
    {Defect::kConductorFresnelApproximate, "conductor_fresnel_approximate",
     "GGX conductor Fresnel by the classic approximation (Cycles until 5.0), off by up to 0.096"},
}};
constexpr bool every_defect_has_one_row() {
  for (size_t v = 0; v < kDefectTable.size(); ++v) {
    int rows = 0;
    for (const DefectInfo& info : kDefectTable) rows += info.defect == Defect(v);
    if (rows != 1) return false;
  }
  return true;
}
static_assert(every_defect_has_one_row(), "kDefectTable needs one row per Defect");
std::string defect_name(Defect d);
Defect parse_defect(const std::string& name);
std::map<std::string, Defect> defect_names();

// Path depth counts segments from the camera (the camera segment is 1).
// The one spelling of "no limit": the full Neumann series in analytic/, no
// cap in the renderer, the word "unlimited" on the command line.
inline constexpr int kUnlimitedDepth = std::numeric_limits<int>::max();
// "unlimited" or the number.
std::string depth_name(int max_depth);

// The renderer's sampling contract, which analytic/ models and must not
// restate: light_solid_angle samples a spherical triangle or rectangle only
// when its solid angle is at least kMinSampledSolidAngle (below it Ω = α + β
// + γ − π loses log10(π/Ω) digits, 6 of 16 at 1e-6 sr) and falls back to
// area sampling otherwise;
inline constexpr double kMinSampledSolidAngle = 1e-6;
// a parallelogram is a rectangle (spherical-rectangle sampling) when its
// edges are perpendicular within this relative tolerance (scene files give
// edges as decimals, perpendicular to within a few ulps);
inline constexpr double kPerpendicularTolerance = 1e-12;
// mis_one_sample takes the BSDF sample with probability c (else the light
// sample): 1/2, the choice that needs no knowledge of the scene.
inline constexpr double kOneSampleBsdfProbability = 0.5;

}  // namespace furnace
