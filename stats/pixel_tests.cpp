#include "stats/pixel_tests.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include <boost/math/distributions/normal.hpp>
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

double bernstein_exponent(double n, double deficit, double mean_variance, double bound) {
  if (!(deficit > 0)) return 0;
  const double denominator = 2 * std::max(0.0, mean_variance) + 2 * std::max(0.0, bound) * deficit / 3;
  return denominator > 0 ? n * deficit * deficit / denominator : HUGE_VAL;
}

double bernstein_deficit(double n, double mean_variance, double bound, double q) {
  // N·d² − (2bL/3)·d − 2v̄L = 0 with L = ln(1/q), its positive root.
  const double l = -std::log(q);
  const double linear = 2 * std::max(0.0, bound) * l / 3;
  return (linear + std::sqrt(linear * linear + 8 * n * std::max(0.0, mean_variance) * l)) / (2 * n);
}

namespace {

// Bernstein's exponent E on the scale of a two-sided test whose critical
// value is `threshold` at level α: |statistic| > threshold exactly when
// exp(−E) < α/2. Negative: the estimate falls short.
double bernstein_on_scale(double exponent, double threshold, double alpha) {
  return -threshold * std::sqrt(exponent / std::log(2 / alpha));
}

// Bernstein's test of a deficit, on the scale of a two-sided test whose
// critical value is `threshold` at level α; `what` names the estimate in the
// message ("the mean", "the image mean").
struct BernsteinTest {
  double statistic = 0, p_value = 1;
  bool pass = true;
  std::string message;
};
BernsteinTest bernstein_test(double n, double deficit, double mean_variance, double bound, double threshold,
                             double alpha, const char* what) {
  const double exponent = bernstein_exponent(n, deficit, mean_variance, bound);
  BernsteinTest b;
  b.statistic = bernstein_on_scale(exponent, threshold, alpha);
  b.p_value = std::min(1.0, 2 * std::exp(-exponent));
  b.pass = exponent < std::log(2 / alpha);
  if (!b.pass) {
    std::ostringstream s;
    s << what << " falls " << deficit << " short of the reference: Bernstein's bound with the exact variance puts "
      << "that below probability " << std::exp(-exponent) << " < alpha/2 = " << alpha / 2 << ".";
    b.message = s.str();
  }
  return b;
}

}  // namespace

namespace {

double normal_two_sided_p(double z) {
  return 2 * boost::math::cdf(boost::math::complement(boost::math::normal_distribution<double>(), std::fabs(z)));
}

// Below the reference, with the exact variance σ²: Bernstein's bound.
MeanTestResult bernstein_below(const RunningMoments& m, double reference, double alpha, double power, bool constant,
                               double exact_variance) {
  const MeanTestResult sample =
      mean_test(m.count, m.mean, constant ? 0.0 : m.sample_variance(), reference, alpha, power);
  MeanTestResult t = sample;
  const double n = double(m.count);
  const BernsteinTest b =
      bernstein_test(n, reference - m.mean, exact_variance, reference, t.threshold, alpha, "the mean");
  t.zero_variance = false;
  t.standard_error = std::sqrt(exact_variance / n);
  t.statistic = b.statistic;
  t.p_value = b.p_value;
  t.pass = b.pass;
  t.message = b.message;
  return t;
}

// Hall's statistic against Student's t quantile (the sample variance alone).
MeanTestResult hall_test(const RunningMoments& m, double reference, double alpha, double power) {
  MeanTestResult t = mean_test(m.count, m.mean, m.sample_variance(), reference, alpha, power);
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
  return t;
}

// Above the reference, with the exact variance σ²: rejected only when the z
// with σ rejects too (and, for a pixel that is not constant, Hall's t). A
// rare contribution below the mean (a blocker) that the run missed shrinks
// the sample variance and inflates t, not z (z = √(N·p) for a missed event
// of probability p); a rare large one that occurred inflates z, not the
// studentised t. The smaller of the two is the statistic.
MeanTestResult above_with_exact_variance(const RunningMoments& m, double reference, double alpha, double power,
                                         bool constant, double exact_variance) {
  MeanTestResult t = constant ? mean_test(m.count, m.mean, 0.0, reference, alpha, power)
                              : hall_test(m, reference, alpha, power);
  const double standard_error = std::sqrt(exact_variance / double(m.count));
  const double z = (m.mean - reference) / standard_error;
  if (constant || z < t.statistic) {
    t.statistic = z;
    t.p_value = normal_two_sided_p(z);
  }
  if (constant) {
    t.zero_variance = false;
    t.standard_error = standard_error;
    t.detectable_bias = (t.threshold + normal_upper_quantile(1 - power)) * standard_error;
  }
  t.pass = t.statistic <= t.threshold;
  t.message.clear();
  if (!t.pass) {
    std::ostringstream s;
    s << "the mean is " << m.mean - reference << " above the reference: " << (constant ? "" : "Hall's t and ")
      << "the z with the exact variance " << (constant ? "exceeds" : "both exceed") << " t_{1-alpha/2} = "
      << t.threshold << " (statistic " << t.statistic << ", alpha " << alpha << ").";
    t.message = s.str();
  }
  return t;
}

}  // namespace

