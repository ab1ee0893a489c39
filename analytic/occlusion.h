// Geometric classification of scene objects relative to a receiving point p
// and an emitter: which objects can block some of the emitter, decided
// conservatively (an object reported "cannot block" provably blocks nothing;
// one reported "may block" must be handled exactly or rejected).
#pragma once

#include "core/scene.h"

namespace furnace::analytic {

// Exact range of the height z(x) = dot(x − p, w) over the points x of a shape
// (w unit). Planar shapes: over the vertices; disk: z(c) ± R·√(1 − (n·w)²);
// sphere: z(c) ± r.
struct ZRange {
  double lo, hi;
};
ZRange height_range(const Shape& shape, const Vec3& p, const Vec3& w);

// A sphere containing the whole shape (not necessarily the smallest).
struct BoundingSphere {
  Vec3 center;
  double radius;
};
BoundingSphere bounding_sphere(const Shape& shape);

// Can the ball `b` meet the convex hull of p and a disk of radius R whose
// centre is at p + h·w + c (c ⟂ w), the disk lying in the plane z = h?
// Sufficient test for "no": for every height z ∈ [z_b − r_b, z_b + r_b] ∩ [0, h]
// the horizontal distance from the ball's centre to the hull's cross-section
// (a disk of centre c·z/h, radius R·z/h) exceeds r_b. That distance minus the
// radius is convex in z, minimised by golden-section search; a relative margin
// of 1e-9 of the scene scale keeps the answer conservative.
bool ball_may_meet_disk_cone(const BoundingSphere& b, const Vec3& p, const Vec3& w, double h, const Vec3& c, double R);

// Can the ball `b` meet the convex hull of the point p and the ball `light`
// (an "ice-cream cone")? Exact for balls: the signed distance from b's centre
// to the hull (the round-cone distance of Quilez, apex radius 0: apex
// region, lateral cone surface, spherical cap) is compared with b's radius,
// with a relative margin of 1e-9 of the scene scale to stay conservative.
// True when p lies inside `light` (nothing can be excluded then).
bool ball_may_meet_ball_cone(const BoundingSphere& b, const Vec3& p, const BoundingSphere& light);

}  // namespace furnace::analytic
