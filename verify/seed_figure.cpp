#include "verify/seed_figure.h"

#include <cmath>

#include "analytic/moments.h"
#include "core/scene.h"
#include "renderer/render.h"
#include "verify/harness.h"
#include "verify/resources.h"

namespace furnace::verify {

namespace {

SeedFigureRender measure(const Scene& scene, const std::vector<double>& reference, Strategy strategy, int spp,
                         uint64_t seed, int threads) {
  RenderOptions options;
  options.strategy = strategy;
  options.spp = spp;
  options.seed = seed;
  options.threads = threads;
  const Image image = render(scene, options);
  SeedFigureRender r;
  r.strategy = strategy_name(strategy);
  r.spp = spp;
  r.seconds = image.seconds;
  double sum_sq = 0, sum_s2 = 0, sum_predicted = 0, sum_reference = 0;
  for (int py = 0; py < image.height; ++py)
    for (int px = 0; px < image.width; ++px) {
      const size_t i = size_t(py) * image.width + px;
      const PixelMoments& m = image.pixels[i];
      r.mean.push_back(m.mean);
      sum_sq += (m.mean - reference[i]) * (m.mean - reference[i]);
      sum_s2 += m.sample_variance();
      const double m2 = analytic::pixel_center_second_moment(strategy, scene, px, py);
      sum_predicted += m2 - reference[i] * reference[i];
      sum_reference += reference[i];
    }
  const double n = double(reference.size());
  r.rmse = std::sqrt(sum_sq / n);
  r.relative_rmse = r.rmse / (sum_reference / n);
  r.mean_sample_variance = sum_s2 / n;
  r.mean_predicted_variance = sum_predicted / n;
  return r;
}

}  // namespace

SeedFigure measure_seed_figure(uint64_t seed, int threads) {
  Scene scene = load_scene(scene_dir() + "/" + kSeedFigureScene);
  scene.camera.width_px = kSeedFigureResolution;
  scene.camera.height_px = kSeedFigureResolution;
  RenderOptions direct;
  direct.strategy = Strategy::kLightArea;
  SeedFigure f;
  f.scene = scene.name;
  f.width = scene.camera.width_px;
  f.height = scene.camera.height_px;
  f.reference = reference_for(scene, direct);
  for (double r : f.reference) f.reference_mean += r;
  f.reference_mean /= double(f.reference.size());
  f.hemisphere = measure(scene, f.reference, Strategy::kUniformHemisphere, kSeedHemisphereSpp, seed, threads);
  f.light = measure(scene, f.reference, Strategy::kLightArea, kSeedLightSpp, seed, threads);
  const auto pixel_variance = [](double per_sample, int spp) { return per_sample / double(spp); };
  f.predicted_variance_ratio = pixel_variance(f.hemisphere.mean_predicted_variance, f.hemisphere.spp) /
                               pixel_variance(f.light.mean_predicted_variance, f.light.spp);
  f.measured_variance_ratio = pixel_variance(f.hemisphere.mean_sample_variance, f.hemisphere.spp) /
                              pixel_variance(f.light.mean_sample_variance, f.light.spp);
  f.measured_mse_ratio = (f.hemisphere.rmse * f.hemisphere.rmse) / (f.light.rmse * f.light.rmse);
  return f;
}

}  // namespace furnace::verify
