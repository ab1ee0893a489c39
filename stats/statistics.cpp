#include "stats/statistics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include <boost/math/distributions/binomial.hpp>
#include <boost/math/distributions/normal.hpp>
#include <boost/math/distributions/students_t.hpp>

namespace furnace::stats {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

void require_level(double p, const char* name) {
  if (!(p > 0 && p < 1)) throw std::invalid_argument(std::string(name) + " must lie in (0, 1), got " + std::to_string(p) + ".");
}

// The last few (a, b) -> f(a, b) of a pure function, per thread: the per-pixel
// tests of a case ask for the same two quantiles (its level and its power) at
// the same degrees of freedom for every pixel, and Boost's inverse takes
// microseconds. A hit returns the value computed before, bit for bit.
template <double (*F)(double, double)>
double memoized(double a, double b) {
  struct Entry {
    double a, b, value;
  };
  static constexpr size_t kEntries = 4;  // a level and a power quantile for two kinds of test
  thread_local Entry entries[kEntries] = {};
  thread_local size_t used = 0, next = 0;
  for (size_t i = 0; i < used; ++i)
    if (entries[i].a == a && entries[i].b == b) return entries[i].value;
  const double value = F(a, b);
  entries[next] = {a, b, value};
  next = (next + 1) % kEntries;
  used = std::max(used, next == 0 ? kEntries : next);
  return value;
}

double t_upper_quantile_uncached(double dof, double q) {
  return boost::math::quantile(boost::math::complement(boost::math::students_t_distribution<double>(dof), q));
}
double normal_upper_quantile_uncached(double q, double) {
  return boost::math::quantile(boost::math::complement(boost::math::normal_distribution<double>(), q));
}

// Upper quantile of Student's t: the x with P(T > x) = q.
double t_upper_quantile(double dof, double q) { return memoized<t_upper_quantile_uncached>(dof, q); }
double normal_two_sided_p(double z) {
  return 2 * boost::math::cdf(boost::math::complement(boost::math::normal_distribution<double>(), std::fabs(z)));
}
double t_two_sided_p(double dof, double t) {
  return 2 * boost::math::cdf(boost::math::complement(boost::math::students_t_distribution<double>(dof), std::fabs(t)));
}

double relative_to(double value, double reference) { return reference != 0 ? value / std::fabs(reference) : kInf; }

// The zero-variance branch shared by the mean, z and comparison tests.
bool exact_agreement(double estimate, double reference) {
  return std::fabs(estimate - reference) <= kZeroVarianceRelTolerance * std::fabs(reference);
}

std::string zero_variance_message(double estimate, double reference, bool pass) {
  std::ostringstream s;
  s.precision(17);
  s << "Zero variance: the estimate " << estimate << (pass ? " agrees with" : " differs from") << " the reference "
    << reference << (pass ? " within" : " by more than") << " the relative tolerance " << kZeroVarianceRelTolerance
    << ".";
  return s.str();
}

}  // namespace

double sidak_alpha(double alpha_family, size_t n_tests) {
  require_level(alpha_family, "alpha_family");
  if (n_tests == 0) throw std::invalid_argument("sidak_alpha needs at least one test.");
  return -std::expm1(std::log1p(-alpha_family) / double(n_tests));
}

double bonferroni_alpha(double alpha_family, size_t n_tests) {
  require_level(alpha_family, "alpha_family");
  if (n_tests == 0) throw std::invalid_argument("bonferroni_alpha needs at least one test.");
  return alpha_family / double(n_tests);
}

double normal_upper_quantile(double q) { return memoized<normal_upper_quantile_uncached>(q, 0.0); }

MeanTestResult mean_test(uint64_t count, double mean, double sample_variance, double reference, double alpha,
                         double power) {
  require_level(alpha, "alpha");
  require_level(power, "power");
  MeanTestResult r;
  r.count = count;
  r.mean = mean;
  r.reference = reference;
  r.alpha = alpha;
  r.p_value = 0;
  r.statistic = kInf;
  if (count < 2) {
    r.message = "Fewer than 2 samples: the variance, hence the test, is undefined.";
    return r;
  }
  if (!std::isfinite(mean) || !std::isfinite(sample_variance) || !std::isfinite(reference) || sample_variance < 0) {
    r.message = "Non-finite mean, variance or reference, or a negative variance.";
    return r;
  }
  r.dof = double(count - 1);
  r.standard_error = std::sqrt(sample_variance / double(count));
  r.threshold = t_upper_quantile(r.dof, alpha / 2);
  // t_{power}: the quantile that the shifted statistic must exceed with probability `power`.
  const double t_power = t_upper_quantile(r.dof, 1 - power);
  r.detectable_bias = (r.threshold + t_power) * r.standard_error;
  r.detectable_relative_bias = relative_to(r.detectable_bias, reference);
  if (sample_variance == 0) {
    r.zero_variance = true;
    r.pass = exact_agreement(mean, reference);
    r.statistic = r.pass ? 0 : kInf;
    r.p_value = r.pass ? 1 : 0;
    r.message = zero_variance_message(mean, reference, r.pass);
    return r;
  }
  r.statistic = (mean - reference) / r.standard_error;
  r.p_value = t_two_sided_p(r.dof, r.statistic);
  r.pass = std::fabs(r.statistic) <= r.threshold;
  if (!r.pass) {
    std::ostringstream s;
    s << "|t| = " << std::fabs(r.statistic) << " exceeds t_{1-alpha/2} = " << r.threshold << " (alpha " << alpha
      << ", p " << r.p_value << ").";
    r.message = s.str();
  }
  return r;
}

