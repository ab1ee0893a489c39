#include "analytic/footprint.h"

#include <algorithm>
#include <cmath>
#include <variant>

#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <boost/math/quadrature/tanh_sinh.hpp>

#include "analytic/reference.h"
#include "core/adaptive_quadrature.h"

namespace furnace::analytic {

namespace {

// Roots in (−½, ½) of a·u² + b·u + c = 0 (all real roots; extra roots only
// add harmless breakpoints).
void add_quadratic_roots(double a, double b, double c, std::vector<double>& cuts) {
  if (a == 0) {
    if (b != 0) cuts.push_back(-c / b);
    return;
  }
  const double disc = b * b - 4 * a * c;
  if (disc < 0) return;
  const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));  // stable pair q/a, c/q
  cuts.push_back(q / a);
  if (q != 0) cuts.push_back(c / q);
}

// Along the scan line of rays o0 + du·u (direction f), the u where the ray
// enters or leaves each object's silhouette (ignoring the other objects:
// occlusion only changes which object is seen at one of these points).
// Planar shapes: the hit point moves linearly, x(u) = x0 + g·u, and the
// inside tests are quadratic (disk) or linear (parallelogram, triangle
// barycentrics) in u; spheres: the ray–centre distance is quadratic in u.
std::vector<double> silhouette_crossings(const Scene& scene, const Vec3& o0, const Vec3& du, const Vec3& f) {
  std::vector<double> cuts;
  // Linear coordinates c(u) = c0 + c1·u of the hit point; roots of c = 0 and c = 1.
  auto linear = [&](double c0, double c1) {
    if (c1 == 0) return;
    cuts.push_back(-c0 / c1);
    cuts.push_back((1 - c0) / c1);
  };
  // The plane through `point` with normal m: the hit point x0 + g·u of the
  // scan line, or false when the plane is seen edge-on (no area on the image).
  Vec3 x0, g;
  auto on_plane = [&](const Vec3& point, const Vec3& m) {
    const double fm = dot(f, m);
    if (fm == 0) return false;
    x0 = o0 + f * (dot(point - o0, m) / fm);
    g = du - f * (dot(du, m) / fm);
    return true;
  };
  for (const Object& object : scene.objects) {
    std::visit(
        overloaded{
            [&](const Sphere& s) {
              // w(u) = (o0 − c) + du·u with its component along f removed; |w|² = R².
              const Vec3 w0 = (o0 - s.center) - f * dot(o0 - s.center, f), w1 = du - f * dot(du, f);
              add_quadratic_roots(dot(w1, w1), 2 * dot(w0, w1), dot(w0, w0) - s.radius * s.radius, cuts);
            },
            [&](const Disk& d) {
              if (!on_plane(d.center, d.normal)) return;
              const Vec3 e = x0 - d.center;
              add_quadratic_roots(dot(g, g), 2 * dot(e, g), dot(e, e) - d.radius * d.radius, cuts);
            },
            [&](const Rectangle& r) {
              const Vec3 m = cross(r.edge_u, r.edge_v);
              if (!on_plane(r.corner, m)) return;
              const double inv_m2 = 1 / length_squared(m);
              const Vec3 q = x0 - r.corner;
              linear(dot(cross(q, r.edge_v), m) * inv_m2, dot(cross(g, r.edge_v), m) * inv_m2);
              linear(dot(cross(r.edge_u, q), m) * inv_m2, dot(cross(r.edge_u, g), m) * inv_m2);
            },
            [&](const Triangle& t) {
              const Vec3 m = cross(t.p1 - t.p0, t.p2 - t.p0);
              if (!on_plane(t.p0, m)) return;
              const double inv_m2 = 1 / length_squared(m);
              const Vec3 e1 = t.p1 - t.p0, e2 = t.p2 - t.p0, q = x0 - t.p0;
              const double b1_0 = dot(cross(q, e2), m) * inv_m2, b1_1 = dot(cross(g, e2), m) * inv_m2;
              const double b2_0 = dot(cross(e1, q), m) * inv_m2, b2_1 = dot(cross(e1, g), m) * inv_m2;
              linear(b1_0, b1_1);
              linear(b2_0, b2_1);
              linear(b1_0 + b2_0, b1_1 + b2_1);
            }},
        object.shape);
  }
  return cuts;
}

