// core/provenance.h: the FNV-1a hash against the published test vectors, the
// file hash against the hash of the same bytes, and the attribute round trip.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/error.h"
#include "core/provenance.h"

namespace furnace {
namespace {

std::string fmt_hex(uint64_t h) {
  char text[32];
  std::snprintf(text, sizeof text, "fnv1a64:%016llx", static_cast<unsigned long long>(h));
  return text;
}

// Test vectors of the FNV reference (Fowler, Noll & Vo; isthe.com/chongo/tech/comp/fnv,
// and draft-eastlake-fnv), computed independently of this code.
TEST(Provenance, Fnv1a64MatchesPublishedVectors) {
  EXPECT_EQ(fnv1a_64(""), 0xcbf29ce484222325ull);  // the offset basis
  EXPECT_EQ(fnv1a_64("a"), 0xaf63dc4c8601ec8cull);
  EXPECT_EQ(fnv1a_64("foobar"), 0x85944171f73967e8ull);
}

TEST(Provenance, FileHashIsTheHashOfItsBytes) {
  const auto path = std::filesystem::temp_directory_path() / ("furnace_hash_" + std::to_string(::getpid()) + ".json");
  const std::string bytes = std::string("{\"name\": \"t\"}\n") + '\0' + "tail";
  std::ofstream(path, std::ios::binary) << bytes;
  EXPECT_EQ(file_content_hash(path), fmt_hex(fnv1a_64(bytes)));
  std::filesystem::remove(path);
  EXPECT_THROW(file_content_hash(path), Error);
}

TEST(Provenance, AttributesRoundTripAndAbsentFieldsStayEmpty) {
  ImageProvenance p;
  p.scene = "disk_occluder";
  p.scene_hash = "fnv1a64:0123456789abcdef";
  p.strategy = "path_mis";
  p.spp = "256";
  p.seed = "7";
  p.max_depth = depth_name(kUnlimitedDepth);
  p.light_selection = "uniform";
  p.defect = "none";
  p.version = furnace_version();
  const auto attributes = p.attributes();
  EXPECT_EQ(attributes.at("furnace.max_depth"), "unlimited");
  EXPECT_EQ(attributes.at("furnace.scene_hash"), "fnv1a64:0123456789abcdef");
  const ImageProvenance back = ImageProvenance::from_attributes(attributes);
  EXPECT_EQ(back.attributes(), attributes);
  EXPECT_TRUE(ImageProvenance::from_attributes({{"other", "x"}}).empty());
  EXPECT_EQ(depth_name(4), "4");
  EXPECT_FALSE(furnace_version().empty());
}

}  // namespace
}  // namespace furnace
