#include "renderer/spherical_sampling.h"

#include "renderer/sampling.h"

#include <algorithm>
#include <cmath>

namespace furnace {

namespace {

double safe_sqrt(double x) { return std::sqrt(std::max(0.0, x)); }

// v/|v| by core's scene_normalize: these are differences and cross products
// of scene-scale vectors, and glibc's 3-argument hypot dominated the profile
// of rectangle-lit path tracing.
Vec3 unit(const Vec3& v) { return scene_normalize(v); }
// Angle between unit vectors, atan2 form (accurate near 0 and π), without hypot.
double angle_of(const Vec3& a, const Vec3& b) { return std::atan2(scene_length(cross(a, b)), dot(a, b)); }

// Unit component of v orthogonal to the unit vector a.
Vec3 orthogonal_part(const Vec3& v, const Vec3& a) { return unit(v - a * dot(v, a)); }

}  // namespace

double spherical_triangle_solid_angle(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double numerator = std::fabs(dot(a, cross(b, c)));
  const double denominator = 1.0 + dot(a, b) + dot(b, c) + dot(c, a);
  return 2.0 * std::atan2(numerator, denominator);  // atan2: correct also when the denominator is ≤ 0
}

std::optional<SphericalTriangleSampler> SphericalTriangleSampler::make(const Triangle& t, const Vec3& origin) {
  // One-sided light: only a viewpoint strictly in front of the triangle sees it.
  if (!(dot(origin - t.p0, t.normal()) > 0)) return std::nullopt;
  SphericalTriangleSampler s;
  s.origin = origin;
  s.triangle = t;
  s.a = unit(t.p0 - origin);
  s.b = unit(t.p1 - origin);
  s.c = unit(t.p2 - origin);
  s.solid_angle = spherical_triangle_solid_angle(s.a, s.b, s.c);
  if (!(s.solid_angle >= kMinSampledSolidAngle)) return std::nullopt;
  // Interior angle at a: between the great-circle tangents towards b and c.
  s.alpha = angle_of(orthogonal_part(s.b, s.a), orthogonal_part(s.c, s.a));
  return s;
}

Vec3 SphericalTriangleSampler::sample(double u1, double u2) const {
  // Arvo 1995: u1 picks the sub-triangle (a, b, ĉ) of area u1·Ω, which fixes ĉ
  // on the arc ac; u2 then picks the point on the arc bĉ by its cosine to b.
  const double area_hat = u1 * solid_angle;
  const double s = std::sin(area_hat - alpha);
  const double t = std::cos(area_hat - alpha);
  const double cos_alpha = std::cos(alpha), sin_alpha = std::sin(alpha);
  const double u = t - cos_alpha;
  const double v = s + sin_alpha * dot(a, b);  // dot(a, b) = cos of the arc ab
  const double q = std::clamp(((v * t - u * s) * cos_alpha - v) / ((v * s + u * t) * sin_alpha), -1.0, 1.0);
  const Vec3 c_hat = a * q + orthogonal_part(c, a) * safe_sqrt((1.0 - q) * (1.0 + q));
  const double z = 1.0 - u2 * (1.0 - dot(c_hat, b));
  if (!(1.0 - z > 0)) return b;  // ĉ = b to working precision: the arc has zero length
  return unit(b * z + orthogonal_part(c_hat, b) * safe_sqrt((1.0 - z) * (1.0 + z)));
}

std::array<double, 2> SphericalTriangleSampler::invert(const Vec3& w) const {
  // ĉ: where the great circle through b and w meets the arc ac (the side of
  // the sub-triangle u1 chose); then u1 is that sub-triangle's share of Ω and
  // u2 the position of w on the arc bĉ by 1 − cos, as in sample().
  Vec3 c_hat = unit(cross(cross(b, w), cross(a, c)));
  if (dot(c_hat, a + c) < 0) c_hat = -c_hat;  // the intersection on the arc, not its antipode
  const double u1 = spherical_triangle_solid_angle(a, b, c_hat) / solid_angle;
  // 1 − cos of unit vectors as |p − q|²/2, which does not cancel for close vectors.
  const double one_minus_cos_w = 0.5 * length_squared(w - b);
  const double one_minus_cos_c = 0.5 * length_squared(c_hat - b);
  const double u2 = one_minus_cos_c > 0 ? one_minus_cos_w / one_minus_cos_c : 0.0;
  const double top = std::nextafter(1.0, 0.0);
  return {std::clamp(u1, 0.0, top), std::clamp(u2, 0.0, top)};
}

namespace {

// atan2(im_a, re_a) + atan2(im_b, re_b) for im_a, im_b > 0 (each angle in
// (0, π)), as the argument of the product (re_a + i·im_a)(re_b + i·im_b)
// taken in (0, 2π). Each factor is first divided by its larger component
// (exact up to one rounding, and it keeps the product's magnitude near 1
// whatever the scene's scale).
double sum_of_two_arguments(double re_a, double im_a, double re_b, double im_b) {
  const double scale_a = 1 / std::fmax(std::fabs(re_a), im_a), scale_b = 1 / std::fmax(std::fabs(re_b), im_b);
  re_a *= scale_a, im_a *= scale_a, re_b *= scale_b, im_b *= scale_b;
  const double sum = std::atan2(re_a * im_b + im_a * re_b, re_a * re_b - im_a * im_b);
  return sum < 0 ? sum + kTwoPi : sum;  // atan2 gives (−π, π]; the sum lies in (0, 2π)
}

}  // namespace

std::optional<SphericalRectangleSampler> SphericalRectangleSampler::make(const Rectangle& r, const Vec3& origin) {
  const double len_u = std::sqrt(length_squared(r.edge_u)), len_v = std::sqrt(length_squared(r.edge_v));
  if (!(std::fabs(dot(r.edge_u, r.edge_v)) <= kPerpendicularTolerance * len_u * len_v)) return std::nullopt;
  SphericalRectangleSampler s;
  s.origin = origin;
  s.x = r.edge_u / len_u;
  s.y = r.edge_v / len_v;
  s.z = unit(cross(r.edge_u, r.edge_v));  // = r.normal()
  const Vec3 d = r.corner - origin;
  s.z0 = dot(d, s.z);
  // One-sided light: the viewpoint must be strictly in front (z0 < 0 in this frame).
  if (!(s.z0 < 0)) return std::nullopt;
  s.x0 = dot(d, s.x);
  s.y0 = dot(d, s.y);
  s.x1 = s.x0 + len_u;
  s.y1 = s.y0 + len_v;
  // The great circles through adjacent corners v00 = (x0, y0, z0), v10, v11,
  // v01 have the normals n0 ∝ (0, z0, −y0), n1 ∝ (−z0, 0, x1),
  // n2 ∝ (0, −z0, y1), n3 ∝ (z0, 0, −x0) (Ureña et al.), and the interior
  // angle at a corner v, π minus the angle between its two normals, is
  // atan2(|z0|·|v|, a product of two coordinates): the normals' lengths cancel
  // in atan2, so no normal is normalised.
  // Each angle is the argument of (product, |z0|·|v|), whose second
  // component is > 0, so it lies in (0, π) and the sum of two lies in
  // (0, 2π): one atan2 of the complex product gives a pair's sum (the
  // argument of a product is the sum of the arguments), two atan2 instead
  // of four.
  const double z0_abs = -s.z0, z0_2 = s.z0 * s.z0;
  const double im0 = z0_abs * std::sqrt(s.x1 * s.x1 + s.y0 * s.y0 + z0_2), re0 = s.y0 * s.x1;   // at v10
  const double im1 = z0_abs * std::sqrt(s.x1 * s.x1 + s.y1 * s.y1 + z0_2), re1 = -s.x1 * s.y1;  // at v11
  const double im2 = z0_abs * std::sqrt(s.x0 * s.x0 + s.y1 * s.y1 + z0_2), re2 = s.x0 * s.y1;   // at v01
  const double im3 = z0_abs * std::sqrt(s.x0 * s.x0 + s.y0 * s.y0 + z0_2), re3 = -s.x0 * s.y0;  // at v00
  const double g01 = sum_of_two_arguments(re0, im0, re1, im1);
  const double g23 = sum_of_two_arguments(re2, im2, re3, im3);
  s.b0 = -s.y0 / std::sqrt(z0_2 + s.y0 * s.y0);  // n0.z
  s.b1 = s.y1 / std::sqrt(z0_2 + s.y1 * s.y1);   // n2.z
  s.k = kTwoPi - g23;
  s.solid_angle = g01 - s.k;
  if (!(s.solid_angle >= kMinSampledSolidAngle)) return std::nullopt;
  return s;
}

Vec3 SphericalRectangleSampler::sample_point(double u1, double u2) const {
  // Ureña et al. 2013: u1 picks the x coordinate by the area of the spherical
  // sub-rectangle left of it; u2 picks y uniformly in the projected height h.
  const double au = u1 * solid_angle + k;
  const double fu = (std::cos(au) * b0 - b1) / std::sin(au);
  const double cu = std::clamp(std::copysign(1.0, fu) / std::sqrt(fu * fu + b0 * b0), -1.0, 1.0);
  const double xu = std::clamp(-(cu * z0) / safe_sqrt((1.0 - cu) * (1.0 + cu)), x0, x1);
  // Lengths by sqrt of sums of squares: scene-scale coordinates (core/vec3.h, scene_length).
  const double dist = std::sqrt(xu * xu + z0 * z0);
  const double h0 = y0 / std::sqrt(dist * dist + y0 * y0);
  const double h1 = y1 / std::sqrt(dist * dist + y1 * y1);
  const double hv = h0 + u2 * (h1 - h0);
  const double one_minus_hv2 = (1.0 - hv) * (1.0 + hv);
  const double yv = one_minus_hv2 > 0 ? std::clamp(hv * dist / std::sqrt(one_minus_hv2), y0, y1) : y1;
  return origin + x * xu + y * yv + z * z0;
}

}  // namespace furnace

