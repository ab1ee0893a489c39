#include "stats/sampler_tests.h"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace furnace::stats {
namespace {

void require_family(double alpha_family, size_t n_tests) {
  if (!(alpha_family > 0 && alpha_family < 1))
    throw std::invalid_argument("chi2_test_sampler: alpha_family must lie in (0, 1), got " +
                                std::to_string(alpha_family) + ".");
  if (n_tests < 1) throw std::invalid_argument("chi2_test_sampler: n_tests must be at least 1.");
}

std::string describe_cells(const SphericalGrid& grid) {
  std::ostringstream s;
  s << grid.phi_bins << " phi x " << grid.t_bins << " (1 - cos theta) cells of equal solid angle over ";
  if (grid.t_max == 2)
    s << "the sphere";
  else if (grid.t_max == 1)
    s << "the upper hemisphere";
  else
    s << "the cone 1 - cos theta <= " << grid.t_max;
  return s.str();
}

bool unit_vector(const Vec3& w) { return is_finite(w) && std::fabs(length(w) - 1) <= kUnitLengthTolerance; }

}  // namespace

SamplerChi2Result chi2_test_sampler(const DirectionSampler& sample, const DirectionPdf& pdf_solid_angle,
                                    const SamplerChi2Options& options) {
  require_family(options.alpha_family, options.n_tests);
  if (options.samples < 1) throw std::invalid_argument("chi2_test_sampler: samples must be at least 1.");
  const DirectionalChi2 chi2(pdf_solid_angle, options.grid);

  SamplerChi2Result r;
  r.seed = options.seed;
  r.alpha_family = options.alpha_family;
  r.n_tests = options.n_tests;
  r.power = options.power;
  r.cells = describe_cells(options.grid);
  std::ostringstream correction;
  correction << "Sidak over " << options.n_tests << (options.n_tests == 1 ? " test" : " tests")
             << " at family alpha " << options.alpha_family;
  r.correction = correction.str();

  UniformStream stream(options.seed);
  std::vector<Vec3> directions;
  directions.reserve(options.samples);
  for (size_t i = 0; i < options.samples; ++i) {
    const std::optional<DirectionSample> s = sample(stream.next2());
    ++r.draws;
    if (!s)
      ++r.failed_draws;
    else if (s->delta)
      ++r.delta_samples;
    else
      directions.push_back(s->direction);
  }
  r.chi2 = chi2.test_with_failures(directions, r.failed_draws + r.delta_samples, options.alpha_family,
                                   options.n_tests, options.power);
  r.pass = r.chi2.pass;
  return r;
}

std::string describe(const SamplerChi2Result& r) {
  const Chi2Result& c = r.chi2;
  std::ostringstream s;
  s << "sampler chi-square " << (r.pass ? "PASS" : "FAIL") << ": chi2 = " << c.statistic << ", dof = " << c.dof
    << ", p = " << c.p_value << (r.pass ? " >= " : " < ") << "alpha = " << c.alpha << " (" << r.correction
    << "); detectable effect w = " << c.detectable_effect << " (Cohen's w, power " << r.power << "); " << r.draws
    << " draws (seed 0x" << std::hex << r.seed << std::dec << ", " << r.failed_draws << " failed, "
    << r.delta_samples << " delta) in " << r.cells << " plus a bin of failed and delta draws, bins pooled (expected < "
    << kMinExpectedCount << "): " << c.pooled_cells << "; integral of the pdf over the grid " << c.pdf_integral << ".";
  // A failure before the statistic (a sample off the grid) says why.
  if (!std::isfinite(c.statistic)) s << " " << c.message;
  return s.str();
}

ConsistencyResult check_sample_consistency(const DirectionSampler& sample, const DirectionPdf& pdf_solid_angle,
                                           const DirectionEval& eval, const ConsistencyOptions& options) {
  if (options.samples < 1) throw std::invalid_argument("check_sample_consistency: samples must be at least 1.");
  if (!(std::isfinite(options.relative_tolerance) && options.relative_tolerance >= 0))
    throw std::invalid_argument("check_sample_consistency: relative_tolerance must be finite and >= 0.");
  ConsistencyResult r;
  r.relative_tolerance = options.relative_tolerance;
  r.weights_checked = bool(eval);
  const double tol = options.relative_tolerance;
  const auto first = [&](size_t i, const std::string& what) {
    if (!r.message.empty()) return;
    std::ostringstream s;
    s << "Draw " << i << ": " << what;
    r.message = s.str();
  };

  UniformStream stream(options.seed);
  for (size_t i = 0; i < options.samples; ++i) {
    const std::optional<DirectionSample> s = sample(stream.next2());
    ++r.draws;
    if (!s) {
      ++r.failed_draws;
      continue;
    }
    if (s->delta) {
      ++r.delta_samples;
      continue;
    }
    ++r.checked;
    const Vec3& w = s->direction;
    if (!unit_vector(w) || !(std::isfinite(s->pdf_solid_angle) && s->pdf_solid_angle > 0) ||
        (r.weights_checked && !(s->weight && std::isfinite(*s->weight)))) {
      ++r.invalid;
      first(i, "the direction is not a finite unit vector, the pdf is not finite and > 0, or the weight is "
               "missing or not finite.");
      continue;
    }
    const double pdf = pdf_solid_angle(w);
    const double pdf_error = std::fabs(s->pdf_solid_angle - pdf) / pdf;
    if (!(pdf_error <= tol)) {  // NaN (pdf 0 or not finite) counts as a mismatch
      ++r.pdf_mismatches;
      std::ostringstream m;
      m << "sample() reported pdf " << s->pdf_solid_angle << ", pdf(direction) = " << pdf << ".";
      first(i, m.str());
    }
    if (std::isfinite(pdf_error)) r.max_pdf_relative_error = std::fmax(r.max_pdf_relative_error, pdf_error);
    if (!r.weights_checked) continue;
    const double expected = eval(w) * std::fabs(w.z) / pdf;
    const double weight_error =
        expected == *s->weight ? 0.0 : std::fabs(*s->weight - expected) / std::fabs(expected);
    if (!(weight_error <= tol)) {
      ++r.weight_mismatches;
      std::ostringstream m;
      m << "sample() reported weight " << *s->weight << ", eval*|cos theta|/pdf = " << expected << ".";
      first(i, m.str());
    }
    if (std::isfinite(weight_error))
      r.max_weight_relative_error = std::fmax(r.max_weight_relative_error, weight_error);
  }
  r.pass = r.checked > 0 && r.invalid == 0 && r.pdf_mismatches == 0 && r.weight_mismatches == 0;
  if (r.checked == 0) r.message = "No non-delta sample was drawn: nothing was checked.";
  return r;
}

std::string describe(const ConsistencyResult& r) {
  std::ostringstream s;
  s << "sample consistency " << (r.pass ? "PASS" : "FAIL") << ": " << r.checked << " samples checked of "
    << r.draws << " draws (" << r.failed_draws << " failed, " << r.delta_samples << " delta); " << r.invalid
    << " invalid, " << r.pdf_mismatches << " pdf mismatches (largest relative error " << r.max_pdf_relative_error
    << ")";
  if (r.weights_checked)
    s << ", " << r.weight_mismatches << " weight mismatches (largest relative error " << r.max_weight_relative_error
      << ")";
  else
    s << ", weights not checked (no eval)";
  s << " at relative tolerance " << r.relative_tolerance << ".";
  if (!r.message.empty()) s << " " << r.message;
  return s.str();
}

}  // namespace furnace::stats
