#include "analytic/occlusion.h"

#include <algorithm>
#include <cmath>
#include <variant>

namespace furnace::analytic {

ZRange height_range(const Shape& shape, const Vec3& p, const Vec3& w) {
  auto z = [&](const Vec3& x) { return dot(x - p, w); };
  auto over = [&](std::initializer_list<Vec3> vertices) {
    ZRange r{INFINITY, -INFINITY};
    for (const Vec3& v : vertices) {
      r.lo = std::min(r.lo, z(v));
      r.hi = std::max(r.hi, z(v));
    }
    return r;
  };
  struct Visitor {
    decltype(z)& zf;
    decltype(over)& overf;
    const Vec3& w;
    ZRange operator()(const Rectangle& r) const {
      return overf({r.corner, r.corner + r.edge_u, r.corner + r.edge_v, r.corner + r.edge_u + r.edge_v});
    }
    ZRange operator()(const Triangle& t) const { return overf({t.p0, t.p1, t.p2}); }
    ZRange operator()(const Sphere& s) const { return {zf(s.center) - s.radius, zf(s.center) + s.radius}; }
    ZRange operator()(const Disk& k) const {
      // Extent of a tilted disk along w: R·sin(angle between its normal and w).
      const double spread = k.radius * length(cross(normalize(k.normal), w));
      return {zf(k.center) - spread, zf(k.center) + spread};
    }
  };
  return std::visit(Visitor{z, over, w}, shape);
}

BoundingSphere bounding_sphere(const Shape& shape) {
  struct Visitor {
    BoundingSphere operator()(const Rectangle& r) const {
      const Vec3 c = r.corner + (r.edge_u + r.edge_v) * 0.5;
      return {c, 0.5 * std::max(length(r.edge_u + r.edge_v), length(r.edge_u - r.edge_v))};
    }
    BoundingSphere operator()(const Triangle& t) const {
      const Vec3 c = (t.p0 + t.p1 + t.p2) / 3.0;
      return {c, std::max({length(t.p0 - c), length(t.p1 - c), length(t.p2 - c)})};
    }
    BoundingSphere operator()(const Sphere& s) const { return {s.center, s.radius}; }
    BoundingSphere operator()(const Disk& k) const { return {k.center, k.radius}; }
  };
  return std::visit(Visitor{}, shape);
}

bool ball_may_meet_disk_cone(const BoundingSphere& b, const Vec3& p, const Vec3& w, double h, const Vec3& c, double R) {
  const Vec3 q = b.center - p;
  const double zq = dot(q, w);
  const Vec3 q_horizontal = q - w * zq;
  const double z_lo = std::max(0.0, zq - b.radius);
  const double z_hi = std::min(h, zq + b.radius);
  if (z_lo > z_hi) return false;
  // Horizontal gap between the ball's centre line and the hull's section at z.
  auto gap = [&](double z) { return length(q_horizontal - c * (z / h)) - R * (z / h); };
  // Golden-section search on the convex gap(z); 80 steps shrink the bracket
  // by 0.618⁸⁰ ≈ 2e-17, below double resolution.
  const double inv_phi = 0.6180339887498949;  // (√5 − 1)/2
  double a = z_lo, e = z_hi;
  double x1 = e - inv_phi * (e - a), x2 = a + inv_phi * (e - a);
  double g1 = gap(x1), g2 = gap(x2);
  for (int i = 0; i < 80; ++i) {
    if (g1 < g2) {
      e = x2; x2 = x1; g2 = g1;
      x1 = e - inv_phi * (e - a); g1 = gap(x1);
    } else {
      a = x1; x1 = x2; g1 = g2;
      x2 = a + inv_phi * (e - a); g2 = gap(x2);
    }
  }
  const double min_gap = std::min({g1, g2, gap(z_lo), gap(z_hi)});
  const double scale = h + length(c) + R + length(q) + b.radius;
  return min_gap <= b.radius + 1e-9 * scale;
}

bool ball_may_meet_ball_cone(const BoundingSphere& b, const Vec3& p, const BoundingSphere& light) {
  const Vec3 axis_vector = light.center - p;
  const double D = length(axis_vector);
  if (D <= light.radius) return true;
  const Vec3 axis = axis_vector / D;
  // (x, y): b's centre along and across the axis from p.
  const Vec3 q = b.center - p;
  const double x = dot(q, axis);
  const double y = length(q - axis * x);
  const double sin_a = light.radius / D;
  const double cos_a = std::sqrt((1 - sin_a) * (1 + sin_a));
  const double along_edge = x * cos_a + y * sin_a;  // projection on the cone's edge direction
  double distance;
  if (along_edge < 0)
    distance = length(q);  // apex region
  else if (along_edge > D * cos_a)
    distance = length(b.center - light.center) - light.radius;  // beyond the tangent circle: the cap
  else
    distance = y * cos_a - x * sin_a;  // across the lateral surface (negative inside)
  const double scale = D + light.radius + length(q) + b.radius;
  return distance <= b.radius + 1e-9 * scale;
}

}  // namespace furnace::analytic
