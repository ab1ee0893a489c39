// Uniform sampling of the solid angle subtended by a triangle (Arvo 1995,
// "Stratified Sampling of Spherical Triangles") and by a rectangle (Ureña,
// Fajardo & King 2013, "An Area-Preserving Parametrization for Spherical
// Rectangles"), seen from a point. Both are area-preserving maps from [0,1)²:
// the density is 1/Ω in solid angle, Ω the subtended solid angle.
//
// Each is a setup struct built once per (shape, viewpoint), with sample() and
// pdf() reading the same Ω. Setups are empty when the shape is seen edge-on,
// from behind its front side (the lights are one-sided) or subtends less than
// kMinSampledSolidAngle, where the maps lose their precision; callers then use
// area sampling, with the same decision in sample() and pdf().
#pragma once

#include <array>
#include <optional>

#include "core/scene.h"
#include "core/strategy.h"

namespace furnace {

// Solid angle of the spherical triangle with unit vertices a, b, c
// (Van Oosterom & Strackee 1983: tan(Ω/2) = |a·(b×c)| / (1 + a·b + b·c + c·a)).
double spherical_triangle_solid_angle(const Vec3& a, const Vec3& b, const Vec3& c);

struct SphericalTriangleSampler {
  Vec3 origin;
  Vec3 a, b, c;           // unit directions from origin to the vertices
  double solid_angle = 0;  // Ω, sr
  double alpha = 0;        // interior angle at a
  Triangle triangle;

  // Empty when the triangle is behind, edge-on or too small (see above).
  static std::optional<SphericalTriangleSampler> make(const Triangle& t, const Vec3& origin);
  // A unit direction uniform in the spherical triangle.
  Vec3 sample(double u1, double u2) const;
  // The (u1, u2) that sample() maps to direction w (w inside the triangle).
  std::array<double, 2> invert(const Vec3& w) const;
  // Density in solid angle (sr⁻¹): 1/Ω (callers pass directions that hit the triangle).
  double pdf() const { return 1.0 / solid_angle; }
};

struct SphericalRectangleSampler {
  Vec3 origin;
  Vec3 x, y, z;            // rectangle frame: x, y along the edges, z away from origin's side
  double x0 = 0, x1 = 0, y0 = 0, y1 = 0, z0 = 0;  // rectangle in that frame, relative to origin (z0 < 0)
  double b0 = 0, b1 = 0, k = 0;
  double solid_angle = 0;  // Ω, sr

  // Requires perpendicular edges; empty for a general parallelogram and in the
  // cases listed at the top of this file.
  static std::optional<SphericalRectangleSampler> make(const Rectangle& r, const Vec3& origin);
  // A point on the rectangle whose direction from origin is uniform in solid angle.
  Vec3 sample_point(double u1, double u2) const;
  // The (u1, u2) that sample_point() maps to `point` (a point of the rectangle).
  std::array<double, 2> invert(const Vec3& point) const;
  double pdf() const { return 1.0 / solid_angle; }
};

}  // namespace furnace
