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
#include <filesystem>
#include <limits>
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
#include "receiver_brute_force.h"

namespace furnace::analytic {
namespace {

// LambertianReceiver (lambertian_receiver.h) and the brute force (receiver_brute_force.h).
using namespace receiver_testing;

// Both sides are quadratures at relative tolerance ≤ 1e-9 per nested
// integral or closed forms to ~1e-13: ten times the nested tolerance covers
// the two levels (as receiver_test's kMomentTolerance).
constexpr double kMomentTolerance = 1e-8;
// What the negative controls get wrong: a factor far outside the tolerance.
constexpr double kWrongFactor = 1.1;

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
  scene.objects.push_back({"floor", Rectangle{{-9, -9, -20}, {18, 0, 0}, {0, 18, 0}}, {kAlbedo, Lambertian{}}, 0});
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

// Worst relative error of the model against the brute force over radiance and every direct strategy.
double worst_against_brute_force(const Scene& scene, const Vec3& p, const Receiver& receiver, LightSelection selection,
                                 const char* label, double lobe_width = 0) {
  const auto lights = receiver_lights(scene, p, receiver.n, 0, selection, receiver.name());
  const BruteResult want = brute_force(scene, p, receiver, selection, lobe_width);
  double worst = relative_error(reflected_radiance(receiver, lights), want.radiance);
  const double radiance_error = worst;
  for (const auto& [s, m] : want.moments) {
    const double got = receiver_second_moment(s, receiver, lights), rel = relative_error(got, m);
    if (!(rel < kMomentTolerance))
      std::printf("  %s, %s: %.17g vs brute force %.17g\n", label, strategy_name(s).c_str(), got, m);
    worst = std::max(worst, rel);
  }
  std::printf("  %-46s radiance %.2e, worst %.2e\n", label, radiance_error, worst);
  return worst;
}

// A view whose mirror direction points at `target` from p (normal n).
Vec3 view_toward(const Vec3& p, const Vec3& n, const Vec3& target) {
  const Vec3 r = normalize(target - p);
  return normalize(n * (2 * dot(n, r)) - r);
}

Vec3 light_centre(const Object& light) {
  return std::visit(overloaded{[](const Disk& d) { return d.center; },
                               [](const Rectangle& r) { return r.corner + (r.edge_u + r.edge_v) * 0.5; },
                               [](const Triangle& t) { return (t.p0 + t.p1 + t.p2) / 3.0; },
                               [](const Sphere& s) { return s.center; }},
                    light.shape);
}

TEST(ReceiverPlanar, PhongMatchesTheBruteForce) {
  double worst = 0;
  for (const PlanarCase& c : planar_cases()) {
    const Scene scene = scene_of(c);
    // The lobe aimed at the (first) light's centre, then 50° off the normal.
    for (const Vec3& wo : {view_toward(c.p, c.n, light_centre(c.lights[0])), normalize(c.n * 2 + kView)}) {
      const PhongReceiver phong(c.n, wo, 0.8, 100);
      worst = std::max(worst, worst_against_brute_force(scene, c.p, phong, c.selection, c.name.c_str()));
    }
  }
  const Scene scene = disk_occluder();
  for (const Vec3& p : occluded_disk_points()) {
    const PhongReceiver phong(kUp, view_toward(p, kUp, Vec3{0.5, 0.3, 2}), 0.8, 100);
    const std::string label = "occluded disk at (" + std::to_string(p.x) + ", " + std::to_string(p.y) + ")";
    worst = std::max(worst, worst_against_brute_force(scene, p, phong, LightSelection::kUniform, label.c_str()));
  }
  std::printf("Phong e = 100 on the receiver model vs brute force: worst relative error %.3g\n", worst);
  EXPECT_LT(worst, kMomentTolerance);
}

TEST(ReceiverPlanar, OccludedDiskMisAgainstTheBruteForce) {
  // moments.h solves MIS for unoccluded emitters only: the Lambertian
  // receiver's MIS moments behind the occluder against the brute force.
  const Scene scene = disk_occluder();
  double worst = 0;
  for (const Vec3& p : occluded_disk_points()) {
    const LambertianReceiver receiver(kUp, kView, kAlbedo);
    const std::string label = "Lambertian, occluded disk at (" + std::to_string(p.x) + ", " + std::to_string(p.y) + ")";
    worst = std::max(worst, worst_against_brute_force(scene, p, receiver, LightSelection::kUniform, label.c_str()));
  }
  EXPECT_LT(worst, kMomentTolerance);
}

TEST(ReceiverPlanar, PhongOfExponentZeroAtNormalViewIsLambertian) {
  // At ωo = n the mirror is n, so e = 0 is f = ρ/π over the whole hemisphere
  // with p_b = 1/(2π): the radiance and the light and hemisphere strategies
  // are Lambertian's, and Phong's bsdf sampling is uniform_hemisphere.
  const double k = kAlbedo / kPi;
  double worst = 0;
  auto check = [&](const Scene& scene, const Vec3& p, const Vec3& n, LightSelection selection) {
    const PhongReceiver phong(n, n, kAlbedo, 0);
    const auto lights = receiver_lights(scene, p, n, 0, selection, phong.name());
    worst = std::max(worst, relative_error(reflected_radiance(phong, lights), k * irradiance(scene, p, n, 0)));
    for (Strategy s : {Strategy::kUniformHemisphere, Strategy::kCosineHemisphere, Strategy::kLightArea,
                       Strategy::kLightSolidAngle})
      worst = std::max(worst, relative_error(receiver_second_moment(s, phong, lights),
                                             k * k * second_moment(s, scene, p, n, 0, selection)));
    worst = std::max(worst, relative_error(receiver_second_moment(Strategy::kBsdf, phong, lights),
                                           k * k * second_moment(Strategy::kUniformHemisphere, scene, p, n, 0, selection)));
  };
  for (const PlanarCase& c : planar_cases()) check(scene_of(c), c.p, c.n, c.selection);
  for (const Vec3& p : occluded_disk_points()) check(disk_occluder(), p, kUp, LightSelection::kUniform);
  std::printf("Phong e = 0 at normal view vs Lambertian closed forms: worst relative error %.3g\n", worst);
  EXPECT_LT(worst, kMomentTolerance);
}

// A point in the penumbra whose mirror direction meets the light's plane
// `offset` outside the occluder's shadow circle (inside the lit ring), along
// the line through the circle's centre.
struct ShadowEdgeView {
  Vec3 p, wo;
};
ShadowEdgeView shadow_edge_view(double offset) {
  const Scene scene = disk_occluder();
  const Vec3 p{0.45, 0.1, 0};
  const auto& light = std::get<Disk>(scene.objects[1].shape);
  const auto& occluder = std::get<Disk>(scene.objects[2].shape);
  const double h = light.center.z - p.z, h_o = occluder.center.z - p.z;
  const Vec3 image = p + (occluder.center - p) * (h / h_o);  // the shadow circle's centre on the light's plane
  const Vec3 outward = normalize(Vec3{light.center.x - image.x, light.center.y - image.y, 0});
  const Vec3 target = image + outward * (occluder.radius * h / h_o + offset);
  return {p, view_toward(p, kUp, target)};
}

TEST(ReceiverPlanar, NarrowLobeAtTheShadowEdgeMatchesTheBruteForce) {
  // Phong e = 10⁴ (lobe width ~ 1/√e = 0.01 rad, ~0.02 on the light's plane)
  // with its peak 0.005 outside the shadow edge, and 0.005 inside it.
  const Scene scene = disk_occluder();
  double worst = 0;
  for (double offset : {0.005, -0.005}) {
    const ShadowEdgeView v = shadow_edge_view(offset);
    const PhongReceiver phong(kUp, v.wo, 0.8, 1e4);
    const std::string label = "e = 1e4, peak " + std::to_string(offset) + " from the shadow edge";
    worst = std::max(worst, worst_against_brute_force(scene, v.p, phong, LightSelection::kUniform, label.c_str(),
                                                      1 / std::sqrt(phong.exponent)));
  }
  EXPECT_LT(worst, kMomentTolerance);
}

// Lobes of GGX's widths (α = 1e-3 is a width ~1e-3 rad, Phong e ~ 1e6) at the
// shadow edge: the radiance against the brute force (radiance term only),
// and the model's cost. Label slow (tests/analytic/CMakeLists.txt): the brute
// force takes half a minute to minutes.
TEST(ReceiverPlanarSlow, GgxWidthLobesAtTheShadowEdge) {
  const Scene scene = disk_occluder();
  for (double exponent : {1e5, 1e6, 4e6})
    for (double offset : {0.0005, -0.0005, 0.002}) {
      const ShadowEdgeView v = shadow_edge_view(offset);
      const PhongReceiver phong(kUp, v.wo, 0.8, exponent);
      const auto start = std::chrono::steady_clock::now();
      const auto lights = receiver_lights(scene, v.p, kUp, 0, LightSelection::kUniform, phong.name());
      const double got = reflected_radiance(phong, lights);
      const auto middle = std::chrono::steady_clock::now();
      const double mis = receiver_second_moment(Strategy::kMisBalance, phong, lights);
      const auto end = std::chrono::steady_clock::now();
      BruteLight light;
      light.object = &scene.objects[1];
      light.front = Vec3{0, 0, -1};
      light.lobe_width = 1 / std::sqrt(exponent);
      light.inner_tolerance = std::max(kBruteInnerTolerance, kNoiseUlps * std::numeric_limits<double>::epsilon() * exponent);
      light.outer_tolerance = 10 * light.inner_tolerance;
      const Disk& disk = std::get<Disk>(scene.objects[1].shape);
      const Disk& occluder = std::get<Disk>(scene.objects[2].shape);
      const double scale = (disk.center.z - v.p.z) / (occluder.center.z - v.p.z);
      const Vec3 image = v.p + (occluder.center - v.p) * scale - disk.center;
      const Frame f = Frame::from_normal(disk.normal);
      light.shadow = Circle2{dot(image, f.s), dot(image, f.t), occluder.radius * scale};
      const double want = disk_terms(phong, light, disk, v.p, radiance_at)[kRadiance];
      const auto brute_end = std::chrono::steady_clock::now();
      std::printf("e = %g, peak %+g from the shadow edge: radiance rel. error %.2e; model radiance %.1f ms, mis_balance "
                  "%.1f ms (E[Y^2] %.6g); brute force %.0f ms\n",
                  exponent, offset, relative_error(got, want), std::chrono::duration<double, std::milli>(middle - start).count(),
                  std::chrono::duration<double, std::milli>(end - middle).count(), mis,
                  std::chrono::duration<double, std::milli>(brute_end - end).count());
    }
}

TEST(ReceiverPlanar, SceneFilesMatchTheLambertianReferencesWhereSolved) {
  // Every scene file, at the hit points of a 5×5 grid of pixel centres on a
  // Lambertian surface: where the receiver model solves the lights, the
  // Lambertian receiver on it must give the Lambertian reference's radiance
  // and every strategy's E[Y²] the Lambertian moments solve.
  double worst = 0;
  size_t solved = 0, refused = 0;
  for (const auto& entry : std::filesystem::directory_iterator(FURNACE_SCENE_DIR)) {
    if (entry.path().extension() != ".json") continue;
    const Scene scene = load_scene(entry.path());
    size_t scene_solved = 0, scene_refused = 0;
    for (int j = 0; j < 5; ++j)
      for (int i = 0; i < 5; ++i) {
        const int px = (2 * i + 1) * scene.camera.width_px / 10, py = (2 * j + 1) * scene.camera.height_px / 10;
        const Camera::Ray ray = scene.camera.pixel_center_ray(px, py);
        const std::optional<Hit> hit = intersect(scene, ray.origin, ray.direction);
        if (!hit) continue;
        const Object& object = scene.objects[hit->object_index];
        if (!object.material.as<Lambertian>() || object.material.albedo == 0) continue;
        const Vec3 n = dot(ray.direction, hit->normal) < 0 ? hit->normal : -hit->normal;
        const LambertianReceiver receiver(n, -ray.direction, kAlbedo);
        std::vector<ReceiverLight> lights;
        try {
          lights = receiver_lights(scene, hit->point, n, hit->object_index, LightSelection::kUniform, receiver.name());
        } catch (const Error&) {
          ++scene_refused;
          continue;
        }
        ++scene_solved;
        const double k = kAlbedo / kPi;
        worst = std::max(worst, relative_error(reflected_radiance(receiver, lights),
                                               k * irradiance(scene, hit->point, n, hit->object_index)));
        for (Strategy s : direct_strategies()) {
          double want = 0;
          try {
            want = k * k * second_moment(s, scene, hit->point, n, hit->object_index);
          } catch (const Error&) {
            continue;  // the Lambertian moments do not solve it (MIS behind an occluder)
          }
          const double rel = relative_error(receiver_second_moment(s, receiver, lights), want);
          if (!(rel < kMomentTolerance))
            std::printf("  %s pixel (%d, %d), %s: relative error %.3g\n", scene.name.c_str(), px, py,
                        strategy_name(s).c_str(), rel);
          worst = std::max(worst, rel);
        }
      }
    std::printf("  %-28s %2zu points solved, %2zu refused\n", scene.name.c_str(), scene_solved, scene_refused);
    solved += scene_solved, refused += scene_refused;
  }
  std::printf("scene files: %zu Lambertian points solved, %zu refused; worst relative error %.3g\n", solved, refused,
              worst);
  EXPECT_GT(solved, 0u);
  EXPECT_LT(worst, kMomentTolerance);
}

TEST(ReceiverPlanar, NegativeControlsAreCaught) {
  const std::vector<PlanarCase> cases = planar_cases();
  // A BSDF density off by a constant.
  double wrong_pdf = 0, radiance_error = 0;
  for (const PlanarCase& c : cases) {
    const LambertianReceiver wrong(c.n, normalize(c.n * 2 + kView), kAlbedo, kWrongFactor);
    wrong_pdf = std::max(wrong_pdf, worst_against_lambertian(scene_of(c), c.p, c.n, c.selection, wrong,
                                                             direct_strategies(), &radiance_error, false));
  }
  // The light density off by a constant: the emitter's area 1.1 times too large.
  const Scene overhead = scene_of(cases[0]);
  const LambertianReceiver right(kUp, kView, kAlbedo);
  auto lights = receiver_lights(overhead, Vec3{}, kUp, 0, LightSelection::kUniform, right.name());
  const double want_area = (kAlbedo / kPi) * (kAlbedo / kPi) * second_moment(Strategy::kLightArea, overhead, Vec3{}, kUp, 0);
  lights[0].planar->area *= kWrongFactor;
  const double wrong_area = relative_error(receiver_second_moment(Strategy::kLightArea, right, lights), want_area);
  // The visible region without the occluder: the lights of the scene with the
  // occluder removed, against the references of the scene with it.
  const Scene scene = disk_occluder();
  Scene unoccluded = scene;
  unoccluded.objects.pop_back();
  ASSERT_EQ(std::get_if<Disk>(&scene.objects.back().shape)->radius, 0.35);  // the occluder is the last object
  double no_occluder = 0;
  for (const Vec3& p : {occluded_disk_points()[0], occluded_disk_points()[1]}) {
    const auto wrong_lights = receiver_lights(unoccluded, p, kUp, 0, LightSelection::kUniform, right.name());
    const LambertianReceiver at_p(kUp, kView, kAlbedo);
    no_occluder = std::max(no_occluder, relative_error(reflected_radiance(at_p, wrong_lights),
                                                       kAlbedo / kPi * irradiance(scene, p, kUp, 0)));
  }
  std::printf("negative controls: density x%.2g worst %.3g, light area x%.2g %.3g, occluder forgotten %.3g\n",
              kWrongFactor, wrong_pdf, kWrongFactor, wrong_area, no_occluder);
  EXPECT_GT(wrong_pdf, kMomentTolerance);
  EXPECT_GT(wrong_area, kMomentTolerance);
  EXPECT_GT(no_occluder, kMomentTolerance);
}

TEST(ReceiverPlanar, RefusesOtherOccluders) {
  // A tilted disk between the receiving point and the light: refused, naming it.
  Scene scene = disk_occluder();
  std::get<Disk>(scene.objects[2].shape).normal = normalize(Vec3{0.3, 0, 1});
  const LambertianReceiver receiver(kUp, kView, kAlbedo);
  try {
    receiver_lights(scene, Vec3{}, kUp, 0, LightSelection::kUniform, receiver.name());
    FAIL() << "a tilted occluder was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'occluder'"), std::string::npos) << e.what();
  }
}

