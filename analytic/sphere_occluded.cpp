#include "analytic/sphere_occluded.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <queue>
#include <string>
#include <utility>
#include <variant>

#include <boost/math/quadrature/gauss_kronrod.hpp>

#include "analytic/disk_light.h"
#include "analytic/error_ledger.h"
#include "analytic/occlusion.h"
#include "analytic/sphere.h"
#include "analytic/unsupported.h"
#include "core/error.h"

namespace furnace::analytic {

namespace {

// Target of the φ-quadrature, relative to the unoccluded E/L (a bound on the
// result), absolute per unit of φ so that it adds up over the pieces.
constexpr double kRelativeTolerance = 1e-13;
// Bisection depth cap: a kink left inside a piece of width 2π/2^40 ≈ 6e-12
// costs O(width²) there, far below the tolerance; smooth pieces stop long before.
constexpr int kMaxDepth = 40;
// Cap on the bisections of the whole φ-integral. The depth cap alone does not
// bound the cost where the tolerance is below the integrand's round-off (a
// receiver far from the origin, where every piece fails down to full depth:
// 2^40 pieces); 1000 bisections are 30,000 integrand evaluations (~0.1 s),
// spent on the pieces with the largest error first. What is left over is
// reported as the estimate's error (error_ledger.h).
constexpr size_t kMaxBisections = 1000;
// An occluder whose plane passes within this fraction of its size from p is
// seen edge-on: it has no solid angle and is skipped.
constexpr double kEdgeOn = 1e-14;

struct Interval {
  double lo, hi;
};

// One occluder in the receiver's cone frame: polygon vertices relative to p,
// or a disk relative to p.
struct Blocker {
  std::vector<Vec3> polygon;
  bool is_disk = false;
  Vec3 disk_center, disk_normal;
  double disk_radius = 0;
};

// The segment where the plane m·y = 0 meets the blocker, or false.
bool plane_section(const Blocker& b, const Vec3& m, Vec3* y0, Vec3* y1) {
  if (b.is_disk) {
    const Vec3 l_raw = cross(m, b.disk_normal);
    const double l_len = length(l_raw);
    if (l_len == 0) return false;  // disk parallel to the plane: measure zero in φ
    const Vec3 l = l_raw / l_len;
    const Vec3 e = cross(b.disk_normal, l);  // in the disk's plane, ⟂ the section line
    const double s = -dot(m, b.disk_center) / dot(m, e);
    const double r = b.disk_radius, as = std::fabs(s);
    if (as >= r) return false;
    const double half = std::sqrt((r - as) * (r + as));  // difference of squares
    const Vec3 mid = b.disk_center + e * s;
    *y0 = mid - l * half;
    *y1 = mid + l * half;
    return true;
  }
  int found = 0;
  Vec3 pts[2];
  const size_t k = b.polygon.size();
  for (size_t i = 0; i < k && found < 2; ++i) {
    const Vec3& a = b.polygon[i];
    const Vec3& c = b.polygon[(i + 1) % k];
    const double da = dot(m, a), dc = dot(m, c);
    if (da == 0) {
      pts[found++] = a;
    } else if ((da < 0 && dc > 0) || (da > 0 && dc < 0)) {
      pts[found++] = a + (c - a) * (da / (da - dc));
    }
  }
  if (found < 2) return false;
  *y0 = pts[0];
  *y1 = pts[1];
  return true;
}

class ConeIntegrand {
 public:
  ConeIntegrand(const Sphere& light, std::vector<Blocker> blockers, const Vec3& p, const Vec3& n)
      : blockers_(std::move(blockers)), n_(n) {
    const Vec3 c = light.center - p;
    D_ = length(c);
    R_ = light.radius;
    a_ = c / D_;
    frame_ = Frame::from_normal(a_);
    theta_max_ = std::atan2(R_, std::sqrt((D_ - R_) * (D_ + R_)));
  }

  const Frame& frame() const { return frame_; }
  double theta_max() const { return theta_max_; }
  const std::vector<Blocker>& blockers() const { return blockers_; }

