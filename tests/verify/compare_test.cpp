// `furnace compare` (verify/compare.h, verify/compare_report.h and the
// command, cli/compare_command.h): negative controls on synthetic renders
// with known noise, bad input, and the false-alarm and power calibration.
//
// A synthetic render is base·(1 + σ·noise) per pixel, noise standard normal
// from a named seed; base is a smooth gradient in [0.5, 1.5] over a 32×32
// image. Every number asserted follows from σ, K and the levels below.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <boost/math/distributions/binomial.hpp>
#include <boost/math/distributions/students_t.hpp>
#include <fmt/format.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfOutputFile.h>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/exr.h"
#include "stats/statistics.h"
#include "stats/test_design.h"
#include "tests/command.h"
#include "tests/verify/rare_event_renders.h"
#include "verify/compare.h"
#include "verify/compare_report.h"
#include "verify/image_report.h"

namespace furnace::verify {
namespace {

namespace fs = std::filesystem;

// Named seeds: side A and side B draw from different streams.
constexpr uint64_t kSeedA = 20261204;
constexpr uint64_t kSeedB = 20261205;
constexpr uint64_t kCalibrationSeed = 31000;
constexpr int kSize = 32;
constexpr double kAlpha = 0.01;
// Relative per-pixel noise of one render (about a 256-spp direct-lighting
// render of disk_occluder).
constexpr double kPixelNoise = 0.01;

double base(size_t i) {
  const double x = double(i % kSize) / (kSize - 1), y = double(i / kSize) / (kSize - 1);
  return 0.5 + 0.5 * x + 0.5 * y;
}

// K renders of base·gain·(1 + σ·noise); `tile_gain` multiplies the 8×8 tile
// at (8, 8) (pixels x, y in [8, 16)).
struct Synthetic {
  int k = 8;
  double sigma = kPixelNoise;
  double gain = 1;
  double tile_gain = 1;
  double r_gain = 1, b_gain = 1;  // colour (rgb mode): R and B scaled, G not
  // Absolute noise of row 0, whose expected value is 0 (a black pixel of a
  // spectral renderer's RGB film): about half its values are negative.
  double zero_row_noise = 0;
  uint64_t seed = kSeedA;
  ChannelMode mode = ChannelMode::kGray;
  // Setters, so that a test names what it changes: Synthetic().set_k(2).set_sigma(0.1).
  Synthetic& set_k(int v) {
    k = v;
    return *this;
  }
  Synthetic& set_sigma(double v) {
    sigma = v;
    return *this;
  }
  Synthetic& set_gain(double v) {
    gain = v;
    return *this;
  }
  Synthetic& set_tile_gain(double v) {
    tile_gain = v;
    return *this;
  }
  Synthetic& set_r_gain(double v) {
    r_gain = v;
    return *this;
  }
  Synthetic& set_b_gain(double v) {
    b_gain = v;
    return *this;
  }
  Synthetic& set_seed(uint64_t v) {
    seed = v;
    return *this;
  }
  Synthetic& set_mode(ChannelMode v) {
    mode = v;
    return *this;
  }
  Synthetic& set_zero_row_noise(double v) {
    zero_row_noise = v;
    return *this;
  }
};

CompareSide synthetic(const Synthetic& s, const std::string& name = "s") {
  CompareSide side;
  std::mt19937_64 rng(s.seed);
  std::normal_distribution<double> noise;
  const size_t n = size_t(kSize) * kSize;
  for (int j = 0; j < s.k; ++j) {
    ForeignImage img;
    img.path = name + std::to_string(j) + ".exr";
    img.width = img.height = kSize;
    img.source_channels = "R, G, B";
    const bool rgb = s.mode == ChannelMode::kRgb;
    img.channels = rgb ? std::vector<std::string>{"R", "G", "B"} : std::vector<std::string>{"gray"};
    img.value.assign(img.channels.size(), std::vector<double>(n));
    for (size_t i = 0; i < n; ++i) {
      const int x = int(i % kSize), y = int(i / kSize);
      const bool in_tile = x >= 8 && x < 16 && y >= 8 && y < 16;
      // Stored as 32-bit floats, as an EXR holds them.
      const double u = noise(rng);
      const double v = y == 0 && s.zero_row_noise > 0
                           ? s.zero_row_noise * u
                           : base(i) * s.gain * (in_tile ? s.tile_gain : 1.0) * (1 + s.sigma * u);
      if (rgb) {
        img.value[0][i] = float(v * s.r_gain);
        img.value[1][i] = float(v);
        img.value[2][i] = float(v * s.b_gain);
      } else {
        img.value[0][i] = float(v);
      }
      if (v < 0) {
        img.negative_values += rgb ? 3 : 1;
        if (v < img.most_negative) {
          img.most_negative = v;
          img.most_negative_channel = rgb ? "R" : "gray";
          img.most_negative_x = x;
          img.most_negative_y = y;
        }
      }
    }
    side.images.push_back(std::move(img));
  }
  return side;
}

bool has(const std::vector<std::string>& words, const std::string& w) {
  return std::find(words.begin(), words.end(), w) != words.end();
}

// One furnace EXR per side: per-pixel s² and N instead of K renders.
constexpr double kSampleNoise = 0.3;  // per sample; at N = 1024 a pixel's noise is ~1 %
constexpr uint32_t kSamples = 1024;
// The relative pixel noise of one such render, kSampleNoise/√kSamples.
const double kFurnaceRenderNoise = kSampleNoise / std::sqrt(double(kSamples));
CompareSide furnace_side(double gain, uint64_t seed, const std::string& name) {
  CompareSide side = synthetic(
      Synthetic().set_k(1).set_sigma(kSampleNoise / std::sqrt(double(kSamples))).set_gain(gain).set_seed(seed), name);
  ForeignImage& img = side.images[0];
  const size_t n = img.value[0].size();
  img.variance.assign(1, std::vector<double>(n));
  img.count.assign(n, kSamples);
  for (size_t i = 0; i < n; ++i) img.variance[0][i] = float(std::pow(kSampleNoise * base(i) * gain, 2));
  return side;
}

#ifndef FURNACE_COMPARE_SLOW  // the unit tests; the slow binary holds only the calibration
// ---------------------------------------------------------------------------
// Verdicts and negative controls.

TEST(Compare, SameDistributionIsSameWithPower) {
  const CompareResult r = compare_renders(synthetic(Synthetic()), synthetic(Synthetic().set_seed(kSeedB)), kAlpha,
                                          kDefaultMaxDetectableDifference);
  EXPECT_EQ(r.verdict, CompareVerdict::kSame) << format_compare(r);
  EXPECT_EQ(exit_code(r.verdict), 0);
  EXPECT_TRUE(r.rejected.empty());
  EXPECT_TRUE(r.image_mean_has_power);
  EXPECT_LE(r.detectable_relative_difference, kDefaultMaxDetectableDifference);
  const ChannelComparison& c = r.channels[0];
  EXPECT_EQ(c.tiles, 16);
  EXPECT_EQ(c.pixel_failures, 0);
  EXPECT_EQ(c.tile_failures, 0);
  EXPECT_TRUE(c.variance_pass);
  // Welch d.o.f. of two sides of 8: between 7 and 14.
  EXPECT_GE(c.dof, 7);
  EXPECT_LE(c.dof, 14);
}

TEST(Compare, GlobalShiftIsDifferentThroughTheMean) {
  const CompareResult r =
      compare_renders(synthetic(Synthetic().set_gain(1.02)), synthetic(Synthetic().set_seed(kSeedB)), kAlpha,
                      kDefaultMaxDetectableDifference);
  EXPECT_EQ(r.verdict, CompareVerdict::kDifferent);
  EXPECT_EQ(exit_code(r.verdict), 1);
  EXPECT_TRUE(has(r.rejected, "mean")) << format_compare(r);
  EXPECT_FALSE(has(r.rejected, "variance")) << format_compare(r);
}

// A 1 % shift confined to one 8×8 tile, with pixel noise chosen so that the
// tile's expected |t| is kTileT while each of its pixels' is kTileT/8: the
// tile test (critical |t| ≈ 5 at α/4/16 and ~14 d.o.f.) must reject, every
// pixel test (critical ≈ 9 at α/4/1024) must pass.
TEST(Compare, OneTileShiftFailsThroughTheTileTestOnly) {
  constexpr int k = 8;
  constexpr double kShift = 0.01, kTileT = 12;
  const double sigma = kShift * 8 / (kTileT * std::sqrt(2.0 / k));
  const CompareResult r = compare_renders(synthetic(Synthetic().set_k(k).set_sigma(sigma).set_tile_gain(1 + kShift)),
                                          synthetic(Synthetic().set_k(k).set_sigma(sigma).set_seed(kSeedB)), kAlpha,
                                          kDefaultMaxDetectableDifference);
  const ChannelComparison& c = r.channels[0];
  EXPECT_EQ(r.verdict, CompareVerdict::kDifferent) << format_compare(r);
  EXPECT_TRUE(has(r.rejected, "tiles")) << format_compare(r);
  EXPECT_EQ(c.tile_failures, 1);
  EXPECT_EQ(c.worst_tile_x, 8);
  EXPECT_EQ(c.worst_tile_y, 8);
  EXPECT_EQ(c.pixel_failures, 0) << format_compare(r);
  EXPECT_FALSE(has(r.rejected, "pixels"));
  EXPECT_FALSE(has(r.rejected, "variance"));
  // Negative control of the control: without the shift nothing rejects.
  const CompareResult same = compare_renders(synthetic(Synthetic().set_k(k).set_sigma(sigma)),
                                             synthetic(Synthetic().set_k(k).set_sigma(sigma).set_seed(kSeedB)), kAlpha,
                                             kDefaultMaxDetectableDifference);
  EXPECT_TRUE(same.rejected.empty()) << format_compare(same);
}

TEST(Compare, DoubledVarianceWithTheSameMeanFailsTheVarianceTestOnly) {
  const CompareResult r =
      compare_renders(synthetic(Synthetic().set_sigma(kPixelNoise * std::sqrt(2.0))),
                      synthetic(Synthetic().set_seed(kSeedB)), kAlpha, kDefaultMaxDetectableDifference);
  const ChannelComparison& c = r.channels[0];
  EXPECT_EQ(r.verdict, CompareVerdict::kDifferent) << format_compare(r);
  ASSERT_EQ(r.rejected.size(), 1u) << format_compare(r);
  EXPECT_EQ(r.rejected[0], "variance");
  EXPECT_FALSE(c.variance_pass);
  EXPECT_GT(c.variance_statistic, 0);
  // The ratio estimate is near 2, and a 2x ratio is far above the detectable one.
  EXPECT_GT(c.variance_ratio, 1.8);
  EXPECT_LT(c.variance_ratio, 2.2);
  EXPECT_LT(c.detectable_variance_ratio, 1.5);
}

TEST(Compare, WithoutTheVarianceTestADoubledVarianceIsSame) {
  // Two renderers (or samplers) with different noise and the same mean.
  const CompareResult r = compare_renders(synthetic(Synthetic().set_sigma(kPixelNoise * std::sqrt(2.0))),
                                          synthetic(Synthetic().set_seed(kSeedB)), kAlpha,
                                          kDefaultMaxDetectableDifference, kDefaultTileSize, false);
  EXPECT_EQ(r.verdict, CompareVerdict::kSame) << format_compare(r);
  EXPECT_EQ(r.families, kCompareFamilies - 1);
  EXPECT_FALSE(r.channels[0].variance_tested);
  EXPECT_NE(format_compare(r).find("not tested"), std::string::npos);
}

TEST(Compare, ColourErrorKeepingTheGrayMeanFailsOnlyPerChannel) {
  // R +3 %, B −3 %: the gray mean is unchanged.
  const Synthetic colour = Synthetic().set_r_gain(1.03).set_b_gain(0.97);
  const CompareResult gray = compare_renders(synthetic(colour), synthetic(Synthetic().set_seed(kSeedB)), kAlpha,
                                             kDefaultMaxDetectableDifference);
  EXPECT_EQ(gray.verdict, CompareVerdict::kSame) << format_compare(gray);
  Synthetic colour_rgb = colour;
  colour_rgb.mode = ChannelMode::kRgb;
  const CompareResult rgb =
      compare_renders(synthetic(colour_rgb), synthetic(Synthetic().set_seed(kSeedB).set_mode(ChannelMode::kRgb)),
                      kAlpha, kDefaultMaxDetectableDifference);
  ASSERT_EQ(rgb.channels.size(), 3u);
  EXPECT_EQ(rgb.verdict, CompareVerdict::kDifferent);
  EXPECT_FALSE(rgb.channels[0].image_mean_pass);
  EXPECT_TRUE(rgb.channels[1].image_mean_pass);
  EXPECT_FALSE(rgb.channels[2].image_mean_pass);
}

TEST(Compare, TwoRendersPerSideAreInconclusive) {
  const CompareResult r = compare_renders(synthetic(Synthetic().set_k(2).set_sigma(0.1)),
                                          synthetic(Synthetic().set_k(2).set_sigma(0.1).set_seed(kSeedB)), kAlpha,
                                          kDefaultMaxDetectableDifference);
  EXPECT_EQ(r.verdict, CompareVerdict::kInconclusive) << format_compare(r);
  EXPECT_EQ(exit_code(r.verdict), 3);
  ASSERT_TRUE(r.advice.needed);
  EXPECT_GT(r.advice.renders_per_side, 2);
  EXPECT_GT(r.advice.spp_factor, 1);
  EXPECT_NE(format_compare(r).find("renders per side"), std::string::npos);
}

// K renders per side whose image means have sample standard deviation
// exactly `sd` (relative): half at gain 1 + a, half at 1 − a (one at 1 for
// odd K), a chosen so that s = sd. Side B holds the same gains on the image
// mirrored left to right (the same image mean, other pixels). The advice from
// 2 renders must name the K at which the image-mean test reaches the
// threshold, and K − 1 must fall short.
CompareSide exact_spread(int k, double sd, bool mirrored) {
  const int pairs = k / 2;
  const double a = sd * std::sqrt(double(k - 1) / (2.0 * pairs));
  CompareSide side = synthetic(Synthetic().set_k(k).set_sigma(0), mirrored ? "b" : "a");
  for (int j = 0; j < k; ++j) {
    const double gain = j < pairs ? 1 + a : (j < 2 * pairs ? 1 - a : 1.0);
    for (size_t i = 0; i < side.images[j].value[0].size(); ++i) {
      const size_t x = i % kSize, y = i / kSize;
      side.images[j].value[0][i] = float(base(mirrored ? y * kSize + (kSize - 1 - x) : i) * gain);
    }
    // Renders with equal gains differ in two pixels by ±kNudge·j, which
    // keeps their mean: identical renders would be refused.
    constexpr double kNudge = 1.0 / 1024;  // exact in float
    side.images[j].value[0][0] += kNudge * j;
    side.images[j].value[0][1] -= kNudge * j;
  }
  return side;
}

TEST(Compare, AdviceReachesTheThresholdWithTheRendersItNames) {
  const double sd = 0.002, target = 0.004;
  auto detectable = [&](int k) {
    return compare_renders(exact_spread(k, sd, false), exact_spread(k, sd, true), kAlpha, target)
        .detectable_relative_difference;
  };
  const CompareResult two = compare_renders(exact_spread(2, sd, false), exact_spread(2, sd, true), kAlpha, target);
  ASSERT_TRUE(two.advice.needed);
  const int k = two.advice.renders_per_side;
  ASSERT_GT(k, 2);
  // Float storage moves s by ~1e-7 relative: a 1e-4 margin.
  EXPECT_LE(detectable(k), target * (1 + 1e-4)) << k;
  EXPECT_GT(detectable(k - 1), target) << k;
}

TEST(Compare, DifferentWinsOverInconclusive) {
  const CompareResult r = compare_renders(synthetic(Synthetic().set_k(2).set_sigma(0.1).set_gain(1.5)),
                                          synthetic(Synthetic().set_k(2).set_sigma(0.1).set_seed(kSeedB)), kAlpha,
                                          kDefaultMaxDetectableDifference);
  EXPECT_FALSE(r.image_mean_has_power);
  EXPECT_EQ(r.verdict, CompareVerdict::kDifferent) << format_compare(r);
}

TEST(Compare, OneFurnaceExrPerSide) {
  const CompareResult same = compare_renders(furnace_side(1, kSeedA, "a"), furnace_side(1, kSeedB, "b"), kAlpha,
                                             kDefaultMaxDetectableDifference);
  EXPECT_EQ(same.method_a, "furnace variance");
  EXPECT_EQ(same.verdict, CompareVerdict::kSame) << format_compare(same);
  EXPECT_GT(same.channels[0].dof, 1000);  // Satterthwaite over 1024 pixels of 1023 d.o.f.
  const CompareResult shifted = compare_renders(furnace_side(1.01, kSeedA, "a"), furnace_side(1, kSeedB, "b"), kAlpha,
                                                kDefaultMaxDetectableDifference);
  EXPECT_EQ(shifted.verdict, CompareVerdict::kDifferent) << format_compare(shifted);
  EXPECT_TRUE(has(shifted.rejected, "mean"));
}

// ---------------------------------------------------------------------------
// Real renders (issue 41): negative values are data, half floats explain
// repeating values, the report prints every critical t and what SAME means.

// Row 0 of every render has expected value 0 and absolute noise
// kZeroRowNoise (a black region of a spectral renderer's film): about half of
// its 8 × 32 values per side are negative. They are used as is: the verdict
// is the one without them, they are counted, and a 2 % difference is still
// DIFFERENT with them (the negative control).
constexpr double kZeroRowNoise = 1.5e-4;

TEST(Compare, NegativeNoiseIsDataAndKeepsTheVerdict) {
  const CompareSide a = synthetic(Synthetic().set_zero_row_noise(kZeroRowNoise));
  const CompareSide b = synthetic(Synthetic().set_zero_row_noise(kZeroRowNoise).set_seed(kSeedB));
  const CompareResult r = compare_renders(a, b, kAlpha, kDefaultMaxDetectableDifference);
  const CompareResult plain = compare_renders(synthetic(Synthetic()), synthetic(Synthetic().set_seed(kSeedB)), kAlpha,
                                              kDefaultMaxDetectableDifference);
  EXPECT_EQ(plain.verdict, CompareVerdict::kSame) << format_compare(plain);
  EXPECT_EQ(r.verdict, plain.verdict) << format_compare(r);
  size_t expected = 0;
  for (const ForeignImage& img : a.images)
    for (double v : img.value[0]) expected += v < 0 ? 1 : 0;
  EXPECT_GT(expected, 8u * kSize / 4);  // about half of 256
  EXPECT_EQ(r.negative_a.values, expected);
  EXPECT_EQ(r.negative_a.images, 8);
  EXPECT_LT(r.negative_a.most_negative, 0);
  EXPECT_EQ(r.negative_a.y, 0);
  EXPECT_EQ(plain.negative_a.values, 0u);
  const std::string text = format_compare(r);
  EXPECT_NE(text.find(fmt::format("negative values (side A): {} in 8 of 8 image(s)", expected)), std::string::npos)
      << text;
  EXPECT_EQ(format_compare(plain).find("negative values"), std::string::npos);
  const nlohmann::json j = compare_json(a, b, r, {}, ChannelMode::kGray, "");
  EXPECT_EQ(j["a"]["negative_values"]["values"], expected);
  EXPECT_EQ(j["b"]["negative_values"]["values"], r.negative_b.values);
  const CompareResult shifted = compare_renders(synthetic(Synthetic().set_zero_row_noise(kZeroRowNoise).set_gain(1.02)),
                                                b, kAlpha, kDefaultMaxDetectableDifference);
  EXPECT_EQ(shifted.verdict, CompareVerdict::kDifferent) << format_compare(shifted);
  EXPECT_TRUE(has(shifted.rejected, "mean"));
}

// `value` rounded to a 16-bit half float's 11 significant bits (normal range).
double half_rounded(double value) {
  int exponent = 0;
  const double mantissa = std::frexp(value, &exponent);  // in [0.5, 1)
  return std::ldexp(std::nearbyint(std::ldexp(mantissa, 11)), exponent - 11);
}

// Pixels whose noise is below a half float's step repeat their values; the
// report says why: half-float rounding when the images are halves, the
// quasi-Monte Carlo or discrete reading otherwise (the negative control).
TEST(Compare, RepeatedHalfFloatValuesAreNamedAsRounding) {
  const double sigma = 1e-4;  // a tenth of the half step at [0.5, 1.5]: 2^-11 to 2^-10
  CompareSide a = synthetic(Synthetic().set_sigma(sigma)), b = synthetic(Synthetic().set_sigma(sigma).set_seed(kSeedB));
  for (CompareSide* side : {&a, &b})
    for (ForeignImage& img : side->images)
      for (double& v : img.value[0]) v = half_rounded(v);
  const CompareResult as_floats = compare_renders(a, b, kAlpha, kDefaultMaxDetectableDifference);
  ASSERT_GT(as_floats.channels[0].pixels_few_values, 0) << format_compare(as_floats);
  EXPECT_NE(format_compare(as_floats).find("quasi-Monte Carlo"), std::string::npos);
  for (ForeignImage& img : a.images) img.half_float = true;
  const CompareResult as_halves = compare_renders(a, b, kAlpha, kDefaultMaxDetectableDifference);
  EXPECT_TRUE(as_halves.half_float_a);
  const std::string text = format_compare(as_halves);
  EXPECT_NE(text.find("half-float rounding, not a quasi-Monte Carlo pattern"), std::string::npos) << text;
  EXPECT_EQ(compare_json(a, b, as_halves, {}, ChannelMode::kGray, "")["a"]["half_float"], true);
}

TEST(Compare, SidesStatingDifferentSppAreWarnedOf) {
  CompareSide a = synthetic(Synthetic()), b = synthetic(Synthetic().set_seed(kSeedB));
  EXPECT_TRUE(compare_warnings(a, b).empty());  // nothing stated: nothing to warn of
  for (ForeignImage& img : a.images) img.stated_spp = "64", img.spp_attribute = "samplesPerPixel";
  for (ForeignImage& img : b.images) img.stated_spp = "64", img.spp_attribute = "samplesPerPixel";
  EXPECT_TRUE(compare_warnings(a, b).empty());  // the same spp: none
  for (ForeignImage& img : b.images) img.stated_spp = "256";
  const std::vector<std::string> across = compare_warnings(a, b);
  ASSERT_EQ(across.size(), 1u);
  EXPECT_NE(across[0].find("states 64 spp (samplesPerPixel)"), std::string::npos) << across[0];
  EXPECT_NE(across[0].find("states 256"), std::string::npos) << across[0];
  a.images[3].stated_spp = "16";  // within a side too
  const std::vector<std::string> within = compare_warnings(a, b);
  ASSERT_EQ(within.size(), 2u);
  EXPECT_NE(within[0].find("side A mixes spp"), std::string::npos) << within[0];
}

// The text prints the critical |t| of the median tile and pixel and of the
// worst ones, so that a near miss can be judged from it; the critical t of a
// Welch test with d.o.f. between 7 and 14 (two sides of 8) lies between the
// t quantiles at those d.o.f.
TEST(Compare, CriticalTOfTilesAndPixelsArePrinted) {
  const CompareResult r = compare_renders(synthetic(Synthetic()), synthetic(Synthetic().set_seed(kSeedB)), kAlpha,
                                          kDefaultMaxDetectableDifference);
  const ChannelComparison& c = r.channels[0];
  const auto quantile = [](double dof, double alpha) {
    return boost::math::quantile(
        boost::math::complement(boost::math::students_t_distribution<double>(dof), alpha / 2));
  };
  for (double t : {c.tile_threshold, c.worst_tile_threshold}) {
    EXPECT_GE(t, quantile(14, c.tile_alpha));
    EXPECT_LE(t, quantile(7, c.tile_alpha));
  }
  EXPECT_GE(c.worst_pixel_threshold, quantile(14, c.pixel_alpha));
  EXPECT_LE(c.worst_pixel_threshold, quantile(7, c.pixel_alpha));
  const std::string text = format_compare(r);
  EXPECT_NE(text.find(fmt::format("critical |t| {:.3g} for the median tile", c.tile_threshold)), std::string::npos)
      << text;
  EXPECT_NE(text.find(fmt::format("critical {:.3g} there), median detectable tile", c.worst_tile_threshold)),
            std::string::npos)
      << text;
  EXPECT_NE(text.find(fmt::format("critical {:.3g} there), median detectable pixel", c.worst_pixel_threshold)),
            std::string::npos)
      << text;
  const nlohmann::json j = compare_json(synthetic(Synthetic()), synthetic(Synthetic().set_seed(kSeedB)), r, {},
                                        ChannelMode::kGray, "");
  EXPECT_EQ(j["channels"][0]["tiles"]["median_threshold"], c.tile_threshold);
  EXPECT_EQ(j["channels"][0]["tiles"]["worst_threshold"], c.worst_tile_threshold);
  EXPECT_EQ(j["channels"][0]["pixels"]["worst_threshold"], c.worst_pixel_threshold);
}

TEST(Compare, SameSaysWhatItMeans) {
  const CompareResult same = compare_renders(synthetic(Synthetic()), synthetic(Synthetic().set_seed(kSeedB)), kAlpha,
                                             kDefaultMaxDetectableDifference);
  ASSERT_EQ(same.verdict, CompareVerdict::kSame);
  const std::string text = format_compare(same);
  EXPECT_NE(text.find(fmt::format("SAME means no difference of the stated size: none of {} or more of the image mean "
                                  "(found with power {}; this comparison detects {})",
                                  percent_text(kDefaultMaxDetectableDifference), stats::kReportedPower,
                                  percent_text(same.detectable_relative_difference))),
            std::string::npos)
      << text;
  EXPECT_EQ(text.substr(text.size() - 14), "verdict: SAME\n");
  const CompareResult different = compare_renders(synthetic(Synthetic().set_gain(1.02)),
                                                  synthetic(Synthetic().set_seed(kSeedB)), kAlpha,
                                                  kDefaultMaxDetectableDifference);
  EXPECT_EQ(format_compare(different).find("SAME means"), std::string::npos);
}

// ---------------------------------------------------------------------------
// Scale: every statement is relative, so dark (mean ~1e-3) and bright (~1e3)
// renders give the verdicts and powers of renders of mean ~1. Per scale:
// two same-distribution sets are SAME with the detectable difference found at
// scale 1 (float storage rounds values relatively: a 1e-4 margin), and a
// difference of the stated size (1 %) is DIFFERENT (the negative control).

class CompareAtScale : public testing::TestWithParam<double> {};

TEST_P(CompareAtScale, SameDistributionIsSameWithThePowerOfScaleOne) {
  const double scale = GetParam();
  const CompareResult one = compare_renders(synthetic(Synthetic()), synthetic(Synthetic().set_seed(kSeedB)), kAlpha,
                                            kDefaultMaxDetectableDifference);
  const CompareResult r = compare_renders(synthetic(Synthetic().set_gain(scale)),
                                          synthetic(Synthetic().set_gain(scale).set_seed(kSeedB)), kAlpha,
                                          kDefaultMaxDetectableDifference);
  EXPECT_EQ(r.verdict, CompareVerdict::kSame) << format_compare(r);
  EXPECT_NEAR(r.channels[0].mean_b.mean / scale, one.channels[0].mean_b.mean, 1e-4 * one.channels[0].mean_b.mean);
  EXPECT_NEAR(r.detectable_relative_difference, one.detectable_relative_difference,
              1e-4 * one.detectable_relative_difference);
  EXPECT_NEAR(r.channels[0].statistic, one.channels[0].statistic, 1e-3 * (1 + std::fabs(one.channels[0].statistic)));
  EXPECT_NEAR(r.channels[0].variance_ratio, one.channels[0].variance_ratio, 1e-4 * one.channels[0].variance_ratio);
}

TEST_P(CompareAtScale, TheStatedDifferenceIsDifferent) {
  const double scale = GetParam();
  const CompareResult r = compare_renders(synthetic(Synthetic().set_gain(scale * (1 + kDefaultMaxDetectableDifference))),
                                          synthetic(Synthetic().set_gain(scale).set_seed(kSeedB)), kAlpha,
                                          kDefaultMaxDetectableDifference);
  EXPECT_EQ(r.verdict, CompareVerdict::kDifferent) << format_compare(r);
  EXPECT_TRUE(has(r.rejected, "mean")) << format_compare(r);
  // A 1 % tile shift at the noise that gives a tile |t| of 12 is found there too.
  constexpr int k = 8;
  constexpr double kShift = 0.01, kTileT = 12;
  const double sigma = kShift * 8 / (kTileT * std::sqrt(2.0 / k));
  const CompareResult tile = compare_renders(
      synthetic(Synthetic().set_k(k).set_sigma(sigma).set_gain(scale).set_tile_gain(1 + kShift)),
      synthetic(Synthetic().set_k(k).set_sigma(sigma).set_gain(scale).set_seed(kSeedB)), kAlpha,
      kDefaultMaxDetectableDifference);
  EXPECT_TRUE(has(tile.rejected, "tiles")) << format_compare(tile);
  EXPECT_EQ(tile.channels[0].worst_tile_x, 8);
}

std::string scale_name(const testing::TestParamInfo<double>& info) { return info.param < 1 ? "Dark" : "Bright"; }
INSTANTIATE_TEST_SUITE_P(Scales, CompareAtScale, testing::Values(1e-3, 1e3), scale_name);

// ---------------------------------------------------------------------------
// Bad input, through the files and the command (`furnace compare`: bad input
// is one line on stderr and exit 2).

class CompareFiles : public testing::Test {
 protected:
  void SetUp() override {
    const auto* info = testing::UnitTest::GetInstance()->current_test_info();
    dir_ =
        fs::temp_directory_path() / (std::string("furnace_compare_") + info->name() + "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Writes side `s` as RGB EXR files; returns their paths.
  std::vector<std::string> write_side(const Synthetic& s, const std::string& name) const {
    const CompareSide side = synthetic(s, name);
    std::vector<std::string> paths;
    for (const ForeignImage& img : side.images) {
      exr::Image file;
      file.width = img.width;
      file.height = img.height;
      for (const char* c : {"R", "G", "B"}) file.floats[c].assign(img.value[0].begin(), img.value[0].end());
      paths.push_back(write(file, img.path));
    }
    return paths;
  }
  std::string write(const exr::Image& file, const std::string& name) const {
    const std::string path = (dir_ / name).string();
    exr::write(path, file);
    return path;
  }
  // The `furnace compare` command line of sides a and b.
  static std::string compare_command(const std::vector<std::string>& a, const std::vector<std::string>& b) {
    std::string command = std::string(FURNACE_CLI) + " compare";
    for (const std::string& path : a) command += " --a " + path;
    for (const std::string& path : b) command += " --b " + path;
    return command;
  }
  // `furnace compare` must exit 2 with one sentence on stderr holding every
  // fragment, write nothing to stdout, and write the BAD INPUT JSON.
  void expect_bad_input(const std::vector<std::string>& a, const std::vector<std::string>& b,
                        const std::vector<std::string>& fragments) const {
    const std::string json_path = (dir_ / "bad.json").string();
    const testing_support::CommandResult run =
        testing_support::run_command(compare_command(a, b) + " --json " + json_path + " 2>&1 >/dev/null");
    EXPECT_EQ(run.exit_code, 2) << run.output;
    const std::string prefix = "furnace: error: ";
    ASSERT_EQ(run.output.rfind(prefix, 0), 0u) << run.output;
    ASSERT_EQ(run.output.back(), '\n') << run.output;
    const std::string msg = run.output.substr(prefix.size(), run.output.size() - prefix.size() - 1);
    for (const std::string& s : fragments) EXPECT_NE(msg.find(s), std::string::npos) << s << " not in: " << msg;
    EXPECT_EQ(msg.back(), '.') << msg;
    EXPECT_EQ(msg.find(". "), std::string::npos) << "one sentence: " << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << "one line: " << msg;
    const nlohmann::json j = nlohmann::json::parse(exr_text(json_path));
    EXPECT_EQ(j["verdict"], "BAD INPUT");
    EXPECT_EQ(j["exit_code"], 2);
  }
  static std::string exr_text(const std::string& path) {
    std::ifstream in(path);
    return std::string(std::istreambuf_iterator<char>(in), {});
  }

  fs::path dir_;
};

TEST_F(CompareFiles, SameDistributionFilesAreSameAndWriteJsonAndZmap) {
  const std::string json_path = (dir_ / "r.json").string(), zmap_path = (dir_ / "t.exr").string();
  const testing_support::CommandResult run = testing_support::run_command(
      compare_command(write_side(Synthetic(), "a"), write_side(Synthetic().set_seed(kSeedB), "b")) + " --json " +
      json_path + " --zmap " + zmap_path + " 2>&1");
  EXPECT_EQ(run.exit_code, 0) << run.output;
  const nlohmann::json j = nlohmann::json::parse(exr_text(json_path));
  EXPECT_EQ(j["verdict"], "SAME");
  EXPECT_EQ(j["channels"][0]["tiles"]["tiles"], 16);
  const exr::Image z = exr::read(zmap_path);
  EXPECT_TRUE(z.has_channel("Y"));
  EXPECT_EQ(z.width, kSize);
}

TEST_F(CompareFiles, ResolutionMismatchIsBadInput) {
  exr::Image small;
  small.width = small.height = 16;
  for (const char* c : {"R", "G", "B"}) small.floats[c].assign(16 * 16, 1.0f);
  std::vector<std::string> b = write_side(Synthetic().set_seed(kSeedB), "b");
  b[1] = write(small, "small.exr");
  expect_bad_input(write_side(Synthetic(), "a"), b, {"small.exr", "16x16", "32x32"});
}

TEST_F(CompareFiles, ChannelMismatchIsBadInput) {
  exr::Image y;
  y.width = y.height = kSize;
  y.floats["Y"].assign(kSize * kSize, 1.0f);
  std::vector<std::string> b = write_side(Synthetic().set_seed(kSeedB), "b");
  b[0] = write(y, "luminance.exr");
  expect_bad_input(write_side(Synthetic(), "a"), b, {"luminance.exr", "Y", "R, G, B"});
}

// NaN and infinite radiance stay bad input (exit 2, one sentence); a finite
// negative value is data (next test). Until issue 41 a negative value was
// refused here too.
TEST_F(CompareFiles, NanAndInfiniteRadianceAreBadInput) {
  const float bad[] = {std::numeric_limits<float>::quiet_NaN(), -std::numeric_limits<float>::infinity()};
  const char* text[] = {"nan", "-inf"};
  for (int k = 0; k < 2; ++k) {
    exr::Image file;
    file.width = file.height = kSize;
    for (const char* c : {"R", "G", "B"}) file.floats[c].assign(kSize * kSize, 1.0f);
    file.floats["G"][kSize * 3 + 5] = bad[k];
    std::vector<std::string> a = write_side(Synthetic(), "a");
    a[2] = write(file, "bad" + std::to_string(k) + ".exr");
    expect_bad_input(a, write_side(Synthetic().set_seed(kSeedB), "b"), {a[2], "(5, 3)", text[k], "'G'"});
  }
}

// pbrt-v4-like files: R, G, B as HALF or FLOAT, the spp as an int
// samplesPerPixel attribute, some values small and negative.
TEST_F(CompareFiles, NegativeValuesAreCountedAndSppAndHalfFloatsAreRead) {
  const auto pbrt_like = [&](const Synthetic& s, const std::string& name, bool as_half, int spp) {
    const CompareSide side = synthetic(s, name);
    std::vector<std::string> paths;
    for (const ForeignImage& img : side.images) {
      const std::string path = (dir_ / img.path).string();
      Imf::Header header(kSize, kSize);
      header.insert("samplesPerPixel", Imf::IntAttribute(spp));
      const Imf::PixelType type = as_half ? Imf::HALF : Imf::FLOAT;
      std::vector<float> plane(img.value[0].begin(), img.value[0].end());
      std::vector<half> halves(plane.begin(), plane.end());
      Imf::FrameBuffer frame;
      for (const char* c : {"R", "G", "B"}) {
        header.channels().insert(c, Imf::Channel(type));
        char* base = as_half ? reinterpret_cast<char*>(halves.data()) : reinterpret_cast<char*>(plane.data());
        const size_t size = as_half ? sizeof(half) : sizeof(float);
        frame.insert(c, Imf::Slice(type, base, size, size * kSize));
      }
      Imf::OutputFile file(path.c_str(), header);
      file.setFrameBuffer(frame);
      file.writePixels(kSize);
      paths.push_back(path);
    }
    return paths;
  };
  const std::vector<std::string> a = pbrt_like(Synthetic().set_zero_row_noise(kZeroRowNoise), "a", false, 64);
  const std::vector<std::string> b =
      pbrt_like(Synthetic().set_zero_row_noise(kZeroRowNoise).set_seed(kSeedB), "b", false, 64);
  const std::string json_path = (dir_ / "r.json").string();
  const testing_support::CommandResult run =
      testing_support::run_command(compare_command(a, b) + " --json " + json_path + " 2>&1");
  EXPECT_EQ(run.exit_code, 0) << run.output;
  const nlohmann::json j = nlohmann::json::parse(exr_text(json_path));
  const size_t negative = j["a"]["negative_values"]["values"];
  EXPECT_GT(negative, 0u);
  EXPECT_EQ(negative % 3, 0u);  // R, G and B of each negative pixel
  EXPECT_GT(j["b"]["negative_values"]["values"], 0);
  EXPECT_EQ(j["a"]["negative_values"]["images"], 8);
  EXPECT_NE(run.output.find(fmt::format("negative values (side A): {} in", negative)), std::string::npos)
      << run.output;
  EXPECT_EQ(j["a"]["stated_spp"][0], 64);
  EXPECT_EQ(j["a"]["half_float"], false);
  EXPECT_TRUE(j["warnings"].empty()) << j["warnings"];
  // Side B as half floats at 256 spp: warned of, and its halves recorded.
  const std::vector<std::string> b_half =
      pbrt_like(Synthetic().set_zero_row_noise(kZeroRowNoise).set_seed(kSeedB), "h", true, 256);
  const testing_support::CommandResult warned =
      testing_support::run_command(compare_command(a, b_half) + " --json " + json_path + " 2>&1");
  EXPECT_NE(warned.output.find("furnace: warning: image '" + a[0] + "' states 64 spp (samplesPerPixel)"),
            std::string::npos)
      << warned.output;
  const nlohmann::json h = nlohmann::json::parse(exr_text(json_path));
  EXPECT_EQ(h["b"]["half_float"], true);
  EXPECT_EQ(h["b"]["stated_spp"][0], 256);
  EXPECT_EQ(h["warnings"].size(), 1u);
}

TEST_F(CompareFiles, OneImageWithoutVarianceIsBadInput) {
  const std::vector<std::string> a = write_side(Synthetic(), "a");
  expect_bad_input({a[0]}, write_side(Synthetic().set_seed(kSeedB), "b"),
                   {a[0], "side a", "two independent renders"});
}

TEST_F(CompareFiles, TheSameFileOnBothSidesIsBadInput) {
  const std::vector<std::string> a = write_side(Synthetic(), "a");
  std::vector<std::string> b = write_side(Synthetic().set_seed(kSeedB), "b");
  b[3] = a[1];
  expect_bad_input(a, b, {a[1], "both sides"});
}

TEST_F(CompareFiles, IdenticalSetsAreBadInput) {
  // The same renders copied to other names: no independence, refused.
  const std::vector<std::string> a = write_side(Synthetic(), "a");
  const std::vector<std::string> b = write_side(Synthetic(), "copy");
  expect_bad_input(a, b, {a[0], b[0], "identical"});
}

#endif  // FURNACE_COMPARE_SLOW

// ---------------------------------------------------------------------------
// Calibration: the false-alarm rate over many same-distribution pairs must be
// at most α (one-sided exact binomial test at kCalibrationLevel), and the
// rejection rate against a difference equal to the reported detectable one
// at least the stated power 0.9 (the reported one is conservative: the
// spread enters at its upper bound). The default run uses kFastTrials; the
// slow label repeats both with kSlowTrials.

// The calibration's level: a measured rate this improbable under the claim fails.
constexpr double kCalibrationLevel = 1e-3;
// A larger α than the default makes false alarms frequent enough to count.
constexpr double kCalibrationAlpha = 0.05;
constexpr int kCalibrationK = 4;
constexpr size_t kFastTrials = 200;

struct Calibration {
  size_t trials = 0, rejections = 0;
  size_t by_family[4] = {0, 0, 0, 0};  // mean, tiles, pixels, variance
  size_t held = 0;                     // pairs where the rare-event guard held a test (none rejecting)
  double mean_detectable = 0;          // mean over trials of the reported detectable difference
};

// `trials` pairs of K renders each, pixel noise `sigma`, both sides scaled by
// `scale` (the image's brightness); side A also by `gain`.
Calibration calibrate(size_t trials, double gain, uint64_t first_seed, double sigma = kPixelNoise,
                      double scale = 1) {
  Calibration cal;
  const char* families[] = {"mean", "tiles", "pixels", "variance"};
  for (size_t t = 0; t < trials; ++t) {
    const uint64_t seed = first_seed + 2 * t;
    const CompareResult r = compare_renders(
        synthetic(Synthetic().set_k(kCalibrationK).set_sigma(sigma).set_gain(scale * gain).set_seed(seed)),
        synthetic(Synthetic().set_k(kCalibrationK).set_sigma(sigma).set_gain(scale).set_seed(seed + 1)),
        kCalibrationAlpha, 1.0);
    ++cal.trials;
    cal.rejections += r.rejected.empty() ? 0 : 1;
    cal.held += r.rejected.empty() && !r.held.empty() ? 1 : 0;
    for (int f = 0; f < 4; ++f) cal.by_family[f] += has(r.rejected, families[f]) ? 1 : 0;
    cal.mean_detectable += r.detectable_relative_difference / double(trials);
  }
  return cal;
}

// P(X ≥ k) for X ~ Binomial(n, p).
double upper_tail(size_t k, size_t n, double p) {
  if (k == 0) return 1;
  return boost::math::cdf(
      boost::math::complement(boost::math::binomial_distribution<double>(double(n), p), double(k - 1)));
}

void expect_false_alarms_at_most_alpha(size_t trials, double scale = 1) {
  const Calibration cal = calibrate(trials, 1.0, kCalibrationSeed, kPixelNoise, scale);
  const double p = upper_tail(cal.rejections, cal.trials, kCalibrationAlpha);
  testing::Test::RecordProperty("false_alarms", int(cal.rejections));
  std::printf("scale %g: false alarms: %zu of %zu (alpha %g; mean %zu, tiles %zu, pixels %zu, variance %zu), P(X >= k) "
              "= %.3g; held by the rare-event guard: %zu; mean detectable difference %.4g%%\n",
              scale, cal.rejections, cal.trials, kCalibrationAlpha, cal.by_family[0], cal.by_family[1], cal.by_family[2],
              cal.by_family[3], p, cal.held, 100 * cal.mean_detectable);
  EXPECT_GT(p, kCalibrationLevel) << cal.rejections << " of " << cal.trials;
}

// A known 0.5 % difference of the mean (an emission change), with the pixel
// noise scaled so that the reported detectable difference is 0.5 %: the
// image-mean test must then reject with probability at least 0.9.
constexpr double kKnownDifference = 0.005;

void expect_power_at_the_detectable_difference(size_t trials, double scale = 1) {
  // The detectable difference scales with the noise: measure it at kPixelNoise.
  const double detectable = calibrate(20, 1.0, kCalibrationSeed + 1000000, kPixelNoise, scale).mean_detectable;
  const double sigma = kPixelNoise * kKnownDifference / detectable;
  const double reported = calibrate(20, 1.0, kCalibrationSeed + 1500000, sigma, scale).mean_detectable;
  const Calibration cal = calibrate(trials, 1 + kKnownDifference, kCalibrationSeed + 2000000, sigma, scale);
  const double rate = double(cal.by_family[0]) / double(cal.trials);
  // P(X ≤ k) under power 0.9: the observed count of image-mean rejections.
  const boost::math::binomial_distribution<double> at_power(double(cal.trials), stats::kReportedPower);
  const double p = boost::math::cdf(at_power, double(cal.by_family[0]));
  std::printf(
      "scale %g: a %.2g%% difference at pixel noise %.3g%% (reported detectable %.4g%%): the image-mean test "
      "rejected %zu of %zu (%.3f), any test %zu; P(X <= k | 0.9) = %.3g\n",
      scale, 100 * kKnownDifference, 100 * sigma, 100 * reported, cal.by_family[0], cal.trials, rate, cal.rejections, p);
  EXPECT_GT(p, kCalibrationLevel);
  // Negative control: the same design without the difference rejects at about α, far below 0.9.
  EXPECT_LT(calibrate(trials, 1.0, kCalibrationSeed + 3000000, sigma, scale).by_family[0], trials / 4);
}

// Mixed sides: K renders against one furnace EXR of the same noise per render.
Calibration calibrate_mixed(size_t trials, int k, uint64_t first_seed) {
  Calibration cal;
  const char* families[] = {"mean", "tiles", "pixels", "variance"};
  for (size_t t = 0; t < trials; ++t) {
    const uint64_t seed = first_seed + 2 * t;
    const CompareResult r = compare_renders(
        synthetic(Synthetic().set_k(k).set_sigma(kFurnaceRenderNoise).set_seed(seed)),
        furnace_side(1, seed + 1, "b"), kCalibrationAlpha, 1.0);
    ++cal.trials;
    cal.rejections += r.rejected.empty() ? 0 : 1;
    cal.held += r.rejected.empty() && !r.held.empty() ? 1 : 0;
    for (int f = 0; f < 4; ++f) cal.by_family[f] += has(r.rejected, families[f]) ? 1 : 0;
  }
  return cal;
}

void expect_mixed_false_alarms_at_most_alpha(size_t trials, int k) {
  const Calibration cal = calibrate_mixed(trials, k, kCalibrationSeed + 5000000);
  const double p = upper_tail(cal.rejections, cal.trials, kCalibrationAlpha);
  std::printf("K = %d renders against one furnace EXR: false alarms %zu of %zu (alpha %g; mean %zu, tiles %zu, pixels "
              "%zu, variance %zu), P(X >= k) = %.3g; held by the rare-event guard: %zu\n",
              k, cal.rejections, cal.trials, kCalibrationAlpha, cal.by_family[0], cal.by_family[1], cal.by_family[2],
              cal.by_family[3], p, cal.held);
  EXPECT_GT(p, kCalibrationLevel) << cal.rejections << " of " << cal.trials;
}

#ifndef FURNACE_COMPARE_SLOW
// ---------------------------------------------------------------------------
// The rare-event guard (compare.h), on tests/verify/rare_event_renders.h's
// renders of a light seen rarely. Side A at 16 spp misses the light pixel
// entirely with probability e^-1 ≈ 0.37; side B at 4096 spp has 256 hits
// there on average.

CompareSide rare_event_side(int spp, uint64_t seed, bool light_present, const std::string& name) {
  return CompareSide{rare_renders(spp, seed, light_present, name)};
}

// Same-distribution pairs, 16 spp against 4096: without the guard (counted as
// held: plain Welch t rejecting) about a third of them would be DIFFERENT at
// the light pixel; with it, the DIFFERENT verdicts stay within α (one-sided
// binomial test at kCalibrationLevel) and the held ones are INCONCLUSIVE.
TEST(CompareRareEvent, AMissedRareLightIsHeldNotDifferent) {
  constexpr size_t kTrials = 200;
  size_t different = 0, held = 0, light_held = 0, inconclusive = 0;
  for (size_t t = 0; t < kTrials; ++t) {
    const CompareResult r = compare_renders(rare_event_side(16, kCalibrationSeed + 7000000 + 2 * t, true, "a"),
                                            rare_event_side(4096, kCalibrationSeed + 7000001 + 2 * t, true, "b"),
                                            kCalibrationAlpha, 1.0, kDefaultTileSize, /*test_variance=*/false);
    different += r.verdict == CompareVerdict::kDifferent ? 1 : 0;
    held += r.held.empty() ? 0 : 1;
    light_held += r.channels[0].worst_held == "pixel (8, 8)" ? 1 : 0;
    inconclusive += r.verdict == CompareVerdict::kInconclusive ? 1 : 0;
    // A held test is never SAME.
    if (!r.held.empty()) {
      EXPECT_NE(r.verdict, CompareVerdict::kSame) << "pair " << t;
    }
  }
  const double p = upper_tail(different, kTrials, kCalibrationAlpha);
  std::printf("missed rare light, 16 against 4096 spp: DIFFERENT %zu of %zu (P(X >= k) = %.3g at alpha %g); held %zu "
              "(at the light pixel %zu), INCONCLUSIVE %zu; without the guard (the plain Welch t) %zu would be "
              "DIFFERENT\n",
              different, kTrials, p, kCalibrationAlpha, held, light_held, inconclusive, different + inconclusive);
  EXPECT_GT(p, kCalibrationLevel);
  // The scenario is exercised: a plain Welch test would have failed many.
  EXPECT_GT(light_held, kTrials / 5);
}

// Negative controls. Side A without the light at that pixel (a renderer that
// drops it): at 16 spp indistinguishable from a missed rare event, so held
// (INCONCLUSIVE) with an spp factor; at that factor × the spp on both sides
// the same defect is DIFFERENT through the light pixel, as it is at 4096 spp.
TEST(CompareRareEvent, AMissingLightIsFoundAtTheSppTheGuardNames) {
  const CompareResult low = compare_renders(rare_event_side(16, kSeedA, false, "a"),
                                            rare_event_side(4096, kSeedB, true, "b"), kAlpha,
                                            kDefaultMaxDetectableDifference, kDefaultTileSize, false);
  const ChannelComparison& c = low.channels[0];
  ASSERT_EQ(low.verdict, CompareVerdict::kInconclusive) << format_compare(low);
  EXPECT_EQ(c.worst_held, "pixel (8, 8)");
  EXPECT_LT(c.worst_held_t, -c.worst_held_threshold);
  EXPECT_GE(c.worst_held_guarded_t, -c.worst_held_threshold);
  ASSERT_TRUE(std::isfinite(c.worst_held_spp_factor));
  const std::string text = format_compare(low);
  EXPECT_NE(text.find("rare-event guard: held"), std::string::npos) << text;
  EXPECT_NE(text.find("held by the rare-event guard, not judged: pixels"), std::string::npos) << text;
  EXPECT_EQ(exit_code(low.verdict), 3);
  const nlohmann::json j = compare_json(rare_event_side(16, kSeedA, false, "a"), rare_event_side(4096, kSeedB, true, "b"),
                                        low, {}, ChannelMode::kGray, "");
  EXPECT_EQ(j["channels"][0]["worst_held"]["test"], "pixel (8, 8)");
  EXPECT_EQ(j["rare_event_guard"]["spp_a"], 16.0);
  EXPECT_EQ(j["verdict"], "INCONCLUSIVE");

  const int factor = int(std::ceil(c.worst_held_spp_factor));
  const CompareResult at_factor = compare_renders(rare_event_side(16 * factor, kSeedA, false, "a"),
                                                  rare_event_side(4096 * factor, kSeedB, true, "b"), kAlpha,
                                                  kDefaultMaxDetectableDifference, kDefaultTileSize, false);
  EXPECT_EQ(at_factor.verdict, CompareVerdict::kDifferent) << "factor " << factor << "\n" << format_compare(at_factor);
  EXPECT_EQ(at_factor.channels[0].worst_pixel_x, 8);
  EXPECT_EQ(at_factor.channels[0].worst_pixel_y, 8);
  const CompareResult both_high = compare_renders(rare_event_side(4096, kSeedA, false, "a"),
                                                  rare_event_side(4096, kSeedB, true, "b"), kAlpha,
                                                  kDefaultMaxDetectableDifference, kDefaultTileSize, false);
  EXPECT_EQ(both_high.verdict, CompareVerdict::kDifferent) << format_compare(both_high);
  EXPECT_TRUE(both_high.held.empty());
}

// Where the light is not rare at either side's spp (4096 against 4096) the
// floor never binds: nothing is held, and two seed sets are SAME.
TEST(CompareRareEvent, EqualSidesHoldNothing) {
  const CompareResult r = compare_renders(rare_event_side(4096, kSeedA, true, "a"),
                                          rare_event_side(4096, kSeedB, true, "b"), kAlpha, 0.05, kDefaultTileSize,
                                          false);
  EXPECT_TRUE(r.held.empty()) << format_compare(r);
  EXPECT_EQ(r.verdict, CompareVerdict::kSame) << format_compare(r);
}

// A side whose files state no spp is taken at the other side's, and the
// report says so; with neither stated, the sides are taken as equal.
TEST(CompareRareEvent, UnstatedSppIsAssumedAndSaid) {
  CompareSide a = rare_event_side(16, kSeedA, true, "a"), b = rare_event_side(4096, kSeedB, true, "b");
  for (ForeignImage& img : a.images) img.stated_spp.clear();
  const CompareResult one = compare_renders(a, b, kAlpha, kDefaultMaxDetectableDifference, kDefaultTileSize, false);
  EXPECT_EQ(one.guard_spp_a, 4096);
  EXPECT_NE(one.guard_assumption.find("side A's files state no spp"), std::string::npos) << one.guard_assumption;
  for (ForeignImage& img : b.images) img.stated_spp.clear();
  const CompareResult none = compare_renders(a, b, kAlpha, kDefaultMaxDetectableDifference, kDefaultTileSize, false);
  EXPECT_EQ(none.guard_spp_a, 1);
  EXPECT_EQ(none.guard_spp_b, 1);
  EXPECT_NE(none.guard_assumption.find("neither side"), std::string::npos);
}

TEST(CompareCalibration, MixedSidesFalseAlarmRateIsAtMostAlpha) {
  expect_mixed_false_alarms_at_most_alpha(kFastTrials, 2);
  expect_mixed_false_alarms_at_most_alpha(kFastTrials, 4);
}
TEST(CompareCalibration, FalseAlarmRateIsAtMostAlpha) { expect_false_alarms_at_most_alpha(kFastTrials); }
TEST(CompareCalibration, PowerAtTheReportedDetectableDifference) {
  expect_power_at_the_detectable_difference(kFastTrials);
}
// Dark (mean ~1e-3) and bright (~1e3) renders: the same false-alarm and
// power claims (issue 41: they were measured at a mean near 1 only).
TEST(CompareCalibration, DarkAndBrightFalseAlarmRateIsAtMostAlpha) {
  expect_false_alarms_at_most_alpha(kFastTrials, 1e-3);
  expect_false_alarms_at_most_alpha(kFastTrials, 1e3);
}
TEST(CompareCalibration, DarkAndBrightPowerAtTheReportedDetectableDifference) {
  expect_power_at_the_detectable_difference(kFastTrials, 1e-3);
  expect_power_at_the_detectable_difference(kFastTrials, 1e3);
}
#else
// The slow label (verify_compare_slow_tests, this file built with
// FURNACE_COMPARE_SLOW): the same claims over kSlowTrials pairs.
constexpr size_t kSlowTrials = 4000;
TEST(CompareCalibrationSlow, FalseAlarmRateIsAtMostAlpha) { expect_false_alarms_at_most_alpha(kSlowTrials); }
TEST(CompareCalibrationSlow, MixedSidesFalseAlarmRateIsAtMostAlpha) {
  expect_mixed_false_alarms_at_most_alpha(kSlowTrials / 2, 2);
  expect_mixed_false_alarms_at_most_alpha(kSlowTrials / 2, 4);
}
TEST(CompareCalibrationSlow, PowerAtTheReportedDetectableDifference) {
  expect_power_at_the_detectable_difference(kSlowTrials / 4);
}
#endif

}  // namespace
}  // namespace furnace::verify
