#include "renderer/exr_io.h"

#include <fmt/format.h>

#include "core/error.h"
#include "core/exr.h"

namespace furnace {

namespace {

constexpr const char* kMeanChannels[] = {"R", "G", "B"};
constexpr const char* kVarianceChannels[] = {"variance.R", "variance.G", "variance.B"};
constexpr const char* kCountChannel = "N";

}  // namespace

void write_exr(const std::filesystem::path& path, const Image& image, const ImageProvenance& provenance) {
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
  exr::Image out;
  out.width = image.width;
  out.height = image.height;
  for (const char* c : kMeanChannels) out.floats[c] = mean;
  for (const char* c : kVarianceChannels) out.floats[c] = variance;
  out.uints[kCountChannel] = std::move(count);
  out.attributes = provenance.attributes();
  out.attributes["furnace.nonfinite_samples"] = std::to_string(image.nonfinite_samples);
  out.attributes["furnace.rays"] = std::to_string(image.rays);
  exr::write(path, out);
}

ImageProvenance render_provenance(const std::filesystem::path& scene_path, const Scene& scene,
                                  const RenderOptions& options) {
  ImageProvenance p;
  p.scene = scene.name;
  p.scene_hash = file_content_hash(scene_path);
  p.strategy = strategy_name(options.strategy);
  p.spp = std::to_string(options.spp);
  p.seed = std::to_string(options.seed);
  p.max_depth = depth_name(options.max_depth);
  p.light_selection = light_selection_name(options.light_selection);
  p.defect = defect_name(options.defect);
  p.convention = transport_convention_name(options.convention);
  p.version = furnace_version();
  return p;
}

ExrImage read_exr(const std::filesystem::path& path) {
  const exr::Image in = exr::read(path);
  const auto require = [&](const char* name, exr::PixelType type) {
    const exr::ChannelInfo* c = nullptr;
    for (const exr::ChannelInfo& info : in.channels)
      if (info.name == name) c = &info;
    if (!c) throw Error(fmt::format("OpenEXR file '{}' has no channel '{}' (written by furnace render?).", in.path, name));
    if (c->type != type)
      throw Error(fmt::format("OpenEXR file '{}': channel '{}' must hold {} pixels.", in.path, name,
                              exr::pixel_type_name(type)));
    if (c->subsampled) throw Error(fmt::format("OpenEXR file '{}': channel '{}' is subsampled.", in.path, name));
  };
  require(kMeanChannels[0], exr::PixelType::kFloat);
  require(kVarianceChannels[0], exr::PixelType::kFloat);
  require(kCountChannel, exr::PixelType::kUint);
  ExrImage out;
  out.width = in.width;
  out.height = in.height;
  out.mean = in.floats.at(kMeanChannels[0]);
  out.variance = in.floats.at(kVarianceChannels[0]);
  out.count = in.uints.at(kCountChannel);
  out.attributes = in.attributes;
  return out;
}

}  // namespace furnace
