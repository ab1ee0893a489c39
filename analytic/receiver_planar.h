// Planar lights (disks, rectangles, triangles) in the receiver model
// (receiver.h): the part of the light a receiving point sees, as an exact
// region of the light's plane, and its decomposition in polar coordinates
// about a centre, which is what receiver_integrals.h integrates over.
//
// Geometry: the light's plane carries the 2-D coordinates (x, y) of the frame
// (s, t), origin at the receiving point p's foot, and p lies at height h > 0
// on the side of the unit normal `toward_receiver` (the emitting side: the
// front, or either side of a two-sided light). The point (x, y) is seen from
// p along v = x·s + y·t − h·toward_receiver, at distance d = |v|, emission
// cosine cos θ' = h/d, and dω = cos θ'/d² dA = h/d³ dA.
//
// The visible region is (light ∩ horizon half-plane) \ ∪ occluder images,
// computed by the exact Booleans of exact_region.h: an occluder is a disk
// parallel to the light strictly between p's height and the light's plane,
// whose central projection from p onto the light's plane is a circle (a
// homothety between parallel planes), as in scenes/disk_occluder.json.
//
// Polar coordinates about a centre C in the plane (the mirror direction's
// hit point, where a narrow lobe peaks): a ray from C at angle φ crosses the
// region's boundary at finitely many ρ, and between consecutive "critical"
// angles (directions to the boundary's vertices, tangents to its arcs,
// the directions of its segments and of its arcs at their nearest points to
// C) the intervals of ρ inside the region change smoothly, with at worst a
// square-root behaviour at a tangent angle (removed by the caller's
// quadratic substitution).
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "analytic/exact_region.h"
#include "core/scene.h"

namespace furnace::analytic {

// Relative height (to the object's size and distance) below which an object
// counts as lying in the receiver's tangent plane: a few hundred ulps.
inline constexpr double kCoplanarTolerance = 1e-13;

// Whether any part of the object rises above p's horizon (unit normal n).
// An object in p's tangent plane (a coplanar neighbour, above the horizon by
// the round-off of p) hides, or sends, a solid angle of that order, far
// below the quadrature's tolerance: it does not count.
bool above_horizon(const Object& object, const Vec3& p, const Vec3& n);

// A planar light as the receiver integrals see it from one receiving point.
struct PlanarEmitter {
  Vec3 s, t;                     // unit axes of the light's plane
  Vec3 toward_receiver;          // unit normal of the plane on p's side (the emitting side)
  double height = 0;             // p's distance from the plane, > 0
  std::vector<Curve2> boundary;  // the visible region, (x, y) about p's foot, positively oriented
  double area = 0;               // the whole emitter's area (light_area samples it uniformly), m²
  // Ω of the whole emitter when light_solid_angle samples it uniformly in
  // solid angle (a triangle, or a rectangle with perpendicular edges, seen
  // from its emitting side, Ω ≥ kMinSampledSolidAngle: the renderer's
  // spherical maps), else 0: sampled by area, as light_area.
  double solid_angle = 0;
};

// The planar emitter `light` of `scene` (a Disk, Rectangle or Triangle) seen
// from p (unit normal n) on object `receiver`. Empty when nothing of it
// reaches p: p behind its emitting face or in its plane, the light below p's
// horizon (above_horizon), or wholly hidden. Objects that provably cannot
// block it (not above_horizon, outside the slab between p and the light's plane, or with a
// bounding ball missing the cone from p over the light's bounding ball) are
// ignored; a disk parallel to the light strictly inside the slab is an
// occluder. Throws furnace::Error naming the scene and the object for any
// other object that may block the light; `who` names the receiver.
std::optional<PlanarEmitter> planar_emitter(const Scene& scene, size_t light, const Vec3& p, const Vec3& n,
                                            size_t receiver, const std::string& who);

// The centre of the polar coordinates for a receiver with mirror direction r
// (unit, world space): the point where r meets the light's plane, or, when r
// does not point at the plane or meets it more than kFarCentre (2) region
// sizes from the centre of the region's bounding box, that centre (a farther
// centre costs ~ε·distance/size relative in round-off: receiver_planar.cpp).
Point2 polar_centre(const PlanarEmitter& light, const Vec3& r);

// The visible region of a planar emitter in polar coordinates about `centre`.
class PolarRegion {
 public:
  PolarRegion(const std::vector<Curve2>& boundary, const Point2& centre);

  const Point2& centre() const { return centre_; }
  // The critical angles, increasing, spanning exactly one turn (the last is
  // the first + 2π): consecutive pairs bound the pieces of the outer integral.
  const std::vector<double>& angles() const { return angles_; }
  // The intervals [ρ_lo, ρ_hi] (ρ ≥ 0, increasing, disjoint) of the ray
  // centre + ρ·(cos φ, sin φ) inside the region, written into `out`.
  void intervals(double cos_phi, double sin_phi, std::vector<std::pair<double, double>>& out) const;

 private:
  struct Crossing {
    double rho;
    bool entering;
  };
  const std::vector<Curve2>& boundary_;
  Point2 centre_;
  std::vector<double> angles_;
};

}  // namespace furnace::analytic
