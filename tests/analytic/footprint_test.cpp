// Box-filtered pixel references: constant fields exactly, silhouettes
// against exact (CGAL) coverage areas, smooth fields against an independent
// tanh–sinh quadrature of the closed form.
#include "analytic/footprint.h"

#include <cmath>
#include <string>

#include <boost/math/quadrature/tanh_sinh.hpp>
#include <gtest/gtest.h>

#include "analytic/disk.h"
#include "analytic/exact_region.h"
#include "analytic/reference.h"

namespace furnace::analytic {
namespace {

Scene top_down(int resolution, double size) {
  Scene scene;
  scene.name = "footprint";
  scene.source = "footprint_test";
  scene.camera.center = {0, 0, 0.5};
  scene.camera.forward = {0, 0, -1};
  scene.camera.up = {0, 1, 0};
  scene.camera.width = scene.camera.height = size;
  scene.camera.width_px = scene.camera.height_px = resolution;
  return scene;
}

TEST(PixelFootprint, ConstantSkyOnFloorIsExact) {
  Scene scene = top_down(4, 4);
  scene.environment.radiance = 1.5;
  scene.objects.push_back({"floor", Rectangle{{-3, -3, 0}, {6, 0, 0}, {0, 6, 0}}, {0.6, Lambertian{}}, 0});
  EXPECT_NEAR(pixel_footprint_radiance(scene, 1, 2), 0.6 * 1.5, 1e-15);
}

// Area of (square ∩ disk) = area(square) − area(square \ disk), the latter
// from the exact region's boundary (½∮ x dy − y dx per piece).
double covered_area(double x0, double y0, double x1, double y1, const Circle2& disk) {
  const Region2 square{{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}, {}};
  double twice = 0;
  for (const Curve2& c : exact_visible_boundary(square, {{{}, disk}}, std::nullopt)) {
    if (!c.is_arc) {
      twice += c.start.x * c.end.y - c.end.x * c.start.y;
      continue;
    }
    const Circle2& k = c.circle;
    const double t1 = c.t0 + c.sweep;
    twice += k.radius * k.radius * c.sweep +
             k.radius * (k.cx * (std::sin(t1) - std::sin(c.t0)) - k.cy * (std::cos(t1) - std::cos(c.t0)));
  }
  return (x1 - x0) * (y1 - y0) - 0.5 * twice;
}

// An emitting disk seen against an empty sky: the average is Le times the
// covered fraction. Tolerance 1e-12: with every jump and kink split out the
// pieces are constant or √-ended, which the quadratures integrate to ~1e-16.
TEST(PixelFootprint, SilhouetteAverageIsCoveredFraction) {
  Scene scene = top_down(4, 4);  // 1 × 1 pixels; pixel (px, py) spans x ∈ [px − 2, px − 1], y ∈ [1 − py, 2 − py]
  const Circle2 disk{0.3, 0.2, 0.9};
  scene.objects.push_back({"lamp", Disk{{disk.cx, disk.cy, 0}, {0, 0, 1}, disk.radius}, {}, 2.0});
  for (int py = 0; py < 4; ++py)
    for (int px = 0; px < 4; ++px) {
      const double x0 = px - 2.0, y0 = 1.0 - py;
      const double expected = 2.0 * covered_area(x0, y0, x0 + 1, y0 + 1, disk);
      EXPECT_NEAR(pixel_footprint_radiance(scene, px, py), expected, 1e-12) << px << " " << py;
    }
}

// Smooth field: an unoccluded disk light over a floor. Independent: nested
// tanh–sinh over the pixel of (ρ/π)·L·E_disk(|x|).
TEST(PixelFootprint, SmoothFieldMatchesIndependentQuadrature) {
  Scene scene = top_down(8, 4);  // 0.5 × 0.5 pixels
  scene.objects.push_back({"floor", Rectangle{{-3, -3, 0}, {6, 0, 0}, {0, 6, 0}}, {0.5, Lambertian{}}, 0});
  scene.objects.push_back({"light", Disk{{0, 0, 1}, {0, 0, -1}, 0.6}, {}, 4.0});
  boost::math::quadrature::tanh_sinh<double> q;
  for (int px : {1, 4}) {
    const int py = 3;
    const double x0 = -2 + 0.5 * px, y1 = 2 - 0.5 * py;
    auto row = [&](double y) {
      return q.integrate([&](double x) { return 0.5 / kPi * 4.0 * disk_irradiance_parallel(0.6, 1.0, std::hypot(x, y)); },
                         x0, x0 + 0.5, 1e-12);
    };
    const double expected = q.integrate(row, y1 - 0.5, y1, 1e-12) / 0.25;
    EXPECT_NEAR(pixel_footprint_radiance(scene, px, py), expected, 1e-9 * expected) << px;
  }
}

}  // namespace
}  // namespace furnace::analytic