  // ∫ V·max(cos θ, 0)·sin α dα over [0, θmax] at azimuth φ.
  double operator()(double phi) const {
    const double cp = std::cos(phi), sp = std::sin(phi);
    const Vec3 w = frame_.s * cp + frame_.t * sp;
    const Vec3 m = frame_.t * cp - frame_.s * sp;  // normal of the plane of the half-plane φ
    const double A = dot(n_, a_), B = dot(n_, w);
    // Horizon: cos θ = ρ·cos(α − δ) ≥ 0.
    const double delta = std::atan2(B, A);
    const double lo = std::fmax(0.0, delta - kPi / 2), hi = std::fmin(theta_max_, delta + kPi / 2);
    if (lo >= hi) return 0;
    std::vector<Interval> blocked;
    for (const Blocker& b : blockers_) {
      Vec3 y0, y1;
      if (!plane_section(b, m, &y0, &y1)) continue;
      add_blocked({dot(y0, a_), dot(y0, w)}, {dot(y1, a_), dot(y1, w)}, &blocked);
    }
    std::sort(blocked.begin(), blocked.end(), [](const Interval& x, const Interval& y) { return x.lo < y.lo; });
    double sum = 0, cursor = lo;
    auto visible = [&](double a0, double a1) {
      if (a1 <= a0) return;
      const double s0 = std::sin(a0), s1 = std::sin(a1);
      // sin²α₁ − sin²α₀ = (s₁ − s₀)(s₁ + s₀); α/2 − sin 2α/4 differenced directly.
      sum += A * 0.5 * (s1 - s0) * (s1 + s0) +
             B * (0.5 * (a1 - a0) - 0.25 * (std::sin(2 * a1) - std::sin(2 * a0)));
    };
    for (const Interval& iv : blocked) {
      if (iv.hi <= cursor) continue;
      if (iv.lo >= hi) break;
      visible(cursor, std::fmin(iv.lo, hi));
      cursor = std::fmax(cursor, iv.hi);
      if (cursor >= hi) break;
    }
    visible(cursor, hi);
    return sum;
  }

 private:
  struct P2 {
    double x, y;  // along a, along w_φ
  };

  // Blocked α-interval(s) of the segment q0q1 in the (a, w_φ) plane.
  void add_blocked(P2 q0, P2 q1, std::vector<Interval>* out) const {
    // Keep the half-plane y ≥ 0 (the other half belongs to φ + π).
    if (q0.y < 0 && q1.y < 0) return;
    // −0 would put atan2 at −π instead of π.
    if (q0.y == 0) q0.y = 0.0;
    if (q1.y == 0) q1.y = 0.0;
    if (q0.y < 0 || q1.y < 0) {
      const double t = q0.y / (q0.y - q1.y);
      const P2 z{q0.x + (q1.x - q0.x) * t, 0.0};
      (q0.y < 0 ? q0 : q1) = z;
    }
    const P2 d{q1.x - q0.x, q1.y - q0.y};
    // Cut where the segment crosses the sphere's great circle |q − (D, 0)| = R.
    double cuts[4] = {0, 1, 1, 1};
    int count = 1;
    const double fx = q0.x - D_, fy = q0.y;
    const double qa = d.x * d.x + d.y * d.y, qb = fx * d.x + fy * d.y;
    const double qc = (std::sqrt(fx * fx + fy * fy) - R_) * (std::sqrt(fx * fx + fy * fy) + R_);
    const double disc = qb * qb - qa * qc;
    if (qa > 0 && disc > 0) {
      const double root = std::sqrt(disc);
      for (double t : {(-qb - root) / qa, (-qb + root) / qa})
        if (t > 0 && t < 1) cuts[count++] = t;
    }
    cuts[count++] = 1;
    for (int i = 0; i + 1 < count; ++i) {
      const double t0 = cuts[i], t1 = cuts[i + 1];
      if (t1 <= t0) continue;
      const double tm = 0.5 * (t0 + t1);
      const double mx = q0.x + d.x * tm - D_, my = q0.y + d.y * tm;
      if (std::hypot(mx, my) < R_) continue;  // inside the sphere: the ray met the sphere first
      const double a0 = std::atan2(q0.y + d.y * t0, q0.x + d.x * t0);
      const double a1 = std::atan2(q0.y + d.y * t1, q0.x + d.x * t1);
      // α is monotone along a line missing p, so the piece spans [min, max].
      const double lo = std::fmin(a0, a1), hi = std::fmin(std::fmax(a0, a1), theta_max_);
      if (lo >= hi) continue;
      // Front or behind the sphere: decided at one direction inside the cone
      // (the two regions of the cone outside the sphere touch only at θmax).
      const double am = 0.5 * (lo + hi);
      const double ux = std::cos(am), uy = std::sin(am);
      const double denom = ux * d.y - uy * d.x;
      if (denom == 0) continue;  // piece along the ray: measure zero
      const double s = (uy * q0.x - ux * q0.y) / denom;
      const double r = ux * (q0.x + d.x * s) + uy * (q0.y + d.y * s);
      const double ds = D_ * std::sin(am);
      const double entry = D_ * ux - std::sqrt(std::fmax((R_ - ds) * (R_ + ds), 0.0));
      if (r < entry) out->push_back({lo, hi});
    }
  }

