#include "analytic/sphere.h"

#include <cmath>
#include <string>

#include "core/error.h"

namespace furnace::analytic {

namespace {

// atan(w) − w without cancellation: −w³·Σ_k (−w²)^k/(2k + 3) for |w| < 0.5
// (terms fall by ≥ 4× each, 30 terms reach 1e-18 relative), the plain
// difference beyond (it then loses under a bit).
double atan_minus_identity(double w) {
  if (std::fabs(w) >= 0.5) return std::atan(w) - w;
  const double z = w * w;
  double sum = 0, power = 1;
  for (int k = 0; k < 30; ++k, power *= -z) sum += power / (2 * k + 3);
  return -w * z * sum;
}

}  // namespace

double sphere_irradiance(const Vec3& center, double R, const Vec3& n) {
  const double D = length(center);
  if (!(D > R) || !(R >= 0))
    throw Error("sphere_irradiance: the receiving point must lie outside the sphere; got centre distance " +
                std::to_string(D) + " and radius " + std::to_string(R) + ".");
  const Vec3 axis = center / D;
  const double sin_a = R / D;
  const double sin2_a = sin_a * sin_a;
  const double cos_b = dot(n, axis);
  if (cos_b >= sin_a) return kPi * sin2_a * cos_b;
  if (cos_b <= -sin_a) return 0.0;
  const double sin_b = length(cross(n, axis));
  const double cos_a = std::sqrt((1 - sin_a) * (1 + sin_a));
  const double x = cos_a / sin_a;
  const double y = -x * cos_b / sin_b;                                 // |y| < 1 while straddling
  const double root = std::sqrt(std::fmax(0.0, (1 - y) * (1 + y)));  // √(1 − y²) without cancellation
  const double acos_y = std::atan2(root, y);
  // With w = sin β·√(1 − y²)/x, the textbook terms −x·sin β·√(1 − y²)·sin²α and
  // atan(w) are both O(α) and cancel to O(α³) for small spheres; since
  // x²·sin²α = cos²α they regroup as (atan(w) − w) + w·sin²α, each O(α³).
  const double w = sin_b * root / x;
  const double value = cos_b * acos_y * sin2_a + atan_minus_identity(w) + w * sin2_a;
  return std::fmax(value, 0.0);
}

}  // namespace furnace::analytic
