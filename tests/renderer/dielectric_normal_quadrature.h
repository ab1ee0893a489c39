// Integrals of a dielectric BSDF (renderer/dielectric.h) over the sphere of
// incident directions, written in the space of microfacet normals m, for
// tests/renderer/dielectric_test.cpp; the supports' thresholds and θm
// breaks also cut the cells of tests/renderer/dielectric_chi2_test.cpp.
//
// Each lobe maps the normals visible from wo one-to-one onto its directions:
// reflection wi = 2(wo·m)m − wo with |dωi/dωm| = 4 wo·m; refraction (Snell
// at the microfacet, η = index below over above) with
// |dωi/dωm| = (η wi·m + wo·m)²/(η²|wi·m|) (Walter et al. 2007 eq. 17,
// inverted). So for any g, ∫_{S²} g(wi) dωi = Σ_lobes ∫ g(wi(m)) |dωi/dωm| dωm
// over the m whose wi lands on the lobe's side of the macrosurface
// (reflection above, refraction below; the BSDF's support). In m the GGX
// peak of width α is resolved by s = tan θm/α (the substitution of
// tests/renderer/ggx_test.cpp).
//
// Quadrature: wo = (sin θo, 0, cos θo), so every integrand is even in φ
// (φ ∈ [0, π], doubled). On a ring of fixed θm, c = wo·m = A cos φ + B
// (A = sin θo sin θm, B = cos θo cos θm), and every edge of a support is a
// threshold on c: visibility c > 0, the reflected direction above the
// horizon c > cos θo/(2 cos θm), from inside (η < 1) no total internal
// reflection c > cos θc = √(1 − η²) and the refracted direction below the
// horizon c > c*(θm) (solved below). The φ range is cut at every threshold,
// so each piece is smooth up to a square-root endpoint (1 − F at the
// critical angle), which the substitution x = (1 − cos πt)/2 makes smooth
// before Gauss–Legendre. The θm integral is cut where a threshold enters or
// leaves a ring (found by scan and bisection) and graded by 2 in s from 0,
// with the tail s → ∞ mapped to a finite interval. Accuracy: ∫ D_ωo dωm = 1
// is met to ≤ 2e-15 over the cases of dielectric_test.cpp (printed there).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <vector>

#include "core/vec3.h"

namespace furnace::testing_support {

// n-point Gauss–Legendre on [0, 1] (Newton on P_n from the Chebyshev guesses).
struct GaussLegendre {
  std::vector<double> x, w;
  explicit GaussLegendre(int n) {
    for (int i = 0; i < n; ++i) {
      double z = std::cos(kPi * (i + 0.75) / (n + 0.5)), dp = 0;
      for (int it = 0; it < 100; ++it) {
        double p0 = 1, p1 = z;
        for (int k = 2; k <= n; ++k) {
          const double p2 = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k;
          p0 = p1, p1 = p2;
        }
        dp = n * (z * p1 - p0) / (z * z - 1);
        const double dz = p1 / dp;
        z -= dz;
        if (std::fabs(dz) < 1e-17) break;
      }
      double p0 = 1, p1 = z;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k;
        p0 = p1, p1 = p2;
      }
      dp = n * (z * p1 - p0) / (z * z - 1);
      x.push_back((1 - z) / 2);
      w.push_back(1 / ((1 - z * z) * dp * dp));  // 2/((1 − z²)P′²) halved for [0, 1]
    }
  }
};

// ∫_a^b f(x) dx with both endpoints smoothed by x = a + (b − a)(1 − cos πt)/2
// (a square root at either end becomes linear in t). f returns K values.
template <size_t K, class F>
void integrate_piece(const GaussLegendre& gl, double a, double b, const F& f, std::array<double, K>& sum) {
  if (!(b > a)) return;
  for (size_t i = 0; i < gl.x.size(); ++i) {
    const double t = gl.x[i];
    const double x = a + (b - a) * (1 - std::cos(kPi * t)) / 2;
    const double dx = (b - a) * kPi * std::sin(kPi * t) / 2;
    const std::array<double, K> v = f(x);
    for (size_t k = 0; k < K; ++k) sum[k] += gl.w[i] * dx * v[k];
  }
}

// The smallest c = wo·m at which a lobe's direction lands on its side (and
// the microfacet is visible), given the view cosine, η and the ring; +2
// when none does.
struct LobeThresholds {
  double reflect, transmit;
};
inline LobeThresholds lobe_thresholds(double cos_o, double eta, double cos_m) {
  LobeThresholds t;
  t.reflect = std::max(0.0, cos_o / (2 * cos_m));  // 2c·cos θm − cos θo > 0
  if (eta >= 1) {
    t.transmit = 0;  // the refracted direction always bends below (c − η cos θt < 0)
    return t;
  }
  // Refracted wi_z = (c − g)·cos θm/η − cos θo/η with g = √(η² − 1 + c²) (= η cos θt),
  // below the horizon ⟺ c − g < k = cos θo/cos θm; c − g falls from cos θc
  // (at c = cos θc) to 1 − η (at c = 1). Past total internal reflection only.
  const double c_crit = std::sqrt((1 - eta) * (1 + eta));
  const double k = cos_o / cos_m;
  if (k >= c_crit) t.transmit = c_crit;
  else if (k <= 1 - eta) t.transmit = 2;
  else t.transmit = (k * k + c_crit * c_crit) / (2 * k);  // c − g = k solved: c* = (k² + 1 − η²)/(2k)
  return t;
}

