#include "verify/check_image.h"

#include <algorithm>
#include <cmath>
#include <string_view>

#include <fmt/format.h>

#include "core/error.h"
#include "core/exr.h"
#include "stats/statistics.h"

namespace furnace::verify {

namespace {

constexpr const char* kRgb[] = {"R", "G", "B"};
constexpr const char* kVarianceRgb[] = {"variance.R", "variance.G", "variance.B"};
constexpr const char* kCountChannel = "N";
// Header attributes stating the spp: pbrt-v4's (an int, src/pbrt/util/image.cpp)
// and Blender's stamp of a Cycles render ("cycles." + view layer + ".samples").
constexpr const char* kPbrtSppAttribute = "samplesPerPixel";
constexpr std::string_view kCyclesPrefix = "cycles.";
constexpr std::string_view kCyclesSuffix = ".samples";

std::string pixel_name(size_t i, int width) { return fmt::format("({}, {})", i % size_t(width), i / size_t(width)); }

// Radiance must be finite at every pixel; finite negative values are data
// (see ForeignImage::negative_values) and are counted into `img`.
void require_radiance(ForeignImage& img, const std::string& channel, const std::vector<double>& v) {
  for (size_t i = 0; i < v.size(); ++i) {
    if (!std::isfinite(v[i]))
      throw Error(fmt::format("image '{}' has radiance {} in channel '{}' at pixel {}; radiance must be finite.",
                              img.path, float(v[i]), channel, pixel_name(i, img.width)));
    if (v[i] >= 0) continue;
    ++img.negative_values;
    if (v[i] < img.most_negative) {
      img.most_negative = v[i];
      img.most_negative_channel = channel;
      img.most_negative_x = int(i % size_t(img.width));
      img.most_negative_y = int(i / size_t(img.width));
    }
  }
}

// The spp the header states (ForeignImage::stated_spp): furnace's own
// attribute, pbrt-v4's int samplesPerPixel, or Blender's
// cycles.<view layer>.samples string.
void read_stated_spp(const exr::Image& file, ForeignImage& img) {
  // Decimal digits of a positive whole number below 10¹⁵, else not a
  // statement of the spp.
  const auto whole = [](const std::string& text) {
    if (text.empty() || text.size() > 15 || text.find_first_not_of("0123456789") != std::string::npos) return false;
    return std::stoll(text) >= 1;
  };
  std::string spp, attribute;
  if (!img.provenance.spp.empty()) {
    spp = img.provenance.spp;
    attribute = "furnace.spp";
  } else if (const auto n = file.numbers.find(kPbrtSppAttribute); n != file.numbers.end()) {
    spp = fmt::format("{}", n->second);
    attribute = kPbrtSppAttribute;
  } else {
    for (const auto& [name, value] : file.attributes)
      if (name.size() > kCyclesPrefix.size() + kCyclesSuffix.size() && name.rfind(kCyclesPrefix, 0) == 0 &&
          name.compare(name.size() - kCyclesSuffix.size(), kCyclesSuffix.size(), kCyclesSuffix) == 0) {
        spp = value;
        attribute = name;
        break;
      }
  }
  if (!whole(spp)) return;
  img.stated_spp = spp;
  img.spp_attribute = attribute;
}

void require_variance(const std::string& path, const std::string& channel, const std::vector<double>& v, int width) {
  for (size_t i = 0; i < v.size(); ++i)
    if (!std::isfinite(v[i]) || v[i] < 0)
      throw Error(fmt::format("image '{}' has variance {} in channel '{}' at pixel {}; a variance must be finite and "
                              "non-negative.",
                              path, float(v[i]), channel, pixel_name(i, width)));
}

void require_counts(const std::string& path, const std::vector<double>& n, int width) {
  for (size_t i = 0; i < n.size(); ++i)
    if (!(n[i] >= 1) || n[i] != std::floor(n[i]) || !std::isfinite(n[i]))
      throw Error(fmt::format("image '{}' has sample count N = {} at pixel {}; every pixel needs a positive whole "
                              "number of samples.",
                              path, n[i], pixel_name(i, width)));
}

}  // namespace

std::string channel_mode_name(ChannelMode mode) { return mode == ChannelMode::kRgb ? "rgb" : "gray"; }

namespace {

// Reads and validates; the resolution is checked against `scene` when given,
// before any channel.
ForeignImage read_image(const std::string& path, const Scene* scene, ChannelMode mode) {
  const exr::Image file = exr::read(path, "image");
  ForeignImage img;
  img.path = path;
  img.width = file.width;
  img.height = file.height;
  if (scene && (img.width != scene->camera.width_px || img.height != scene->camera.height_px))
    throw Error(fmt::format("image '{}' is {}x{} pixels but scene '{}' field 'camera.resolution' is [{}, {}].", path,
                            img.width, img.height, scene->source, scene->camera.width_px, scene->camera.height_px));
  img.provenance = ImageProvenance::from_attributes(file.attributes);

  const bool rgb = file.has_channel("R") && file.has_channel("G") && file.has_channel("B");
  if (mode == ChannelMode::kRgb && !rgb)
    throw Error(fmt::format("image '{}' lacks one of the R, G and B channels that --channels rgb tests (its "
                            "channels: {}).",
                            path, file.channel_list()));
  if (!rgb && !file.has_channel("Y"))
    throw Error(fmt::format("image '{}' has neither R, G and B channels nor a Y channel (its channels: {}).", path,
                            file.channel_list()));
  std::vector<std::vector<double>> planes;
  for (const char* c : kRgb)
    if (rgb) planes.push_back(file.values(c));
  if (!rgb) planes.push_back(file.values("Y"));
  img.source_channels = rgb ? "R, G, B" : "Y";
  for (size_t c = 0; c < planes.size(); ++c) require_radiance(img, rgb ? kRgb[c] : "Y", planes[c]);
  for (const exr::ChannelInfo& info : file.channels)
    if (info.type == exr::PixelType::kHalf &&
        (rgb ? (info.name == "R" || info.name == "G" || info.name == "B") : info.name == "Y"))
      img.half_float = true;
  read_stated_spp(file, img);

  const bool furnace_exr = rgb && file.has_channel(kVarianceRgb[0]) && file.has_channel(kVarianceRgb[1]) &&
                           file.has_channel(kVarianceRgb[2]) && file.has_channel(kCountChannel);
  std::vector<std::vector<double>> variances;
  for (const char* c : kVarianceRgb)
    if (file.has_channel(c)) {
      variances.push_back(file.values(c));
      require_variance(path, c, variances.back(), img.width);
    }
  if (file.has_channel(kCountChannel)) {
    img.count = file.values(kCountChannel);
    require_counts(path, img.count, img.width);
  }
  if (!furnace_exr) img.count.clear();

  const size_t n = size_t(img.width) * size_t(img.height);
  if (mode == ChannelMode::kRgb) {
    img.channels = {"R", "G", "B"};
    img.value = std::move(planes);
    if (furnace_exr) img.variance = std::move(variances);
  } else {
    img.channels = {"gray"};
    img.value.assign(1, std::vector<double>(n, 0.0));
    for (const auto& plane : planes)
      for (size_t i = 0; i < n; ++i) img.value[0][i] += plane[i] / double(planes.size());
    if (furnace_exr) {
      // ((s_R + s_G + s_B)/3)²: see the header.
      img.variance.assign(1, std::vector<double>(n, 0.0));
      for (size_t i = 0; i < n; ++i) {
        double mean_sd = 0;
        for (const auto& v : variances) mean_sd += std::sqrt(v[i]) / 3.0;
        img.variance[0][i] = mean_sd * mean_sd;
      }
    }
  }
  return img;
}

}  // namespace

ForeignImage read_foreign_image(const std::string& path, const Scene& scene, ChannelMode mode) {
  return read_image(path, &scene, mode);
}

ForeignImage read_foreign_image(const std::string& path, ChannelMode mode) { return read_image(path, nullptr, mode); }

void reject_identical_images(const std::vector<ForeignImage>& images, const std::vector<double>& reference) {
  for (size_t a = 0; a < images.size(); ++a)
    for (size_t b = a + 1; b < images.size(); ++b) {
      if (images[a].value != images[b].value) continue;
      bool exact = true;  // a zero-variance render: every value on the reference
      for (const auto& plane : images[a].value)
        for (size_t i = 0; i < plane.size() && exact; ++i)
          exact = std::fabs(plane[i] - reference[i]) <= stats::kZeroVarianceRelTolerance * std::fabs(reference[i]);
      if (exact) continue;
      throw Error(fmt::format("images '{}' and '{}' hold identical pixels; independent renders (different seeds) "
                              "are needed to measure the spread.",
                              images[a].path, images[b].path));
    }
}

NegativeValues count_negative_values(const std::vector<ForeignImage>& images) {
  NegativeValues n;
  for (const ForeignImage& img : images) {
    if (img.negative_values == 0) continue;
    n.values += img.negative_values;
    ++n.images;
    if (img.most_negative < n.most_negative) {
      n.most_negative = img.most_negative;
      n.path = img.path;
      n.channel = img.most_negative_channel;
      n.x = img.most_negative_x;
      n.y = img.most_negative_y;
    }
  }
  return n;
}

bool any_half_float(const std::vector<ForeignImage>& images) {
  return std::any_of(images.begin(), images.end(), [](const ForeignImage& img) { return img.half_float; });
}

double images_spp(const std::vector<ForeignImage>& images) {
  const std::string& first = images[0].stated_spp;
  bool same = !first.empty();
  for (const ForeignImage& img : images) same = same && img.stated_spp == first;
  if (same) return std::stod(first);
  if (!images[0].count.empty()) return stats::median(images[0].count);
  return 0;
}

GuardSpp guard_spp(const std::vector<ForeignImage>& a, const std::vector<ForeignImage>& b, const std::string& a_owner,
                   const std::string& b_owner, const std::string& neither) {
  const bool a_exr = a.size() == 1, b_exr = b.size() == 1;
  GuardSpp g;
  g.a = a_exr ? 0 : images_spp(a);
  g.b = b_exr ? 0 : images_spp(b);
  if (!a_exr && !b_exr && g.a == 0 && g.b == 0) {
    g.a = g.b = 1;
    g.assumption = neither + " files state their spp: the rare-event guard takes them as equal";
    return g;
  }
  const auto assume = [&](bool exr, double& spp, const std::vector<ForeignImage>& other, bool other_exr,
                          double other_spp, const std::string& owner, const std::string& other_owner) {
    if (exr || spp > 0) return;
    spp = other_exr ? images_spp(other) : other_spp;
    g.assumption = fmt::format("{} files state no spp: the rare-event guard takes them at {} {}, {:.6g}", owner,
                               other_owner, other_exr ? "median N" : "spp", spp);
  };
  assume(a_exr, g.a, b, b_exr, g.b, a_owner, b_owner);
  assume(b_exr, g.b, a, a_exr, g.a, b_owner, a_owner);
  return g;
}

}  // namespace furnace::verify
