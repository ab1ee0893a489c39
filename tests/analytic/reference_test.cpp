// Scene-level dispatch: the default scene's image against closed-form
// decompositions, symmetry, horizon and facing rules, objects that cannot
// block, and refusal (furnace::Error) of unsupported configurations.
#include "analytic/reference.h"

#include <cmath>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "analytic/disk.h"
#include "core/error.h"

namespace furnace::analytic {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

Scene default_scene() { return load_scene(std::string(FURNACE_SCENE_DIR) + "/disk_occluder.json"); }

const Disk& disk_of(const Scene& s, const std::string& name) {
  for (const Object& o : s.objects)
    if (o.name == name) return std::get<Disk>(o.shape);
  throw std::runtime_error("no object " + name);
}
const Object& object_of(const Scene& s, const std::string& name) {
  for (const Object& o : s.objects)
    if (o.name == name) return o;
  throw std::runtime_error("no object " + name);
}

// A hand-built scene: receiver z = 0 (albedo ρ), disk light at z = h facing down.
Scene light_over_floor(double h, double R, double le) {
  Scene scene;
  scene.name = "test";
  scene.source = "reference_test";
  scene.objects.push_back({"floor", Rectangle{{-2, -2, 0}, {4, 0, 0}, {0, 4, 0}}, {0.5, Lambertian{}}, 0});
  scene.objects.push_back({"light", Disk{{0, 0, h}, {0, 0, -1}, R}, {}, le});
  return scene;
}

TEST(DefaultScene, ImageHasOneFiniteNonNegativeValuePerPixel) {
  const Scene scene = default_scene();
  const std::vector<double> image = reference_image(scene);
  ASSERT_EQ(image.size(), size_t(scene.camera.width_px) * scene.camera.height_px);
  for (double v : image) {
    EXPECT_TRUE(std::isfinite(v));
    EXPECT_GE(v, 0);
  }
}

// At the foot of the axis the occluder's image is concentric: the visible
// region is an annulus, E = L·(E_disk(R) − E_disk(ρ·h/h_o)) by two closed forms.
TEST(DefaultScene, AxisPointIsAnnulusDifference) {
  const Scene scene = default_scene();
  const Disk& light = disk_of(scene, "light");
  const Disk& occluder = disk_of(scene, "occluder");
  const double le = object_of(scene, "light").emitted_radiance;
  const double h = light.center.z, image_radius = occluder.radius * h / occluder.center.z;
  const double outer = disk_irradiance_parallel(light.radius, h, 0);
  const double expected = le * (outer - disk_irradiance_parallel(image_radius, h, 0));
  const double value = irradiance(scene, {0, 0, 0}, {0, 0, 1}, size_t(0));
  EXPECT_LE(std::fabs(value - expected), 8 * kEps * le * outer);
}

// Far from the axis the occluder hides nothing (its image misses the light):
// the pixel is (ρ/π)·L·E_disk exactly.
TEST(DefaultScene, CornerPixelIsUnoccludedClosedForm) {
  const Scene scene = default_scene();
  const Disk& light = disk_of(scene, "light");
  const double le = object_of(scene, "light").emitted_radiance;
  const double albedo = object_of(scene, "receiver").material.albedo;
  const Camera::Ray ray = scene.camera.pixel_center_ray(0, 0);
  const Vec3 p = ray.origin + ray.direction * (ray.origin.z / -ray.direction.z);
  const double d = std::hypot(p.x, p.y);
  const double expected = albedo * kInvPi * le * disk_irradiance_parallel(light.radius, light.center.z, d);
  EXPECT_LE(std::fabs(pixel_center_radiance(scene, 0, 0) - expected), 4 * kEps * expected);
}

// The scene is symmetric under x → −x and y → −y; so must the image be (the
// camera's pixel centres are symmetric, the geometry is exactly centred).
TEST(DefaultScene, ImageIsMirrorSymmetric) {
  const Scene scene = default_scene();
  const std::vector<double> image = reference_image(scene);
  const int w = scene.camera.width_px, hgt = scene.camera.height_px;
  double peak = 0;
  for (double v : image) peak = std::max(peak, v);
  for (int py = 0; py < hgt; ++py)
    for (int px = 0; px < w; ++px) {
      const double v = image[size_t(py) * w + px];
      EXPECT_NEAR(v, image[size_t(py) * w + (w - 1 - px)], 64 * kEps * peak);
      EXPECT_NEAR(v, image[size_t(hgt - 1 - py) * w + px], 64 * kEps * peak);
    }
}

TEST(Irradiance, ReceiverFacingAwayOrBehindLightGetsNothing) {
  const Scene scene = light_over_floor(2.0, 0.75, 4.0);
  EXPECT_EQ(irradiance(scene, {0, 0, 0}, {0, 0, -1}, size_t(0)), 0.0);  // faces away
  EXPECT_EQ(irradiance(scene, {0, 0, 3}, {0, 0, 1}, std::nullopt), 0.0);   // above the light's back
  EXPECT_EQ(irradiance(scene, {0, 0, 2}, {0, 0, 1}, std::nullopt), 0.0);   // in the light's plane
}

TEST(Irradiance, UnoccludedDiskIsClosedForm) {
  const double le = 4.0;
  const Scene scene = light_over_floor(2.0, 0.75, le);
  const double value = irradiance(scene, {0.3, -0.4, 0}, {0, 0, 1}, size_t(0));
  EXPECT_EQ(value, le * disk_irradiance_parallel(0.75, 2.0, 0.5));
}

TEST(Irradiance, ObjectsThatCannotBlockAreIgnored) {
  Scene scene = light_over_floor(2.0, 0.75, 4.0);
  const double alone = irradiance(scene, {0, 0, 0}, {0, 0, 1}, size_t(0));
  scene.objects.push_back({"side_sphere", Sphere{{3, 0, 1}, 0.5}, {}, 0});         // outside the cone
  scene.objects.push_back({"above_light", Triangle{{0, 0, 3}, {1, 0, 3}, {0, 1, 3}}, {}, 0});  // beyond the light
  scene.objects.push_back({"below_floor", Sphere{{0, 0, -2}, 1.0}, {}, 0});       // under p's plane
  scene.objects.push_back({"tilted_far", Disk{{-2, 2, 1}, normalize(Vec3{1, 1, 1}), 0.3}, {}, 0});
  EXPECT_EQ(irradiance(scene, {0, 0, 0}, {0, 0, 1}, size_t(0)), alone);
}

TEST(Irradiance, ParallelDiskOccluderCoveringTheLightGivesExactZero) {
  Scene scene = light_over_floor(2.0, 0.75, 4.0);
  scene.objects.push_back({"cover", Disk{{0, 0, 1}, {0, 0, 1}, 0.5}, {}, 0});  // image radius 1.0 ⊃ light
  EXPECT_EQ(irradiance(scene, {0, 0, 0}, {0, 0, 1}, size_t(0)), 0.0);
}

TEST(Irradiance, UnsupportedBlockersAreRefusedWithTheirName) {
  Scene scene = light_over_floor(2.0, 0.75, 4.0);
  scene.objects.push_back({"ball_in_the_way", Sphere{{0, 0, 1}, 0.2}, {}, 0});
  try {
    irradiance(scene, {0, 0, 0}, {0, 0, 1}, size_t(0));
    FAIL() << "expected furnace::Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("ball_in_the_way"), std::string::npos) << e.what();
  }
}

TEST(Irradiance, UnoccludedEnvironmentIsPiTimesRadiance) {
  Scene scene;
  scene.name = "env";
  scene.objects.push_back({"floor", Rectangle{{-2, -2, 0}, {4, 0, 0}, {0, 4, 0}}, {0.5, Lambertian{}}, 0});
  scene.environment.radiance = 0.7;
  EXPECT_EQ(irradiance(scene, {0, 0, 0}, {0, 0, 1}, size_t(0)), kPi * 0.7);
}

TEST(PixelCenterRadiance, MissSeesEnvironmentAndLightSeesItsEmission) {
  Scene scene = light_over_floor(2.0, 0.75, 4.0);
  scene.environment.radiance = 0.25;
  scene.objects.erase(scene.objects.begin());  // no floor
  scene.camera.center = {0, 0, 0};
  scene.camera.forward = {0, 0, 1};  // looking up at the light's emitting face
  scene.camera.up = {0, 1, 0};
  scene.camera.width = scene.camera.height = 4;
  scene.camera.width_px = scene.camera.height_px = 4;
  EXPECT_EQ(pixel_center_radiance(scene, 1, 1), 4.0);   // centre (−0.5, 0.5): on the light
  EXPECT_EQ(pixel_center_radiance(scene, 0, 0), 0.25);  // corner (−1.5, 1.5): misses
}

}  // namespace
}  // namespace furnace::analytic