TEST(ReceiverPlanar, BackFacingLightsGiveExactZero) {
  PlanarCase c{"one-sided rectangle from behind", {light("rect", Rectangle{{-0.3, -0.3, 1.2}, {0.7, 0, 0}, {0, 0.6, 0}}, 2)},
               Vec3{}, kUp};
  const LambertianReceiver receiver(kUp, kView, kAlbedo);
  const auto lights = receiver_lights(scene_of(c), c.p, c.n, 0, LightSelection::kUniform, receiver.name());
  EXPECT_TRUE(lights.empty());
  EXPECT_EQ(reflected_radiance(receiver, lights), 0.0);
}

TEST(ReceiverPlanar, CostAtAnOccludedDiskPoint) {
  // Wall-clock cost of one radiance and one multi-sample MIS moment at the
  // penumbra point (reported, not asserted: the machine is shared).
  const Scene scene = disk_occluder();
  for (double exponent : {100.0, 1e4}) {
    const ShadowEdgeView v = shadow_edge_view(0.005);
    const PhongReceiver phong(kUp, v.wo, 0.8, exponent);
    const auto start = std::chrono::steady_clock::now();
    const auto lights = receiver_lights(scene, v.p, kUp, 0, LightSelection::kUniform, phong.name());
    const double radiance = reflected_radiance(phong, lights);
    const auto middle = std::chrono::steady_clock::now();
    const double moment = receiver_second_moment(Strategy::kMisBalance, phong, lights);
    const auto end = std::chrono::steady_clock::now();
    std::printf("Phong e = %g at the shadow edge: radiance %.6g in %.2f ms (lights included), mis_balance E[Y^2] %.6g "
                "in %.2f ms\n",
                exponent, radiance, std::chrono::duration<double, std::milli>(middle - start).count(), moment,
                std::chrono::duration<double, std::milli>(end - middle).count());
    EXPECT_GT(radiance, 0);
  }
}

}  // namespace
}  // namespace furnace::analytic
