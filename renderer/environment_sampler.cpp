#include "renderer/environment_sampler.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace furnace {

namespace {

// Normalises a running sum in place so its last entry is exactly 1 (when the
// sum is positive): the inversion below must never run past the end.
void normalise_cdf(std::vector<double>::iterator first, std::vector<double>::iterator last) {
  const double sum = *(last - 1);
  if (!(sum > 0)) return;
  for (auto it = first; it != last; ++it) *it /= sum;
  *(last - 1) = 1.0;
}

// The bin of a uniform u under a cumulative table (entries non-decreasing,
// last 1) and u rescaled to [0, 1) inside it. Bins of zero probability are
// never returned: upper_bound skips entries equal to their predecessor.
struct Inverted {
  int index;
  double u;
};
Inverted invert_cdf(const double* cdf, int n, double u) {
  const int k = std::min(int(std::upper_bound(cdf, cdf + n, u) - cdf), n - 1);  // u → 1 round-off: last bin
  const double lo = k > 0 ? cdf[k - 1] : 0.0;
  const double width = cdf[k] - lo;
  const double rescaled = width > 0 ? (u - lo) / width : 0.5;
  return {k, std::clamp(rescaled, 0.0, 1.0)};
}

}  // namespace

EnvironmentSampler::EnvironmentSampler(std::shared_ptr<const LatLongMap> map) : map_(std::move(map)) {
  FURNACE_CHECK(map_ && map_->width > 0 && map_->height > 0);
  const int w = map_->width, h = map_->height;
  const double d_theta = kPi / h, d_phi = 2 * kPi / w;
  cos_edge_.resize(size_t(h) + 1);
  for (int i = 0; i <= h; ++i) cos_edge_[i] = std::cos(i * d_theta);
  cos_edge_[0] = 1.0;
  cos_edge_[h] = -1.0;
  row_cdf_.resize(h);
  row_cdf_missing_sin_theta_.resize(h);
  column_cdf_.resize(size_t(h) * w);
  double rows = 0, rows_missing = 0;
  for (int i = 0; i < h; ++i) {
    double sum = 0;
    for (int j = 0; j < w; ++j) column_cdf_[size_t(i) * w + j] = sum += map_->texel(i, j);
    // cos θ_i − cos θ_{i+1} = 2 sin(θ_mid) sin(Δθ/2): no cancellation near the poles.
    const double d_cos = 2 * std::sin((i + 0.5) * d_theta) * std::sin(0.5 * d_theta);
    row_cdf_[i] = rows += sum * d_phi * d_cos;
    // DEFECT(env_missing_sin_theta): the row weight without the sin θ Jacobian (Δθ in place of Δcos θ).
    row_cdf_missing_sin_theta_[i] = rows_missing += sum * d_phi * d_theta;
    normalise_cdf(column_cdf_.begin() + ptrdiff_t(i) * w, column_cdf_.begin() + ptrdiff_t(i + 1) * w);
  }
  total_ = rows;
  normalise_cdf(row_cdf_.begin(), row_cdf_.end());
  normalise_cdf(row_cdf_missing_sin_theta_.begin(), row_cdf_missing_sin_theta_.end());
}

double EnvironmentSampler::texel_pdf_solid_angle(int i, int j) const {
  return total_ > 0 ? map_->texel(i, j) / total_ : 0.0;
}

std::optional<EnvironmentSample> EnvironmentSampler::sample(double u1, double u2, Defect defect) const {
  if (!has_power()) return std::nullopt;
  const int w = map_->width, h = map_->height;
  const std::vector<double>& rows = defect == Defect::kEnvMissingSinTheta ? row_cdf_missing_sin_theta_ : row_cdf_;
  const Inverted row = invert_cdf(rows.data(), h, u1);
  const Inverted column = invert_cdf(column_cdf_.data() + size_t(row.index) * w, w, u2);
  // Uniform in cos θ between the row's edges, uniform in φ across the column.
  const double cos_theta = cos_edge_[row.index] + row.u * (cos_edge_[row.index + 1] - cos_edge_[row.index]);
  const double sin_theta = std::sqrt(std::fmax(0.0, (1 - cos_theta) * (1 + cos_theta)));
  const double phi = (column.index + column.u) * (2 * kPi / w);
  EnvironmentSample s;
  s.wi_world = {sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta};
  // The density of the texel the direction lies in, through the map's own
  // lookup: the same texel whose radiance the estimator reads.
  s.pdf_solid_angle = pdf_solid_angle(s.wi_world);
  if (!(s.pdf_solid_angle > 0)) return std::nullopt;  // round-off across a texel edge into a black texel
  return s;
}

double EnvironmentSampler::pdf_solid_angle(const Vec3& wi_world) const {
  return texel_pdf_solid_angle(map_->row_of(wi_world), map_->column_of(wi_world));
}

}  // namespace furnace