// v (pixel units about the centre ray's origin o_c) where a scan line becomes
// tangent to a silhouette or crosses a polygon vertex: spheres c_v ± R, disks
// c_v ± R·√(1 − (n·up)²) (the ellipse's extent), polygons their vertices.
std::vector<double> silhouette_extremes(const Scene& scene, const Vec3& o_c, const Vec3& up, double pixel_height) {
  std::vector<double> cuts;
  auto v_of = [&](const Vec3& x) { return dot(x - o_c, up) / pixel_height; };
  for (const Object& object : scene.objects) {
    std::visit(overloaded{[&](const Sphere& s) {
                            cuts.push_back(v_of(s.center) - s.radius / pixel_height);
                            cuts.push_back(v_of(s.center) + s.radius / pixel_height);
                          },
                          [&](const Disk& d) {
                            const double nu = dot(normalize(d.normal), up);
                            const double extent = d.radius * std::sqrt(std::fmax(0.0, (1 - nu) * (1 + nu))) / pixel_height;
                            cuts.push_back(v_of(d.center) - extent);
                            cuts.push_back(v_of(d.center) + extent);
                          },
                          [&](const Rectangle& r) {
                            for (const Vec3& x :
                                 {r.corner, r.corner + r.edge_u, r.corner + r.edge_v, r.corner + r.edge_u + r.edge_v})
                              cuts.push_back(v_of(x));
                          },
                          [&](const Triangle& t) {
                            for (const Vec3& x : {t.p0, t.p1, t.p2}) cuts.push_back(v_of(x));
                          }},
               object.shape);
  }
  return cuts;
}

// The sorted breakpoints inside (−½, ½), with the ends.
std::vector<double> clean_cuts(std::vector<double> cuts) {
  std::vector<double> out{-0.5, 0.5};
  for (double c : cuts)
    if (std::isfinite(c) && c > -0.5 && c < 0.5) out.push_back(c);
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

double pixel_footprint_radiance(const Scene& scene, int px, int py, double tolerance) {
  using boost::math::quadrature::gauss_kronrod;
  const Camera& camera = scene.camera;
  const Camera::Ray centre = camera.pixel_center_ray(px, py);
  const Vec3 forward = centre.direction;
  const Vec3 right = normalize(cross(forward, camera.up));
  const Vec3 up = cross(right, forward);
  const double pixel_height = camera.height / camera.height_px;
  const Vec3 du = right * (camera.width / camera.width_px);
  const Vec3 dv = up * pixel_height;

  auto scan_line = [&](double v) {
    const Vec3 o0 = centre.origin + dv * v;
    const std::vector<double> cuts = clean_cuts(silhouette_crossings(scene, o0, du, forward));
    auto f = [&](double u) { return ray_radiance(scene, o0 + du * u, forward); };
    double sum = 0;
    for (size_t i = 0; i + 1 < cuts.size(); ++i)
      if (cuts[i + 1] > cuts[i]) sum += gauss_kronrod<double, 15>::integrate(f, cuts[i], cuts[i + 1], 8, tolerance);
    return sum;
  };
  // Rows where the chord structure changes: silhouette tangencies and vertices,
  // and where silhouettes cross the pixel's left and right edges (the
  // clipped chord has a kink there).
  std::vector<double> row_cuts = silhouette_extremes(scene, centre.origin, up, pixel_height);
  for (double side : {-0.5, 0.5}) {
    const std::vector<double> edge = silhouette_crossings(scene, centre.origin + du * side, dv, forward);
    row_cuts.insert(row_cuts.end(), edge.begin(), edge.end());
  }
  const std::vector<double> rows = clean_cuts(row_cuts);
  // tanh–sinh outside: at a tangency the chord length goes like √(v − v_t),
  // an end-point singularity it absorbs (Gauss–Kronrod converges slowly there).
  boost::math::quadrature::tanh_sinh<double> outer;
  double sum = 0;
  for (size_t i = 0; i + 1 < rows.size(); ++i)
    if (rows[i + 1] > rows[i]) sum += tanh_sinh_integral(outer, scan_line, rows[i], rows[i + 1], tolerance);
  return sum;
}

std::vector<double> footprint_reference_image(const Scene& scene, double tolerance) {
  const Camera& camera = scene.camera;
  std::vector<double> image(size_t(camera.width_px) * size_t(camera.height_px));
  for (int py = 0; py < camera.height_px; ++py)
    for (int px = 0; px < camera.width_px; ++px)
      image[size_t(py) * camera.width_px + px] = pixel_footprint_radiance(scene, px, py, tolerance);
  return image;
}

}  // namespace furnace::analytic
