// require_unoccluded (analytic/emitter.h): which objects provably block
// nothing of an emitter, so that its unoccluded kernels (second moments)
// apply. Beyond the ball-cone test, a planar emitter admits every object
// wholly on the far side of its plane, and one that reaches the plane only
// from there when the two are apart (a coplanar light beside it, as in the
// built-in scene grazing_emitters); anything that could meet a segment from
// the receiving point to the light is still refused.
#include "analytic/emitter.h"

#include <gtest/gtest.h>

#include "analytic/moments.h"
#include "core/error.h"
#include "core/strategy.h"

namespace furnace::analytic {
namespace {

// A floor (the receiver, object 0), a rectangle light standing in the plane
// x = 0 facing +x (object 1), and `other` (object 2); p just in front of the
// light's plane, near grazing.
Scene scene_with(const Shape& other) {
  Scene scene;
  scene.name = "emitter_test";
  scene.source = "emitter_test";
  scene.objects.push_back({"floor", Rectangle{{-1, -1.5, 0}, {2, 0, 0}, {0, 3, 0}}, {0.5, Lambertian{}}, 0});
  scene.objects.push_back({"light", Rectangle{{0, 0.15, 0.5}, {0, 0.7, 0}, {0, 0, 0.7}}, {}, 4.0});
  scene.objects.push_back({"other", other, {0.5, Lambertian{}}, 0});
  return scene;
}

const Vec3 kP{0.01, -0.9, 0};
const Vec3 kN{0, 0, 1};

bool admitted(const Shape& other) {
  try {
    require_unoccluded(scene_with(other), 1, kP, kN, size_t(0));
    return true;
  } catch (const Error&) {
    return false;
  }
}

TEST(RequireUnoccluded, CoplanarObjectApartFromThePlanarLightCannotBlock) {
  EXPECT_TRUE(admitted(Disk{{0, -0.5, 0.85}, {1, 0, 0}, 0.35}));
  EXPECT_TRUE(admitted(Disk{{0, -0.5, 0.85}, {-1, 0, 0}, 0.35}));  // either orientation
}

TEST(RequireUnoccluded, ObjectWhollyBehindThePlanarLightCannotBlock) {
  EXPECT_TRUE(admitted(Disk{{-0.2, 0.5, 0.85}, {1, 0, 0}, 0.6}));  // covers the light in projection
  EXPECT_TRUE(admitted(Sphere{{-0.5, 0.5, 0.85}, 0.4}));
}

// Negative controls: what can meet a segment from p to the light stays refused.
TEST(RequireUnoccluded, ObjectsThatCouldBlockAreStillRefused) {
  EXPECT_FALSE(admitted(Disk{{1e-9, 0.5, 0.85}, {1, 0, 0}, 0.6}));  // a hair in front, covering the light
  EXPECT_FALSE(admitted(Disk{{0, 0.5, 0.85}, {1, 0, 0}, 0.3}));     // coplanar, on the light itself
  EXPECT_FALSE(admitted(Disk{{0, -0.1, 0.85}, {0, 1, 0}, 0.3}));    // standing across the plane
  EXPECT_FALSE(admitted(Sphere{{0.005, -0.3, 0.3}, 0.1}));          // between p and the light
}

// The kernels then see only the light: the light_area second moment with the
// coplanar disk beside it equals the one without it, to the bit.
TEST(RequireUnoccluded, AdmittedCoplanarObjectLeavesTheSecondMomentAlone) {
  const Scene with = scene_with(Disk{{0, -0.5, 0.85}, {1, 0, 0}, 0.35});
  Scene without = with;
  without.objects.pop_back();
  for (Strategy s : {Strategy::kLightArea, Strategy::kLightSolidAngle, Strategy::kMisPower}) {
    const double a = second_moment(s, with, kP, kN, size_t(0));
    EXPECT_GT(a, 0);
    EXPECT_EQ(a, second_moment(s, without, kP, kN, size_t(0))) << strategy_name(s);
  }
}

}  // namespace
}  // namespace furnace::analytic
