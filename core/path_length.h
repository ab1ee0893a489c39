// How long a path tracer's paths are, before anything is rendered: the rule
// that refuses a scene whose answer is infinite at the requested depth, and a
// bound on the expected number of path segments that refuses (or states) a
// render that would take about forever.
//
// The bound. A path tracer continues a path by sampling its BSDF, whose
// weight f·cos/pdf has expectation the directional albedo, at most the
// material's `albedo` ρ for every BSDF furnace models (Lambertian, mirror,
// normalised Phong, single-scattering GGX and the dielectric lose energy,
// none gains it; a dielectric's transmission in the radiance convention
// also carries 1/η′², which T below leaves out, as Russian roulette does).
// From segment R (the roulette depth) on, Russian roulette keeps a path of
// throughput T with probability min(1, T) and divides T by it, so a surviving
// path has T ≥ 1 and E[T] shrinks by at most ρmax per segment:
// P(alive after k roulettes) ≤ E[T] ≤ ρmax^k, and
//   E[segments] ≤ R + ρmax / (1 − ρmax)        (and ≤ the depth limit),
// whether or not paths escape. It is infinite at unlimited depth when some
// object has ρ = 1 or roulette never starts. A closed scene keeps every path
// inside, so its bound is all there is: past kMaxExpectedPathSegments the
// render is refused. An open scene lets paths escape (a white furnace with
// albedo 1 ends after a few segments), so its bound may be far too large:
// it is rendered, with a cap on each path (kOpenScenePathSegmentCap) that
// stops a render of a scene that is closed but not marked so.
#pragma once

#include <optional>
#include <string>

#include "core/scene.h"

namespace furnace {

// Past this expected number of segments per path a closed scene is refused
// (albedo above 1 − 1e-5 at unlimited depth with the default roulette).
inline constexpr double kMaxExpectedPathSegments = 1e5;
// Past this one the render states the bound before it starts.
inline constexpr double kStatedPathSegments = 1e3;
// A path of an open scene whose bound exceeds kMaxExpectedPathSegments ends
// the render with an error when it reaches this many segments.
inline constexpr int kOpenScenePathSegmentCap = 1 << 20;

// Why the scene's radiance is infinite for paths of at most max_segments
// segments, or nullopt: a closed scene at unlimited depth in which something
// emits and every object reflects with albedo ≥ 1 through an energy-keeping
// BSDF (Lambertian or mirror), so every bounce returns all the light.
std::optional<std::string> infinite_answer_reason(const Scene& scene, int max_segments);

// The bound above on a path tracer's expected segments per camera path
// (infinity when there is none).
double expected_path_segments_bound(const Scene& scene, int max_segments, int roulette_depth);

// Throws furnace::Error naming the scene's file when its answer is infinite
// at max_segments, or when it is closed and its bound exceeds
// kMaxExpectedPathSegments (with the object whose albedo sets it).
void require_bounded_paths(const Scene& scene, int max_segments, int roulette_depth);

// Whether the renderer must cap an open scene's paths at
// kOpenScenePathSegmentCap (its bound exceeds kMaxExpectedPathSegments).
bool needs_path_segment_cap(const Scene& scene, int max_segments, int roulette_depth);

// A sentence stating the bound when it exceeds kStatedPathSegments (for a
// command to print before it renders), or nullopt.
std::optional<std::string> path_length_statement(const Scene& scene, int max_segments, int roulette_depth);

}  // namespace furnace