ZTestResult z_test(double estimate, double reference, double standard_error, double alpha, double power) {
  require_level(alpha, "alpha");
  require_level(power, "power");
  ZTestResult r;
  r.alpha = alpha;
  r.statistic = kInf;
  if (!std::isfinite(estimate) || !std::isfinite(reference) || !std::isfinite(standard_error) || standard_error < 0) {
    r.message = "Non-finite estimate, reference or standard error, or a negative standard error.";
    return r;
  }
  r.standard_error = standard_error;
  r.threshold = normal_upper_quantile(alpha / 2);
  r.detectable_bias = (r.threshold + normal_upper_quantile(1 - power)) * standard_error;
  r.detectable_relative_bias = relative_to(r.detectable_bias, reference);
  if (standard_error == 0) {
    r.zero_variance = true;
    r.pass = exact_agreement(estimate, reference);
    r.statistic = r.pass ? 0 : kInf;
    r.p_value = r.pass ? 1 : 0;
    r.message = zero_variance_message(estimate, reference, r.pass);
    return r;
  }
  r.statistic = (estimate - reference) / standard_error;
  r.p_value = normal_two_sided_p(r.statistic);
  r.pass = std::fabs(r.statistic) <= r.threshold;
  if (!r.pass) {
    std::ostringstream s;
    s << "|z| = " << std::fabs(r.statistic) << " exceeds z_{1-alpha/2} = " << r.threshold << " (alpha " << alpha
      << ").";
    r.message = s.str();
  }
  return r;
}

double sample_variance_variance(const RunningMoments& m) {
  if (m.count < 2) return 0;
  const double n = double(m.count);
  const double s2 = m.m2 / (n - 1);
  const double mu4 = m.m4 / n;
  const double s4 = s2 * s2;
  return std::max(0.0, (mu4 - (n - 3) / (n - 1) * s4) / n);  // > 0 whenever m2 > 0 (see header)
}

double detectable_relative_variance_error(double k) {
  if (!(k >= 0)) return kInf;
  return k < 1 ? k / (1 - k) : kInf;
}

VarianceTestResult variance_test(const RunningMoments& m, double predicted_variance, double alpha, double power) {
  require_level(alpha, "alpha");
  require_level(power, "power");
  VarianceTestResult r;
  r.count = m.count;
  r.predicted_variance = predicted_variance;
  r.alpha = alpha;
  r.statistic = kInf;
  if (m.count < kMinVarianceTestSamples) {
    std::ostringstream s;
    s << "Only " << m.count << " samples; the variance test needs at least " << kMinVarianceTestSamples << ".";
    r.message = s.str();
    return r;
  }
  if (!std::isfinite(m.mean) || !std::isfinite(m.m2) || !std::isfinite(m.m4) || m.m2 < 0 || m.m4 < 0 ||
      !std::isfinite(predicted_variance) || predicted_variance < 0) {
    r.message = "Non-finite or negative moment sums or predicted variance.";
    return r;
  }
  const double n = double(m.count);
  r.sample_variance = m.m2 / (n - 1);
  r.threshold = normal_upper_quantile(alpha / 2);
  const double z_power = normal_upper_quantile(1 - power);
  if (predicted_variance == 0) {
    // An exact estimator: only float-geometry noise is allowed.
    r.zero_variance = true;
    r.pass = std::sqrt(r.sample_variance) <= kZeroVarianceRelTolerance * std::fabs(m.mean);
    r.statistic = r.pass ? 0 : kInf;
    r.p_value = r.pass ? 1 : 0;
    r.detectable_relative_error = kInf;
    std::ostringstream s;
    s << "Zero predicted variance: the sample standard deviation " << std::sqrt(r.sample_variance)
      << (r.pass ? " is within " : " exceeds ") << kZeroVarianceRelTolerance << " times |mean| = " << std::fabs(m.mean)
      << ".";
    r.message = s.str();
    return r;
  }
  r.standard_error = std::sqrt(sample_variance_variance(m));
  r.detectable_relative_error =
      detectable_relative_variance_error((r.threshold + z_power) * r.standard_error / predicted_variance);
  if (r.standard_error == 0) {
    // m2 == 0: every sample equal, yet a nonzero variance was predicted.
    r.message = "All samples are equal but the predicted variance is nonzero.";
    return r;
  }
  r.statistic = (r.sample_variance - predicted_variance) / r.standard_error;
  r.p_value = normal_two_sided_p(r.statistic);
  r.pass = std::fabs(r.statistic) <= r.threshold;
  if (!r.pass) {
    std::ostringstream s;
    s << "Sample variance " << r.sample_variance << " vs predicted " << predicted_variance << ": |z| = "
      << std::fabs(r.statistic) << " exceeds " << r.threshold << " (alpha " << alpha << ").";
    r.message = s.str();
  }
  return r;
}

