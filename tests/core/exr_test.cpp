// core/exr.h and core/atomic_file.h: the one OpenEXR reader/writer and the
// one atomic file writer. Round trips are exact (FLOAT, HALF, UINT, string
// attributes, offset data windows); every failure is one sentence naming the
// file and what is wrong; a failed write leaves nothing behind.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <Imath/half.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>

#include "core/atomic_file.h"
#include "core/environment_map.h"
#include "core/error.h"
#include "core/exr.h"

namespace furnace {
namespace {

namespace fs = std::filesystem;

class ExrModule : public testing::Test {
 protected:
  void SetUp() override {
    const auto* info = testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / (std::string("furnace_core_exr_") + info->name() + "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  size_t files_in_dir() const { return size_t(std::distance(fs::directory_iterator(dir_), fs::directory_iterator())); }

  // The message is one sentence and holds every fragment.
  static void expect_sentence(const std::string& message, const std::vector<std::string>& fragments) {
    for (const std::string& f : fragments) EXPECT_NE(message.find(f), std::string::npos) << f << " not in: " << message;
    ASSERT_FALSE(message.empty());
    EXPECT_EQ(message.back(), '.') << message;
    EXPECT_EQ(message.find(". "), std::string::npos) << "one sentence: " << message;
  }

  static exr::Image sample_image() {
    exr::Image image;
    image.width = 3;
    image.height = 2;
    image.floats["R"] = {0.1f, 0.2f, 0.3f, 0.4f, 0.5f, std::numeric_limits<float>::infinity()};
    image.floats["variance.R"] = {1e-30f, 2, 3, 4, 5, 6};
    image.uints["N"] = {1, 2, 3, 4, 5, 4294967295u};
    image.attributes = {{"furnace.scene", "disk_occluder"}, {"note", "two words"}};
    return image;
  }

  fs::path dir_;
};

TEST_F(ExrModule, RoundTripIsExactForFloatUintAndAttributes) {
  const exr::Image image = sample_image();
  const fs::path path = dir_ / "round.exr";
  exr::write(path, image);
  EXPECT_EQ(files_in_dir(), 1u);  // no temporary left behind
  const exr::Image back = exr::read(path);
  EXPECT_EQ(back.path, path.string());
  EXPECT_EQ(back.width, 3);
  EXPECT_EQ(back.height, 2);
  EXPECT_EQ(back.floats, image.floats);
  EXPECT_EQ(back.uints, image.uints);
  EXPECT_EQ(back.attribute("furnace.scene"), "disk_occluder");
  EXPECT_EQ(back.attribute("note"), "two words");
  EXPECT_FALSE(back.attribute("absent").has_value());
  // OpenEXR lists channels alphabetically, with their stored types.
  ASSERT_EQ(back.channels.size(), 3u);
  EXPECT_EQ(back.channels[0].name, "N");
  EXPECT_EQ(back.channels[0].type, exr::PixelType::kUint);
  EXPECT_EQ(back.channels[1].name, "R");
  EXPECT_EQ(back.channels[2].name, "variance.R");
  EXPECT_EQ(back.channels[2].type, exr::PixelType::kFloat);
  EXPECT_EQ(back.channel_list(), "N, R, variance.R");
  // values() is exact for every type, UINT included beyond 2^24.
  EXPECT_EQ(back.values("N").back(), 4294967295.0);
  EXPECT_EQ(back.values("R")[0], double(0.1f));
}

TEST_F(ExrModule, HalfChannelsAndOffsetDataWindowsReadInPlace) {
  // A HALF Y channel in a data window that starts at (10, 20), written by OpenEXR directly.
  const fs::path path = dir_ / "window.exr";
  const Imath::Box2i window({10, 20}, {12, 21});
  Imf::Header header(window, window);
  header.channels().insert("Y", Imf::Channel(Imf::HALF));
  std::vector<half> pixels = {half(0.5f), half(1.0f), half(2.0f), half(0.25f), half(8.0f), half(-1.0f)};
  Imf::FrameBuffer frame;
  frame.insert("Y", Imf::Slice::Make(Imf::HALF, pixels.data(), window, sizeof(half)));
  {
    Imf::OutputFile file(path.string().c_str(), header);
    file.setFrameBuffer(frame);
    file.writePixels(2);
  }
  const exr::Image back = exr::read(path);
  ASSERT_EQ(back.width, 3);
  ASSERT_EQ(back.height, 2);
  EXPECT_EQ(back.channels[0].type, exr::PixelType::kHalf);
  EXPECT_EQ(back.values("Y"), (std::vector<double>{0.5, 1.0, 2.0, 0.25, 8.0, -1.0}));
}

TEST_F(ExrModule, MissingChannelNamesFileChannelAndWhatIsThere) {
  const fs::path path = dir_ / "rgb.exr";
  exr::write(path, sample_image());
  try {
    exr::read(path).values("G");
    FAIL() << "no exception";
  } catch (const Error& e) {
    expect_sentence(e.what(), {path.string(), "'G'", "N, R, variance.R"});
  }
}

TEST_F(ExrModule, MissingFileIsNamed) {
  const fs::path path = dir_ / "absent.exr";
  try {
    exr::read(path, "environment map");
    FAIL() << "no exception";
  } catch (const Error& e) {
    expect_sentence(e.what(), {"environment map", path.string(), "does not exist"});
  }
}

TEST_F(ExrModule, NonExrFileIsNamed) {
  const fs::path path = dir_ / "text.exr";
  std::ofstream(path) << "not an image";
  try {
    exr::read(path);
    FAIL() << "no exception";
  } catch (const Error& e) {
    expect_sentence(e.what(), {"cannot read", path.string(), "not an OpenEXR file"});
  }
}

TEST_F(ExrModule, TruncatedFileIsOneSentenceNamingTheFile) {
  const fs::path path = dir_ / "cut.exr";
  exr::write(path, sample_image());
  fs::resize_file(path, fs::file_size(path) / 2);
  try {
    exr::read(path);
    FAIL() << "no exception";
  } catch (const Error& e) {
    expect_sentence(e.what(), {"cannot read", path.string()});
  }
}

TEST_F(ExrModule, WrongChannelSizeIsRejectedAndNothingIsWritten) {
  exr::Image image = sample_image();
  image.floats["R"].pop_back();
  const fs::path path = dir_ / "short.exr";
  try {
    exr::write(path, image);
    FAIL() << "no exception";
  } catch (const Error& e) {
    expect_sentence(e.what(), {path.string(), "'R'", "5 values", "3x2"});
  }
  EXPECT_EQ(files_in_dir(), 0u);
}

TEST_F(ExrModule, EmptyImageIsRejected) {
  EXPECT_THROW(exr::write(dir_ / "empty.exr", exr::Image{}), Error);
  EXPECT_EQ(files_in_dir(), 0u);
}

TEST_F(ExrModule, WriteIntoMissingDirectoryNamesTheFileAndLeavesNothing) {
  const fs::path path = dir_ / "no" / "such" / "out.exr";
  try {
    exr::write(path, sample_image());
    FAIL() << "no exception";
  } catch (const Error& e) {
    expect_sentence(e.what(), {"cannot write", path.string()});
  }
  EXPECT_EQ(files_in_dir(), 0u);
}

TEST_F(ExrModule, OverwriteReplacesTheFileWhole) {
  const fs::path path = dir_ / "twice.exr";
  exr::write(path, sample_image());
  exr::Image small;
  small.width = small.height = 1;
  small.floats["Y"] = {7};
  exr::write(path, small);
  EXPECT_EQ(exr::read(path).values("Y"), std::vector<double>{7});
  EXPECT_EQ(files_in_dir(), 1u);
}

TEST_F(ExrModule, AtomicTextWriteReplacesAndLeavesNoTemporary) {
  const fs::path path = dir_ / "report.md";
  write_text_file_atomically(path, "first\n");
  write_text_file_atomically(path, "second\n");
  std::ifstream in(path);
  EXPECT_EQ(std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>()), "second\n");
  EXPECT_EQ(files_in_dir(), 1u);
}

TEST_F(ExrModule, FailedWriterLeavesTheOldFileAndNoTemporary) {
  const fs::path path = dir_ / "keep.txt";
  write_text_file_atomically(path, "old\n");
  try {
    write_file_atomically(
        path,
        [](const fs::path& tmp) {
          std::ofstream(tmp) << "half";
          throw std::runtime_error("disk full");
        },
        "report file");
    FAIL() << "no exception";
  } catch (const Error& e) {
    expect_sentence(e.what(), {"cannot write report file", path.string(), "disk full"});
  }
  std::ifstream in(path);
  EXPECT_EQ(std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>()), "old\n");
  EXPECT_EQ(files_in_dir(), 1u);
}

TEST_F(ExrModule, ConcurrentWritersOfOneFileNeverMix) {
  // Each writer has its own temporary; the survivor is one writer's whole text.
  const fs::path path = dir_ / "busy.txt";
  const std::string a(1 << 20, 'a'), b(1 << 20, 'b');
  std::thread first([&] { for (int i = 0; i < 8; ++i) write_text_file_atomically(path, a); });
  std::thread second([&] { for (int i = 0; i < 8; ++i) write_text_file_atomically(path, b); });
  first.join();
  second.join();
  std::ifstream in(path);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_TRUE(text == a || text == b);
  EXPECT_EQ(files_in_dir(), 1u);
}

// The committed environment map loads through the module exactly as OpenEXR
// itself reads it (an independent FLOAT read of the file's Y channel).
TEST(ExrModuleCommittedFile, EnvironmentMapLoadsBitIdentically) {
  const std::string path = std::string(FURNACE_SCENE_DIR) + "/environment_map.exr";
  Imf::InputFile file(path.c_str());
  const Imath::Box2i dw = file.header().dataWindow();
  const int width = dw.max.x - dw.min.x + 1, height = dw.max.y - dw.min.y + 1;
  std::vector<float> y(size_t(width) * height);
  Imf::FrameBuffer frame;
  frame.insert("Y", Imf::Slice::Make(Imf::FLOAT, y.data(), dw, sizeof(float)));
  file.setFrameBuffer(frame);
  file.readPixels(dw.min.y, dw.max.y);
  const LatLongMap map = load_latlong_exr(path);
  ASSERT_EQ(map.width, width);
  ASSERT_EQ(map.height, height);
  ASSERT_EQ(map.texels.size(), y.size());
  for (size_t i = 0; i < y.size(); ++i) ASSERT_EQ(map.texels[i], double(y[i])) << i;
}

}  // namespace
}  // namespace furnace