// The thresholds on c = wo·m of the ring θm: visibility, the reflected
// direction above the horizon, the refracted direction below it, and (η < 1)
// the critical cosine. A lobe is supported where c exceeds each of its own.
inline std::array<double, 4> ring_thresholds(const Vec3& wo, double eta, double theta_m) {
  const LobeThresholds t = lobe_thresholds(wo.z, eta, std::cos(theta_m));
  const double c_crit = eta < 1 ? std::sqrt((1 - eta) * (1 + eta)) : 0.0;
  return {0.0, t.reflect, t.transmit, c_crit};
}

// The θm ∈ (0, π/2) where a threshold enters or leaves the ring's range
// [cos(θo + θm), cos(θo − θm)] of c (the topology of a ring's support
// changes there): a scan of kScan steps and bisection to full precision.
inline std::vector<double> support_theta_breaks(const Vec3& wo, double eta) {
  constexpr int kScan = 4000;
  const double theta_o = std::atan2(wo.x, wo.z);
  std::vector<double> breaks;
  for (int which = 0; which < 4; ++which)
    for (int side = -1; side <= 1; side += 2) {
      const auto g = [&](double th) {
        const double range = std::cos(side > 0 ? th - theta_o : th + theta_o);
        return ring_thresholds(wo, eta, th)[size_t(which)] - range;
      };
      double prev_th = 0, prev = g(0);
      for (int i = 1; i <= kScan; ++i) {
        const double th = kPi / 2 * i / kScan;
        const double v = g(th);
        if ((prev < 0) != (v < 0)) {
          double lo = prev_th, hi = th;
          for (int it = 0; it < 80; ++it) {
            const double mid = (lo + hi) / 2;
            ((g(mid) < 0) == (prev < 0) ? lo : hi) = mid;
          }
          breaks.push_back((lo + hi) / 2);
        }
        prev_th = th, prev = v;
      }
    }
  std::sort(breaks.begin(), breaks.end());
  return breaks;
}

// ∫ f dωm over the normals visible from wo, K values at once;
// f(m, in_reflect, in_transmit) receives the normal and whether its reflected
// and refracted directions lie on their lobes' sides (decided per piece).
template <size_t K>
std::array<double, K> integrate_over_normals(
    const Vec3& wo, double alpha, double eta, int order,
    const std::function<std::array<double, K>(const Vec3& m, bool reflect_ok, bool transmit_ok)>& f) {
  const GaussLegendre gl(order);
  const double sin_o = wo.x, cos_o = wo.z;
  const double c_crit = eta < 1 ? std::sqrt((1 - eta) * (1 + eta)) : 0.0;
  // The ring integral at θm (φ ∈ [0, π], doubled), cut at each threshold.
  const auto ring = [&](double theta_m) {
    const double sm = std::sin(theta_m), cm = std::cos(theta_m);
    const double a = sin_o * sm, b = cos_o * cm;
    const std::array<double, 4> c = ring_thresholds(wo, eta, theta_m);
    std::vector<double> cuts{0.0, kPi};
    for (double ci : c) {
      if (!(a > 0)) break;
      const double cos_phi = (ci - b) / a;
      if (cos_phi > -1 && cos_phi < 1) cuts.push_back(std::acos(cos_phi));
    }
    std::sort(cuts.begin(), cuts.end());
    std::array<double, K> sum{};
    const LobeThresholds t = lobe_thresholds(cos_o, eta, cm);
    for (size_t i = 0; i + 1 < cuts.size(); ++i) {
      const double mid = (cuts[i] + cuts[i + 1]) / 2, c_mid = a * std::cos(mid) + b;
      if (!(c_mid > 0)) continue;  // invisible
      const bool reflect_ok = c_mid > t.reflect, transmit_ok = c_mid > t.transmit && c_mid > c_crit;
      integrate_piece<K>(gl, cuts[i], cuts[i + 1],
                         [&](double phi) { return f({sm * std::cos(phi), sm * std::sin(phi), cm}, reflect_ok, transmit_ok); },
                         sum);
    }
    for (double& v : sum) v *= 2 * sm;  // φ symmetry; dωm = sin θm dθm dφ
    return sum;
  };
  std::vector<double> breaks = support_theta_breaks(wo, eta);
  // s = tan θm/α, graded by 2 from 0 (the lobe of width ~1 in s), the breaks
  // in s, and the tail beyond the last finite break.
  std::vector<double> s_breaks{0.0};
  for (double s = 0.125; s < 1e6; s *= 2) s_breaks.push_back(s);
  for (double th : breaks)
    if (th > 0 && th < kPi / 2) s_breaks.push_back(std::tan(th) / alpha);
  std::sort(s_breaks.begin(), s_breaks.end());
  s_breaks.erase(std::unique(s_breaks.begin(), s_breaks.end()), s_breaks.end());
  std::array<double, K> total{};
  const auto in_s = [&](double s) {
    const double q = alpha * s;
    const double theta_m = std::atan(q);
    const double dtheta_ds = alpha / (1 + q * q);
    std::array<double, K> v = ring(theta_m);
    for (double& x : v) x *= dtheta_ds;
    return v;
  };
  for (size_t i = 0; i + 1 < s_breaks.size(); ++i) integrate_piece<K>(gl, s_breaks[i], s_breaks[i + 1], in_s, total);
  // Tail: s = s_last/(1 − t), t ∈ [0, 1).
  const double s_last = s_breaks.back();
  for (size_t i = 0; i < gl.x.size(); ++i) {
    const double t = gl.x[i];
    const double s = s_last / (1 - t), ds = s_last / ((1 - t) * (1 - t));
    const std::array<double, K> v = in_s(s);
    for (size_t k = 0; k < K; ++k) total[k] += gl.w[i] * ds * v[k];
  }
  return total;
}

}  // namespace furnace::testing_support