double sample_skewness(const RunningMoments& m) {
  if (m.count == 0 || !(m.m2 > 0)) return 0;
  const double n = double(m.count);
  return (m.m3 / n) / std::pow(m.m2 / n, 1.5);
}

bool clt_adequate(const RunningMoments& m) {
  const double g1 = sample_skewness(m);
  return !(double(m.count) < kCochranSkewnessFactor * g1 * g1);
}

MeanTestResult mean_test(const RunningMoments& m, double reference, double alpha, double power) {
  const double variance = m.count > 1 ? m.m2 / double(m.count - 1) : 0.0;
  MeanTestResult r = mean_test(m.count, m.mean, variance, reference, alpha, power);
  r.skewness = sample_skewness(m);
  r.clt_adequate = clt_adequate(m);
  if (!r.clt_adequate) {
    std::ostringstream s;
    s << (r.message.empty() ? "" : r.message + " ") << "Skewness " << r.skewness << " needs N > "
      << kCochranSkewnessFactor * r.skewness * r.skewness << " for a normal mean (Cochran), N = " << m.count
      << ": alpha is approximate.";
    r.message = s.str();
  }
  return r;
}

MeanTestSummary mean_tests(const std::vector<SampleSummary>& summaries, const std::vector<double>& references,
                           double alpha_family, double power) {
  if (summaries.size() != references.size())
    throw std::invalid_argument("mean_tests: summaries and references differ in size.");
  MeanTestSummary out;
  out.tests = summaries.size();
  out.alpha_family = alpha_family;
  if (summaries.empty()) {
    out.pass = true;
    return out;
  }
  out.alpha_each = sidak_alpha(alpha_family, summaries.size());
  std::vector<double> detectable;
  detectable.reserve(summaries.size());
  for (size_t i = 0; i < summaries.size(); ++i) {
    const SampleSummary& s = summaries[i];
    const MeanTestResult t = mean_test(s.count, s.mean, s.sample_variance, references[i], out.alpha_each, power);
    if (!t.pass) ++out.failures;
    const double abs_t = std::fabs(t.statistic);
    if (i == 0 || abs_t > out.worst_abs_statistic) {
      out.worst_abs_statistic = abs_t;
      out.worst_index = i;
    }
    if (references[i] != 0 && std::isfinite(t.detectable_relative_bias))
      detectable.push_back(t.detectable_relative_bias);
  }
  out.median_detectable_relative_bias = detectable.empty() ? kInf : median(std::move(detectable));
  out.pass = out.failures == 0;
  return out;
}

WelchStatistic welch_statistic(const MeanEstimate& a, const MeanEstimate& b) {
  WelchStatistic w;
  const double va = a.variance_of_mean, vb = b.variance_of_mean;
  w.difference = a.mean - b.mean;
  w.standard_error = std::sqrt(va + vb);
  if (w.standard_error == 0) {
    w.statistic = w.difference == 0 ? 0.0 : std::copysign(kInf, w.difference);
    w.dof = kInf;
    return w;
  }
  // Welch–Satterthwaite; a zero-variance side contributes nothing.
  const double denom = (va > 0 ? va * va / a.dof : 0) + (vb > 0 ? vb * vb / b.dof : 0);
  w.dof = denom > 0 ? (va + vb) * (va + vb) / denom : kInf;
  w.statistic = w.difference / w.standard_error;
  return w;
}

