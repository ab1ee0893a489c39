// Tiny shared math: a double-precision 3-vector and an orthonormal frame.
// This is the only header analytic/ and renderer/ share besides the scene
// description; it holds no sampling code, so a bug in the renderer's warps
// cannot leak into the references.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

namespace furnace {

struct Vec3 {
  double x = 0, y = 0, z = 0;

  constexpr Vec3() = default;
  constexpr Vec3(double x_, double y_, double z_) : x(x_), y(y_), z(z_) {}

  constexpr double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  constexpr Vec3 operator-() const { return {-x, -y, -z}; }
  constexpr Vec3 operator+(const Vec3& b) const { return {x + b.x, y + b.y, z + b.z}; }
  constexpr Vec3 operator-(const Vec3& b) const { return {x - b.x, y - b.y, z - b.z}; }
  constexpr Vec3 operator*(double s) const { return {x * s, y * s, z * s}; }
  constexpr Vec3 operator/(double s) const { return {x / s, y / s, z / s}; }
  Vec3& operator+=(const Vec3& b) { x += b.x; y += b.y; z += b.z; return *this; }
  Vec3& operator-=(const Vec3& b) { x -= b.x; y -= b.y; z -= b.z; return *this; }
  Vec3& operator*=(double s) { x *= s; y *= s; z *= s; return *this; }
  constexpr bool operator==(const Vec3& b) const { return x == b.x && y == b.y && z == b.z; }
};

constexpr Vec3 operator*(double s, const Vec3& v) { return v * s; }
constexpr double dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double length_squared(const Vec3& v) { return dot(v, v); }
// hypot-based so that tiny (1e-200) and huge (1e200) vectors neither underflow nor overflow.
inline double length(const Vec3& v) { return std::hypot(v.x, v.y, v.z); }
inline Vec3 normalize(const Vec3& v) { return v / length(v); }
// The same by the square root of the squared length, for vectors of scene
// scale: coordinates are within ±1e6 (core/scene.h, kMaxCoordinate), so for
// |v| within 1e±150 the squares neither overflow nor underflow, and the
// renderer's hot paths skip glibc's 3-argument hypot (three divisions).
inline double scene_length(const Vec3& v) { return std::sqrt(length_squared(v)); }
inline Vec3 scene_normalize(const Vec3& v) { return v / scene_length(v); }
inline bool is_finite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
// The largest |component|; NaN if any component is NaN. (std::max, not
// std::fmax: fmax is a libm call here and would drop a NaN.)
inline double max_abs_component(const Vec3& v) {
  const double m = std::max(std::fabs(v.x), std::max(std::fabs(v.y), std::fabs(v.z)));
  return v.x == v.x && v.y == v.y && v.z == v.z ? m : std::numeric_limits<double>::quiet_NaN();
}

// Angle between two unit vectors by the atan2 form, accurate near 0 and π
// where acos(dot) loses half its digits.
inline double angle_between(const Vec3& a, const Vec3& b) {
  return std::atan2(length(cross(a, b)), dot(a, b));
}

// Orthonormal frame (s, t, n) around a unit normal n. Local z is n.
// Construction: Duff et al. 2017, "Building an Orthonormal Basis, Revisited"
// (branchless, continuous except on the n.z = -0 seam).
struct Frame {
  Vec3 s, t, n;

  static Frame from_normal(const Vec3& n) {
    const double sign = std::copysign(1.0, n.z);
    const double a = -1.0 / (sign + n.z);
    const double b = n.x * n.y * a;
    Frame f;
    f.s = {1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x};
    f.t = {b, sign + n.y * n.y * a, -n.y};
    f.n = n;
    return f;
  }
  Vec3 world_from_local(const Vec3& v) const { return s * v.x + t * v.y + n * v.z; }
  Vec3 local_from_world(const Vec3& v) const { return {dot(v, s), dot(v, t), dot(v, n)}; }
};

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kInvPi = 0.31830988618379067154;

}  // namespace furnace
