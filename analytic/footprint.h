// Box-filtered pixel references: the average of the direct-lighting radiance
// over a pixel's footprint on the orthographic camera's image plane, for
// renderers that jitter the camera ray inside the pixel.
#pragma once

#include <vector>

#include "core/scene.h"

namespace furnace::analytic {

// (1/|P|) ∫_P ray_radiance(origin(u, v), forward) du dv over the pixel P =
// [−½, ½]² (in pixel units) about the centre of pixel (px, py), the ray origin
// being the centre ray's origin moved by u·(width/width_px) along
// right = normalize(forward × up) and v·(height/height_px) along
// up' = right × forward (Camera::pixel_center_ray's frame).
// Method: nested adaptive quadrature (tanh–sinh over v, Gauss–Kronrod 15
// over u). The radiance jumps where a ray enters or leaves an object's silhouette:
// along each scan line those u are solved for directly (the hit point moves
// linearly over planar shapes, so the inside tests are linear or quadratic
// in u; the ray–centre distance of a sphere is quadratic), and the inner
// integral is split there. The outer integral is split where scan lines are
// tangent to silhouettes (ellipse and circle extremes) or pass polygon
// vertices, or where silhouettes cross the pixel's side edges. Penumbra kinks (where the visible part of a light changes
// topology) are left to the adaptivity. Relative tolerance `tolerance` per
// level. Units: those of radiance. Throws furnace::Error where ray_radiance does.
double pixel_footprint_radiance(const Scene& scene, int px, int py, double tolerance = 1e-9);

// pixel_footprint_radiance for every pixel, row-major.
std::vector<double> footprint_reference_image(const Scene& scene, double tolerance = 1e-9);

}  // namespace furnace::analytic
