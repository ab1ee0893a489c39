#include "core/exr.h"

#include <exception>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfDoubleAttribute.h>
#include <OpenEXR/ImfFloatAttribute.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfTestFile.h>
#include <fmt/format.h>

#include "core/atomic_file.h"
#include "core/error.h"

namespace furnace::exr {

namespace {

namespace fs = std::filesystem;

// OpenEXR's messages sometimes end with a period and sometimes not, and some
// hold two sentences; ours must stay one sentence ending with one period.
std::string as_clause(std::string text) {
  while (!text.empty() && (text.back() == '.' || text.back() == ' ' || text.back() == '\n')) text.pop_back();
  for (size_t at = text.find(". "); at != std::string::npos; at = text.find(". ", at)) text.replace(at, 2, "; ");
  return text;
}

PixelType from_imf(Imf::PixelType type) {
  switch (type) {
    case Imf::UINT: return PixelType::kUint;
    case Imf::HALF: return PixelType::kHalf;
    default: return PixelType::kFloat;
  }
}

}  // namespace

const char* pixel_type_name(PixelType type) {
  switch (type) {
    case PixelType::kUint: return "UINT";
    case PixelType::kHalf: return "HALF";
    case PixelType::kFloat: return "FLOAT";
  }
  return "?";
}

bool Image::has_channel(const std::string& name) const { return floats.count(name) || uints.count(name); }

std::string Image::channel_list() const {
  std::string list;
  for (const ChannelInfo& c : channels) list += (list.empty() ? "" : ", ") + c.name;
  return list.empty() ? "none" : list;
}

std::vector<double> Image::values(const std::string& name) const {
  if (const auto f = floats.find(name); f != floats.end()) return {f->second.begin(), f->second.end()};
  if (const auto u = uints.find(name); u != uints.end()) return {u->second.begin(), u->second.end()};
  throw Error(fmt::format("image '{}' has no full-resolution channel '{}' (its channels: {}).", path, name,
                          channel_list()));
}

std::optional<std::string> Image::attribute(const std::string& name) const {
  const auto a = attributes.find(name);
  if (a == attributes.end()) return std::nullopt;
  return a->second;
}

Image read(const fs::path& path, std::string_view what) {
  const std::string file_name = path.string();
  std::error_code ec;
  if (!fs::is_regular_file(path, ec))
    throw Error(fmt::format("{} '{}' does not exist or is not a regular file.", what, file_name));
  bool tiled = false, deep = false, multi_part = false;
  if (!Imf::isOpenExrFile(file_name.c_str(), tiled, deep, multi_part))
    throw Error(fmt::format("cannot read {} '{}': it is not an OpenEXR file (it does not begin with the OpenEXR "
                            "magic number).",
                            what, file_name));
  if (deep)
    throw Error(fmt::format("cannot read {} '{}': it is a deep OpenEXR file, and only flat images are read.", what,
                            file_name));
  Image image;
  image.path = file_name;
  try {
    Imf::InputFile file(file_name.c_str());  // a multi-part file: its first part
    const Imf::Header& header = file.header();
    const Imath::Box2i dw = header.dataWindow();
    const long width = long(dw.max.x) - long(dw.min.x) + 1;
    const long height = long(dw.max.y) - long(dw.min.y) + 1;
    if (width < 1 || height < 1 || width > kMaxDimension || height > kMaxDimension)
      throw Error(fmt::format("{} '{}' has a data window of {}x{} pixels; expected 1 to {} per side.", what,
                              file_name, width, height, kMaxDimension));
    image.width = int(width);
    image.height = int(height);
    for (auto a = header.begin(); a != header.end(); ++a) {
      if (const auto* s = dynamic_cast<const Imf::StringAttribute*>(&a.attribute()))
        image.attributes[a.name()] = s->value();
      else if (const auto* i = dynamic_cast<const Imf::IntAttribute*>(&a.attribute()))
        image.numbers[a.name()] = double(i->value());
      else if (const auto* f = dynamic_cast<const Imf::FloatAttribute*>(&a.attribute()))
        image.numbers[a.name()] = double(f->value());
      else if (const auto* d = dynamic_cast<const Imf::DoubleAttribute*>(&a.attribute()))
        image.numbers[a.name()] = d->value();
    }

    const size_t n = size_t(width) * size_t(height);
    Imf::FrameBuffer frame;
    for (auto c = header.channels().begin(); c != header.channels().end(); ++c) {
      ChannelInfo info{c.name(), from_imf(c.channel().type), c.channel().xSampling != 1 || c.channel().ySampling != 1};
      image.channels.push_back(info);
      if (info.subsampled) continue;
      // Slice::Make addresses the buffer from the data window's origin.
      if (info.type == PixelType::kUint) {
        std::vector<uint32_t>& plane = image.uints[info.name];
        plane.resize(n);
        frame.insert(c.name(), Imf::Slice::Make(Imf::UINT, plane.data(), dw, sizeof(uint32_t)));
      } else {
        std::vector<float>& plane = image.floats[info.name];
        plane.resize(n);
        frame.insert(c.name(), Imf::Slice::Make(Imf::FLOAT, plane.data(), dw, sizeof(float)));
      }
    }
    file.setFrameBuffer(frame);
    file.readPixels(dw.min.y, dw.max.y);
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw Error(fmt::format("cannot read {} '{}': {}.", what, file_name, as_clause(e.what())));
  }
  return image;
}

void write(const fs::path& path, const Image& image, std::string_view what) {
  const std::string file_name = path.string();
  if (image.width < 1 || image.height < 1 || image.width > kMaxDimension || image.height > kMaxDimension)
    throw Error(fmt::format("cannot write {} '{}': the image is {}x{} pixels; expected 1 to {} per side.", what,
                            file_name, image.width, image.height, kMaxDimension));
  if (image.floats.empty() && image.uints.empty())
    throw Error(fmt::format("cannot write {} '{}': the image has no channels.", what, file_name));
  const size_t n = size_t(image.width) * size_t(image.height);
  for (const auto& [name, plane] : image.floats)
    if (plane.size() != n || image.uints.count(name))
      throw Error(fmt::format("cannot write {} '{}': channel '{}' holds {} values for {}x{} pixels{}.", what,
                              file_name, name, plane.size(), image.width, image.height,
                              image.uints.count(name) ? " and is also given as a UINT channel" : ""));
  for (const auto& [name, plane] : image.uints)
    if (plane.size() != n)
      throw Error(fmt::format("cannot write {} '{}': channel '{}' holds {} values for {}x{} pixels.", what,
                              file_name, name, plane.size(), image.width, image.height));

  Imf::Header header(image.width, image.height);
  header.compression() = Imf::ZIP_COMPRESSION;
  for (const auto& [name, value] : image.attributes) header.insert(name, Imf::StringAttribute(value));
  Imf::FrameBuffer frame;
  const size_t fstride = sizeof(float), ustride = sizeof(uint32_t);
  // OpenEXR only reads through the slices' pointers while writing.
  for (const auto& [name, plane] : image.floats) {
    header.channels().insert(name, Imf::Channel(Imf::FLOAT));
    frame.insert(name, Imf::Slice(Imf::FLOAT, const_cast<char*>(reinterpret_cast<const char*>(plane.data())), fstride,
                                  fstride * size_t(image.width)));
  }
  for (const auto& [name, plane] : image.uints) {
    header.channels().insert(name, Imf::Channel(Imf::UINT));
    frame.insert(name, Imf::Slice(Imf::UINT, const_cast<char*>(reinterpret_cast<const char*>(plane.data())), ustride,
                                  ustride * size_t(image.width)));
  }
  write_file_atomically(
      path,
      [&](const fs::path& tmp) {
        Imf::OutputFile file(tmp.string().c_str(), header);
        file.setFrameBuffer(frame);
        file.writePixels(image.height);
      },  // the file is closed (and flushed) when `file` goes out of scope, before the rename
      what);
}

}  // namespace furnace::exr