namespace furnace {

std::array<double, 2> SphericalRectangleSampler::invert(const Vec3& point) const {
  const Vec3 d = point - origin;
  const double xu = std::clamp(dot(d, x), x0, x1);
  const double yv = std::clamp(dot(d, y), y0, y1);
  // u1: solid angle of the sub-rectangle [x0, xu] × [y0, y1] over Ω, by two
  // Van Oosterom–Strackee triangles (accurate however thin the strip is).
  const Vec3 v00 = unit({x0, y0, z0}), v01 = unit({x0, y1, z0}), vu0 = unit({xu, y0, z0}), vu1 = unit({xu, y1, z0});
  const double strip = spherical_triangle_solid_angle(v00, vu0, vu1) + spherical_triangle_solid_angle(v00, vu1, v01);
  // u2: the height h = y/√(d² + y²) is uniform in [h0, h1] along the column at xu.
  const double dist = std::sqrt(xu * xu + z0 * z0);
  const double h0 = y0 / std::sqrt(dist * dist + y0 * y0);
  const double h1 = y1 / std::sqrt(dist * dist + y1 * y1);
  const double hv = yv / std::sqrt(dist * dist + yv * yv);
  const double top = std::nextafter(1.0, 0.0);
  return {std::clamp(strip / solid_angle, 0.0, top), std::clamp((hv - h0) / (h1 - h0), 0.0, top)};
}

}  // namespace furnace
