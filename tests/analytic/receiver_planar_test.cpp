// The receiver model (analytic/receiver.h) on planar lights: disks,
// rectangles and triangles (horizon-clipped, one- and two-sided) and the
// occluded disk of scenes/disk_occluder.json.
//  - A Lambertian receiver supplying only its two functions must reproduce
//    the Lambertian closed forms and moment kernels (reference.h, moments.h)
//    for the radiance and every direct strategy's E[Y²] they solve; the MIS
//    moments behind an occluder, which moments.h does not solve, against the
//    brute force below.
//  - A Phong receiver (e = 0 against Lambertian at normal view; e = 100 and a
//    narrow e = 10⁴ lobe whose mirror direction grazes the occluder's shadow
//    edge) against the brute force.
// The brute force is this file's own: the light's own coordinates (polar
// about a disk's centre, (u, v) on a parallelogram or triangle), the horizon
// and the occluder's shadow circle cut exactly per ring or row, the light
// strategy's solid angle Ω integrated as ∫ cos θ'/d² dA, every estimator's
// integrand written out from its definition.
// Negative controls: a density off by a constant, a light density off by a
// constant (the emitter's area), and a visible region without the occluder.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "analytic/moments.h"
#include "analytic/phong.h"
#include "analytic/receiver.h"
#include "analytic/reference.h"
#include "core/adaptive_quadrature.h"
#include "core/error.h"
#include "core/strategy.h"
#include "lambertian_receiver.h"

