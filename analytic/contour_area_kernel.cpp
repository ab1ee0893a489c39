#include "analytic/contour_area_kernel.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <boost/math/quadrature/gauss.hpp>

#include "analytic/error_ledger.h"
#include "core/adaptive_quadrature.h"
#include "core/vec3.h"

namespace furnace::analytic {

namespace {

// Caps of each piece's adaptive quadrature (contour_area_kernel's contract):
// 40 levels resolve a feature 1e-12 of the piece wide (F within 1e-12·r of
// an arc); 2000 bisections bound the cost where round-off noise keeps every
// piece failing. What is not reached goes to the ledger.
constexpr double kContourAreaTolerance = 1e-14;
constexpr int kContourAreaDepth = 40;
constexpr size_t kContourAreaBisections = 2000;

using Rule20 = boost::math::quadrature::gauss<double, 20>;

// ∫_0^T sin²t·cos⁴t dt and ∫_0^T sin⁴t·cos²t dt, T ∈ [0, π/2]: the closed
// forms cancel for small T (the values are ~ T³/3 and ~ T⁵/5); every node's
// term is ≥ 0.
double sin2_cos4_integral(double T) {
  return Rule20::integrate(
      [](double t) {
        const double s = std::sin(t), c = std::cos(t);
        return s * s * c * c * c * c;
      },
      0.0, T);
}
double sin4_cos2_integral(double T) {
  return Rule20::integrate(
      [](double t) {
        const double s = std::sin(t), c = std::cos(t);
        return s * s * s * s * c * c;
      },
      0.0, T);
}

}  // namespace

double contour_area_kernel(const std::vector<Curve2>& boundary, double h, double a, double n1, double n2,
                           bool foot_inside) {
  const double h2 = h * h, h3 = h2 * h;
  // G/ρ² (F inside) or −(G∞ − G)/ρ² (F outside) at q ≠ 0, with
  // cq = n1·qx + n2·qy = c·ρ; divided by ρ² so that s²dφ = q × dq is the measure.
  auto radial_over_rho2 = [&](double qx, double qy) {
    const double rho2 = qx * qx + qy * qy, rho = std::sqrt(rho2);
    const double W = h2 + rho2, W3 = W * W * W;
    const double cq = n1 * qx + n2 * qy;
    if (foot_inside) {
      const double i1 = (W * W + W * h2 + h2 * h2) / (6 * h2 * h2 * W3);  // I1/ρ²
      const double i3 = (rho2 + 3 * h2) / (12 * h2 * W3);                 // I3/ρ⁴
      // I2/ρ³ = J2(T)/(h³ρ³) → 1/(3h⁶) as ρ → 0 (J2 ~ T³/3).
      const double i2 = rho > 0 ? sin2_cos4_integral(std::atan2(rho, h)) / (h3 * rho2 * rho) : 1 / (3 * h3 * h3);
      return a * a * i1 + 2 * a * cq * i2 + cq * cq * i3;
    }
    const double t1 = h2 / (6 * W3);
    const double t2 = sin4_cos2_integral(std::atan2(h, rho)) / h3;
    const double t3 = h2 * (h2 + 3 * rho2) / (12 * W3);
    return -(a * a * t1 + 2 * a * (cq / rho) * t2 + (cq / rho) * (cq / rho) * t3) / rho2;
  };
  double sum = 0, magnitude = 0, error = 0;
  auto integrate = [&](const auto& f, double lo, double hi) {
    if (!(hi > lo)) return 0.0;
    double piece_error = 0;
    const double value = adaptive_gauss_kronrod_relative<31>(f, lo, hi, kContourAreaTolerance, kContourAreaDepth, 1,
                                                             kContourAreaBisections, &piece_error);
    error += piece_error;
    magnitude += std::fabs(value);
    return value;
  };
  for (const Curve2& c : boundary) {
    if (!c.is_arc) {
      const double ax = c.start.x, ay = c.start.y, bx = c.end.x, by = c.end.y;
      const double ex = bx - ax, ey = by - ay, len = std::hypot(ex, ey);
      if (!(len > 0)) continue;
      const double d0 = (ax * ey - ay * ex) / len;  // > 0: counter-clockwise about F
      if (d0 == 0) continue;                        // the line passes through F: dφ = 0
      const double sign = d0 > 0 ? 1 : -1;
      const double px = sign * ey / len, py = -sign * ex / len, tx = ex / len, ty = ey / len;
      const double dist = std::fabs(d0);
      const double psi_a = std::atan2(ax * tx + ay * ty, dist), psi_b = std::atan2(bx * tx + by * ty, dist);
      // dφ = ±dψ along the segment: the integrand is the radial term itself.
      auto g = [&](double psi) {
        const double along = dist * std::tan(psi);
        const double qx = px * dist + tx * along, qy = py * dist + ty * along;
        return radial_over_rho2(qx, qy) * (qx * qx + qy * qy);
      };
      const double value = integrate(g, std::fmin(psi_a, psi_b), std::fmax(psi_a, psi_b));
      sum += (psi_b >= psi_a) == (d0 > 0) ? value : -value;  // dφ = sign(d0)·dψ along the edge
      continue;
    }
    const Circle2& k = c.circle;
    const double r = k.radius;
    auto g = [&](double t) {
      const double ct = std::cos(t), st = std::sin(t);
      return radial_over_rho2(k.cx + r * ct, k.cy + r * st) * r * (r + k.cx * ct + k.cy * st);
    };
    const double lo = std::fmin(c.t0, c.t0 + c.sweep), hi = std::fmax(c.t0, c.t0 + c.sweep);
    // Cuts at the arc's points nearest to and farthest from F (the kernel's
    // peak when F is close to the arc lies at an end of a piece).
    std::vector<double> cuts = {lo, hi};
    const double t_near = std::atan2(-k.cy, -k.cx);
    for (int j = -4; j <= 4; ++j) {
      const double t = t_near + j * kPi;
      if (t > lo && t < hi) cuts.push_back(t);
    }
    std::sort(cuts.begin(), cuts.end());
    double value = 0;
    for (size_t i = 0; i + 1 < cuts.size(); ++i) value += integrate(g, cuts[i], cuts[i + 1]);
    sum += c.sweep >= 0 ? value : -value;
  }
  const double result = std::fmax(sum, 0.0);
  const double cancelled = std::fmax(magnitude - std::fabs(sum), 0.0);
  if (result > 0) ErrorLedger::report(error + kRoundoffUlps * std::numeric_limits<double>::epsilon() * cancelled, result);
  return result;
}

}  // namespace furnace::analytic
