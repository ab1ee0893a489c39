// Every direct-lighting strategy passes the mean tests against the exact
// reference on the disk-with-occluder scene, and every deliberately wrong
// variant (negative control) fails them.
//
// Budget and levels: each case renders the 32×32 default scene at kSpp
// samples per pixel with a fixed named seed; its 1024 pixel t-tests and its
// image-mean z-test share the family-wise level kCaseAlpha by the Šidák
// correction (verify/harness.cpp). The tests print the smallest relative bias
// each case detects with power kReportedPower.
#include <gtest/gtest.h>

#include <string>

#include "verify/harness.h"

namespace furnace::verify {
namespace {

constexpr int kSpp = 512;
constexpr uint64_t kSeed = 0x5eed2026;  // fixed: a pass today fails only when the code changes
// Per case. The suite's cases are separate ctest tests; 1e-3 keeps the
// chance that any of the 3 correct cases raises a false alarm below 0.3 %.
constexpr double kCaseAlpha = 1e-3;

std::string scene_path() { return std::string(FURNACE_SCENE_DIR) + "/disk_occluder.json"; }

Verdict run(Strategy s, Defect d) {
  Case c;
  c.scene_path = scene_path();
  c.options.strategy = s;
  c.options.defect = d;
  c.options.spp = kSpp;
  c.options.seed = kSeed;
  return run_case(c, kCaseAlpha);
}

void report(const Verdict& v) {
  std::printf("%s", format_table({v}, kCaseAlpha).c_str());
  testing::Test::RecordProperty("detectable_relative_bias", std::to_string(v.detectable_rel_bias));
  testing::Test::RecordProperty("z", std::to_string(v.z));
}

class CorrectStrategy : public testing::TestWithParam<Strategy> {};

TEST_P(CorrectStrategy, PassesMeanTestsOnDiskOccluder) {
  const Verdict v = run(GetParam(), Defect::kNone);
  report(v);
  EXPECT_EQ(v.nonfinite_samples, 0u);
  EXPECT_EQ(v.pixel_failures, 0) << "worst |t| " << v.worst_pixel_t;
  EXPECT_LT(std::fabs(v.z), v.threshold);
  EXPECT_TRUE(v.pass);
  // Power: the image-mean test must resolve biases well below the 10 % of
  // the pdf negative control, or the controls below would prove nothing.
  EXPECT_LT(v.detectable_rel_bias, 0.01);
}

INSTANTIATE_TEST_SUITE_P(DiskOccluder, CorrectStrategy, testing::ValuesIn(all_strategies()),
                         [](const testing::TestParamInfo<Strategy>& info) {
                           std::string name;
                           bool upper = true;
                           for (char ch : strategy_name(info.param)) {
                             if (ch == '_') { upper = true; continue; }
                             name += upper ? char(std::toupper(ch)) : ch;
                             upper = false;
                           }
                           return name;
                         });

struct Control {
  const char* name;
  Strategy strategy;
  Defect defect;
};

class NegativeControl : public testing::TestWithParam<Control> {};

TEST_P(NegativeControl, FailsMeanTests) {
  const Verdict v = run(GetParam().strategy, GetParam().defect);
  report(v);
  EXPECT_FALSE(v.pass) << "a deliberately wrong estimator passed: the test has no power against it";
}

INSTANTIATE_TEST_SUITE_P(
    DiskOccluder, NegativeControl,
    testing::Values(Control{"LightAreaDropLightCosine", Strategy::kLightArea, Defect::kDropLightCosine},
                    Control{"LightAreaSkipShadowRay", Strategy::kLightArea, Defect::kSkipShadowRay},
                    Control{"LightAreaPdfOffByConstant", Strategy::kLightArea, Defect::kPdfOffByConstant},
                    Control{"CosinePdfOffByConstant", Strategy::kCosineHemisphere, Defect::kPdfOffByConstant},
                    Control{"UniformPdfOffByConstant", Strategy::kUniformHemisphere, Defect::kPdfOffByConstant}),
    [](const testing::TestParamInfo<Control>& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace furnace::verify
