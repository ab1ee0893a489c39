#include "analytic/circle_region.h"

#include <boost/math/quadrature/gauss_kronrod.hpp>

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"
#include "core/vec3.h"

namespace furnace::analytic {

namespace {

double centre_distance(const Circle2& a, const Circle2& b) { return std::hypot(b.cx - a.cx, b.cy - a.cy); }

// `inner` lies in the closed disk of `outer`.
bool contains(const Circle2& outer, const Circle2& inner) {
  return centre_distance(outer, inner) + inner.radius <= outer.radius;
}

bool strictly_inside(double x, double y, const Circle2& c) { return std::hypot(x - c.cx, y - c.cy) < c.radius; }

void check_circle(const Circle2& c, const char* role) {
  if (!std::isfinite(c.cx) || !std::isfinite(c.cy) || !std::isfinite(c.radius) || !(c.radius >= 0))
    throw Error(std::string("visible_boundary: the ") + role + " circle needs a finite centre and a finite radius >= 0; got centre (" +
                std::to_string(c.cx) + ", " + std::to_string(c.cy) + "), radius " + std::to_string(c.radius) + ".");
}

// Parameter angles (on circle k) of the two proper intersection points of
// circles k and j, appended to `angles`; nothing when they do not cross.
void append_crossings(const Circle2& k, const Circle2& j, std::vector<double>& angles) {
  const double d = centre_distance(k, j);
  if (!(d > std::fabs(k.radius - j.radius) && d < k.radius + j.radius)) return;
  // Foot of the common chord at distance a from k's centre along the centre
  // line: a = (d² + r_k² − r_j²)/(2d), with r_k² − r_j² as a product.
  const double a = (d * d + (k.radius - j.radius) * (k.radius + j.radius)) / (2.0 * d);
  // Half-chord √(r_k² − a²) as √((r_k − a)(r_k + a)); atan2 keeps the half
  // angle accurate near 0 and π where acos(a/r_k) would not be.
  const double half_chord = std::sqrt(std::fmax(0.0, (k.radius - a) * (k.radius + a)));
  const double base = std::atan2(j.cy - k.cy, j.cx - k.cx);
  const double half_angle = std::atan2(half_chord, a);
  angles.push_back(base - half_angle);
  angles.push_back(base + half_angle);
}

}  // namespace

std::vector<Arc> visible_boundary(const Circle2& light, const std::vector<Circle2>& occluders) {
  check_circle(light, "light");
  for (const Circle2& o : occluders) check_circle(o, "occluder");
  if (light.radius == 0) return {};

  // Occluders that matter: overlap the light with positive area, not inside
  // another occluder (the first of identical duplicates is kept).
  std::vector<Circle2> kept;
  for (const Circle2& o : occluders) {
    if (o.radius == 0) continue;
    if (contains(o, light)) return {};
    if (centre_distance(o, light) >= o.radius + light.radius) continue;
    kept.push_back(o);
  }
  std::vector<Circle2> active;
  for (size_t i = 0; i < kept.size(); ++i) {
    bool redundant = false;
    for (size_t j = 0; j < kept.size() && !redundant; ++j) {
      if (i == j || !contains(kept[j], kept[i])) continue;
      const bool identical = contains(kept[i], kept[j]);
      redundant = !identical || j < i;
    }
    if (!redundant) active.push_back(kept[i]);
  }

  std::vector<Circle2> circles{light};
  circles.insert(circles.end(), active.begin(), active.end());

  std::vector<Arc> arcs;
  for (size_t k = 0; k < circles.size(); ++k) {
    const Circle2& c = circles[k];
    std::vector<double> angles;
    for (size_t j = 0; j < circles.size(); ++j)
      if (j != k) append_crossings(c, circles[j], angles);
    // Angles into [angles[0], angles[0] + 2π), sorted: consecutive pairs bound arcs.
    std::vector<double> cuts;
    if (angles.empty()) {
      cuts = {0.0, 2.0 * kPi};
    } else {
      const double start = angles[0];
      for (double t : angles) {
        const double offset = t - start;
        cuts.push_back(start + (offset - 2.0 * kPi * std::floor(offset / (2.0 * kPi))));
      }
      std::sort(cuts.begin(), cuts.end());
      cuts.push_back(cuts.front() + 2.0 * kPi);
    }
    const bool is_light = k == 0;
    for (size_t i = 0; i + 1 < cuts.size(); ++i) {
      const double sweep = cuts[i + 1] - cuts[i];
      if (!(sweep > 0)) continue;  // a doubled cut (tangency): empty arc
      const double mid = cuts[i] + 0.5 * sweep;
      const double mx = c.cx + c.radius * std::cos(mid);
      const double my = c.cy + c.radius * std::sin(mid);
      bool keep = is_light || strictly_inside(mx, my, light);
      for (size_t j = 1; j < circles.size() && keep; ++j)
        if (j != k && strictly_inside(mx, my, circles[j])) keep = false;
      if (!keep) continue;
      if (is_light)
        arcs.push_back({c, cuts[i], sweep});
      else
        arcs.push_back({c, cuts[i + 1], -sweep});  // holes run clockwise
    }
  }
  return arcs;
}

double occluded_disk_irradiance(double h, const Circle2& light, const std::vector<Circle2>& occluders) {
  double sum = 0;
  for (const Arc& arc : visible_boundary(light, occluders)) sum += arc_contour(h, arc.circle, arc.t0, arc.sweep);
  // Round-off on arcs that nearly cancel can leave a tiny negative; the true
  // integral of a positive kernel over a region is ≥ 0.
  return std::fmax(sum, 0.0);
}

double contour_quadrature(const std::vector<Arc>& arcs, const std::function<double(double)>& g_over_s2) {
  using boost::math::quadrature::gauss_kronrod;
  double sum = 0;
  for (const Arc& arc : arcs) {
    const Circle2& c = arc.circle;
    auto integrand = [&](double t) {
      const double ct = std::cos(t), st = std::sin(t);
      const double x = c.cx + c.radius * ct, y = c.cy + c.radius * st;
      return g_over_s2(x * x + y * y) * c.radius * (c.radius + c.cx * ct + c.cy * st);
    };
    const double lo = std::fmin(arc.t0, arc.t0 + arc.sweep), hi = std::fmax(arc.t0, arc.t0 + arc.sweep);
    const double value = gauss_kronrod<double, 61>::integrate(integrand, lo, hi, 10, 1e-14);
    sum += arc.sweep >= 0 ? value : -value;
  }
  return sum;
}

}  // namespace furnace::analytic
