#include "renderer/exr_io.h"

#include <unistd.h>

#include <atomic>
#include <exception>
#include <string>
#include <system_error>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <fmt/format.h>

#include "core/error.h"

namespace furnace {

namespace {
// OpenEXR's messages sometimes end with a period and sometimes not; the
// error sentence must end with exactly one.
std::string as_sentence_end(std::string text) {
  while (!text.empty() && (text.back() == '.' || text.back() == ' ')) text.pop_back();
  return text + ".";
}
}  // namespace


namespace {

constexpr const char* kMeanChannels[] = {"R", "G", "B"};
constexpr const char* kVarianceChannels[] = {"variance.R", "variance.G", "variance.B"};
constexpr const char* kCountChannel = "N";
// Largest width or height read_exr accepts: the scene loader's resolution limit.
constexpr long kMaxDimension = 16384;

// A name in the destination directory no other writer in this or another process uses.
std::filesystem::path temporary_path_for(const std::filesystem::path& path) {
  static std::atomic<unsigned> counter{0};
  const std::string name = fmt::format(".{}.tmp-{}-{}", path.filename().string(), ::getpid(), counter++);
  return path.parent_path() / name;
}

}  // namespace

void write_exr(const std::filesystem::path& path, const Image& image) {
  const size_t n = size_t(image.width) * size_t(image.height);
  if (image.width < 1 || image.height < 1 || image.pixels.size() != n)
    throw Error(fmt::format("cannot write OpenEXR file '{}': the image is {}x{} with {} pixels.", path.string(),
                            image.width, image.height, image.pixels.size()));
  std::vector<float> mean(n), variance(n);
  std::vector<uint32_t> count(n);
  for (size_t i = 0; i < n; ++i) {
    const PixelMoments& m = image.pixels[i];
    mean[i] = float(m.mean);
    variance[i] = float(m.sample_variance());
    count[i] = m.count > UINT32_MAX ? UINT32_MAX : uint32_t(m.count);
  }

  Imf::Header header(image.width, image.height);
  header.compression() = Imf::ZIP_COMPRESSION;
  header.insert("furnace.nonfinite_samples", Imf::StringAttribute(std::to_string(image.nonfinite_samples)));
  header.insert("furnace.rays", Imf::StringAttribute(std::to_string(image.rays)));
  Imf::FrameBuffer frame;
  const size_t fstride = sizeof(float), ustride = sizeof(uint32_t);
  for (const char* c : kMeanChannels) {
    header.channels().insert(c, Imf::Channel(Imf::FLOAT));
    frame.insert(c, Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(mean.data()), fstride, fstride * image.width));
  }
  for (const char* c : kVarianceChannels) {
    header.channels().insert(c, Imf::Channel(Imf::FLOAT));
    frame.insert(c, Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(variance.data()), fstride, fstride * image.width));
  }
  header.channels().insert(kCountChannel, Imf::Channel(Imf::UINT));
  frame.insert(kCountChannel, Imf::Slice(Imf::UINT, reinterpret_cast<char*>(count.data()), ustride, ustride * image.width));

  const std::filesystem::path tmp = temporary_path_for(path);
  try {
    {
      Imf::OutputFile file(tmp.string().c_str(), header);
      file.setFrameBuffer(frame);
      file.writePixels(image.height);
    }  // closed (and flushed) before the rename
    std::filesystem::rename(tmp, path);
  } catch (const std::exception& e) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    throw Error(fmt::format("cannot write OpenEXR file '{}': {}", path.string(), as_sentence_end(e.what())));
  }
}

ExrImage read_exr(const std::filesystem::path& path) {
  try {
    Imf::InputFile file(path.string().c_str());
    const Imf::Header& header = file.header();
    const Imath::Box2i dw = header.dataWindow();
    const long width = long(dw.max.x) - long(dw.min.x) + 1;
    const long height = long(dw.max.y) - long(dw.min.y) + 1;
    if (width < 1 || height < 1 || width > kMaxDimension || height > kMaxDimension)
      throw Error(fmt::format("OpenEXR file '{}' has a data window of {}x{} pixels; expected 1 to {} per side.",
                              path.string(), width, height, kMaxDimension));
    const auto require = [&](const char* name, Imf::PixelType type, const char* type_name) {
      const Imf::Channel* c = header.channels().findChannel(name);
      if (!c) throw Error(fmt::format("OpenEXR file '{}' has no channel '{}' (written by furnace render?).", path.string(), name));
      if (c->type != type)
        throw Error(fmt::format("OpenEXR file '{}': channel '{}' must hold {} pixels.", path.string(), name, type_name));
      if (c->xSampling != 1 || c->ySampling != 1)
        throw Error(fmt::format("OpenEXR file '{}': channel '{}' is subsampled.", path.string(), name));
    };
    require(kMeanChannels[0], Imf::FLOAT, "FLOAT");
    require(kVarianceChannels[0], Imf::FLOAT, "FLOAT");
    require(kCountChannel, Imf::UINT, "UINT");

    ExrImage out;
    out.width = int(width);
    out.height = int(height);
    const size_t n = size_t(width) * size_t(height);
    out.mean.resize(n);
    out.variance.resize(n);
    out.count.resize(n);
    // Slices are addressed from the data window's origin.
    const ptrdiff_t origin = -ptrdiff_t(dw.min.x) - ptrdiff_t(dw.min.y) * ptrdiff_t(width);
    Imf::FrameBuffer frame;
    const size_t fstride = sizeof(float), ustride = sizeof(uint32_t);
    frame.insert(kMeanChannels[0], Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(out.mean.data() + origin),
                                              fstride, fstride * width));
    frame.insert(kVarianceChannels[0], Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(out.variance.data() + origin),
                                                  fstride, fstride * width));
    frame.insert(kCountChannel, Imf::Slice(Imf::UINT, reinterpret_cast<char*>(out.count.data() + origin), ustride,
                                           ustride * width));
    file.setFrameBuffer(frame);
    file.readPixels(dw.min.y, dw.max.y);
    return out;
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw Error(fmt::format("cannot read OpenEXR file '{}': {}", path.string(), as_sentence_end(e.what())));
  }
}

}  // namespace furnace
