#include "core/path_length.h"

#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "core/error.h"
#include "core/strategy.h"

namespace furnace {

namespace {

const std::string& scene_label(const Scene& scene) { return scene.source.empty() ? scene.name : scene.source; }

// The object of largest albedo (the first of them), or nullptr for no object.
const Object* most_reflective(const Scene& scene) {
  const Object* best = nullptr;
  for (const Object& o : scene.objects)
    if (!best || o.material.albedo > best->material.albedo) best = &o;
  return best;
}

}  // namespace

std::optional<std::string> infinite_answer_reason(const Scene& scene, int max_segments) {
  if (!scene.closed || max_segments != kUnlimitedDepth || scene.objects.empty()) return std::nullopt;
  bool emits = !scene.point_lights.empty();
  for (const Object& o : scene.objects) {
    if (!(o.material.albedo >= 1) || !o.material.info().keeps_energy_at_unit_albedo) return std::nullopt;
    emits = emits || o.is_emitter();
  }
  if (!emits) return std::nullopt;
  return std::string("a closed enclosure whose every object reflects with albedo 1 (Lambertian or mirror) has "
                     "infinite radiance at unlimited depth");
}

double expected_path_segments_bound(const Scene& scene, int max_segments, int roulette_depth) {
  const double depth_limit =
      max_segments == kUnlimitedDepth ? std::numeric_limits<double>::infinity() : double(max_segments);
  const Object* o = most_reflective(scene);
  const double rho = o ? std::fmax(0.0, o->material.albedo) : 0.0;
  // Up to the roulette depth every path goes on (in a closed scene).
  if (roulette_depth >= max_segments) return depth_limit;
  const double after = rho >= 1 ? std::numeric_limits<double>::infinity() : rho / (1 - rho);
  return std::fmin(depth_limit, double(roulette_depth) + after);
}

void require_bounded_paths(const Scene& scene, int max_segments, int roulette_depth) {
  if (const auto reason = infinite_answer_reason(scene, max_segments))
    throw Error(fmt::format("scene '{}' is refused: {}; set a finite max depth (--max-depth N).", scene_label(scene),
                            *reason));
  if (!scene.closed) return;
  const double bound = expected_path_segments_bound(scene, max_segments, roulette_depth);
  if (bound <= kMaxExpectedPathSegments) return;
  const Object* o = most_reflective(scene);
  if (roulette_depth >= max_segments)
    throw Error(fmt::format("scene '{}' is refused: it is closed, so at unlimited depth without Russian roulette "
                            "(roulette depth {}) no path ends; set a finite max depth (--max-depth N) or a "
                            "roulette depth.",
                            scene_label(scene), roulette_depth));
  throw Error(fmt::format("scene '{}' is refused: it is closed and its object '{}' reflects with albedo {}, so a "
                          "path's expected length is bounded only by {:.3g} segments, past the {:.0e} furnace "
                          "renders; set a finite max depth (--max-depth N).",
                          scene_label(scene), o ? o->name : "", o ? o->material.albedo : 0.0, bound,
                          kMaxExpectedPathSegments));
}

bool needs_path_segment_cap(const Scene& scene, int max_segments, int roulette_depth) {
  return max_segments > kOpenScenePathSegmentCap &&
         expected_path_segments_bound(scene, max_segments, roulette_depth) > kMaxExpectedPathSegments;
}

std::optional<std::string> path_length_statement(const Scene& scene, int max_segments, int roulette_depth) {
  const double bound = expected_path_segments_bound(scene, max_segments, roulette_depth);
  if (bound <= kStatedPathSegments) return std::nullopt;
  if (!std::isfinite(bound) || bound > kMaxExpectedPathSegments)
    return fmt::format("scene '{}': the expected path length has no useful bound (an object reflects with albedo "
                       "near 1 at depth {}); as the scene is open, paths that escape end it, and a path reaching "
                       "{} segments stops the render.",
                       scene_label(scene), depth_name(max_segments), kOpenScenePathSegmentCap);
  return fmt::format("scene '{}': paths are expected to be up to {:.3g} segments long (albedo near 1 at depth {}).",
                     scene_label(scene), bound, depth_name(max_segments));
}

}  // namespace furnace
