// Exact 2-D Boolean operations on the regions that appear in a light's plane
// (the light, its horizon half-plane, the central projections of occluders),
// returning the visible region's boundary as oriented segments and circle
// arcs in double precision. The only interface to CGAL: the implementation
// (exact_region.cpp, the one CGAL translation unit) uses the exact kernel
// (Exact_predicates_exact_constructions_kernel) with the circle–segment
// traits of 2D Regularized Boolean Set-Operations, so the combinatorics
// (which arcs bound the region, where they meet) are exact for the
// double-precision inputs; only the final conversion of the (one-root)
// vertex coordinates to double rounds.
#pragma once

#include <optional>
#include <vector>

#include "analytic/disk.h"

namespace furnace::analytic {

struct Point2 {
  double x = 0, y = 0;
};

// Signed area of a simple polygon (shoelace): positive when counter-clockwise.
double signed_area(const std::vector<Point2>& v);

// A simple polygon (either winding) or, when `circle` is set, a disk.
struct Region2 {
  std::vector<Point2> polygon;
  std::optional<Circle2> circle;
};

// The closed half-plane a·x + b·y + c ≥ 0.
struct HalfPlane2 {
  double a = 0, b = 0, c = 0;
};

// One piece of a positively oriented boundary (outer boundaries
// counter-clockwise, holes clockwise): a segment start → end, or an arc of
// `circle` from angle t0 through the signed sweep (|sweep| ≤ π for CGAL's
// x-monotone pieces), start and end being its end points.
struct Curve2 {
  bool is_arc = false;
  Point2 start, end;
  Circle2 circle;
  double t0 = 0, sweep = 0;
};

// Boundary of (light ∩ keep) \ ∪ occluders. `keep` (optional) is clipped as
// a large convex polygon covering the light's bounding box four times over.
// Empty when nothing is visible. Throws furnace::Error for degenerate input
// (a polygon with fewer than 3 vertices, zero area or not simple — checked
// with exact predicates — or a circle of radius ≤ 0).
std::vector<Curve2> exact_visible_boundary(const Region2& light, const std::vector<Region2>& occluders,
                                           const std::optional<HalfPlane2>& keep);

}  // namespace furnace::analytic
