// Swept grids of hard geometry, each value against an independent reference
// in 50-digit arithmetic (boost::multiprecision::cpp_bin_float_50): tiny
// tilted disks and rectangles, near-total and tilted blocking of the sky, a
// near-contact occluder, the light-area kernel of a rectangle just above the
// receiver. The references integrate the definition E/L = ∫ cos θ cos θ'/r² dA
// over the emitter's plane with one coordinate in closed form (in 50 digits)
// and the other by adaptive Gauss–Kronrod in 50 digits, or evaluate the
// textbook (cancelling) closed form in 50 digits, where cancellation costs
// nothing. Each class prints the worst relative error it found.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <boost/multiprecision/cpp_bin_float.hpp>
#include <gtest/gtest.h>

#include "analytic/light_moments.h"
#include "analytic/moments.h"
#include "analytic/reference.h"

namespace furnace::analytic {
namespace {

using Big = boost::multiprecision::cpp_bin_float_50;

constexpr double kEps = std::numeric_limits<double>::epsilon();
// What `furnace analytic` claims: 1e-13 relative (≈ 450 ε). The double
// evaluation of a sum of a dozen positive terms, an atan2 and a few products
// errs by a few tens of ε; the rest is margin for the conditioning of the
// inputs, which are exact doubles here.
constexpr double kSweepTolerance = 450 * kEps;
// The 50-digit references' own tolerance: far below kSweepTolerance.
constexpr double kReferenceTolerance = 1e-25;

double relative_error(double value, const Big& expected) {
  if (expected == 0) return std::fabs(value);
  return static_cast<double>(abs((Big(value) - expected) / expected));
}

Big integrate(const std::function<Big(Big)>& f, const Big& a, const Big& b) {
  return boost::math::quadrature::gauss_kronrod<Big, 61>::integrate(f, a, b, 25, kReferenceTolerance);
}

// ∫_{-U}^{U} du/(u² + c²)^k in closed form for k = 2 and k = 4 (reduction
// formula ∫du/(u²+c²)^{j+1} = u/(2j c²(u²+c²)^j) + (2j−1)/(2j c²)·∫du/(u²+c²)^j).
Big power_integral(const Big& U, const Big& c, int k) {
  const Big c2 = c * c, w = U * U + c2;
  Big value = 2 * atan(U / c) / c;  // j = 1: ∫ du/(u²+c²)
  for (int j = 1; j < k; ++j) value = 2 * U / (2 * j * c2 * pow(w, j)) + Big(2 * j - 1) / (2 * j * c2) * value;
  return value;
}

// Scene: a floor (the receiver, excluded) and the objects given.
Scene scene_with(std::vector<Object> objects, double environment = 0) {
  Scene scene;
  scene.name = "precision";
  scene.source = "precision_sweep_test";
  scene.objects.push_back({"floor", Rectangle{{-5, -5, -1}, {10, 0, 0}, {0, 10, 0}}, {0.5, Lambertian{}}, 0});
  for (Object& o : objects) scene.objects.push_back(std::move(o));
  scene.environment.radiance = environment;
  return scene;
}

// Receiver at the origin, normal tilted by `tilt_degrees` from +z towards +y.
Vec3 tilted_normal(double tilt_degrees) {
  const double t = tilt_degrees * kPi / 180;
  return {0, std::sin(t), std::cos(t)};
}

// E/L from the region of the plane z = 1 (seen from the origin, normal n in
// the yz-plane) given as v ∈ [v0, v1] with u ∈ [−U(v), U(v)]: n·x = n_y v + n_z,
// cos θ' = 1/r, so E/L = ∫ max(n_y v + n_z, 0)·∫ du/(u² + v² + 1)² dv, the
// inner integral in closed form, the outer split at the horizon v = −n_z/n_y.
Big plane_region_irradiance(const Vec3& n, const Big& v0, const Big& v1, const std::function<Big(Big)>& U,
                            const std::function<Big(Big)>& v_of, const std::function<Big(Big)>& dv_of) {
  auto f = [&](const Big& s) {
    const Big v = v_of(s);
    const Big cos_part = Big(n.y) * v + Big(n.z);
    if (cos_part <= 0) return Big(0);
    return cos_part * power_integral(U(s), sqrt(v * v + 1), 2) * dv_of(s);
  };
  // Horizon in the parameter s: found by bisection on v_of (monotone).
  std::vector<Big> cuts{v0, v1};
  if (n.y != 0) {
    const Big v_h = -Big(n.z) / Big(n.y);
    if (v_of(v0) < v_h && v_h < v_of(v1)) {
      Big lo = v0, hi = v1;
      for (int i = 0; i < 200; ++i) {
        const Big mid = (lo + hi) / 2;
        (v_of(mid) < v_h ? lo : hi) = mid;
      }
      cuts.insert(cuts.begin() + 1, lo);
    }
  }
  Big sum = 0;
  for (size_t i = 0; i + 1 < cuts.size(); ++i) sum += integrate(f, cuts[i], cuts[i + 1]);
  return sum;
}

// The largest relative error of a sweep and where it occurred.
struct WorstError {
  double error = 0;
  std::string where = "nowhere";
  void note(double err, const std::string& at) {
    if (err > error) error = err, where = at;
  }
  void print(const char* what) const {
    std::printf("[ precision ] %-34s worst relative error %.3g (%.1f eps) at %s\n", what, error, error / kEps,
                where.c_str());
  }
};

const std::vector<double> kTilts{0, 30, 60, 85, 89, 89.9, 89.98, 89.99, 89.999};

// A disk light of radius R, centre (0, 0, 1), facing down; R/h = R.
TEST(PrecisionSweep, TinyDiskTimesTilt) {
  WorstError worst;
  for (double R : {1e3, 10.0, 1.0, 1e-1, 1e-2, 1e-3, 1e-4, 1e-6}) {
    const Scene scene = scene_with({{"light", Disk{{0, 0, 1}, {0, 0, -1}, R}, {}, 1.0}});
    for (double tilt : kTilts) {
      const Vec3 n = tilted_normal(tilt);
      // v = R sin ψ, U = R cos ψ: no square-root end points.
      const Big bigR(R);
      const Big expected = plane_region_irradiance(
          n, -boost::math::constants::half_pi<Big>(), boost::math::constants::half_pi<Big>(),
          [&](const Big& s) { return bigR * cos(s); }, [&](const Big& s) { return bigR * sin(s); },
          [&](const Big& s) { return bigR * cos(s); });
      const double e = irradiance(scene, {0, 0, 0}, n, size_t(0));
      const double err = relative_error(e, expected);
      EXPECT_LE(err, kSweepTolerance) << "R/h " << R << " tilt " << tilt;
      worst.note(err, "R/h " + std::to_string(R) + ", tilt " + std::to_string(tilt));
    }
  }
  worst.print("tiny disk x tilt");
}

// A square light of side s centred over the receiver at height 1, facing down.
TEST(PrecisionSweep, TinyRectangleTimesTilt) {
  WorstError worst;
  for (double s : {1e3, 10.0, 1.0, 1e-1, 1e-2, 1e-3, 1e-4, 1e-6}) {
    const Scene scene = scene_with({{"light", Rectangle{{-s / 2, -s / 2, 1}, {0, s, 0}, {s, 0, 0}}, {}, 1.0}});
    for (double tilt : kTilts) {
      const Vec3 n = tilted_normal(tilt);
      const Big half = Big(s) / 2;
      const Big expected = plane_region_irradiance(
          n, -half, half, [&](const Big&) { return half; }, [](const Big& v) { return v; },
          [](const Big&) { return Big(1); });
      const double e = irradiance(scene, {0, 0, 0}, n, size_t(0));
      const double err = relative_error(e, expected);
      EXPECT_LE(err, kSweepTolerance) << "side/distance " << s << " tilt " << tilt;
      worst.note(err, "side " + std::to_string(s) + ", tilt " + std::to_string(tilt));
    }
  }
  worst.print("tiny rectangle x tilt");
}

// A black disk of radius 1 parallel to the receiver at height h hides all of
// the sky but a sliver: E = L·(π − π F), F by Howell's textbook formula in 50 digits.
TEST(PrecisionSweep, NearTotalSkyBlocking) {
  WorstError worst;
  for (double h : {1e-2, 1e-3, 1e-4, 1e-5, 1e-6})
    for (double d : {0.0, 0.5, 0.99}) {
      const Scene scene = scene_with({{"blocker", Disk{{d, 0, h}, {0, 0, 1}, 1.0}, {}, 0}}, 1.0);
      const Big R2 = 1, h2 = Big(h) * h, d2 = Big(d) * d, sum = h2 + d2 + R2;
      const Big blocked = boost::math::constants::half_pi<Big>() * (1 - (h2 + d2 - R2) / sqrt(sum * sum - 4 * R2 * d2));
      const Big expected = boost::math::constants::pi<Big>() - blocked;
      const double e = irradiance(scene, {0, 0, 0}, {0, 0, 1}, size_t(0));
      const double err = relative_error(e, expected);
      EXPECT_LE(err, kSweepTolerance) << "h " << h << " d " << d;
      worst.note(err, "h " + std::to_string(h) + ", d " + std::to_string(d));
    }
  worst.print("near-total sky blocking");
}

// A tilted black disk over the receiver: E = L·(π − Ω⊥), Ω⊥ by a polar
// integral over the disk in 50 digits (radial Gauss–Kronrod inside, angular
// outside); and the uniform-hemisphere second moment 2π·L²·∫_open cos²θ dω =
// 2π·L²·(2π/3 − ∫_disk cos²θ dω) the same way.
TEST(PrecisionSweep, TiltedDiskBlockingTheSky) {
  WorstError worst, worst_moment;
  for (double tilt : {0.3, 0.9, 1.3})
    for (double height : {0.5, 0.05}) {
      const Vec3 m{0, std::sin(tilt), std::cos(tilt)};
      const double R = 0.3 * height / 0.5;
      const Scene scene = scene_with({{"blocker", Disk{{0, 0, height}, m, R}, {}, 0}}, 1.0);
      const Frame f = Frame::from_normal(m);
      auto angular = [&](const Big& phi) {
        const Big c = cos(phi), s = sin(phi);
        const Big ux = Big(f.s.x) * c + Big(f.t.x) * s, uy = Big(f.s.y) * c + Big(f.t.y) * s,
                  uz = Big(f.s.z) * c + Big(f.t.z) * s;
        auto radial = [&](const Big& rho) {
          const Big x = rho * ux, y = rho * uy, z = Big(height) + rho * uz;
          const Big r2 = x * x + y * y + z * z;
          const Big m_dot = abs(Big(m.x) * x + Big(m.y) * y + Big(m.z) * z);
          return rho * z * m_dot / (r2 * r2);
        };
        return integrate(radial, Big(0), Big(R));
      };
      const Big expected = boost::math::constants::pi<Big>() -
                           integrate(angular, Big(0), boost::math::constants::two_pi<Big>());
      const double e = irradiance(scene, {0, 0, 0}, {0, 0, 1}, size_t(0));
      const double err = relative_error(e, expected);
      EXPECT_LE(err, kSweepTolerance) << "tilt " << tilt << " height " << height;
      worst.note(err, "tilt " + std::to_string(tilt) + ", height " + std::to_string(height));
      // cos²θ dω = z²·|m·x|/r⁵ dA: the radial integrand times z/r.
      auto angular2 = [&](const Big& phi) {
        const Big c = cos(phi), s = sin(phi);
        const Big ux = Big(f.s.x) * c + Big(f.t.x) * s, uy = Big(f.s.y) * c + Big(f.t.y) * s,
                  uz = Big(f.s.z) * c + Big(f.t.z) * s;
        auto radial = [&](const Big& rho) {
          const Big x = rho * ux, y = rho * uy, z = Big(height) + rho * uz;
          const Big r2 = x * x + y * y + z * z;
          const Big m_dot = abs(Big(m.x) * x + Big(m.y) * y + Big(m.z) * z);
          return rho * z * z * m_dot / (r2 * r2 * sqrt(r2));
        };
        return integrate(radial, Big(0), Big(R));
      };
      const Big two_pi = boost::math::constants::two_pi<Big>();
      const Big moment = two_pi * (two_pi / 3 - integrate(angular2, Big(0), two_pi));
      const double m2 = second_moment(Strategy::kUniformHemisphere, scene, {0, 0, 0}, {0, 0, 1}, size_t(0));
      const double err2 = relative_error(m2, moment);
      EXPECT_LE(err2, kSweepTolerance) << "uniform-hemisphere moment, tilt " << tilt << " height " << height;
      worst_moment.note(err2, "the grid");
    }
  worst.print("tilted disk blocking the sky");
  worst_moment.print("  its uniform-hemisphere moment");
}

// A disk light (radius 0.5 at height 1) behind a parallel disk occluder of
// radius 0.3·h at height h ≪ 1 right over the receiver: an annulus 0.3 < s < 0.5
// stays visible, E/L = F(0.5) − F(0.3) (Howell, 50 digits).
TEST(PrecisionSweep, NearContactOccluder) {
  WorstError worst;
  auto howell = [](const Big& R) { return boost::math::constants::pi<Big>() * R * R / (1 + R * R); };
  for (double h : {1e-3, 1e-4, 1e-5, 1e-6}) {
    const Scene scene = scene_with({{"light", Disk{{0, 0, 1}, {0, 0, -1}, 0.5}, {}, 1.0},
                                    {"occluder", Disk{{0, 0, h}, {0, 0, 1}, 0.3 * h}, {}, 0}});
    const Big expected = howell(Big(0.5)) - howell(Big(0.3 * h) / Big(h));
    const double e = irradiance(scene, {0, 0, 0}, {0, 0, 1}, size_t(0));
    const double err = relative_error(e, expected);
    EXPECT_LE(err, kSweepTolerance) << "h " << h;
    worst.note(err, "h " + std::to_string(h));
  }
  worst.print("near-contact occluder");
}

// The light-area kernel ∫ (cos θ cos θ'/r²)² dA = ∫ h⁴/(u² + v² + h²)⁴ du dv of a
// rectangle [x0, x1] × [y0, y1] at height h over the receiver: inner integral
// in closed form, outer adaptive, both in 50 digits.
TEST(PrecisionSweep, LightAreaKernelOfNearRectangle) {
  WorstError worst;
  struct Placement {
    const char* name;
    double x0, x1, y0, y1;
  };
  for (double h : {1e-1, 1e-2, 1e-3, 1e-4})
    for (const Placement& pl : {Placement{"centred", -0.5, 0.5, -0.5, 0.5}, Placement{"corner", 0, 1, 0, 1},
                                Placement{"outside", 0.2, 1.2, -0.5, 0.5}}) {
      const std::vector<Vec3> vertices{{pl.x0, pl.y0, h}, {pl.x1, pl.y0, h}, {pl.x1, pl.y1, h}, {pl.x0, pl.y1, h}};
      const Big H(h), H4 = H * H * H * H;
      auto outer = [&](const Big& v) {
        const Big c = sqrt(v * v + H * H);
        // ∫_{x0}^{x1} = (F(x1) − F(x0)) with F odd: half the symmetric integrals, signed.
        auto half = [&](double x) { return (x < 0 ? -1 : 1) * power_integral(abs(Big(x)), c, 4) / 2; };
        return H4 * (half(pl.x1) - half(pl.x0));
      };
      std::vector<Big> cuts{Big(pl.y0), Big(pl.y1)};
      if (pl.y0 < 0 && pl.y1 > 0) cuts.insert(cuts.begin() + 1, Big(0));
      Big expected = 0;
      for (size_t i = 0; i + 1 < cuts.size(); ++i) expected += integrate(outer, cuts[i], cuts[i + 1]);
      const double value = polygon_area_kernel(vertices, {0, 0, 1});
      const double err = relative_error(value, expected);
      EXPECT_LE(err, kSweepTolerance) << "h " << h << " " << pl.name;
      worst.note(err, "h " + std::to_string(h) + ", " + pl.name);
    }
  worst.print("light-area kernel, near rectangle");
}

// Multi-sample MIS (one BSDF and one solid-angle light sample) under a unit
// square light centred h above the receiver, facing down: E[Y²] = E[Y_b²] +
// E[Y_l²] + 2·E[Y_b]·E[Y_l], each term ∫ g(cos θ) dω with p_b = cos θ/π and
// p_l = 1/Ω, Ω = 4·atan(ab/(h·√(a² + b² + h²))) (a = b = ½). Reference in 50
// digits: by the square's 8-fold symmetry, φ ∈ [0, π/4] with the edge at
// ρ = ½/cos φ, and the polar angle t about the normal in [0, atan(ρ/h)],
// dω = sin t dt dφ, cos θ = cos t.
TEST(PrecisionSweep, MisMomentsOfNearSquare) {
  WorstError worst;
  for (int beta : {1, 2})
    for (double h : {1e-2, 1e-4, 1e-6}) {
      const Scene scene = scene_with({{"light", Rectangle{{-0.5, -0.5, h}, {0, 1, 0}, {1, 0, 0}}, {}, 1.0}});
      const Big H(h), a(0.5), pi = boost::math::constants::pi<Big>();
      const Big p_light = 1 / (4 * atan(a * a / (H * sqrt(2 * a * a + H * H))));
      auto weight = [&](const Big& x, const Big& y) {
        const Big xb = beta == 2 ? x * x : x, yb = beta == 2 ? y * y : y;
        return xb / (xb + yb);
      };
      auto term = [&](int k) {
        auto g = [&](const Big& c) {
          const Big p_bsdf = c / pi;
          switch (k) {
            case 0: { const Big w = weight(p_bsdf, p_light); return w * w * c * c / p_bsdf; }
            case 1: { const Big w = weight(p_light, p_bsdf); return w * w * c * c / p_light; }
            case 2: return weight(p_bsdf, p_light) * c;
            default: return weight(p_light, p_bsdf) * c;
          }
        };
        auto over_phi = [&](const Big& phi) {
          const Big T = atan(a / (cos(phi) * H));
          return integrate([&](const Big& t) { return g(cos(t)) * sin(t); }, Big(0), T);
        };
        return 8 * integrate(over_phi, Big(0), pi / 4);
      };
      const Big expected = term(0) + term(1) + 2 * term(2) * term(3);
      const Strategy strategy = beta == 2 ? Strategy::kMisPower : Strategy::kMisBalance;
      const double m2 = second_moment(strategy, scene, {0, 0, 0}, {0, 0, 1}, size_t(0));
      const double err = relative_error(m2, expected);
      EXPECT_LE(err, kSweepTolerance) << "beta " << beta << " h " << h;
      worst.note(err, "beta " + std::to_string(beta) + ", h " + std::to_string(h));
    }
  worst.print("MIS moments, near square");
}

}  // namespace
}  // namespace furnace::analytic
