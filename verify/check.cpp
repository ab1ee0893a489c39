#include "verify/check.h"

#include <algorithm>
#include <cmath>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <fmt/format.h>

#include "analytic/global.h"
#include "analytic/reference.h"
#include "core/error.h"
#include "verify/pixel_tests.h"
#include "verify/statistics.h"

namespace furnace::verify {

ForeignImage read_foreign_image(const std::string& path, const Scene& scene) {
  ForeignImage img;
  img.path = path;
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i dw = file.header().dataWindow();
    img.width = dw.max.x - dw.min.x + 1;
    img.height = dw.max.y - dw.min.y + 1;
    if (img.width != scene.camera.width_px || img.height != scene.camera.height_px)
      throw Error(fmt::format("image '{}' is {}x{} pixels but scene '{}' field 'camera.resolution' is [{}, {}].", path,
                              img.width, img.height, scene.source, scene.camera.width_px, scene.camera.height_px));
    const Imf::ChannelList& channels = file.header().channels();
    std::vector<std::string> names;
    if (channels.findChannel("R") && channels.findChannel("G") && channels.findChannel("B"))
      names = {"R", "G", "B"};
    else if (channels.findChannel("Y"))
      names = {"Y"};
    else
      throw Error(fmt::format("image '{}' has neither R, G and B channels nor a Y channel.", path));
    const bool furnace_exr = channels.findChannel("variance.R") && channels.findChannel("N");

    const size_t n = size_t(img.width) * img.height;
    std::vector<std::vector<float>> planes(names.size() + (furnace_exr ? 2 : 0), std::vector<float>(n));
    Imf::FrameBuffer frame;
    const size_t xs = sizeof(float), ys = sizeof(float) * size_t(img.width);
    // Slices are addressed from the data window's origin.
    auto base = [&](std::vector<float>& plane) {
      return reinterpret_cast<char*>(plane.data()) - (ptrdiff_t(dw.min.x) * xs + ptrdiff_t(dw.min.y) * ys);
    };
    for (size_t c = 0; c < names.size(); ++c)
      frame.insert(names[c].c_str(), Imf::Slice(Imf::FLOAT, base(planes[c]), xs, ys));
    if (furnace_exr) {
      frame.insert("variance.R", Imf::Slice(Imf::FLOAT, base(planes[names.size()]), xs, ys));
      frame.insert("N", Imf::Slice(Imf::FLOAT, base(planes[names.size() + 1]), xs, ys));
    }
    file.setFrameBuffer(frame);
    file.readPixels(dw.min.y, dw.max.y);

    img.value.assign(n, 0.0);
    for (size_t c = 0; c < names.size(); ++c)
      for (size_t i = 0; i < n; ++i) img.value[i] += double(planes[c][i]) / double(names.size());
    for (size_t i = 0; i < n; ++i)
      if (!std::isfinite(img.value[i]))
        throw Error(fmt::format("image '{}' has a non-finite value at pixel ({}, {}).", path, i % img.width,
                                i / img.width));
    if (furnace_exr) {
      img.variance.assign(planes[names.size()].begin(), planes[names.size()].end());
      img.count.assign(planes[names.size() + 1].begin(), planes[names.size() + 1].end());
    }
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw Error(fmt::format("cannot read OpenEXR image '{}': {}", path, e.what()));
  }
  return img;
}

