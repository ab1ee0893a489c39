// The one CGAL translation unit of analytic/ (≈30 CPU-s and 1.3 GiB to
// compile): exact Boolean set operations on circle–segment polygons.
#include "analytic/exact_region.h"

#include <cmath>
#include <iterator>
#include <string>

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/General_polygon_set_2.h>
#include <CGAL/Gps_circle_segment_traits_2.h>
#include <CGAL/Polygon_2.h>

#include "core/error.h"
#include "core/vec3.h"

namespace furnace::analytic {

namespace {

using Kernel = CGAL::Exact_predicates_exact_constructions_kernel;
using Traits = CGAL::Gps_circle_segment_traits_2<Kernel>;
using Polygon = Traits::General_polygon_2;
using PolygonWithHoles = Traits::General_polygon_with_holes_2;
using PolygonSet = CGAL::General_polygon_set_2<Traits>;
using Curve = Traits::Curve_2;
using XCurve = Traits::X_monotone_curve_2;

// Splits a curve into x-monotone pieces (directed as the curve) and appends them.
void append_pieces(const Curve& curve, Polygon& polygon) {
  std::vector<boost::variant<Traits::Point_2, XCurve>> pieces;
  Traits().make_x_monotone_2_object()(curve, std::back_inserter(pieces));
  for (const auto& piece : pieces)
    if (const XCurve* x = boost::get<XCurve>(&piece)) polygon.push_back(*x);
}

// A counter-clockwise CGAL polygon for a region (circles are counter-clockwise
// by default in Kernel::Circle_2).
Polygon to_cgal(const Region2& region) {
  Polygon polygon;
  if (region.circle) {
    const Circle2& c = *region.circle;
    if (!(c.radius > 0)) throw Error("exact_visible_boundary: a circle needs a radius > 0.");
    // Squared radius formed exactly from the double radius.
    const Kernel::FT r(c.radius);
    append_pieces(Curve(Kernel::Circle_2(Kernel::Point_2(c.cx, c.cy), r * r)), polygon);
    return polygon;
  }
  std::vector<Point2> v = region.polygon;
  const double area = signed_area(v);
  if (v.size() < 3 || !(std::fabs(area) > 0))
    throw Error("exact_visible_boundary: a polygon needs at least 3 vertices and a non-zero area.");
  if (area < 0) std::reverse(v.begin(), v.end());
  // The Booleans require simple polygons (a violated precondition is
  // undefined behaviour in a release build): check exactly, refuse otherwise.
  CGAL::Polygon_2<Kernel> outline;
  for (const Point2& q : v) outline.push_back(Kernel::Point_2(q.x, q.y));
  if (!outline.is_simple())
    throw Error("exact_visible_boundary: a projected polygon is not simple (self-intersecting or with repeated vertices).");
  for (size_t i = 0; i < v.size(); ++i) {
    const Point2& a = v[i];
    const Point2& b = v[(i + 1) % v.size()];
    if (a.x == b.x && a.y == b.y) continue;  // repeated vertex
    append_pieces(Curve(Kernel::Point_2(a.x, a.y), Kernel::Point_2(b.x, b.y)), polygon);
  }
  return polygon;
}

// The half-plane clipped to a box around the light: a convex polygon.
Region2 half_plane_box(const HalfPlane2& keep, const Region2& light) {
  double x_lo = INFINITY, x_hi = -INFINITY, y_lo = INFINITY, y_hi = -INFINITY;
  if (light.circle) {
    const Circle2& c = *light.circle;
    x_lo = c.cx - c.radius, x_hi = c.cx + c.radius, y_lo = c.cy - c.radius, y_hi = c.cy + c.radius;
  }
  for (const Point2& p : light.polygon) {
    x_lo = std::fmin(x_lo, p.x), x_hi = std::fmax(x_hi, p.x);
    y_lo = std::fmin(y_lo, p.y), y_hi = std::fmax(y_hi, p.y);
  }
  // Grow the box so that its edges stay well away from the light.
  const double margin = 2 * std::fmax(x_hi - x_lo, y_hi - y_lo);
  const std::vector<Point2> box{{x_lo - margin, y_lo - margin}, {x_hi + margin, y_lo - margin},
                                {x_hi + margin, y_hi + margin}, {x_lo - margin, y_hi + margin}};
  Region2 clipped;
  auto side = [&](const Point2& p) { return keep.a * p.x + keep.b * p.y + keep.c; };
  for (size_t i = 0; i < box.size(); ++i) {
    const Point2& a = box[i];
    const Point2& b = box[(i + 1) % box.size()];
    const double sa = side(a), sb = side(b);
    if (sa >= 0) clipped.polygon.push_back(a);
    if ((sa > 0 && sb < 0) || (sa < 0 && sb > 0)) {
      const double t = sa / (sa - sb);
      clipped.polygon.push_back({a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)});
    }
  }
  return clipped;
}

Point2 to_double(const Traits::Point_2& p) { return {CGAL::to_double(p.x()), CGAL::to_double(p.y())}; }

Curve2 to_curve2(const XCurve& x) {
  Curve2 out;
  out.start = to_double(x.source());
  out.end = to_double(x.target());
  if (x.is_linear()) return out;
  out.is_arc = true;
  const Kernel::Circle_2 circle = x.supporting_circle();
  out.circle = {CGAL::to_double(circle.center().x()), CGAL::to_double(circle.center().y()),
                std::sqrt(CGAL::to_double(circle.squared_radius()))};
  out.t0 = std::atan2(out.start.y - out.circle.cy, out.start.x - out.circle.cx);
  const double t1 = std::atan2(out.end.y - out.circle.cy, out.end.x - out.circle.cx);
  // x-monotone arcs span at most half a turn, so the angle difference reduced
  // to [−π, π] is the sweep up to the turn's sign: a counter-clockwise arc
  // reduced below −π/2 is a half circle that rounding pushed across ±π (and a
  // tiny arc may come out as a tiny negative sweep, which is its true length
  // within rounding).
  const double d = std::remainder(t1 - out.t0, 2 * kPi);
  if (x.orientation() == CGAL::COUNTERCLOCKWISE)
    out.sweep = d < -kPi / 2 ? d + 2 * kPi : d;
  else
    out.sweep = d > kPi / 2 ? d - 2 * kPi : d;
  return out;
}

void append_boundary(const Polygon& polygon, std::vector<Curve2>& out) {
  for (auto it = polygon.curves_begin(); it != polygon.curves_end(); ++it) out.push_back(to_curve2(*it));
}

}  // namespace

std::vector<Curve2> exact_visible_boundary(const Region2& light, const std::vector<Region2>& occluders,
                                           const std::optional<HalfPlane2>& keep) {
  PolygonSet set;
  set.insert(to_cgal(light));
  if (keep) set.intersection(to_cgal(half_plane_box(*keep, light)));
  for (const Region2& o : occluders) set.difference(to_cgal(o));
  std::vector<PolygonWithHoles> parts;
  set.polygons_with_holes(std::back_inserter(parts));
  std::vector<Curve2> boundary;
  for (const PolygonWithHoles& part : parts) {
    append_boundary(part.outer_boundary(), boundary);
    for (auto hole = part.holes_begin(); hole != part.holes_end(); ++hole) append_boundary(*hole, boundary);
  }
  return boundary;
}

double signed_area(const std::vector<Point2>& v) {
  double twice = 0;
  for (size_t i = 0; i < v.size(); ++i) {
    const Point2& a = v[i];
    const Point2& b = v[(i + 1) % v.size()];
    twice += a.x * b.y - a.y * b.x;
  }
  return 0.5 * twice;
}

}  // namespace furnace::analytic
