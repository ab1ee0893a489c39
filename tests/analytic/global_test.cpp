// Global-illumination closed forms (analytic/global.h): the truncated
// Neumann series against its explicit sum, the limits ρ → 0, ρ → 1 and
// unlimited depth, and the scene classification's refusals.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "analytic/global.h"
#include "core/error.h"
#include "core/scene.h"

namespace furnace::analytic {
namespace {

// Relative tolerance for the closed form against the explicit sum: the sum of
// k ≤ 200 positive terms accumulates at most ~k/2 ulps of rounding.
constexpr double kSeriesTolerance = 128 * std::numeric_limits<double>::epsilon();

double explicit_series(double le, double rho, int segments) {
  double sum = 0, term = le;
  for (int j = 0; j < segments; ++j, term *= rho) sum += term;
  return sum;
}

TEST(UniformEnclosure, ClosedFormMatchesExplicitNeumannSum) {
  for (double rho : {0.0, 0.1, 0.5, 0.9, 0.99, 0.999999})
    for (int k : {1, 2, 3, 4, 8, 64, 200}) {
      const double expected = explicit_series(2.5, rho, k);
      EXPECT_NEAR(uniform_enclosure_radiance(2.5, rho, k), expected, kSeriesTolerance * expected)
          << "rho " << rho << " k " << k;
    }
}

TEST(UniformEnclosure, Limits) {
  EXPECT_DOUBLE_EQ(uniform_enclosure_radiance(3, 0.9, kUnlimitedDepth), 3 / (1 - 0.9));
  EXPECT_EQ(uniform_enclosure_radiance(3, 1.0, 7), 21.0);  // ρ = 1: k terms of Le
  EXPECT_EQ(uniform_enclosure_radiance(3, 0.0, 5), 3.0);   // black walls: emission only
  // ρ → 1 at finite depth: no cancellation in 1 − ρ^k (relative 1e-15 away from k·Le).
  const double rho = 1 - 1e-12;
  EXPECT_NEAR(uniform_enclosure_radiance(1, rho, 10), 10 * (1 - 4.5e-12), 1e-14);
}

TEST(ConvexFurnace, OneBounceOfTheEnvironment) {
  EXPECT_EQ(convex_furnace_radiance(2, 0.6, 1), 0.0);
  EXPECT_DOUBLE_EQ(convex_furnace_radiance(2, 0.6, 2), 1.2);
  EXPECT_DOUBLE_EQ(convex_furnace_radiance(2, 0.6, kUnlimitedDepth), 1.2);
}

const char* kBlockerScene = R"({
  "name": "blocker", "closed": true,
  "camera": {"type": "orthographic", "center": [0, 0, 0.7], "forward": [0, 0, -1], "up": [0, 1, 0],
             "size": [1, 1], "resolution": [2, 2]},
  "objects": [
    {"shape": {"type": "rectangle", "corner": [-1, -1, -1], "edge_u": [2, 0, 0], "edge_v": [0, 2, 0]}, "material": {"type": "lambertian", "albedo": 0.5}, "emission": 1},
    {"shape": {"type": "rectangle", "corner": [-1, -1, 1], "edge_u": [0, 2, 0], "edge_v": [2, 0, 0]}, "material": {"type": "lambertian", "albedo": 0.5}, "emission": 1},
    {"shape": {"type": "rectangle", "corner": [-1, -1, -1], "edge_u": [0, 2, 0], "edge_v": [0, 0, 2]}, "material": {"type": "lambertian", "albedo": 0.5}, "emission": 1},
    {"shape": {"type": "rectangle", "corner": [1, -1, -1], "edge_u": [0, 0, 2], "edge_v": [0, 2, 0]}, "material": {"type": "lambertian", "albedo": 0.5}, "emission": 1},
    {"shape": {"type": "rectangle", "corner": [-1, -1, -1], "edge_u": [0, 0, 2], "edge_v": [2, 0, 0]}, "material": {"type": "lambertian", "albedo": 0.5}, "emission": 1},
    {"shape": {"type": "rectangle", "corner": [-1, 1, -1], "edge_u": [2, 0, 0], "edge_v": [0, 0, 2]}, "material": {"type": "lambertian", "albedo": 0.5}, "emission": 1},
    {"name": "card", "shape": {"type": "disk", "center": [0.3, 0.2, 0.1], "normal": [0, 0, 1], "radius": 0.2}, "material": {"type": "lambertian", "albedo": 0.5}, "emission": 1, "two_sided": true}
  ]
})";

TEST(GlobalReference, EnclosureWithTwoSidedBlockerIsUniform) {
  const Scene scene = parse_scene(kBlockerScene, "blocker.json");
  for (double v : global_reference_image(scene, kUnlimitedDepth)) EXPECT_DOUBLE_EQ(v, 2.0);
  for (double v : global_reference_image(scene, 3)) EXPECT_DOUBLE_EQ(v, 1.75);
}

// Negative control: the same blocker emitting on one side only is refused,
// naming it (the renderer gives 1.617 where Le/(1−ρ) says 1.667 for such a scene).
TEST(GlobalReference, OneSidedInteriorEmitterIsRefused) {
  std::string text = kBlockerScene;
  const std::string two_sided = ", \"two_sided\": true";
  text.erase(text.find(two_sided), two_sided.size());
  const Scene scene = parse_scene(text, "blocker.json");
  try {
    global_reference_image(scene, kUnlimitedDepth);
    FAIL() << "accepted a one-sided interior emitter";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'card'"), std::string::npos) << e.what();
  }
}

TEST(GlobalReference, OpenSceneWithSeveralReflectorsIsRefused) {
  std::string text = kBlockerScene;
  text.replace(text.find("\"closed\": true"), 14, "\"closed\": false");
  EXPECT_THROW(global_reference_image(parse_scene(text, "open.json"), 4), Error);
}

}  // namespace
}  // namespace furnace::analytic
