// Spherical emitters: irradiance from a uniform Lambertian sphere, including
// the case where the sphere straddles the receiver's horizon.
#pragma once

#include "core/vec3.h"

namespace furnace::analytic {

// E/L at p = ∫_{cone of the sphere} max(cos θ, 0) dω for a sphere of radius R
// whose centre is at `center` relative to p (|center| > R), unit normal n.
// With sin α = R/|center| (the cone's half-angle) and β the angle between n
// and the centre direction (cos β = n·ĉ):
//   whole cone above the horizon (cos β ≥ sin α):  π·sin²α·cos β;
//   whole cone below (cos β ≤ −sin α):             0;
//   straddling: with x = cos α/sin α and y = −x·cos β/sin β,
//     E/L = (cos β·acos(y) − x·sin β·√(1 − y²))·sin²α + atan(sin β·√(1 − y²)/x).
// Snyder, "Area Light Sources for Real-Time Graphics", Microsoft Research
// MSR-TR-96-11 (1996); the form of Lagarde & de Rousiers, "Moving Frostbite to
// Physically Based Rendering 3.0", SIGGRAPH 2014 course notes, eq. 19. Here
// acos and atan are written as atan2 (no loss at y → ±1), x = cos α/sin α is
// computed from √((1−sin α)(1+sin α)), sin β from |n × ĉ|, and — because the
// x·sin β·√(1 − y²)·sin²α and atan(·) terms are O(α) and cancel to O(α³) for
// small spheres — regrouped with w = sin β·√(1 − y²)/x as
//     E/L = cos β·acos(y)·sin²α + (atan(w) − w) + w·sin²α,
// atan(w) − w summed as a series for |w| < 0.5.
// Units: dimensionless (E/L). Domain: |center| > R ≥ 0; throws
// furnace::Error for a receiving point inside or on the sphere.
double sphere_irradiance(const Vec3& center, double R, const Vec3& n);

}  // namespace furnace::analytic
