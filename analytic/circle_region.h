// The visible part of a disk emitter behind disk occluders parallel to it,
// as a region of the emitter plane bounded by circle arcs (a hand-rolled
// Boolean "light minus union of occluder images" for circles only).
#pragma once

#include <functional>
#include <vector>

#include "analytic/disk.h"

namespace furnace::analytic {

// One oriented arc: points circle.c + r·(cos t, sin t), t from t0 to
// t0 + sweep. sweep > 0 is counter-clockwise in the plane's 2-D coordinates.
struct Arc {
  Circle2 circle;
  double t0 = 0;
  double sweep = 0;
};

// Boundary of light \ ∪ occluders, positively oriented (outer boundary
// counter-clockwise, holes clockwise). Method: split every circle at its
// proper intersections with the others; keep arcs of the light whose
// midpoint lies outside every occluder, and arcs of occluders whose midpoint
// lies inside the light and outside every other occluder (reversed).
// Occluders that contain the light make the result empty; occluders disjoint
// from the light or contained in another occluder are dropped first, and
// duplicate occluders are merged, so coincident circles never reach the
// midpoint test. Tangent circles (no proper intersection) are resolved by the
// midpoint test. Radii must be finite and ≥ 0 (zero-radius occluders are
// dropped); throws furnace::Error otherwise.
std::vector<Arc> visible_boundary(const Circle2& light, const std::vector<Circle2>& occluders);

// E/L = ∫_{light \ ∪ occluders} h²/(h² + s²)² dA for an emitter plane at
// height h > 0 above p, 2-D coordinates centred on p's foot point: the sum
// of arc_contour over visible_boundary. For parallel occluder disks of
// radius ρ at height h_o ∈ (0, h) centred at in-plane offset c (from p's
// foot), the occluder image is the circle of centre c·h/h_o, radius ρ·h/h_o
// (central projection from p between parallel planes is a homothety).
// Returns exactly 0 when the occluders cover the light (no arcs survive).
// With no occluder it returns disk_irradiance_parallel exactly.
double occluded_disk_irradiance(double h, const Circle2& light, const std::vector<Circle2>& occluders);

// ∫_A f(s) dA over the region bounded by `arcs`, for any radial density f
// about the origin (the foot point), by the same Green's-theorem step as
// arc_contour: ∫_A f dA = ∮ G(s) dφ with G(s) = ∫₀^s f(s')·s' ds'. The caller
// passes G(s)/s² as a function of s² (finite at s = 0, so arcs through the
// foot point are harmless); along an arc, s²·dφ = r·(r + cx cos t + cy sin t) dt.
// Each arc is integrated by adaptive Gauss–Kronrod (61 points, relative
// tolerance 1e-14 of the arc's |integrand| integral, depth ≤ 10).
// Returns exactly 0 for an empty boundary.
double contour_quadrature(const std::vector<Arc>& arcs, const std::function<double(double)>& g_over_s2);

}  // namespace furnace::analytic
