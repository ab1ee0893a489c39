// occluded_disk_irradiance (arc Boolean + contour integral) against an
// independent polar area quadrature, exact zeros when the light is hidden,
// and exact reductions (no occluder, disjoint occluder, concentric annulus).
#include "analytic/circle_region.h"

#include <cmath>
#include <limits>
#include <ostream>
#include <string>

#include <gtest/gtest.h>

#include "core/error.h"
#include "core/vec3.h"
#include "region_quadrature.h"

namespace furnace::analytic {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

struct OccludedCase {
  std::string name;
  double h;
  Circle2 light;
  std::vector<Circle2> occluders;
};

void PrintTo(const OccludedCase& c, std::ostream* os) { *os << c.name; }

// Default scene (light R = 0.75 at h = 2, occluder ρ = 0.35 at h_o = 1, so
// image radius 0.7 centred at −2·p_xy while the light centre is at −p_xy)
// seen from receiver points p = (x, 0).
OccludedCase default_scene_at(const std::string& name, double x) {
  return {name, 2.0, {-x, 0, 0.75}, {{-2 * x, 0, 0.7}}};
}

std::vector<OccludedCase> all_occluded_cases() {
  return {
      default_scene_at("DefaultSceneCentreAnnulus", 0.0),
      default_scene_at("DefaultSceneImageInsideOffCentre", 0.04),
      default_scene_at("DefaultScenePartialOverlap", 0.3),
      default_scene_at("DefaultSceneSliver", 1.4),
      {"OccluderCoversFootPoint", 0.5, {0.2, 0.1, 1.0}, {{0.0, 0.0, 0.5}}},
      {"TwoOverlappingOccluders", 1.0, {0, 0, 1.0}, {{0.5, 0, 0.5}, {0.2, 0.4, 0.45}}},
      {"TwoDisjointHoles", 1.0, {0, 0, 1.0}, {{0.5, 0, 0.3}, {-0.4, -0.2, 0.35}}},
      {"ThreeOccludersChain", 0.7, {0.3, 0, 1.2}, {{0.0, 0.0, 0.6}, {0.7, 0.3, 0.6}, {1.2, -0.4, 0.5}}},
      {"OccluderSplitsLightInTwo", 1.0, {0, 0, 1.0}, {{0, 0.0, 0.0}, {0, 0, 0}, {-1.0, 0, 0.9}, {1.0, 0, 0.9}}},
      {"NearPlanePartial", 0.05, {0, 0, 1.0}, {{0.6, 0.2, 0.5}}},
      {"FarLightPartial", 20.0, {1.0, 0.5, 0.8}, {{1.5, 0.5, 0.6}}},
  };
}

class OccludedDisk : public testing::TestWithParam<OccludedCase> {};

// Tolerance 1e-11 relative: the quadrature is split at every kink but still
// limited by its requested 1e-14/1e-15 per level and by nesting.
TEST_P(OccludedDisk, MatchesPolarAreaQuadrature) {
  const OccludedCase& c = GetParam();
  const double value = occluded_disk_irradiance(c.h, c.light, c.occluders);
  const double expected = testing_support::visible_irradiance_quadrature(c.h, c.light, c.occluders);
  ASSERT_GT(expected, 0);
  EXPECT_LE(std::fabs(value - expected) / expected, 1e-11) << "value " << value << " quadrature " << expected;
}

INSTANTIATE_TEST_SUITE_P(Configurations, OccludedDisk, testing::ValuesIn(all_occluded_cases()),
                         [](const auto& info) { return info.param.name; });

TEST(OccludedDiskExact, NoOccluderIsTheClosedFormBitForBit) {
  const Circle2 light{0.3, -0.2, 0.75};
  EXPECT_EQ(occluded_disk_irradiance(2.0, light, {}), disk_irradiance_parallel(0.75, 2.0, std::hypot(0.3, -0.2)));
}

TEST(OccludedDiskExact, DisjointOccluderChangesNothing) {
  const Circle2 light{0.3, -0.2, 0.75};
  EXPECT_EQ(occluded_disk_irradiance(2.0, light, {{3.0, 0, 1.0}}), occluded_disk_irradiance(2.0, light, {}));
}

// A concentric hole: E(annulus) = E(R_outer) − E(R_inner), both closed forms.
// The contour sums the same two full turns, so only the subtraction rounds:
// 4 ulps of the larger term relative to the result.
TEST(OccludedDiskExact, ConcentricAnnulusIsDifferenceOfDisks) {
  for (double inner : {0.01, 0.3, 0.7}) {
    const double h = 2.0, outer = 0.75;
    const double outer_e = disk_irradiance_parallel(outer, h, 0);
    const double expected = outer_e - disk_irradiance_parallel(inner, h, 0);
    const double value = occluded_disk_irradiance(h, {0, 0, outer}, {{0, 0, inner}});
    EXPECT_LE(std::fabs(value - expected), 4 * kEps * outer_e) << "inner " << inner;
  }
}

struct HiddenCase {
  std::string name;
  Circle2 light;
  std::vector<Circle2> occluders;
};

void PrintTo(const HiddenCase& c, std::ostream* os) { *os << c.name; }

class FullyHiddenDisk : public testing::TestWithParam<HiddenCase> {};

TEST_P(FullyHiddenDisk, IsExactlyZero) {
  const HiddenCase& c = GetParam();
  EXPECT_TRUE(visible_boundary(c.light, c.occluders).empty());
  EXPECT_EQ(occluded_disk_irradiance(1.0, c.light, c.occluders), 0.0);
}

INSTANTIATE_TEST_SUITE_P(
    Configurations, FullyHiddenDisk,
    testing::Values(HiddenCase{"SameCircle", {0.2, 0.1, 0.5}, {{0.2, 0.1, 0.5}}},
                    HiddenCase{"LargerConcentric", {0, 0, 0.5}, {{0, 0, 0.6}}},
                    HiddenCase{"LargerOffCentre", {0.3, 0, 0.5}, {{0.1, 0.1, 1.0}}},
                    HiddenCase{"TwoHalvesCover", {0, 0, 1.0}, {{-0.5, 0, 1.2}, {0.5, 0, 1.2}}},
                    HiddenCase{"ThreeCover", {0, 0, 1.0}, {{0.6, 0, 1.0}, {-0.3, 0.52, 1.0}, {-0.3, -0.52, 1.0}}}),
    [](const auto& info) { return info.param.name; });

TEST(VisibleBoundary, DuplicateOccludersCountOnce) {
  const Circle2 light{0, 0, 1.0};
  const Circle2 hole{0.3, 0.2, 0.4};
  EXPECT_EQ(occluded_disk_irradiance(1.0, light, {hole, hole}), occluded_disk_irradiance(1.0, light, {hole}));
}

TEST(VisibleBoundary, NestedOccluderIsDropped) {
  const Circle2 light{0, 0, 1.0};
  EXPECT_EQ(occluded_disk_irradiance(1.0, light, {{0.3, 0.2, 0.5}, {0.35, 0.2, 0.1}}),
            occluded_disk_irradiance(1.0, light, {{0.3, 0.2, 0.5}}));
}

TEST(VisibleBoundary, RejectsNonFiniteAndNegativeRadii) {
  EXPECT_THROW(visible_boundary({0, 0, -1}, {}), Error);
  EXPECT_THROW(visible_boundary({0, 0, 1}, {{NAN, 0, 1}}), Error);
}

}  // namespace
}  // namespace furnace::analytic
