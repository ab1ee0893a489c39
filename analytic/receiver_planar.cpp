// Planar lights in the receiver model (receiver_planar.h): the visible region
// and its polar decomposition.
#include "analytic/receiver_planar.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <variant>

#include "analytic/light_moments.h"
#include "analytic/occlusion.h"
#include "analytic/unsupported.h"
#include "core/error.h"
#include "core/strategy.h"

namespace furnace::analytic {

namespace {

// |n₁ × n₂| below this counts as parallel (as planar_light.cpp and
// disk_light.cpp): an occluder disk tilted by less projects to a circle
// within rounding.
constexpr double kParallelSine = 1e-12;

// A mirror hit farther than this many region sizes from the region's box
// centre is no peak the region resolves (the lobe's tail is smooth at the
// region's scale there): polar coordinates about a point at distance L
// squeeze the region into an angle ~size/L, and the nodes' positions
// x = C + ρ·(cos φ, sin φ) carry round-off ~ε·L, a relative error ~ε·L/size
// in every value. At 1e3 (before) a disk of radius 0.02 at height 2 seen by
// a GGX receiver at α = 1, μo = 0.05 (hit 950 radii away) was off by 2.9e-13
// against 50-digit values (tests/analytic/ggx_precision_test.cpp); at 2
// the amplification is a few ε.
constexpr double kFarCentre = 2;

// The light's corners (rectangles, triangles) in order around it.
std::vector<Vec3> corners(const Shape& shape) {
  return std::visit(overloaded{[](const Rectangle& r) {
                                 const auto c = r.corners();
                                 return std::vector<Vec3>(c.begin(), c.end());
                               },
                               [](const Triangle& t) { return std::vector<Vec3>{t.p0, t.p1, t.p2}; },
                               [](const Disk&) { return std::vector<Vec3>{}; },
                               [](const Sphere&) { return std::vector<Vec3>{}; }},
                    shape);
}

// Ω the renderer's light_solid_angle strategy samples uniformly, else 0 (by
// area): its contract in core/strategy.h, as light_solid_angle_moments.cpp.
double sampled_solid_angle(const Shape& shape, const Vec3& p) {
  const bool spherical_map = std::visit(
      overloaded{[](const Rectangle& r) {
                   return std::fabs(dot(r.edge_u, r.edge_v)) <=
                          kPerpendicularTolerance * length(r.edge_u) * length(r.edge_v);
                 },
                 [](const Triangle&) { return true; }, [](const Disk&) { return false; },
                 [](const Sphere&) { return false; }},
      shape);
  if (!spherical_map) return 0;
  std::vector<Vec3> relative;
  for (const Vec3& v : corners(shape)) relative.push_back(v - p);
  const double omega = polygon_solid_angle(relative);
  return omega >= kMinSampledSolidAngle ? omega : 0.0;
}

// The angle of (x, y), and the angle reduced into [base, base + 2π).
double reduce(double angle, double base) {
  const double offset = angle - base;
  return base + (offset - 2 * kPi * std::floor(offset / (2 * kPi)));
}

}  // namespace

bool above_horizon(const Object& object, const Vec3& p, const Vec3& n) {
  const BoundingSphere ball = bounding_sphere(object.shape);
  const double round_off = kCoplanarTolerance * (ball.radius + length(ball.center - p));
  return height_range(object.shape, p, n).hi > round_off;
}

std::optional<PlanarEmitter> planar_emitter(const Scene& scene, size_t light_index, const Vec3& p, const Vec3& n,
                                            size_t receiver, const std::string& who) {
  const Object& light = scene.objects[light_index];
  const std::optional<Plane> plane = plane_of(light.shape);
  FURNACE_CHECK(plane.has_value());
  Vec3 front = normalize(plane->normal);
  double h = dot(p - plane->point, front);
  if (h < 0 && light.two_sided) front = -front, h = -h;
  if (!(h > 0)) return std::nullopt;  // behind its emitting face, or in its plane
  if (!above_horizon(light, p, n)) return std::nullopt;
  const ZRange over_horizon = height_range(light.shape, p, n);

  PlanarEmitter out;
  const Frame frame = Frame::from_normal(front);
  out.s = frame.s, out.t = frame.t, out.toward_receiver = front, out.height = h;
  const Vec3 foot = p - front * h;
  auto to_2d = [&](const Vec3& x) { return Point2{dot(x - foot, frame.s), dot(x - foot, frame.t)}; };

  Region2 region;
  if (const auto* disk = std::get_if<Disk>(&light.shape)) {
    const Point2 c = to_2d(disk->center);
    region.circle = Circle2{c.x, c.y, disk->radius};
  }
  for (const Vec3& v : corners(light.shape)) region.polygon.push_back(to_2d(v));
  std::optional<HalfPlane2> keep;
  if (over_horizon.lo < 0) keep = HalfPlane2{dot(n, frame.s), dot(n, frame.t), -h * dot(n, front)};

  // Occluders: parallel disks strictly between p and the light's plane.
  const Vec3 w = -front;
  const BoundingSphere light_ball = bounding_sphere(light.shape);
  std::vector<Region2> occluders;
  for (size_t j = 0; j < scene.objects.size(); ++j) {
    if (j == light_index || j == receiver) continue;
    const Object& object = scene.objects[j];
    if (!above_horizon(object, p, n)) continue;  // below the horizon, or in its plane
    const ZRange z = height_range(object.shape, p, w);
    if (z.hi <= 0 || z.lo >= h) continue;  // behind p's parallel plane or beyond the light's
    if (!ball_may_meet_ball_cone(bounding_sphere(object.shape), p, light_ball)) continue;
    const auto* disk = std::get_if<Disk>(&object.shape);
    if (disk && length(cross(normalize(disk->normal), front)) <= kParallelSine && z.lo > 0 && z.hi < h) {
      const double scale = h / dot(disk->center - p, w);
      const Point2 c = to_2d(p + (disk->center - p) * scale);
      occluders.push_back({{}, Circle2{c.x, c.y, disk->radius * scale}});
      continue;
    }
    unsupported_configuration(scene, "the object '" + object.name + "', which may block the light '" + light.name +
                                         "' seen from " + who +
                                         " (only disks parallel to a planar light, strictly between, are solved)");
  }
  out.boundary = exact_visible_boundary(region, occluders, keep);
  if (out.boundary.empty()) return std::nullopt;
  out.area = shape_area(light.shape);
  out.solid_angle = sampled_solid_angle(light.shape, p);
  return out;
}

Point2 polar_centre(const PlanarEmitter& light, const Vec3& r) {
  double x_lo = INFINITY, x_hi = -INFINITY, y_lo = INFINITY, y_hi = -INFINITY;
  auto grow = [&](double x0, double x1, double y0, double y1) {
    x_lo = std::fmin(x_lo, x0), x_hi = std::fmax(x_hi, x1), y_lo = std::fmin(y_lo, y0), y_hi = std::fmax(y_hi, y1);
  };
  for (const Curve2& c : light.boundary) {
    grow(c.start.x, c.start.x, c.start.y, c.start.y);
    if (c.is_arc) grow(c.circle.cx - c.circle.radius, c.circle.cx + c.circle.radius, c.circle.cy - c.circle.radius,
                       c.circle.cy + c.circle.radius);
  }
  const Point2 box_centre{0.5 * (x_lo + x_hi), 0.5 * (y_lo + y_hi)};
  const double size = std::fmax(x_hi - x_lo, y_hi - y_lo);
  const double toward_plane = -dot(r, light.toward_receiver);
  if (!(toward_plane > 0)) return box_centre;
  const double t = light.height / toward_plane;
  const Point2 hit{dot(r, light.s) * t, dot(r, light.t) * t};
  if (!(std::hypot(hit.x - box_centre.x, hit.y - box_centre.y) <= kFarCentre * size)) return box_centre;
  return hit;
}

PolarRegion::PolarRegion(const std::vector<Curve2>& boundary, const Point2& centre)
    : boundary_(boundary), centre_(centre) {
  const double cx = centre.x, cy = centre.y;
  std::vector<double> raw;
  auto direction_of = [&](double x, double y) { raw.push_back(std::atan2(y - cy, x - cx)); };
  for (const Curve2& c : boundary) {
    direction_of(c.start.x, c.start.y);
    direction_of(c.end.x, c.end.y);
    if (!c.is_arc) {
      // The segment's own direction, both ways: where a ray from a centre
      // close to its line turns from crossing it near to crossing it far.
      const double along = std::atan2(c.end.y - c.start.y, c.end.x - c.start.x);
      raw.push_back(along), raw.push_back(along + kPi);
      continue;
    }
    // An arc's circle: the tangents from C (C outside it), and the
    // directions of its tangent at the point nearest C.
    const double dx = c.circle.cx - cx, dy = c.circle.cy - cy, D = std::hypot(dx, dy);
    const double toward = std::atan2(dy, dx);
    raw.push_back(toward + kPi / 2), raw.push_back(toward - kPi / 2);
    if (D > c.circle.radius) {
      const double half = std::asin(c.circle.radius / D);
      raw.push_back(toward + half), raw.push_back(toward - half);
    }
  }
  const double base = raw.empty() ? 0.0 : raw.front();
  for (double& a : raw) a = reduce(a, base);
  std::sort(raw.begin(), raw.end());
  // Angles that coincide to rounding bound no piece worth a quadrature.
  for (double a : raw)
    if (angles_.empty() || a - angles_.back() > 1e-14) angles_.push_back(a);
  angles_.push_back(base + 2 * kPi);
}

void PolarRegion::intervals(double cos_phi, double sin_phi, std::vector<std::pair<double, double>>& out) const {
  out.clear();
  // A ray crosses each segment once and each arc at most twice: room for
  // the boundary of a light behind a few dozen occluders.
  constexpr int kMaxCrossings = 128;
  Crossing crossings[kMaxCrossings];
  int count = 0;
  auto add = [&](double rho, double tx, double ty) {
    FURNACE_CHECK(count < kMaxCrossings);
    // Interior to the left of the boundary's direction (tx, ty): the ray
    // enters where it turns left of it.
    crossings[count++] = {rho, tx * sin_phi - ty * cos_phi > 0};
  };
  for (const Curve2& c : boundary_) {
    if (!c.is_arc) {
      // centre + ρ·u = a + τ·(b − a), τ ∈ [0, 1], ρ > 0.
      const double ex = c.end.x - c.start.x, ey = c.end.y - c.start.y;
      const double ax = c.start.x - centre_.x, ay = c.start.y - centre_.y;
      const double denom = cos_phi * ey - sin_phi * ex;
      if (denom == 0) continue;
      const double rho = (ax * ey - ay * ex) / denom;
      const double tau = (ax * sin_phi - ay * cos_phi) / denom;
      if (rho > 0 && tau >= 0 && tau <= 1) add(rho, ex, ey);
      continue;
    }
    // |centre + ρ·u − O|² = R²: ρ² + 2bρ + (|w|² − R²) = 0, w = centre − O.
    const Circle2& k = c.circle;
    const double wx = centre_.x - k.cx, wy = centre_.y - k.cy;
    const double b = wx * cos_phi + wy * sin_phi;
    const double perp = wx * sin_phi - wy * cos_phi;  // w's part across the ray
    const double disc = (k.radius - perp) * (k.radius + perp);
    if (!(disc > 0)) continue;
    const double root = std::sqrt(disc);
    // The two roots without cancellation: q = −b ∓ root, the other c/q.
    const double q = b > 0 ? -b - root : -b + root;
    const double c0 = (std::hypot(wx, wy) - k.radius) * (std::hypot(wx, wy) + k.radius);
    const double roots[2] = {q, q != 0 ? c0 / q : 0.0};
    for (double rho : roots) {
      if (!(rho > 0)) continue;
      const double x = centre_.x + rho * cos_phi - k.cx, y = centre_.y + rho * sin_phi - k.cy;
      const double theta = std::atan2(y, x);
      const double from_middle = std::remainder(theta - (c.t0 + 0.5 * c.sweep), 2 * kPi);
      if (!(std::fabs(from_middle) <= 0.5 * std::fabs(c.sweep))) continue;
      const double sign = c.sweep >= 0 ? 1 : -1;
      add(rho, -sign * y, sign * x);
    }
  }
  std::sort(crossings, crossings + count, [](const Crossing& a, const Crossing& b) { return a.rho < b.rho; });
  if (count == 0) return;
  bool inside = !crossings[0].entering;  // a ray that first leaves starts inside
  double start = 0;
  for (int i = 0; i < count; ++i) {
    if (crossings[i].entering && !inside) start = crossings[i].rho, inside = true;
    else if (!crossings[i].entering && inside) {
      if (crossings[i].rho > start) out.emplace_back(start, crossings[i].rho);
      inside = false;
    }
  }
}

}  // namespace furnace::analytic
