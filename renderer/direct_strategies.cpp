#include "renderer/direct_strategies.h"

#include <algorithm>
#include <cmath>
#include <variant>

#include <fmt/format.h>

#include "core/error.h"
#include "renderer/render_options.h"
#include "renderer/sampling.h"

namespace furnace {

namespace {

DirectionSample local_direction_sample(const ShadingContext& ctx, const Vec3& wi_local, double pdf_solid_angle,
                                       Defect defect) {
  DirectionSample s;
  s.wi_world = ctx.frame.world_from_local(wi_local);
  s.pdf_solid_angle = pdf_solid_angle;
  s.weight = ctx.bsdf.eval(ctx.wo_local, wi_local) * std::fabs(wi_local.z) / pdf_in_weight(pdf_solid_angle, defect);
  return s;
}

}  // namespace

// ---------------------------------------------------------------------------

std::optional<DirectionSample> UniformHemisphereStrategy::sample(const ShadingContext& ctx, const Uniform3& u) const {
  const Vec3 wi_local = sample_uniform_hemisphere(u[1], u[2]);
  const double pdf_solid_angle = uniform_hemisphere_pdf(wi_local);
  if (!(pdf_solid_angle > 0)) return std::nullopt;
  return local_direction_sample(ctx, wi_local, pdf_solid_angle, defect);
}
double UniformHemisphereStrategy::pdf(const ShadingContext& ctx, const Vec3& wi_world) const {
  return uniform_hemisphere_pdf(ctx.frame.local_from_world(wi_world));
}

std::optional<DirectionSample> CosineHemisphereStrategy::sample(const ShadingContext& ctx, const Uniform3& u) const {
  const Vec3 wi_local = sample_cosine_hemisphere(u[1], u[2]);
  const double pdf_solid_angle = cosine_hemisphere_pdf(wi_local);
  if (!(pdf_solid_angle > 0)) return std::nullopt;
  return local_direction_sample(ctx, wi_local, pdf_solid_angle, defect);
}
double CosineHemisphereStrategy::pdf(const ShadingContext& ctx, const Vec3& wi_world) const {
  return cosine_hemisphere_pdf(ctx.frame.local_from_world(wi_world));
}

std::optional<DirectionSample> BsdfStrategy::sample(const ShadingContext& ctx, const Uniform3& u) const {
  const auto b = ctx.bsdf.sample(ctx.wo_local, u[1], u[2], u[0]);
  if (!b) return std::nullopt;
  DirectionSample s;
  s.wi_world = ctx.frame.world_from_local(b->wi_local);
  s.pdf_solid_angle = b->pdf_solid_angle;
  s.delta = b->delta;
  s.radiance_scale = b->radiance_scale;
  // DEFECT(pdf_off_by_constant) for non-delta samples: weight·pdf/(1.1·pdf).
  s.weight = (!s.delta && defect == Defect::kPdfOffByConstant) ? b->weight / kDefectPdfFactor : b->weight;
  return s;
}
double BsdfStrategy::pdf(const ShadingContext& ctx, const Vec3& wi_world) const {
  return ctx.bsdf.pdf(ctx.wo_local, ctx.frame.local_from_world(wi_world));
}

// ---------------------------------------------------------------------------

MisWeights mis_weights(const MisPdfs& pdfs, int beta, Defect defect) {
  if (defect == Defect::kMisUnnormalisedWeight) {
    // DEFECT(mis_unnormalised_weight): p_a^β/max(p_a, p_b)^β; the weights sum to 1 + (min/max)^β.
    const double larger = std::fmax(pdfs.p_bsdf, pdfs.p_light);
    if (!(larger > 0)) return {};
    return {std::pow(pdfs.p_bsdf / larger, beta), std::pow(pdfs.p_light / larger, beta)};
  }
  if (defect == Defect::kMisPowerExponent3 && beta == 2) {
    // DEFECT(mis_power_exponent_3): β = 3 where β = 2 is claimed. The weights
    // still sum to 1 (unbiased); the variance is another estimator's.
    const double a = std::pow(pdfs.p_bsdf, 3), b = std::pow(pdfs.p_light, 3);
    if (!(a + b > 0)) return {};
    return {a / (a + b), b / (a + b)};
  }
  return {mis_weight(pdfs.p_bsdf, pdfs.p_light, beta), mis_weight(pdfs.p_light, pdfs.p_bsdf, beta)};
}

MisPdfs DirectLighting::mis_pdfs(const ShadingContext& ctx, const Vec3& wi_world,
                                 const std::optional<SurfaceHit>& hit) const {
  return {BsdfStrategy{defect_}.pdf(ctx, wi_world), light_.pdf(ctx, wi_world, hit)};
}

DirectLighting::DirectLighting(const EmbreeScene& scene, const LightSet& lights, Strategy strategy, Defect defect)
    : DirectLighting(scene, lights, std::vector<Strategy>{strategy}, defect) {}

DirectLighting::DirectLighting(const EmbreeScene& scene, const LightSet& lights,
                               const std::vector<Strategy>& strategies, Defect defect)
    : scene_(scene), lights_(lights), defect_(defect) {
  if (strategies.empty() || strategies.size() > kMaxSharedEstimators)
    throw Error(fmt::format("DirectLighting estimates 1 to {} strategies from shared samples, got {}.",
                            kMaxSharedEstimators, strategies.size()));
  for (Strategy s : strategies)
    if (!shares_samples(strategies.front(), s))
      throw Error(fmt::format("strategies '{}' and '{}' do not draw the same samples, so one render cannot give both.",
                              strategy_name(strategies.front()), strategy_name(s)));
  strategy_ = strategies.front();
  n_estimators_ = strategies.size();
  for (size_t e = 0; e < n_estimators_; ++e) betas_[e] = strategy_info(strategies[e]).mis_beta;
  light_.scene = &scene;
  light_.lights = &lights;
  light_.emitter_sampling = strategy_ == Strategy::kLightArea ? EmitterSampling::kArea : EmitterSampling::kSolidAngle;
  light_.defect = defect;
}

// The batch estimators below do, for each sample i of the batch, what the
// single-sample estimator of the strategy does, in the same order, so every
// sample draws the same numbers from rngs[i] and gets the same value. The
// shadow rays of a batch's light samples are traced together, as one Embree
// packet (rays from one shading point towards the lights are coherent);
// sampled directions are traced one by one, as they are drawn: Embree's
// packets did not make those incoherent rays faster, and keeping them for
// later cost more than they saved. Light samples are filled in place: copying
// a whole sample a call just returned through memory stalled the loads.

namespace {

// A batch's light samples, filled in place, and their visibility: the shadow
// rays of those that need one (not DEFECT(skip_shadow_ray)'s assumed ones)
// are traced together and counted.
struct LightBatch {
  LightSample samples[kRayPacket];  // default-constructed, as LightStrategy::sample requires
  bool sampled[kRayPacket] = {};    // a sample with a non-zero weight
  bool visible[kRayPacket] = {};    // after trace()
  RayArgs rays[kRayPacket];
  size_t lane[kRayPacket];
  bool occluded[kRayPacket];
  size_t m = 0;

