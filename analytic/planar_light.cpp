#include "analytic/planar_light.h"

#include <cmath>
#include <functional>
#include <string>
#include <variant>

#include <boost/math/quadrature/gauss_kronrod.hpp>

#include "analytic/contour_area_kernel.h"
#include "analytic/disk.h"
#include "analytic/disk_light.h"
#include "analytic/error_ledger.h"
#include "analytic/occlusion.h"
#include "analytic/polygon.h"
#include "analytic/small_emitter.h"
#include "analytic/unsupported.h"
#include "core/adaptive_quadrature.h"

namespace furnace::analytic {

namespace {

// ∫_lo^hi f along a boundary piece to 1e-14 relative, at most 10 bisection
// levels; `error` (added to) receives the error estimate in the integral's
// units. Boost 1.74's own recursive Gauss–Kronrod returns its leaves'
// estimates for the rule mapped to [−1, 1], π times too small on a full arc.
template <class F>
double contour_piece(const F& f, double lo, double hi, double* error) {
  return adaptive_gauss_kronrod_relative<61>(f, lo, hi, 1e-14, 10, 1, kUnlimitedBisections, error);
}

// As in disk_light.cpp: |n₁ × n₂| below this counts as parallel.
constexpr double kParallelSine = 1e-12;

std::vector<Vec3> polygon_vertices(const Rectangle& r) {
  return {r.corner, r.corner + r.edge_u, r.corner + r.edge_u + r.edge_v, r.corner + r.edge_v};
}
std::vector<Vec3> polygon_vertices(const Triangle& t) { return {t.p0, t.p1, t.p2}; }

// The part of a polygon with height z(x) = dot(x − p, w) ≤ h (Sutherland–Hodgman).
std::vector<Vec3> clip_below(const std::vector<Vec3>& v, const Vec3& p, const Vec3& w, double h) {
  std::vector<Vec3> out;
  for (size_t i = 0; i < v.size(); ++i) {
    const Vec3& a = v[i];
    const Vec3& b = v[(i + 1) % v.size()];
    const double da = h - dot(a - p, w), db = h - dot(b - p, w);
    if (da >= 0) out.push_back(a);
    if ((da > 0 && db < 0) || (da < 0 && db > 0)) out.push_back(a + (b - a) * (da / (da - db)));
  }
  return out;
}

// The part of a polygon on the side of the plane through p and the points a,
// b (all in world space) that contains `inside` (Sutherland–Hodgman).
std::vector<Vec3> clip_by_plane_through_p(const std::vector<Vec3>& v, const Vec3& p, const Vec3& a, const Vec3& b,
                                          const Vec3& inside) {
  Vec3 m = cross(a - p, b - p);
  if (dot(m, inside - p) < 0) m = -m;
  std::vector<Vec3> out;
  for (size_t i = 0; i < v.size(); ++i) {
    const Vec3& x = v[i];
    const Vec3& y = v[(i + 1) % v.size()];
    const double dx = dot(m, x - p), dy = dot(m, y - p);
    if (dx >= 0) out.push_back(x);
    if ((dx > 0 && dy < 0) || (dx < 0 && dy > 0)) out.push_back(x + (y - x) * (dx / (dx - dy)));
  }
  return out;
}

// Relative size below which a projected occluder counts as a sliver.
constexpr double kSliverArea = 1e-12;

// Drops points within `tolerance` of their predecessor (cyclically).
std::vector<Point2> without_repeats(const std::vector<Point2>& v, double tolerance) {
  std::vector<Point2> out;
  for (const Point2& q : v)
    if (out.empty() || std::hypot(q.x - out.back().x, q.y - out.back().y) > tolerance) out.push_back(q);
  while (out.size() > 1 && std::hypot(out.front().x - out.back().x, out.front().y - out.back().y) <= tolerance)
    out.pop_back();
  return out;
}

}  // namespace

double contour_irradiance(const Vec3& origin, const Vec3& e1, const Vec3& e2, const std::vector<Curve2>& boundary,
                          const Vec3& p, const Vec3& n) {
  auto world = [&](double x, double y) { return origin + e1 * x + e2 * y - p; };  // relative to p
  double sum = 0, error = 0;
  for (const Curve2& c : boundary) {
    if (!c.is_arc) {
      // Lambert's edge term Θ·(n·unit(a × b)), Θ by atan2.
      const Vec3 a = world(c.start.x, c.start.y), b = world(c.end.x, c.end.y);
      const Vec3 axb = cross(a, b - a);  // = a × b, accurate when a ∥ b
      const double len = length(axb);
      if (len > 0) sum += std::atan2(len, dot(a, b)) * (dot(n, axb) / len);
      continue;
    }
    const Circle2& k = c.circle;
    auto integrand = [&](double t) {
      const double ct = std::cos(t), st = std::sin(t);
      const Vec3 x = world(k.cx + k.radius * ct, k.cy + k.radius * st);
      const Vec3 dx = (e2 * ct - e1 * st) * k.radius;
      return dot(n, cross(x, dx)) / length_squared(x);
    };
    const double lo = std::fmin(c.t0, c.t0 + c.sweep), hi = std::fmax(c.t0, c.t0 + c.sweep);
    double arc_error = 0;
    const double value = contour_piece(integrand, lo, hi, &arc_error);
    sum += c.sweep >= 0 ? value : -value;
    error += arc_error;
  }
  const double result = 0.5 * std::fabs(sum);
  ErrorLedger::report(0.5 * error, result);
  return result;
}

namespace {

// Everything the planar references need: the light plane's frame (origin at
// p's foot), p's height above it, the light, occluder images and horizon
// half-plane in 2-D. `visible` is false when nothing of the light reaches p.
struct PlanarSetup {
  bool visible = false;
  const Disk* disk = nullptr;
  std::vector<Vec3> light_vertices;
  Vec3 front, foot;
  Frame frame;
  double h = 0;
  Region2 light_region;
  std::vector<Region2> occluders;
  std::optional<HalfPlane2> keep;
};

PlanarSetup setup_planar(const Scene& scene, size_t light_index, const Vec3& p, const Vec3& n,
                         std::optional<size_t> receiver) {
  PlanarSetup out;
  const Object& light = scene.objects[light_index];
  // The light as a disk or a polygon (its vertices).
  const Disk* disk = nullptr;
  std::vector<Vec3> light_vertices;
  std::visit(overloaded{[&](const Disk& d) { disk = &d; },
                        [&](const Sphere&) {
                          unsupported_configuration(scene, "the sphere light '" + light.name + "' on the planar-light path");
                        },
                        [&](const Rectangle& r) { light_vertices = polygon_vertices(r); },
                        [&](const Triangle& t) { light_vertices = polygon_vertices(t); }},
             light.shape);

  // Emitting face towards p, height h of p above the light's plane.
  const Vec3 on_light = disk ? disk->center : light_vertices[0];
  Vec3 front = disk ? normalize(disk->normal)
                    : normalize(cross(light_vertices[1] - light_vertices[0], light_vertices[2] - light_vertices[0]));
  double h = dot(p - on_light, front);
  if (h < 0 && light.two_sided) front = -front, h = -h;
  if (!(h > 0)) return out;
  const ZRange over_horizon = height_range(light.shape, p, n);
  if (over_horizon.hi <= 0) return out;

  // 2-D frame of the light plane, origin at p's foot point.
  const Vec3 w = -front;
  const Frame frame = Frame::from_normal(front);
  const Vec3 foot = p - front * h;
  auto to_2d = [&](const Vec3& x) { return Point2{dot(x - foot, frame.s), dot(x - foot, frame.t)}; };

  Region2 light_region;
  if (disk) {
    const Point2 c = to_2d(disk->center);
    light_region.circle = Circle2{c.x, c.y, disk->radius};
  } else {
    for (const Vec3& v : light_vertices) light_region.polygon.push_back(to_2d(v));
  }
  std::optional<HalfPlane2> keep;
  if (over_horizon.lo < 0) keep = HalfPlane2{dot(n, frame.s), dot(n, frame.t), dot(n, foot - p)};

  std::vector<Region2> occluders;
  const BoundingSphere light_ball = bounding_sphere(light.shape);
  // The light's bounding square in its plane (world space) and its centre.
  double x_lo = INFINITY, x_hi = -INFINITY, y_lo = INFINITY, y_hi = -INFINITY;
  if (light_region.circle) {
    const Circle2& c = *light_region.circle;
    x_lo = c.cx - c.radius, x_hi = c.cx + c.radius, y_lo = c.cy - c.radius, y_hi = c.cy + c.radius;
  }
  for (const Point2& q : light_region.polygon) {
    x_lo = std::fmin(x_lo, q.x), x_hi = std::fmax(x_hi, q.x);
    y_lo = std::fmin(y_lo, q.y), y_hi = std::fmax(y_hi, q.y);
  }
  auto world = [&](double x, double y) { return foot + frame.s * x + frame.t * y; };
  const Vec3 pyramid[4] = {world(x_lo, y_lo), world(x_hi, y_lo), world(x_hi, y_hi), world(x_lo, y_hi)};
  const Vec3 light_centre = world(0.5 * (x_lo + x_hi), 0.5 * (y_lo + y_hi));
  const double light_extent = std::fmax(x_hi - x_lo, y_hi - y_lo);
  const double light_square_area = light_extent * light_extent;
  for (size_t j = 0; j < scene.objects.size(); ++j) {
    if (j == light_index || (receiver && j == *receiver)) continue;
    const Object& object = scene.objects[j];
    if (height_range(object.shape, p, n).hi <= 0) continue;  // wholly below the horizon
    const ZRange z = height_range(object.shape, p, w);
    if (z.hi <= 0 || z.lo >= h) continue;  // behind p's parallel plane or beyond the light's
    if (!ball_may_meet_ball_cone(bounding_sphere(object.shape), p, light_ball)) continue;
    // The occluder as a disk or a polygon (its vertices); neither for a sphere.
    const Disk* occluder_disk = nullptr;
    std::vector<Vec3> occluder_vertices;
    std::visit(overloaded{[&](const Disk& d) { occluder_disk = &d; }, [](const Sphere&) {},
                          [&](const Rectangle& r) { occluder_vertices = polygon_vertices(r); },
                          [&](const Triangle& t) { occluder_vertices = polygon_vertices(t); }},
               object.shape);
    if (occluder_disk && length(cross(normalize(occluder_disk->normal), front)) <= kParallelSine) {
      const double scale = h / dot(occluder_disk->center - p, w);
      const Point2 c = to_2d(p + (occluder_disk->center - p) * scale);
      occluders.push_back({{}, Circle2{c.x, c.y, occluder_disk->radius * scale}});
      continue;
    }
    if (!occluder_vertices.empty()) {
      // Keep only the part inside the pyramid from p over the light's bounding
      // square (it contains every segment from p to the light, so the rest
      // blocks nothing); its only point at p's height is p itself, so an
      // occluder standing on the receiver plane away from p projects to a
      // bounded polygon.
      std::vector<Vec3> clipped = clip_below(occluder_vertices, p, w, h);
      for (int k = 0; k < 4 && clipped.size() >= 3; ++k)
        clipped = clip_by_plane_through_p(clipped, p, pyramid[k], pyramid[(k + 1) % 4], light_centre);
      if (clipped.size() < 3) continue;  // outside the pyramid: blocks nothing
      Region2 image;
      bool in_front = clipped.size() >= 3;
      for (const Vec3& v : clipped) {
        const double zv = dot(v - p, w);
        in_front = in_front && zv > 0;
        if (in_front) image.polygon.push_back(to_2d(p + (v - p) * (h / zv)));
      }
      if (!in_front)
        unsupported_configuration(scene, "object '" + object.name + "', which touches the receiving point while it may block the light '" +
                                             light.name + "',");
      // Slivers: an occluder that only touches the pyramid (a wall sharing an
      // edge with the light, as in a closed box) leaves a polygon of zero or
      // rounding-level area, which would violate the Booleans' simplicity
      // precondition. Drop repeated points and polygons of area below
      // kSliverArea of the light's bounding square; the light they could
      // hide is at most that fraction of its area.
      image.polygon = without_repeats(image.polygon, kSliverArea * light_extent);
      if (image.polygon.size() < 3 || std::fabs(signed_area(image.polygon)) <= kSliverArea * light_square_area) continue;
      occluders.push_back(image);
      continue;
    }
    unsupported_configuration(scene, "object '" + object.name + "' (a sphere or a tilted disk) which may block the light '" +
                                         light.name + "'");
  }

  out.visible = true;
  out.disk = disk;
  out.light_vertices = light_vertices;
  out.front = front;
  out.foot = foot;
  out.frame = frame;
  out.h = h;
  out.light_region = light_region;
  out.occluders = occluders;
  out.keep = keep;
  return out;
}

}  // namespace

double planar_light_irradiance(const Scene& scene, size_t light_index, const Vec3& p, const Vec3& n,
                               std::optional<size_t> receiver) {
  const PlanarSetup setup = setup_planar(scene, light_index, p, n, receiver);
  if (!setup.visible) return 0.0;
  if (setup.occluders.empty()) {
    // Closed forms: Lambert for polygons (clipped to the horizon, small ones
    // by the area rule); Howell's disk when n is parallel to the light.
    if (!setup.disk) {
      std::vector<Vec3> relative;
      for (const Vec3& v : setup.light_vertices) relative.push_back(v - p);
      return polygon_irradiance(relative, n);
    }
    if (!setup.keep && length(cross(n, setup.front)) <= kParallelSine) {
      const Circle2& c = *setup.light_region.circle;
      return disk_irradiance_parallel(c.radius, setup.h, std::hypot(c.cx, c.cy));
    }
    // A small tilted disk, horizon-clipped or not: the arc integral's terms
    // would cancel; the area rule keeps every digit (small_emitter.h).
    const Vec3 center = setup.disk->center - p;
    const double R = setup.disk->radius;
    if (R <= kSmallAngle * (length(center) - R)) return small_disk_irradiance(center, setup.front, R, n);
  }
  const std::vector<Curve2> boundary = exact_visible_boundary(setup.light_region, setup.occluders, setup.keep);
  return contour_irradiance(setup.foot, setup.frame.s, setup.frame.t, boundary, p, n);
}

double planar_light_cos2_solid_angle(const Scene& scene, size_t light_index, const Vec3& p, const Vec3& n,
                                     std::optional<size_t> receiver) {
  const PlanarSetup setup = setup_planar(scene, light_index, p, n, receiver);
  if (!setup.visible) return 0.0;
  const std::vector<Curve2> boundary = exact_visible_boundary(setup.light_region, setup.occluders, setup.keep);
  const Vec3 &e1 = setup.frame.s, &e2 = setup.frame.t;
  const double h = setup.h;
  // Each boundary piece as x(t) (relative to p) and dx/dt, t ∈ [lo, hi], with its direction sign.
  double sigma = 0, first = 0, second = 0, error = 0;
  for (const Curve2& c : boundary) {
    std::function<Vec3(double)> x_of, dx_of;
    std::function<Point2(double)> q_of, dq_of;  // plane coordinates and derivative
    double lo = 0, hi = 1, sign = 1;
    if (c.is_arc) {
      const Circle2 k = c.circle;
      q_of = [k](double t) { return Point2{k.cx + k.radius * std::cos(t), k.cy + k.radius * std::sin(t)}; };
      dq_of = [k](double t) { return Point2{-k.radius * std::sin(t), k.radius * std::cos(t)}; };
      lo = std::fmin(c.t0, c.t0 + c.sweep), hi = std::fmax(c.t0, c.t0 + c.sweep);
      sign = c.sweep >= 0 ? 1 : -1;
    } else {
      const Point2 a = c.start, b = c.end;
      q_of = [a, b](double t) { return Point2{a.x + (b.x - a.x) * t, a.y + (b.y - a.y) * t}; };
      dq_of = [a, b](double) { return Point2{b.x - a.x, b.y - a.y}; };
    }
    auto x = [&](double t) { const Point2 q = q_of(t); return setup.foot + e1 * q.x + e2 * q.y - p; };
    auto dx = [&](double t) { const Point2 d = dq_of(t); return e1 * d.x + e2 * d.y; };
    // σ: Green's theorem about the foot point, G(s)/s² = 1/(r(r + h)), s²dφ = q × q'.
    auto sigma_integrand = [&](double t) {
      const Point2 q = q_of(t), d = dq_of(t);
      const double r = std::hypot(h, std::hypot(q.x, q.y));
      return (q.x * d.y - q.y * d.x) / (r * (r + h));
    };
    // First moment ½ n·(x × dx)/|x|² (its sign orients the boundary) and the
    // second-moment boundary term (n·u)·n·(x × dx)/|x|².
    auto first_integrand = [&](double t) { const Vec3 xt = x(t); return dot(n, cross(xt, dx(t))) / length_squared(xt); };
    auto second_integrand = [&](double t) {
      const Vec3 xt = x(t);
      return dot(n, xt) / length(xt) * dot(n, cross(xt, dx(t))) / length_squared(xt);
    };
    double e_sigma = 0, e_first = 0, e_second = 0;
    sigma += sign * contour_piece(sigma_integrand, lo, hi, &e_sigma);
    first += sign * contour_piece(first_integrand, lo, hi, &e_first);
    second += sign * contour_piece(second_integrand, lo, hi, &e_second);
    error += e_sigma + e_second;
  }
  const double s = first >= 0 ? 1.0 : -1.0;
  const double result = (std::fabs(sigma) + s * second) / 3;
  ErrorLedger::report(error / 3, result);
  return result;
}

namespace {

// Whether q lies inside the simple polygon v (crossing number).
bool inside_polygon(const std::vector<Point2>& v, Point2 q) {
  bool inside = false;
  for (size_t i = 0, j = v.size() - 1; i < v.size(); j = i++) {
    if ((v[i].y > q.y) != (v[j].y > q.y) &&
        q.x < v[j].x + (v[i].x - v[j].x) * (q.y - v[j].y) / (v[i].y - v[j].y))
      inside = !inside;
  }
  return inside;
}

bool inside_region(const Region2& region, Point2 q) {
  if (region.circle) return std::hypot(q.x - region.circle->cx, q.y - region.circle->cy) < region.circle->radius;
  return inside_polygon(region.polygon, q);
}

}  // namespace

double planar_light_area_kernel(const Scene& scene, size_t light_index, const Vec3& p, const Vec3& n,
                                std::optional<size_t> receiver) {
  const PlanarSetup setup = setup_planar(scene, light_index, p, n, receiver);
  if (!setup.visible) return 0.0;
  if (setup.disk && setup.occluders.empty()) {
    const Vec3 center = setup.disk->center - p;
    const double R = setup.disk->radius;
    if (R <= kSmallAngle * (length(center) - R)) return small_disk_area_kernel(center, setup.front, R, n);
  }
  const std::vector<Curve2> boundary = exact_visible_boundary(setup.light_region, setup.occluders, setup.keep);
  if (boundary.empty()) return 0.0;
  // The foot point F is the origin of the plane coordinates; x − p = F − p + qx·e1 + qy·e2, F − p = −h·front.
  const Point2 foot{0, 0};
  bool foot_inside = inside_region(setup.light_region, foot) && (!setup.keep || setup.keep->c >= 0);
  for (const Region2& o : setup.occluders) foot_inside = foot_inside && !inside_region(o, foot);
  // Magnitude of the world coordinates the plane coordinates were computed from.
  const BoundingSphere ball = bounding_sphere(scene.objects[light_index].shape);
  const double scale = std::fmax(max_abs_component(p), max_abs_component(ball.center) + ball.radius);
  return contour_area_kernel(boundary, setup.h, -setup.h * dot(n, setup.front), dot(n, setup.frame.s),
                             dot(n, setup.frame.t), foot_inside, scale);
}

Scene as_lone_unit_emitter(const Scene& scene, size_t object) {
  Scene alone;
  alone.name = scene.name;
  alone.source = scene.source;
  alone.objects.push_back(scene.objects[object]);
  alone.objects.back().emitted_radiance = 1;
  alone.objects.back().two_sided = true;
  return alone;
}

}  // namespace furnace::analytic
