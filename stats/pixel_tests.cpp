#include "stats/pixel_tests.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include <boost/math/distributions/students_t.hpp>

namespace furnace::stats {

double hall_statistic(const RunningMoments& m, double reference) {
  const double n = double(m.count);
  const double s = std::sqrt(m.sample_variance());
  const double skewness = sample_skewness(m);
  const double t = (m.mean - reference) / s;
  return std::sqrt(n) * (t + skewness * t * t / 3 + skewness * skewness * t * t * t / 27 + skewness / (6 * n));
}

bool round_off_only(const RunningMoments& m) {
  return std::sqrt(m.sample_variance()) <= kZeroVarianceRelTolerance * std::fabs(m.mean);
}

bool zero_variance_image(const std::vector<RunningMoments>& pixels) {
  bool all = true;
  for (const RunningMoments& m : pixels) all = all && round_off_only(m);
  return all;
}

PixelTestResult pixel_mean_test(const RunningMoments& m, double reference, double alpha, bool zero_variance_image,
                                double power) {
  PixelTestResult r;
  const bool constant = round_off_only(m);
  if (!constant && !clt_adequate(m)) {
    r.status = PixelStatus::kSkewed;
    return r;
  }
  r.test = mean_test(m.count, m.mean, constant ? 0.0 : m.sample_variance(), reference, alpha, power);
  if (!constant) {
    // Hall's statistic replaces the plain t, against the same t quantile.
    MeanTestResult& t = r.test;
    t.statistic = hall_statistic(m, reference);
    t.pass = std::fabs(t.statistic) <= t.threshold;
    // mean_test leaves dof = 0 when it refused the input (N < 2, non-finite values).
    t.p_value = t.dof > 0 && std::isfinite(t.statistic)
                    ? 2 * boost::math::cdf(boost::math::complement(boost::math::students_t_distribution<double>(t.dof),
                                                                   std::fabs(t.statistic)))
                    : 0.0;
    t.message.clear();
    if (!t.pass) {
      std::ostringstream s;
      s << "Hall's |t| = " << std::fabs(t.statistic) << " exceeds t_{1-alpha/2} = " << t.threshold << " (alpha "
        << alpha << ", p " << t.p_value << ").";
      t.message = s.str();
    }
  }
  if (constant && !r.test.pass && !zero_variance_image) r.status = PixelStatus::kConstantMiss;
  return r;
}

ImageMeanTestResult image_mean_test(const std::vector<double>& pixel_means,
                                    const std::vector<double>& variances_of_mean,
                                    const std::vector<double>& references, double alpha, bool exact, double power) {
  if (pixel_means.empty() || pixel_means.size() != references.size() ||
      variances_of_mean.size() != references.size())
    throw std::invalid_argument("image_mean_test: needs equally many pixel means, variances and references, at least one.");
  double sum_estimate = 0, sum_reference = 0, sum_variance_of_mean = 0;
  for (size_t i = 0; i < references.size(); ++i) {
    sum_estimate += pixel_means[i];
    sum_reference += references[i];
    sum_variance_of_mean += variances_of_mean[i];
  }
  const double p = double(references.size());
  ImageMeanTestResult r;
  r.image_mean = sum_estimate / p;
  r.reference_mean = sum_reference / p;
  const double standard_error = std::sqrt(sum_variance_of_mean) / p;
  r.test = z_test(r.image_mean, r.reference_mean, exact ? 0.0 : standard_error, alpha, power);
  return r;
}

AggregateVarianceTestResult aggregate_variance_test(const std::vector<VarianceTestResult>& pixels,
                                                    const std::vector<double>& references, double alpha,
                                                    bool zero_variance_image, double power) {
  if (pixels.size() != references.size())
    throw std::invalid_argument("aggregate_variance_test: pixels and references differ in size.");
  AggregateVarianceTestResult r;
  double sum_var_s2 = 0;
  for (const VarianceTestResult& vt : pixels) {
    r.sum_sample_variance += vt.sample_variance;
    r.sum_predicted_variance += vt.predicted_variance;
    sum_var_s2 += vt.standard_error * vt.standard_error;
  }
  const ZTestResult z =
      z_test(r.sum_sample_variance, r.sum_predicted_variance, std::sqrt(sum_var_s2), alpha, power);
  r.statistic = z.statistic;
  r.threshold = z.threshold;
  r.detectable_relative_error = detectable_relative_variance_error(z.detectable_relative_bias);
  r.pass = z.pass;
  r.message = z.message;
  if (zero_variance_image) {
    r.zero_variance_image = true;
    r.statistic = 0;
    double sum_reference_squared = 0;
    for (double reference : references) sum_reference_squared += reference * reference;
    r.pass = r.sum_predicted_variance <=
             kZeroVarianceRelTolerance * kZeroVarianceRelTolerance * sum_reference_squared;
    std::ostringstream s;
    s << "Zero-variance image: the predicted variances sum to " << r.sum_predicted_variance
      << (r.pass ? ", within " : ", more than ") << kZeroVarianceRelTolerance
      << "² times the sum of squared references " << sum_reference_squared << ".";
    r.message = s.str();
  }
  return r;
}

}  // namespace furnace::stats
