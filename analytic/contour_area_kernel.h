// The light-area second-moment kernel of a planar region of any shape (arcs
// and segments: a disk light cut by a tilted receiver's horizon, minus the
// images of occluders), by Green's theorem about the receiving point's foot
// point on the region's plane.
#pragma once

#include <vector>

#include "analytic/exact_region.h"

namespace furnace::analytic {

// K = ∫_A (n·(x − p))²·h²/(h² + ρ²)⁴ dA = ∫_A (cos θ·cos θ'/r²)² dA, m⁻², over a
// region A of a plane at distance h > 0 from p, lying on the upper side of
// p's horizon (n·(x − p) ≥ 0 on A). Coordinates q = (qx, qy) in the plane are
// centred on p's foot point F (ρ = |q|) and n·(x − p) = a + n1·qx + n2·qy.
// `boundary` is A's positively oriented boundary (exact_visible_boundary);
// `foot_inside` says whether F lies in A (with F's distance from the
// boundary it selects the form below, not the value: both forms are exact,
// the wrong one only loses digits).
//
// Method. Along the ray from F at azimuth φ, with c = (n1 cos φ + n2 sin φ),
//   G(ρ) = ∫_0^ρ (a + c s)² h² s/(h² + s²)⁴ ds = a²·I1 + 2ac·I2 + c²·I3,
//   I1 = ρ²(W² + W h² + h⁴)/(6h⁴W³),  I3 = ρ⁴(ρ² + 3h²)/(12h²W³),
//   I2 = J2(T)/h³,  J2(T) = ∫_0^T sin²t cos⁴t dt,  T = atan2(ρ, h),  W = h² + ρ²
// (s = h tan t in I2; I1 and I3 with the differences W³ − h⁶ and
// (W − h²)²(W + 2h²) factored, so nothing cancels for ρ ≪ h), and
// K = ∮_∂A G dφ (Green's theorem in polar coordinates about F).
// When F is inside A, or outside by at most h, that is the form used: every
// ray's G is ≥ 0 (inside), or the near crossing's G is a fraction of G∞ that
// does not cancel the far one's by more than a few digits (within h).
// When F is outside by more than h, the rays' near and far crossings give G values close to
// the limit G∞ = a²/(6h⁴) + 2ac(π/32)/h³ + c²/(12h²) (~ 1/h⁴ as h → 0) that
// cancel, so the tail G∞ − G is integrated instead (∮ G∞ dφ = 0 around a
// region not holding F):
//   K = −∮ (G∞ − G) dφ,  G∞ − G = a²h²/(6W³) + 2ac·J4(π/2 − T)/h³ + c²h²(h² + 3ρ²)/(12W³),
//   J4(x) = ∫_0^x sin⁴t cos²t dt.
// J2 and J4 by their binomial series in sin T or cos T
// (sin_cos_power_integral.h: a few ulps, no trigonometric call, no
// cancelling closed form), sin T and cos T from ρ and h (sin_cos_of_atan2).
// Segments are integrated in their own polar angle ψ about the foot of the
// perpendicular from F (dφ = ±dψ, which spreads a segment passing close to
// F), arcs in their parameter t with s²dφ = r(r + cx cos t + cy sin t) dt,
// split at the points nearest to and farthest from F; each piece by adaptive
// Gauss–Kronrod (31 points) to 1e-14 of its first estimate, at most
// kContourAreaDepth levels and kContourAreaBisections bisections (a bounded
// cost). Reported to the open ErrorLedger: the pieces' error estimates plus
// kRoundoffUlps·ε times what cancels between pieces (Σ|piece| − |K|), and
// the conditioning on the boundary's position, rounded at ε·coordinate_scale
// (the magnitude of the world coordinates it came from):
// kRoundoffUlps·ε·coordinate_scale·∮ f ds, ∮ f ds by one 31-point
// Gauss–Kronrod rule per piece. That term dominates when F is within ~h of
// the boundary, where K ~ 1/h⁴ moves by ~ f·δ per unit length of a boundary
// displaced by δ (about ε·scale/h relative).
// Cost: O(pieces × (2·bisections + 1) × 31) kernel evaluations, each with a
// polynomial of at most 48 terms.
double contour_area_kernel(const std::vector<Curve2>& boundary, double h, double a, double n1, double n2,
                           bool foot_inside, double coordinate_scale);

}  // namespace furnace::analytic
