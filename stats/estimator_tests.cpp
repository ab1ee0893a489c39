#include "stats/estimator_tests.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "stats/pixel_tests.h"

namespace furnace::stats {
namespace {

void require_options(const EstimatorTestOptions& options, double reference) {
  if (!(options.alpha_family > 0 && options.alpha_family < 1))
    throw std::invalid_argument("estimator_mean_test: alpha_family must lie in (0, 1), got " +
                                std::to_string(options.alpha_family) + ".");
  if (options.n_tests < 1) throw std::invalid_argument("estimator_mean_test: n_tests must be at least 1.");
  if (!std::isfinite(reference)) throw std::invalid_argument("estimator_mean_test: the reference is not finite.");
}

EstimatorMeanTestResult test_moments(const RunningMoments& m, size_t nonfinite, double reference,
                                     const EstimatorTestOptions& options) {
  EstimatorMeanTestResult r;
  r.nonfinite = nonfinite;
  r.seed = options.seed;
  r.alpha_family = options.alpha_family;
  r.n_tests = options.n_tests;
  r.power = options.power;
  std::ostringstream correction;
  correction << "Sidak over " << options.n_tests << (options.n_tests == 1 ? " test" : " tests")
             << " at family alpha " << options.alpha_family;
  r.correction = correction.str();
  const double alpha = sidak_alpha(options.alpha_family, options.n_tests);

  // A lone estimator is its own "image": when it is constant it must match exactly.
  const PixelTestResult pixel = pixel_mean_test(m, reference, alpha, round_off_only(m), options.power);
  // A skewed mean is not tested; the plain t's numbers (standard error,
  // detectable bias) are still reported, without a verdict.
  r.test = pixel.status == PixelStatus::kSkewed ? mean_test(m, reference, alpha, options.power) : pixel.test;
  r.test.count = m.count;
  r.test.mean = m.mean;
  r.test.reference = reference;
  r.test.alpha = alpha;
  r.test.skewness = sample_skewness(m);
  r.test.clt_adequate = clt_adequate(m);
  if (nonfinite > 0) {
    r.verdict = Verdict::kFail;
    r.message = std::to_string(nonfinite) + " samples were not finite.";
  } else if (pixel.status == PixelStatus::kSkewed) {
    r.verdict = Verdict::kInconclusive;
    std::ostringstream s;
    s << "The mean is too skewed for the normal approximation (skewness " << r.test.skewness << ": Cochran's rule needs "
      << kCochranSkewnessFactor * r.test.skewness * r.test.skewness << " samples, " << m.count
      << " drawn): draw more samples.";
    r.message = s.str();
  } else {
    r.verdict = pixel.test.pass ? Verdict::kPass : Verdict::kFail;
    r.message = !pixel.test.message.empty() ? pixel.test.message
                : r.test.zero_variance      ? "Constant estimator: exact agreement required and found."
                                            : "Hall's skewness-corrected t within the threshold.";
  }
  return r;
}

}  // namespace

const char* verdict_name(Verdict v) {
  switch (v) {
    case Verdict::kPass: return "PASS";
    case Verdict::kFail: return "FAIL";
    case Verdict::kInconclusive: return "INCONCLUSIVE";
  }
  return "?";
}

EstimatorMeanTestResult estimator_mean_test(const Estimator& estimator, double reference,
                                            const EstimatorTestOptions& options) {
  require_options(options, reference);
  if (options.samples < 2) throw std::invalid_argument("estimator_mean_test: samples must be at least 2.");
  UniformStream stream(options.seed);
  RunningMoments m;
  size_t nonfinite = 0;
  for (size_t i = 0; i < options.samples; ++i) {
    const double y = estimator(stream);
    if (std::isfinite(y))
      m.add(y);
    else
      ++nonfinite;
  }
  return test_moments(m, nonfinite, reference, options);
}

EstimatorMeanTestResult estimator_mean_test(const RunningMoments& moments, double reference,
                                            const EstimatorTestOptions& options) {
  require_options(options, reference);
  return test_moments(moments, 0, reference, options);
}

std::string describe(const EstimatorMeanTestResult& r) {
  const MeanTestResult& t = r.test;
  std::ostringstream s;
  s.precision(8);
  s << "estimator mean " << verdict_name(r.verdict) << ": mean = " << t.mean << " +- " << t.standard_error
    << " (SE) against reference " << t.reference << " (relative difference "
    << (t.reference != 0 ? (t.mean - t.reference) / std::fabs(t.reference) : t.mean - t.reference)
    << "); statistic = " << t.statistic << ", threshold = " << t.threshold << ", dof = " << t.dof
    << ", p = " << t.p_value << ", alpha = " << t.alpha << " (" << r.correction << "); " << t.count
    << " samples (seed 0x" << std::hex << r.seed << std::dec << ", " << r.nonfinite << " not finite), skewness " << t.skewness
    << "; detectable bias " << t.detectable_bias << " (relative " << t.detectable_relative_bias << ", power "
    << r.power << "). " << r.message;
  return s.str();
}

}  // namespace furnace::stats