CheckResult check_images(const Scene& scene, const std::vector<ForeignImage>& images, double alpha,
                         int max_segments) {
  FURNACE_CHECK(!images.empty());
  const std::vector<double> reference =
      max_segments > 0 ? analytic::global_reference_image(scene, max_segments) : analytic::reference_image(scene);
  const size_t n = reference.size();
  const size_t k = images.size();
  const bool use_furnace_variance = k == 1;
  if (k == 1 && images[0].variance.empty())
    throw Error(fmt::format("checking needs at least two independent renders (different seeds) to estimate the "
                            "error bars, or one furnace EXR with variance and N channels; '{}' alone has neither.",
                            images[0].path));
  CheckResult r;
  r.images = int(k);
  r.pixels = int(n);
  r.method = use_furnace_variance ? "furnace variance z" : fmt::format("across-images t ({} d.o.f.)", k - 1);
  const double alpha_each = stats::sidak_alpha(alpha, n + 1);

  std::vector<double> detectable;
  double sum_sq = 0;
  std::vector<double> image_means(k, 0.0);
  std::vector<double> pixel_means, variances_of_mean;
  for (size_t i = 0; i < n; ++i) {
    double mean = 0;
    for (const auto& img : images) mean += img.value[i];
    mean /= double(k);
    sum_sq += (mean - reference[i]) * (mean - reference[i]);
    r.image_mean += mean;
    r.reference_mean += reference[i];
    pixel_means.push_back(mean);
    for (size_t j = 0; j < k; ++j) image_means[j] += images[j].value[i];
    stats::MeanTestResult t;
    if (use_furnace_variance) {
      const double count = images[0].count[i];
      t = stats::mean_test(uint64_t(count), mean, images[0].variance[i], reference[i], alpha_each);
      variances_of_mean.push_back(count > 0 ? images[0].variance[i] / count : 0.0);
    } else {
      double m2 = 0;
      for (const auto& img : images) m2 += (img.value[i] - mean) * (img.value[i] - mean);
      t = stats::mean_test(k, mean, m2 / double(k - 1), reference[i], alpha_each);
    }
    if (!t.pass) ++r.pixel_failures;
    if (reference[i] > 0 && std::isfinite(t.detectable_relative_bias)) detectable.push_back(t.detectable_relative_bias);
  }
  r.image_mean /= double(n);
  r.reference_mean /= double(n);
  r.relative_rmse = std::sqrt(sum_sq / double(n)) / (r.reference_mean > 0 ? r.reference_mean : 1.0);
  stats::MeanTestResult image_test;
  if (use_furnace_variance) {
    const stats::ZTestResult z =
        stats::image_mean_test(pixel_means, variances_of_mean, reference, alpha_each, false).test;
    r.statistic = z.statistic;
    r.threshold = z.threshold;
    r.detectable_relative_bias = z.detectable_relative_bias;
    r.pass = z.pass;
  } else {
    double m2 = 0;
    for (double& m : image_means) m /= double(n);
    for (double m : image_means) m2 += (m - r.image_mean) * (m - r.image_mean);
    image_test = stats::mean_test(k, r.image_mean, m2 / double(k - 1), r.reference_mean, alpha_each);
    r.statistic = image_test.statistic;
    r.threshold = image_test.threshold;
    r.detectable_relative_bias = image_test.detectable_relative_bias;
    r.pass = image_test.pass;
  }
  r.median_pixel_detectable_relative_bias = stats::median(std::move(detectable));
  r.pass = r.pass && r.pixel_failures == 0;
  return r;
}

std::string format_check(const Scene& scene, const CheckResult& r, double alpha) {
  return fmt::format(
      "scene {}: {} image(s), {} pixels, method {}, family-wise alpha {} (Sidak over pixels + image mean)\n"
      "image mean {:.6g}, reference {:.6g}, statistic {:.3f} (critical {:.3f}), detectable bias {:.3g}% at power {}\n"
      "pixel failures {}/{}, median detectable pixel bias {:.3g}%, relative RMSE {:.3e}\n"
      "verdict: {}\n",
      scene.name, r.images, r.pixels, r.method, alpha, r.image_mean, r.reference_mean, r.statistic, r.threshold,
      100 * r.detectable_relative_bias, stats::kDefaultPower, r.pixel_failures, r.pixels,
      100 * r.median_pixel_detectable_relative_bias, r.relative_rmse, r.pass ? "PASS" : "FAIL");
}

}  // namespace furnace::verify