  // Draws sample i and queues its shadow ray.
  void draw(size_t i, const LightStrategy& light, const ShadingContext& ctx, const Uniform3& u,
            EmitterSetups* setups) {
    LightSample& s = samples[i];
    sampled[i] = light.sample(ctx, u, setups, s) && s.weight != 0;
    if (!sampled[i]) return;
    visible[i] = s.assume_visible;
    if (s.assume_visible) return;  // DEFECT(skip_shadow_ray)
    rays[m] = shadow_ray(s);
    lane[m++] = i;
  }
  void trace(const EmbreeScene& scene, TraceCounters& counters) {
    counters.rays += m;
    scene.occluded(rays, m, occluded);
    for (size_t j = 0; j < m; ++j) visible[lane[j]] = !occluded[j];
  }
  // f(i, sample) for every sample drawn with a non-zero weight whose light is visible, in sample order.
  template <typename F>
  void for_each_visible(size_t n, F&& f) const {
    for (size_t i = 0; i < n; ++i)
      if (sampled[i] && visible[i]) f(i, samples[i]);
  }
};

}  // namespace

template <typename DirectionStrategy>
void DirectLighting::estimate_direction(const DirectionStrategy& strategy, const ShadingContext& ctx, Rng* rngs,
                                        size_t n, TraceCounters& counters, double* out) const {
  for (size_t i = 0; i < n; ++i) {
    out[i] = 0.0;
    const auto s = strategy.sample(ctx, next_uniform3(rngs[i]));
    if (!s || s->weight == 0) continue;  // nothing to trace for a zero weight
    const auto hit = trace_from(scene_, ctx, s->wi_world, counters, defect_);
    out[i] = s->weight * emitted_radiance_towards(scene_.scene(), hit, s->wi_world);
  }
}

void DirectLighting::estimate_light(const ShadingContext& ctx, Rng* rngs, size_t n, TraceCounters& counters,
                                    EmitterSetups* setups, double* out) const {
  LightBatch light;
  for (size_t i = 0; i < n; ++i) {
    out[i] = 0.0;
    light.draw(i, light_, ctx, next_uniform3(rngs[i]), setups);
  }
  light.trace(scene_, counters);
  light.for_each_visible(n, [&](size_t i, const LightSample& s) { out[i] = s.weight * s.radiance; });
}

void DirectLighting::estimate_mis(const ShadingContext& ctx, Rng* rngs, size_t n, TraceCounters& counters,
                                  EmitterSetups* setups, double* const* out) const {
  const BsdfStrategy bsdf{defect_};
  LightBatch light;
  for (size_t i = 0; i < n; ++i) {
    double estimate[kMaxSharedEstimators] = {};
    // One BSDF sample, weighted against the light strategy's density for the same direction.
    if (const auto s = bsdf.sample(ctx, next_uniform3(rngs[i])); s && s->weight != 0) {
      const auto hit = trace_from(scene_, ctx, s->wi_world, counters, defect_);
      const double le = emitted_radiance_towards(scene_.scene(), hit, s->wi_world);
      if (le > 0) {
        const double p_light = s->delta ? 0.0 : light_.pdf(ctx, s->wi_world, hit, setups);
        for (size_t e = 0; e < n_estimators_; ++e) {
          const double w = s->delta ? 1.0 : mis_weights({s->pdf_solid_angle, p_light}, betas_[e], defect_).w_bsdf;
          estimate[e] += w * s->weight * le;
        }
      }
    }
    for (size_t e = 0; e < n_estimators_; ++e) out[e][i] = estimate[e];
    // One light sample (its shadow ray traced with the batch's).
    light.draw(i, light_, ctx, next_uniform3(rngs[i]), setups);
  }
  light.trace(scene_, counters);
  // The light samples, weighted against the BSDF's density (0 for a delta BSDF,
  // whose eval is 0 anyway); a point-light sample only against nothing
  // (weight 1): BSDF sampling never finds it.
  light.for_each_visible(n, [&](size_t i, const LightSample& s) {
    const double p_bsdf = bsdf.pdf(ctx, s.wi_world);
    for (size_t e = 0; e < n_estimators_; ++e) {
      const double w = s.delta ? delta_light_mis_weight(s, p_bsdf, defect_)
                               : mis_weights({p_bsdf, s.pdf_solid_angle}, betas_[e], defect_).w_light;
      out[e][i] += w * s.weight * s.radiance;
    }
  });
}

void DirectLighting::estimate_one_sample(const ShadingContext& ctx, Rng* rngs, size_t n, TraceCounters& counters,
                                         EmitterSetups* setups, double* out) const {
  const BsdfStrategy bsdf{defect_};
  // DEFECT(one_sample_no_selection_prob): the densities are summed without c and 1 − c.
  const bool forget = defect_ == Defect::kOneSampleNoSelectionProb;
  const double c = forget ? 1.0 : kOneSampleBsdfProbability;
  const double c_light = forget ? 1.0 : 1.0 - kOneSampleBsdfProbability;
  LightBatch light;  // the samples that chose the light strategy, weighed once their shadow rays are traced
  for (size_t i = 0; i < n; ++i) {
    out[i] = 0.0;
    if (rngs[i].next_double() < kOneSampleBsdfProbability) {
      const auto s = bsdf.sample(ctx, next_uniform3(rngs[i]));
      if (!s || s->weight == 0) continue;
      const auto hit = trace_from(scene_, ctx, s->wi_world, counters, defect_);
      const double le = emitted_radiance_towards(scene_.scene(), hit, s->wi_world);
      if (!(le > 0)) continue;
      // A delta lobe: only this strategy covers it, chosen with probability c.
      if (s->delta) {
        out[i] = s->weight * le / c;
        continue;
      }
      // weight·p_bsdf = f·cos θ: the estimate f·cos θ·Le/(c·p_bsdf + (1 − c)·p_light).
      const double p_light = light_.pdf(ctx, s->wi_world, hit, setups);
      out[i] = s->weight * s->pdf_solid_angle * le / (c * s->pdf_solid_angle + c_light * p_light);
      continue;
    }
    light.draw(i, light_, ctx, next_uniform3(rngs[i]), setups);
  }
  light.trace(scene_, counters);
  light.for_each_visible(n, [&](size_t i, const LightSample& s) {
    // A point light: only this strategy covers it, chosen with probability 1 − c.
    if (s.delta) {
      out[i] = s.weight * s.radiance / c_light;
      return;
    }
    const double p_bsdf = bsdf.pdf(ctx, s.wi_world);
    out[i] = s.weight * s.pdf_solid_angle * s.radiance / (c * p_bsdf + c_light * s.pdf_solid_angle);
  });
}

double DirectLighting::estimate(const ShadingContext& ctx, Rng& rng, TraceCounters& counters,
                                EmitterSetups* setups) const {
  double out = 0;
  estimate(ctx, &rng, 1, counters, setups, &out);
  return out;
}

void DirectLighting::estimate(const ShadingContext& ctx, Rng* rngs, size_t n, TraceCounters& counters,
                              EmitterSetups* setups, double* out) const {
  FURNACE_CHECK(n_estimators_ == 1);
  double* const outs[1] = {out};
  estimate_shared(ctx, rngs, n, counters, setups, outs);
}

void DirectLighting::estimate_shared(const ShadingContext& ctx, Rng* rngs, size_t n, TraceCounters& counters,
                                     EmitterSetups* setups, double* const* out) const {
  FURNACE_CHECK(n <= kRayPacket);
  if (ctx.bsdf.is_black()) {
    for (size_t e = 0; e < n_estimators_; ++e) std::fill(out[e], out[e] + n, 0.0);
    return;
  }
  switch (strategy_) {
    case Strategy::kUniformHemisphere:
      return estimate_direction(UniformHemisphereStrategy{defect_}, ctx, rngs, n, counters, out[0]);
    case Strategy::kCosineHemisphere:
      return estimate_direction(CosineHemisphereStrategy{defect_}, ctx, rngs, n, counters, out[0]);
    case Strategy::kBsdf: return estimate_direction(BsdfStrategy{defect_}, ctx, rngs, n, counters, out[0]);
    case Strategy::kLightArea:
    case Strategy::kLightSolidAngle: return estimate_light(ctx, rngs, n, counters, setups, out[0]);
    case Strategy::kMisBalance:
    case Strategy::kMisPower: return estimate_mis(ctx, rngs, n, counters, setups, out);
    case Strategy::kMisOneSample: return estimate_one_sample(ctx, rngs, n, counters, setups, out[0]);
    case Strategy::kPathNaive:
    case Strategy::kPathMis: break;
  }
  FURNACE_CHECK(false && "DirectLighting::estimate called with a path-tracing strategy");
}

}  // namespace furnace