PixelTestResult pixel_mean_test(const RunningMoments& m, double reference, double alpha, bool zero_variance_image,
                                double power, double exact_variance) {
  PixelTestResult r;
  const bool constant = round_off_only(m);
  // The exact variance is used where it is positive (a zero one leaves the
  // constant pixel's exact-match rule below) and the input is sane.
  const bool known = std::isfinite(exact_variance) && exact_variance > 0 && m.count >= 2 && std::isfinite(m.mean) &&
                     std::isfinite(reference);
  if (known && m.mean < reference) {
    r.test = bernstein_below(m, reference, alpha, power, constant, exact_variance);
  } else if (known && m.mean > reference && (constant || clt_adequate(m))) {
    r.test = above_with_exact_variance(m, reference, alpha, power, constant, exact_variance);
  } else if (!constant && !clt_adequate(m)) {
    r.status = PixelStatus::kSkewed;
    return r;
  } else if (constant) {
    r.test = mean_test(m.count, m.mean, 0.0, reference, alpha, power);
    if (!r.test.pass && !zero_variance_image) r.status = PixelStatus::kConstantMiss;
    return r;
  } else {
    r.test = hall_test(m, reference, alpha, power);
  }
  if (known) {
    // The power statement covers both sides: Bernstein's below, the
    // sample-variance (or exact-variance z) test's above.
    const double n = double(m.count);
    const double low_detectable = bernstein_deficit(n, exact_variance, reference, alpha / 2) +
                                  normal_upper_quantile(1 - power) * std::sqrt(exact_variance / n);
    r.test.detectable_bias = std::max(r.test.detectable_bias, low_detectable);
    r.test.detectable_relative_bias = reference != 0 ? r.test.detectable_bias / std::fabs(reference) : HUGE_VAL;
  }
  return r;
}

ImageMeanTestResult image_mean_test(const std::vector<double>& pixel_means,
                                    const std::vector<double>& variances_of_mean,
                                    const std::vector<double>& references, double alpha, bool exact, double power,
                                    const std::vector<double>& exact_variances, uint64_t samples_per_pixel) {
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
  if (exact || exact_variances.empty()) return r;
  if (exact_variances.size() != references.size() || samples_per_pixel < 2)
    throw std::invalid_argument("image_mean_test: needs one exact variance per pixel and at least 2 samples each.");
  double sum_variance = 0, bound = 0;
  for (size_t i = 0; i < references.size(); ++i) {
    sum_variance += std::max(0.0, exact_variances[i]);
    bound = std::max(bound, references[i]);
  }
  const double n = double(samples_per_pixel) * p;  // every sample of the image
  const double mean_variance = sum_variance / p;
  const double low_detectable = bernstein_deficit(n, mean_variance, bound, alpha / 2) +
                                normal_upper_quantile(1 - power) * std::sqrt(mean_variance / n);
  ZTestResult& z = r.test;
  z.detectable_bias = std::max(z.detectable_bias, low_detectable);
  z.detectable_relative_bias = r.reference_mean != 0 ? z.detectable_bias / std::fabs(r.reference_mean) : HUGE_VAL;
  if (!std::isfinite(r.image_mean)) return r;
  if (r.image_mean > r.reference_mean) {
    // Above: the z with the exact variances must reject too (as a pixel's).
    const double exact_z = (r.image_mean - r.reference_mean) / std::sqrt(mean_variance / n);
    if (exact_z < z.statistic) {
      z.statistic = exact_z;
      z.p_value = normal_two_sided_p(exact_z);
      z.pass = z.statistic <= z.threshold;
      z.message = z.pass ? "" : "the image mean is above the reference by more than both the sample and the exact "
                                "standard errors allow.";
    }
    return r;
  }
  if (!(r.image_mean < r.reference_mean)) return r;
  const BernsteinTest b = bernstein_test(n, r.reference_mean - r.image_mean, mean_variance, bound, z.threshold, alpha,
                                         "the image mean");
  z.zero_variance = false;
  z.standard_error = std::sqrt(mean_variance / n);
  z.statistic = b.statistic;
  z.p_value = b.p_value;
  z.pass = b.pass;
  z.message = b.message;
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
