#include "renderer/path_tracer.h"

#include <algorithm>

#include <fmt/format.h>

#include "core/error.h"
#include "core/path_length.h"

namespace furnace {

namespace {
// β of path_mis's MIS heuristic (the strategy table's).
constexpr int kPathMisBeta = strategy_info(Strategy::kPathMis).mis_beta;
}  // namespace

PathTracer::PathTracer(const EmbreeScene& scene, const LightSet& lights, const RenderOptions& options)
    : scene_(scene),
      next_event_(is_path_tracer(options.strategy) && samples_lights(options.strategy)),
      max_depth_(options.max_depth),
      roulette_depth_(options.roulette_depth),
      segment_cap_(needs_path_segment_cap(scene.scene(), options.max_depth, options.roulette_depth)
                       ? kOpenScenePathSegmentCap
                       : options.max_depth),
      defect_(options.defect),
      convention_(options.convention) {
  light_.scene = &scene;
  light_.lights = &lights;
  light_.emitter_sampling = EmitterSampling::kSolidAngle;
  light_.defect = options.defect;
  bsdf_.defect = options.defect;
}

double PathTracer::radiance(const Vec3& direction, const std::optional<SurfaceHit>& first_hit, Rng& rng,
                            TraceCounters& counters, EmitterSetups* setups) const {
  const Scene& scene = scene_.scene();
  double radiance = 0;
  double throughput = 1;
  // The product of the transport convention's factors in throughput (a
  // dielectric's 1/η′² per transmission): roulette judges throughput/scale,
  // so a path inside glass is not killed for carrying η² more radiance.
  double radiance_scale = 1;
  std::optional<SurfaceHit> hit = first_hit;
  Vec3 wi_world = direction;
  // The vertex the current segment left from, for MIS of emission found by BSDF sampling.
  std::optional<ShadingContext> previous;
  double previous_pdf_bsdf = 0;
  bool previous_delta = true;  // the camera segment counts as delta: its emission is never MIS-weighted

  for (int depth = 1;; ++depth) {
    // Emission reached by the segment just traced.
    const double le = emitted_radiance_towards(scene, hit, wi_world);
    if (le > 0) {
      double w = 1;
      // DEFECT(double_count_emission): weight 1 here although the light sample also counts this emission.
      if (next_event_ && !previous_delta && defect_ != Defect::kDoubleCountEmission)
        w = mis_weight(previous_pdf_bsdf, light_.pdf(*previous, wi_world, hit, setups), kPathMisBeta);
      radiance += throughput * w * le;
    }
    if (!hit || depth >= max_depth_) break;
    if (depth >= segment_cap_)
      throw Error(fmt::format("scene '{}': a path reached {} segments: the scene is not marked closed, yet it keeps "
                              "its paths like a closed enclosure of albedo near 1; set a finite max depth "
                              "(--max-depth N).",
                              scene.source.empty() ? scene.name : scene.source, segment_cap_));

    const Object& object = scene.objects[hit->object];
    const ShadingContext ctx = ShadingContext::at(*hit, -wi_world, object.material, defect_, convention_);
    if (ctx.bsdf.is_black()) break;

    if (next_event_ && !ctx.bsdf.is_delta()) {
      if (const auto s = light_.sample(ctx, next_uniform3(rng), setups); s && s->weight != 0) {
        if (light_visible(scene_, *s, counters)) {
          // A point light (delta) is found by light sampling only: weight 1.
          const double p_bsdf = bsdf_.pdf(ctx, s->wi_world);
          const double w = s->delta ? delta_light_mis_weight(*s, p_bsdf, defect_)
                                    : mis_weight(s->pdf_solid_angle, p_bsdf, kPathMisBeta);
          radiance += throughput * w * s->weight * s->radiance;
        }
      }
    }

    const auto s = bsdf_.sample(ctx, next_uniform3(rng));
    if (!s || s->weight == 0) break;
    throughput *= s->weight;
    radiance_scale *= s->radiance_scale;

    if (depth >= roulette_depth_) {
      const double survive = std::min(1.0, throughput / radiance_scale);
      if (!(rng.next_double() < survive)) break;
      // Unbiased: E[throughput'] = throughput. DEFECT(roulette_no_reweight) skips the division.
      if (defect_ != Defect::kRouletteNoReweight) throughput /= survive;
    }

    hit = trace_from(scene_, ctx, s->wi_world, counters, defect_);
    wi_world = s->wi_world;
    previous = ctx;
    previous_pdf_bsdf = s->pdf_solid_angle;
    previous_delta = s->delta;
  }
  return radiance;
}

}  // namespace furnace
