// EXR output: a round trip keeps means and variances to float precision and
// counts exactly; failures name the file and the problem and leave nothing
// behind.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>

#include "core/error.h"
#include "renderer/exr_io.h"

namespace furnace {
namespace {

namespace fs = std::filesystem;

class ExrIo : public testing::Test {
 protected:
  void SetUp() override {
    const auto* info = testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / (std::string("furnace_exr_") + info->name() + "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  static Image make_image(int w, int h) {
    Image image;
    image.width = w;
    image.height = h;
    image.pixels.resize(size_t(w) * h);
    for (int i = 0; i < w * h; ++i)
      for (int s = 0; s <= i % 7; ++s) image.pixels[i].add(0.1 * i + 0.37 * s * s);
    image.rays = 1234;
    return image;
  }
  size_t files_in_dir() const { return size_t(std::distance(fs::directory_iterator(dir_), fs::directory_iterator())); }

  fs::path dir_;
};

TEST_F(ExrIo, RoundTripKeepsMeanVarianceAndCount) {
  const Image image = make_image(5, 3);
  const fs::path path = dir_ / "round.exr";
  write_exr(path, image);
  EXPECT_EQ(files_in_dir(), 1u);  // no temporary left behind
  const ExrImage back = read_exr(path);
  ASSERT_EQ(back.width, 5);
  ASSERT_EQ(back.height, 3);
  for (size_t i = 0; i < image.pixels.size(); ++i) {
    EXPECT_EQ(back.mean[i], float(image.pixels[i].mean));
    EXPECT_EQ(back.variance[i], float(image.pixels[i].sample_variance()));
    EXPECT_EQ(back.count[i], image.pixels[i].count);
  }
}

TEST_F(ExrIo, CountChannelReadsIntoAFloatFrameBuffer) {
  // N is stored as UINT (exact counts); readers that ask for FLOAT (verify's
  // `furnace check`) get OpenEXR's conversion, exact below 2^24.
  const Image image = make_image(3, 2);
  const fs::path path = dir_ / "count.exr";
  write_exr(path, image);
  Imf::InputFile file(path.string().c_str());
  std::vector<float> n(6);
  Imf::FrameBuffer frame;
  frame.insert("N", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(n.data()), sizeof(float), 3 * sizeof(float)));
  file.setFrameBuffer(frame);
  file.readPixels(0, 1);
  for (size_t i = 0; i < n.size(); ++i) EXPECT_EQ(n[i], float(image.pixels[i].count));
}

TEST_F(ExrIo, OverwritesAnExistingFileAtomically) {
  const fs::path path = dir_ / "twice.exr";
  write_exr(path, make_image(2, 2));
  write_exr(path, make_image(4, 1));
  EXPECT_EQ(read_exr(path).width, 4);
  EXPECT_EQ(files_in_dir(), 1u);
}

TEST_F(ExrIo, WriteIntoMissingDirectoryNamesTheFile) {
  const fs::path path = dir_ / "no" / "such" / "dir" / "out.exr";
  try {
    write_exr(path, make_image(2, 2));
    FAIL() << "no exception";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(path));
  EXPECT_EQ(files_in_dir(), 0u);
}

TEST_F(ExrIo, ReadMissingFileNamesTheFile) {
  const fs::path path = dir_ / "absent.exr";
  try {
    read_exr(path);
    FAIL() << "no exception";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
  }
}

TEST_F(ExrIo, ReadNonExrFileNamesTheFile) {
  const fs::path path = dir_ / "text.exr";
  std::ofstream(path) << "not an image";
  EXPECT_THROW(read_exr(path), Error);
}

TEST_F(ExrIo, MissingChannelIsNamed) {
  // A valid EXR with R, G, B only (what an ordinary tool would write).
  const fs::path path = dir_ / "rgb.exr";
  Imf::Header header(2, 2);
  std::vector<float> pixels(4, 0.5f);
  Imf::FrameBuffer frame;
  for (const char* c : {"R", "G", "B"}) {
    header.channels().insert(c, Imf::Channel(Imf::FLOAT));
    frame.insert(c, Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(pixels.data()), sizeof(float), 2 * sizeof(float)));
  }
  {
    Imf::OutputFile file(path.string().c_str(), header);
    file.setFrameBuffer(frame);
    file.writePixels(2);
  }
  try {
    read_exr(path);
    FAIL() << "no exception";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(path.string()), std::string::npos) << what;
    EXPECT_NE(what.find("'variance.R'"), std::string::npos) << what;
  }
}

TEST_F(ExrIo, LayoutAndProvenanceAreInTheFile) {
  // The channels and types of the layout in exr_io.h, and the provenance attributes.
  ImageProvenance provenance;
  provenance.scene = "disk_occluder";
  provenance.scene_hash = "fnv1a64:0123456789abcdef";
  provenance.strategy = "path_mis";
  provenance.max_depth = depth_name(kUnlimitedDepth);
  const fs::path path = dir_ / "layout.exr";
  write_exr(path, make_image(2, 2), provenance);
  Imf::InputFile file(path.string().c_str());
  std::vector<std::string> names;
  for (auto c = file.header().channels().begin(); c != file.header().channels().end(); ++c) {
    names.push_back(c.name());
    EXPECT_EQ(c.channel().type, names.back() == "N" ? Imf::UINT : Imf::FLOAT) << c.name();
  }
  EXPECT_EQ(names, (std::vector<std::string>{"B", "G", "N", "R", "variance.B", "variance.G", "variance.R"}));
  const ExrImage back = read_exr(path);
  EXPECT_EQ(back.attributes.at("furnace.scene"), "disk_occluder");
  EXPECT_EQ(back.attributes.at("furnace.scene_hash"), "fnv1a64:0123456789abcdef");
  EXPECT_EQ(back.attributes.at("furnace.max_depth"), "unlimited");
  EXPECT_EQ(back.attributes.at("furnace.rays"), "1234");
}

TEST_F(ExrIo, RenderProvenanceHashesTheSceneFile) {
  const std::string scene_path = std::string(FURNACE_SCENE_DIR) + "/disk_occluder.json";
  const Scene scene = load_scene(scene_path);
  RenderOptions options;
  options.strategy = Strategy::kPathMis;
  options.spp = 17;
  options.seed = 5;
  options.max_depth = 4;
  const ImageProvenance p = render_provenance(scene_path, scene, options);
  EXPECT_EQ(p.scene, "disk_occluder");
  EXPECT_EQ(p.scene_hash, file_content_hash(scene_path));
  EXPECT_EQ(p.strategy, "path_mis");
  EXPECT_EQ(p.spp, "17");
  EXPECT_EQ(p.seed, "5");
  EXPECT_EQ(p.max_depth, "4");
  EXPECT_EQ(p.light_selection, "uniform");
  EXPECT_EQ(p.defect, "none");
  EXPECT_EQ(p.version, furnace_version());
}

TEST_F(ExrIo, EmptyImageIsRejected) {
  EXPECT_THROW(write_exr(dir_ / "empty.exr", Image{}), Error);
  EXPECT_EQ(files_in_dir(), 0u);
}

}  // namespace
}  // namespace furnace