  std::vector<Blocker> blockers_;
  Vec3 n_, a_;
  Frame frame_;
  double D_, R_, theta_max_;
};

double azimuth(const Frame& f, const Vec3& y) { return std::atan2(dot(y, f.t), dot(y, f.s)); }

// Azimuths where the integrand has a kink known in closed form.
std::vector<double> kinks(const ConeIntegrand& g) {
  const Frame& f = g.frame();
  std::vector<double> phis;
  auto add = [&](double phi) {
    phis.push_back(phi);
    phis.push_back(phi + kPi);  // the same plane bounds the opposite half-plane
  };
  const double cos2 = std::cos(g.theta_max()) * std::cos(g.theta_max());
  for (const Blocker& b : g.blockers()) {
    if (!b.is_disk) {
      const size_t k = b.polygon.size();
      for (size_t i = 0; i < k; ++i) {
        const Vec3& y0 = b.polygon[i];
        const Vec3 e = b.polygon[(i + 1) % k] - y0;
        add(azimuth(f, y0));
        // Edge y0 + t·e on the cone (a·y)² = cos²θmax·|y|².
        const double qa = dot(f.n, e) * dot(f.n, e) - cos2 * dot(e, e);
        const double qb = dot(f.n, y0) * dot(f.n, e) - cos2 * dot(y0, e);
        const double qc = dot(f.n, y0) * dot(f.n, y0) - cos2 * dot(y0, y0);
        const double disc = qb * qb - qa * qc;
        if (qa == 0 || disc < 0) continue;
        for (double t : {(-qb - std::sqrt(disc)) / qa, (-qb + std::sqrt(disc)) / qa})
          if (t > 0 && t < 1) add(azimuth(f, y0 + e * t));
      }
      continue;
    }
    // Planes through a tangent to the disk: tangent lines from the origin to
    // the disk's projection along a (an ellipse c2 + r·E·(cos ψ, sin ψ)),
    // νᵀ(c2·c2ᵀ − r²·E·Eᵀ)ν = 0 for the line's normal ν.
    const Vec3 e1 = normalize(cross(b.disk_normal, std::fabs(b.disk_normal.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0}));
    const Vec3 e2 = cross(b.disk_normal, e1);
    const double cx = dot(b.disk_center, f.s), cy = dot(b.disk_center, f.t);
    const double E11 = dot(e1, f.s), E12 = dot(e2, f.s), E21 = dot(e1, f.t), E22 = dot(e2, f.t);
    const double r2 = b.disk_radius * b.disk_radius;
    const double M11 = cx * cx - r2 * (E11 * E11 + E12 * E12);
    const double M12 = cx * cy - r2 * (E11 * E21 + E12 * E22);
    const double M22 = cy * cy - r2 * (E21 * E21 + E22 * E22);
    const double disc = M12 * M12 - M11 * M22;
    if (disc < 0) continue;
    // Roots of M11·νx² + 2·M12·νx·νy + M22·νy² = 0 as directions.
    const double root = std::sqrt(disc);
    for (double sign : {-1.0, 1.0}) {
      double nx, ny;
      if (std::fabs(M11) >= std::fabs(M22)) {
        if (M11 == 0) continue;
        nx = -M12 + sign * root;
        ny = M11;
      } else {
        nx = M22;
        ny = -M12 + sign * root;
      }
      add(std::atan2(ny, nx) + kPi / 2);  // the line's direction is ν rotated by 90°
    }
  }
  return phis;
}

// Globally adaptive 15-point Gauss–Kronrod over the pieces between `cuts`:
// the piece with the largest error estimate is bisected first, until the
// summed estimate meets `abs_tolerance`, kMaxBisections are used, or the
// worst piece is kMaxDepth levels deep. Returns the integral and stores the
// summed error estimate it reached in `*error`.
double adaptive(const std::function<double(double)>& f, const std::vector<double>& cuts, double abs_tolerance,
                double* error) {
  struct Piece {
    double a, b, value, error;
    int depth;
    bool operator<(const Piece& other) const { return error < other.error; }
  };
  auto rule = [&](double a, double b, int depth) {
    double e = 0;
    const double v = boost::math::quadrature::gauss_kronrod<double, 15>::integrate(f, a, b, 0, 0, &e);
    // Boost 1.74 reports |K15 − G7| of the rule mapped to [−1, 1]: scale by the half-width.
    return Piece{a, b, v, 0.5 * (b - a) * e, depth};
  };
  std::priority_queue<Piece> pieces;
  double total_error = 0;
  for (size_t i = 0; i + 1 < cuts.size(); ++i)
    if (cuts[i + 1] > cuts[i]) {
      const Piece piece = rule(cuts[i], cuts[i + 1], 0);
      total_error += piece.error;
      pieces.push(piece);
    }
  for (size_t bisections = 0; bisections < kMaxBisections && !pieces.empty(); ++bisections) {
    if (total_error <= abs_tolerance || pieces.top().depth >= kMaxDepth) break;
    const Piece worst = pieces.top();
    pieces.pop();
    const double mid = 0.5 * (worst.a + worst.b);
    const Piece left = rule(worst.a, mid, worst.depth + 1), right = rule(mid, worst.b, worst.depth + 1);
    total_error += left.error + right.error - worst.error;
    pieces.push(left);
    pieces.push(right);
  }
  // Sum values and errors afresh (the running total drifts by rounding).
  double sum = 0;
  *error = 0;
  for (; !pieces.empty(); pieces.pop()) {
    sum += pieces.top().value;
    *error += pieces.top().error;
  }
  return sum;
}

}  // namespace

double occluded_sphere_irradiance(const Sphere& light, const std::vector<Shape>& occluders, const Vec3& p,
                                  const Vec3& n) {
  const double unoccluded = sphere_irradiance(light.center - p, light.radius, n);
  if (unoccluded == 0) return 0.0;
  std::vector<Blocker> blockers;
  for (const Shape& shape : occluders) {
    // The blocker, or nothing for one seen edge-on from p.
    std::optional<Blocker> blocker = std::visit(
        overloaded{[&](const Rectangle& r) -> std::optional<Blocker> {
                     Blocker b;
                     b.polygon = {r.corner - p, r.corner + r.edge_u - p, r.corner + r.edge_u + r.edge_v - p,
                                  r.corner + r.edge_v - p};
                     const double size = length(r.edge_u) + length(r.edge_v);
                     if (std::fabs(dot(r.normal(), b.polygon[0])) <= kEdgeOn * size) return std::nullopt;
                     return b;
                   },
                   [&](const Triangle& t) -> std::optional<Blocker> {
                     Blocker b;
                     b.polygon = {t.p0 - p, t.p1 - p, t.p2 - p};
                     const double size = length(t.p1 - t.p0) + length(t.p2 - t.p0);
                     if (std::fabs(dot(t.normal(), b.polygon[0])) <= kEdgeOn * size) return std::nullopt;
                     return b;
                   },
                   [&](const Disk& d) -> std::optional<Blocker> {
                     Blocker b;
                     b.is_disk = true;
                     b.disk_center = d.center - p;
                     b.disk_normal = d.normal;
                     b.disk_radius = d.radius;
                     if (std::fabs(dot(d.normal, b.disk_center)) <= kEdgeOn * d.radius) return std::nullopt;
                     return b;
                   },
                   [](const Sphere&) -> std::optional<Blocker> {
                     throw Error("occluded_sphere_irradiance: a sphere occluder is outside what this reference solves.");
                   }},
        shape);
    if (blocker) blockers.push_back(std::move(*blocker));
  }
  const ConeIntegrand g(light, std::move(blockers), p, n);
  // Breakpoints in [φ₀, φ₀ + 2π) with φ₀ = 0; kink azimuths wrapped into it.
  std::vector<double> cuts{0.0, 2 * kPi};
  for (double phi : kinks(g)) {
    const double wrapped = phi - 2 * kPi * std::floor(phi / (2 * kPi));
    if (wrapped > 0 && wrapped < 2 * kPi) cuts.push_back(wrapped);
  }
  std::sort(cuts.begin(), cuts.end());
  const std::function<double(double)> f = [&g](double phi) { return g(phi); };
  double error = 0;
  const double sum = adaptive(f, cuts, kRelativeTolerance * unoccluded, &error);
  // The integrand is ≥ 0; round-off must not make a fully hidden light negative.
  const double result = std::fmax(sum, 0.0);
  // Relative to the result, or to the unoccluded value when all is hidden.
  ErrorLedger::report(error, result > 0 ? result : unoccluded);
  return result;
}

double sphere_light_irradiance(const Scene& scene, size_t emitter, const Vec3& p, const Vec3& n,
                               std::optional<size_t> receiver) {
  const Object& light = scene.objects[emitter];
  const Sphere& sphere = std::get<Sphere>(light.shape);
  const double unoccluded = sphere_irradiance(sphere.center - p, sphere.radius, n);
  if (unoccluded == 0) return 0.0;
  const BoundingSphere light_ball = bounding_sphere(light.shape);
  std::vector<Shape> occluders;
  for (size_t j = 0; j < scene.objects.size(); ++j) {
    if (j == emitter || (receiver && j == *receiver)) continue;
    const Object& object = scene.objects[j];
    if (height_range(object.shape, p, n).hi <= 0) continue;
    if (!ball_may_meet_ball_cone(bounding_sphere(object.shape), p, light_ball)) continue;
    if (!is_planar(object.shape))
      unsupported_configuration(scene, "object '" + object.name + "', which may block part of the emitter '" +
                                           light.name + "' where only planar occluders of a sphere light are solved,");
    occluders.push_back(object.shape);
  }
  if (occluders.empty()) return unoccluded;
  return occluded_sphere_irradiance(sphere, occluders, p, n);
}

}  // namespace furnace::analytic
