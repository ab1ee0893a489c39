#include "analytic/intersect.h"

#include <cmath>
#include <variant>

namespace furnace::analytic {

namespace {

std::optional<double> accept(double t, double t_min) {
  if (std::isfinite(t) && t > t_min) return t;
  return std::nullopt;
}

// Ray parameter of the hit with the plane through `point` with normal `n`;
// NaN or ±inf when the ray is parallel (rejected by accept()).
double plane_t(const Vec3& point, const Vec3& n, const Vec3& o, const Vec3& d) {
  return dot(point - o, n) / dot(d, n);
}

}  // namespace

std::optional<double> intersect_rectangle(const Rectangle& r, const Vec3& o, const Vec3& d, double t_min) {
  const Vec3 N = cross(r.edge_u, r.edge_v);
  const double t = plane_t(r.corner, N, o, d);
  if (!accept(t, t_min)) return std::nullopt;
  // Barycentric-like coordinates of the hit: q = s·u + t·v solved with the
  // cross products against N (exact for parallelograms, any edge lengths).
  const Vec3 q = o + d * t - r.corner;
  const double inv_n2 = 1.0 / length_squared(N);
  const double s = dot(cross(q, r.edge_v), N) * inv_n2;
  const double v = dot(cross(r.edge_u, q), N) * inv_n2;
  if (s < 0 || s > 1 || v < 0 || v > 1) return std::nullopt;
  return t;
}

std::optional<double> intersect_disk(const Disk& disk, const Vec3& o, const Vec3& d, double t_min) {
  const double t = plane_t(disk.center, disk.normal, o, d);
  if (!accept(t, t_min)) return std::nullopt;
  if (length(o + d * t - disk.center) > disk.radius) return std::nullopt;
  return t;
}

std::optional<double> intersect_sphere(const Sphere& s, const Vec3& o, const Vec3& d, double t_min) {
  const double d_len = length(d);
  const Vec3 dn = d / d_len;
  const Vec3 oc = o - s.center;
  const double b = dot(oc, dn);
  const Vec3 f = oc - dn * b;  // centre-to-ray perpendicular
  const double f_len = length(f);
  const double disc = (s.radius - f_len) * (s.radius + f_len);
  if (disc < 0) return std::nullopt;
  const double q = -b - std::copysign(std::sqrt(disc), b);
  const double c = (length(oc) - s.radius) * (length(oc) + s.radius);
  double t0 = q, t1 = c / q;
  if (q == 0) t1 = t0;  // origin at the centre's tangent point: double root
  if (t0 > t1) std::swap(t0, t1);
  if (auto t = accept(t0 / d_len, t_min)) return t;
  return accept(t1 / d_len, t_min);
}

std::optional<double> intersect_triangle(const Triangle& tri, const Vec3& o, const Vec3& d, double t_min) {
  const Vec3 e1 = tri.p1 - tri.p0;
  const Vec3 e2 = tri.p2 - tri.p0;
  const Vec3 pvec = cross(d, e2);
  const double det = dot(e1, pvec);
  if (det == 0) return std::nullopt;
  const double inv_det = 1.0 / det;
  const Vec3 tvec = o - tri.p0;
  const double u = dot(tvec, pvec) * inv_det;
  if (u < 0 || u > 1) return std::nullopt;
  const Vec3 qvec = cross(tvec, e1);
  const double v = dot(d, qvec) * inv_det;
  if (v < 0 || u + v > 1) return std::nullopt;
  return accept(dot(e2, qvec) * inv_det, t_min);
}

std::optional<double> intersect_shape(const Shape& shape, const Vec3& o, const Vec3& d, double t_min) {
  struct Visitor {
    const Vec3& o;
    const Vec3& d;
    double t_min;
    std::optional<double> operator()(const Rectangle& r) const { return intersect_rectangle(r, o, d, t_min); }
    std::optional<double> operator()(const Disk& k) const { return intersect_disk(k, o, d, t_min); }
    std::optional<double> operator()(const Sphere& s) const { return intersect_sphere(s, o, d, t_min); }
    std::optional<double> operator()(const Triangle& t) const { return intersect_triangle(t, o, d, t_min); }
  };
  return std::visit(Visitor{o, d, t_min}, shape);
}

}  // namespace furnace::analytic