ComparisonTestResult comparison_test(const SampleSummary& a, const SampleSummary& b, double alpha, double power) {
  if (a.count < 2 || b.count < 2) {
    require_level(alpha, "alpha");
    require_level(power, "power");
    ComparisonTestResult r;
    r.alpha = alpha;
    r.statistic = kInf;
    r.message = "Each estimator needs at least 2 samples.";
    return r;
  }
  return welch_test(MeanEstimate{a.mean, a.sample_variance / double(a.count), double(a.count - 1)},
                         MeanEstimate{b.mean, b.sample_variance / double(b.count), double(b.count - 1)}, alpha,
                         power);
}

ComparisonTestResult welch_test(const MeanEstimate& a, const MeanEstimate& b, double alpha, double power) {
  require_level(alpha, "alpha");
  require_level(power, "power");
  ComparisonTestResult r;
  r.alpha = alpha;
  r.statistic = kInf;
  if (!(a.dof >= 1) || !(b.dof >= 1)) {
    r.message = "Each estimator needs at least 2 samples.";
    return r;
  }
  if (!std::isfinite(a.mean) || !std::isfinite(b.mean) || !std::isfinite(a.variance_of_mean) ||
      !std::isfinite(b.variance_of_mean) || a.variance_of_mean < 0 || b.variance_of_mean < 0) {
    r.message = "Non-finite means or variances, or a negative variance.";
    return r;
  }
  const WelchStatistic w = welch_statistic(a, b);
  r.difference = w.difference;
  r.standard_error = w.standard_error;
  if (r.standard_error == 0) {
    r.zero_variance = true;
    r.pass = exact_agreement(a.mean, b.mean);
    r.statistic = r.pass ? 0 : kInf;
    r.p_value = r.pass ? 1 : 0;
    r.message = zero_variance_message(a.mean, b.mean, r.pass);
    return r;
  }
  r.dof = w.dof;
  r.statistic = w.statistic;
  const bool normal = !std::isfinite(r.dof);
  r.p_value = normal ? normal_two_sided_p(r.statistic) : t_two_sided_p(r.dof, r.statistic);
  r.threshold = normal ? normal_upper_quantile(alpha / 2) : t_upper_quantile(r.dof, alpha / 2);
  const double power_quantile = normal ? normal_upper_quantile(1 - power) : t_upper_quantile(r.dof, 1 - power);
  r.detectable_difference = (r.threshold + power_quantile) * r.standard_error;
  r.detectable_relative_difference = relative_to(r.detectable_difference, b.mean);
  r.pass = std::fabs(r.statistic) <= r.threshold;
  if (!r.pass) {
    std::ostringstream s;
    s << "Means differ by " << r.difference << ": |t| = " << std::fabs(r.statistic) << " exceeds " << r.threshold
      << " (Welch, " << r.dof << " dof, alpha " << alpha << ").";
    r.message = s.str();
  }
  return r;
}

double binomial_two_sided_p_value(size_t k, size_t n, double p) {
  if (k > n) throw std::invalid_argument("binomial_two_sided_p_value: more successes than trials.");
  const boost::math::binomial_distribution<double> dist(double(n), p);
  const double lower = boost::math::cdf(dist, double(k));                                    // P(X ≤ k)
  const double upper = k == 0 ? 1.0 : boost::math::cdf(boost::math::complement(dist, double(k - 1)));  // P(X ≥ k)
  return std::min(1.0, 2 * std::min(lower, upper));
}

RejectionRate measure_rejection_rate(const std::function<bool(uint64_t seed)>& rejects, size_t trials,
                                     double expected_rate, uint64_t first_seed, double ci_level) {
  require_level(expected_rate, "expected_rate");
  require_level(ci_level, "ci_level");
  if (trials == 0) throw std::invalid_argument("measure_rejection_rate needs at least one trial.");
  RejectionRate r;
  r.trials = trials;
  r.expected_rate = expected_rate;
  r.ci_level = ci_level;
  for (size_t i = 0; i < trials; ++i)
    if (rejects(first_seed + i)) ++r.rejections;
  r.rate = double(r.rejections) / double(trials);
  using Binomial = boost::math::binomial_distribution<double>;
  const double tail = (1 - ci_level) / 2;
  r.ci_low = Binomial::find_lower_bound_on_p(double(trials), double(r.rejections), tail);
  r.ci_high = Binomial::find_upper_bound_on_p(double(trials), double(r.rejections), tail);
  r.binomial_p_value = binomial_two_sided_p_value(r.rejections, trials, expected_rate);
  return r;
}

double median(std::vector<double> values) {
  if (values.empty()) return 0;
  const auto mid = values.begin() + values.size() / 2;
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

}  // namespace furnace::stats