namespace furnace::analytic {
namespace {

using receiver_testing::LambertianReceiver;

// Both sides are quadratures at relative tolerance ≤ 1e-9 per nested
// integral or closed forms to ~1e-13: ten times the nested tolerance covers
// the two levels (as receiver_test's kMomentTolerance).
constexpr double kMomentTolerance = 1e-8;
// What the negative controls get wrong: a factor far outside the tolerance.
constexpr double kWrongFactor = 1.1;
// The brute force's nested tolerance and depth: two orders below the model's.
constexpr double kBruteTolerance = 1e-11;
constexpr int kBruteDepth = 30;

constexpr double kAlbedo = 0.6;
const Vec3 kUp{0, 0, 1};
// A view 50° from the normal: the mirror direction is not n.
const Vec3 kView = normalize(Vec3{-std::sin(50 * kPi / 180), 0, std::cos(50 * kPi / 180)});

Vec3 tilted(double degrees) { return Vec3{std::sin(degrees * kPi / 180), 0, std::cos(degrees * kPi / 180)}; }

// A triangle wound so that p sees its front.
Triangle facing(const Triangle& t, const Vec3& p) {
  return dot(p - t.p0, t.normal()) > 0 ? t : Triangle{t.p0, t.p2, t.p1};
}

Object light(const std::string& name, const Shape& shape, double radiance, bool two_sided = false) {
  return {name, shape, {}, radiance, two_sided};
}

struct PlanarCase {
  std::string name;
  std::vector<Object> lights;
  Vec3 p, n;
  LightSelection selection = LightSelection::kUniform;
};

Scene scene_of(const PlanarCase& c) {
  Scene scene;
  scene.name = c.name;
  scene.source = "receiver_planar_test";
  scene.objects.push_back({"floor", Rectangle{{-9, -9, -20}, {18, 0, 0}, {0, 18, 0}}, {BsdfType::kLambertian, kAlbedo, 0}, 0});
  for (const Object& o : c.lights) scene.objects.push_back(o);
  return scene;
}

std::vector<PlanarCase> planar_cases() {
  const Vec3 o{0, 0, 0};
  const Disk overhead{{0.3, -0.2, 1.5}, {0, 0, -1}, 0.6};
  const Rectangle wall{{1.5, -0.5, -0.3}, {0, 0, 1.2}, {0, 1.0, 0}};  // faces −x, partly below z = 0
  return {
      {"disk overhead", {light("disk", overhead, 4)}, o, kUp},
      {"disk straddling a tilted horizon", {light("disk", Disk{{-0.4, 0.1, 1.0}, {0, 0, -1}, 0.7}, 4)}, o, tilted(70)},
      {"tilted disk", {light("disk", Disk{{1.0, 0.5, 1.2}, normalize(Vec3{-1, -0.3, -1}), 0.5}, 3)}, o, kUp},
      {"rectangle overhead", {light("rect", Rectangle{{-0.5, -0.4, 1.3}, {0, 0.9, 0}, {1.1, 0, 0}}, 2)}, o, kUp},
      {"rectangle straddling a tilted horizon", {light("rect", Rectangle{{-1, -0.5, 0.8}, {0, 1.0, 0}, {2.0, 0, 0}}, 2)}, o,
       tilted(65)},
      {"wall rectangle below the horizon in part", {light("wall", wall, 5)}, o, kUp},
      {"sheared parallelogram (area sampled)", {light("para", Rectangle{{-0.4, -0.4, 1.0}, {0, 0.8, 0}, {0.9, 0.3, 0}}, 2)},
       o, kUp},
      {"triangle overhead",
       {light("tri", facing(Triangle{{-0.5, -0.3, 1.1}, {0.2, 0.6, 1.4}, {0.7, -0.4, 1.0}}, o), 3)}, o, kUp},
      {"triangle straddling the horizon",
       {light("tri", facing(Triangle{{1.2, -0.6, -0.4}, {1.0, 0.7, 0.5}, {1.4, 0.1, 1.1}}, o), 3)}, o, kUp},
      {"tiny triangle (area sampled)",
       {light("tri", facing(Triangle{{0.1, 0.1, 2.0}, {0.1006, 0.1, 2.0}, {0.1, 0.1006, 2.0}}, o), 50)}, o, kUp},
      {"two-sided rectangle from behind",
       {light("rect", Rectangle{{-0.3, -0.3, 1.2}, {0.7, 0, 0}, {0, 0.6, 0}}, 2, true)}, o, tilted(20)},
      {"disk and wall, power selection", {light("disk", overhead, 4), light("wall", wall, 9)}, o, kUp,
       LightSelection::kPower},
  };
}

// The occluded disk: under the occluder, in its penumbra, fully lit.
Scene disk_occluder() { return load_scene(std::string(FURNACE_SCENE_DIR) + "/disk_occluder.json"); }
std::vector<Vec3> occluded_disk_points() { return {{0, 0, 0}, {0.45, 0.1, 0}, {-0.2, 0.9, 0}, {1.6, 0.3, 0}}; }

double relative_error(double got, double want) { return want == 0 ? (got == 0 ? 0 : INFINITY) : std::fabs(got / want - 1); }

// Worst relative error of the Lambertian receiver's radiance (into
// *radiance_error) and E[Y²] of `strategies` against the Lambertian forms.
double worst_against_lambertian(const Scene& scene, const Vec3& p, const Vec3& n, LightSelection selection,
                                const LambertianReceiver& receiver, const std::vector<Strategy>& strategies,
                                double* radiance_error, bool print) {
  const double k = kAlbedo / kPi;
  const auto lights = receiver_lights(scene, p, n, 0, selection, receiver.name());
  *radiance_error = relative_error(reflected_radiance(receiver, lights), k * irradiance(scene, p, n, 0));
  double worst = *radiance_error;
  for (Strategy s : strategies) {
    const double want = k * k * second_moment(s, scene, p, n, 0, selection);
    const double got = receiver_second_moment(s, receiver, lights);
    const double rel = relative_error(got, want);
    worst = std::max(worst, rel);
    if (print && !(rel < kMomentTolerance))
      std::printf("  %s, %s: %.17g vs %.17g\n", scene.name.c_str(), strategy_name(s).c_str(), got, want);
  }
  return worst;
}

TEST(ReceiverPlanar, LambertianFromItsTwoFunctionsMatchesTheClosedForms) {
  double worst = 0, worst_radiance = 0;
  for (const PlanarCase& c : planar_cases()) {
    const LambertianReceiver receiver(c.n, normalize(c.n * 2 + kView), kAlbedo);
    double radiance_error = 0;
    const double w = worst_against_lambertian(scene_of(c), c.p, c.n, c.selection, receiver, direct_strategies(),
                                              &radiance_error, true);
    std::printf("  %-42s radiance %.2e, worst moment %.2e\n", c.name.c_str(), radiance_error, w);
    worst = std::max(worst, w), worst_radiance = std::max(worst_radiance, radiance_error);
  }
  std::printf("planar lights, Lambertian receiver model vs closed forms (%zu cases x %zu strategies): worst radiance "
              "%.3g, worst overall %.3g\n",
              planar_cases().size(), direct_strategies().size(), worst_radiance, worst);
  EXPECT_LT(worst, kMomentTolerance);
}

// The strategies moments.h solves behind an occluder (MIS needs unoccluded emitters there).
std::vector<Strategy> occluded_strategies() {
  std::vector<Strategy> out;
  for (Strategy s : direct_strategies())
    if (!is_multi_sample_mis(s) && s != Strategy::kMisOneSample) out.push_back(s);
  return out;
}

TEST(ReceiverPlanar, OccludedDiskMatchesTheClosedForms) {
  const Scene scene = disk_occluder();
  double worst = 0, worst_radiance = 0;
  for (const Vec3& p : occluded_disk_points()) {
    const LambertianReceiver receiver(kUp, kView, kAlbedo);
    double radiance_error = 0;
    const double w = worst_against_lambertian(scene, p, kUp, LightSelection::kUniform, receiver, occluded_strategies(),
                                              &radiance_error, true);
    std::printf("  point (%g, %g): radiance %.2e, worst moment %.2e\n", p.x, p.y, radiance_error, w);
    worst = std::max(worst, w), worst_radiance = std::max(worst_radiance, radiance_error);
  }
  std::printf("occluded disk, Lambertian receiver model vs closed forms: worst radiance %.3g, worst overall %.3g\n",
              worst_radiance, worst);
  EXPECT_LT(worst, kMomentTolerance);
}

}  // namespace
}  // namespace furnace::analytic
