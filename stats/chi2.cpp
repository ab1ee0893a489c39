#include "stats/chi2.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>

#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/non_central_chi_squared.hpp>

#include "core/adaptive_quadrature.h"

namespace furnace::stats {
namespace {

constexpr double kTwoPi = 2 * kPi;

// ∫_{a0}^{a1} ∫_{b0}^{b1} f(a, b) db da, inner integral over b.
template <class F>
double integrate_2d(const F& f, double a0, double a1, double b0, double b1) {
  const auto inner = [&](double a) {
    return adaptive_gauss_kronrod_relative<kQuadraturePoints>([&](double b) { return f(a, b); }, b0, b1,
                                                              kQuadratureInnerRelTolerance, kQuadratureMaxDepth,
                                                              kQuadratureInitialPieces, kQuadratureMaxBisections);
  };
  return adaptive_gauss_kronrod_relative<kQuadraturePoints>(inner, a0, a1, kQuadratureRelTolerance,
                                                            kQuadratureMaxDepth, kQuadratureInitialPieces,
                                                            kQuadratureMaxBisections);
}

// Cell of a direction on a spherical grid; −1 if not a finite unit vector or outside.
long spherical_cell_of(const Vec3& w, const SphericalGrid& grid) {
  if (!is_finite(w) || !(std::fabs(length(w) - 1) <= kUnitLengthTolerance)) return -1;
  const double t = w.z > 0 ? (w.x * w.x + w.y * w.y) / (1 + w.z) : 1 - w.z;  // 1 − cos θ without cancellation
  if (!(t <= grid.t_max * (1 + kGridRimSlack))) return -1;
  const long row = std::min(long(t / grid.t_max * grid.t_bins), long(grid.t_bins - 1));
  double phi = std::atan2(w.y, w.x);
  if (phi < 0) phi += kTwoPi;
  const long col = std::min(long(phi / kTwoPi * grid.phi_bins), long(grid.phi_bins - 1));
  return row * grid.phi_bins + col;
}

// Shared tail of the directional and planar tests: count samples per cell,
// report the first sample that is outside the grid, then run Pearson. With
// `failures` (draws that returned no sample), the expected counts are of all
// draws and the failures form one more bin, expected N·(1 − ∫pdf).
template <class Sample, class CellOf, class Describe>
Chi2Result histogram_and_test(const std::vector<Sample>& samples, const std::vector<double>& probabilities,
                              double integral, const CellOf& cell_of, const Describe& describe_cell,
                              double alpha_family, size_t n_tests, double power,
                              std::optional<size_t> failures = std::nullopt) {
  const double alpha = sidak_alpha(alpha_family, n_tests);
  std::vector<double> observed(probabilities.size(), 0.0);
  for (size_t i = 0; i < samples.size(); ++i) {
    const long c = cell_of(samples[i]);
    if (c < 0) {
      Chi2Result r;
      r.alpha = alpha;
      r.samples = samples.size();
      r.cells = probabilities.size();
      r.pdf_integral = integral;
      r.statistic = std::numeric_limits<double>::infinity();
      std::ostringstream s;
      s << "Sample " << i << " is not finite, not of unit length, or outside the test grid.";
      r.message = s.str();
      return r;
    }
    observed[size_t(c)] += 1;
  }
  const double n = double(samples.size()) + double(failures.value_or(0));
  std::vector<double> expected(probabilities.size());
  for (size_t c = 0; c < probabilities.size(); ++c) {
    expected[c] = n * probabilities[c];
    if (expected[c] == 0 && observed[c] > 0) {
      Chi2Result r;
      r.alpha = alpha;
      r.samples = samples.size();
      r.cells = probabilities.size();
      r.pdf_integral = integral;
      r.statistic = std::numeric_limits<double>::infinity();
      std::ostringstream s;
      s << observed[c] << " samples fell in " << describe_cell(c) << ", where the pdf integrates to 0.";
      r.message = s.str();
      return r;
    }
  }
  if (failures) {
    // A pdf that integrates to 1 or more over the grid leaves no room for a
    // failed draw: the bin's expectation is 0 and any failure fails the test.
    const double expected_failures = n * std::max(0.0, 1 - integral);
    if (expected_failures == 0 && *failures > 0) {
      Chi2Result r;
      r.alpha = alpha;
      r.samples = size_t(n);
      r.cells = probabilities.size();
      r.pdf_integral = integral;
      r.statistic = std::numeric_limits<double>::infinity();
      std::ostringstream s;
      s << *failures << " draws returned no sample, but the pdf integrates to " << integral
        << " >= 1 over the grid.";
      r.message = s.str();
      return r;
    }
    observed.push_back(double(*failures));
    expected.push_back(expected_failures);
  }
  Chi2Result r = chi2_from_counts(observed, expected, alpha, power);
  r.cells = probabilities.size();  // grid cells; the failure bin is not one
  r.pdf_integral = integral;
  return r;
}


// Completes a chi-square result from its statistic: p-value, verdict, the
// effect (Cohen's w) detectable with `power` for `effective_n` samples, and
// the message, "<label> = X with D dof (P cells pooled), p = ...".
void finish_chi2(Chi2Result& r, double chi2, double alpha, double power, double effective_n, const char* label) {
  r.statistic = chi2;
  const boost::math::chi_squared_distribution<double> dist(r.dof);
  r.p_value = boost::math::cdf(boost::math::complement(dist, chi2));
  r.pass = r.p_value >= alpha;
  // Power: the non-centrality λ at which the statistic exceeds the critical
  // value with probability `power`; w = √(λ/N).
  const double critical = boost::math::quantile(boost::math::complement(dist, alpha));
  try {
    const double lambda = boost::math::non_central_chi_squared_distribution<double>::find_non_centrality(
        double(r.dof), critical, 1 - power);
    r.detectable_effect = effective_n > 0 ? std::sqrt(lambda / effective_n) : std::numeric_limits<double>::infinity();
  } catch (const std::exception&) {
    r.detectable_effect = std::numeric_limits<double>::quiet_NaN();  // reported, never used for the verdict
  }
  std::ostringstream s;
  s << label << " = " << chi2 << " with " << r.dof << " dof (" << r.pooled_cells << " cells pooled), p = "
    << r.p_value << (r.pass ? " >= " : " < ") << "alpha = " << alpha << ".";
  r.message = s.str();
}

}  // namespace

Chi2Result chi2_from_counts(const std::vector<double>& observed, const std::vector<double>& expected, double alpha,
                            double power) {
  if (observed.size() != expected.size())
    throw std::invalid_argument("chi2_from_counts: observed and expected differ in size.");
  Chi2Result r;
  r.alpha = alpha;
  r.cells = observed.size();
  r.statistic = std::numeric_limits<double>::infinity();
  double n = 0;
  for (double o : observed) n += o;
  r.samples = size_t(n);

  // Bins with enough expectation stand alone; the rest are pooled.
  std::vector<std::pair<double, double>> bins;  // (expected, observed)
  double pool_expected = 0, pool_observed = 0;
  for (size_t i = 0; i < observed.size(); ++i) {
    if (!(expected[i] >= 0) || !std::isfinite(expected[i])) {
      std::ostringstream s;
      s << "Expected count of bin " << i << " is " << expected[i] << ": the pdf is negative or not finite there.";
      r.message = s.str();
      return r;
    }
    if (expected[i] == 0) {
      if (observed[i] > 0) {
        std::ostringstream s;
        s << observed[i] << " samples fell in bin " << i << ", where the pdf integrates to 0.";
        r.message = s.str();
        return r;
      }
      continue;
    }
    if (expected[i] < kMinExpectedCount) {
      pool_expected += expected[i];
      pool_observed += observed[i];
      ++r.pooled_cells;
    } else {
      bins.emplace_back(expected[i], observed[i]);
    }
  }
  if (r.pooled_cells > 0) {
    if (pool_expected >= kMinExpectedCount || bins.empty()) {
      bins.emplace_back(pool_expected, pool_observed);
    } else {
      // Too little expectation even pooled: merge it into the smallest bin.
      auto smallest = std::min_element(bins.begin(), bins.end());
      smallest->first += pool_expected;
      smallest->second += pool_observed;
    }
  }
  r.dof = int(bins.size()) - 1;
  if (r.dof < 1) {
    r.message = "Fewer than 2 bins reach the minimum expected count: draw more samples or use a coarser grid.";
    return r;
  }
  double chi2 = 0;
  for (const auto& [e, o] : bins) chi2 += (o - e) * (o - e) / e;
  finish_chi2(r, chi2, alpha, power, n, "chi2");
  return r;
}

// ---------------------------------------------------------------------------

DirectionalChi2::DirectionalChi2(const DirectionPdf& pdf_solid_angle, const SphericalGrid& grid) : grid_(grid) {
  if (grid.phi_bins < 1 || grid.phi_bins % 2 == 0)
    throw std::invalid_argument("DirectionalChi2: phi_bins must be odd, got " + std::to_string(grid.phi_bins) + ".");
  if (grid.t_bins < 1) throw std::invalid_argument("DirectionalChi2: t_bins must be positive.");
  if (!(grid.t_max > 0 && grid.t_max <= 2))
    throw std::invalid_argument("DirectionalChi2: t_max = 1 - cos(theta_max) must lie in (0, 2].");
  // Direction at t = 1 − cos θ and φ; sin θ = √(t(2 − t)) without cancellation.
  const auto pdf_at = [&](double t, double phi) {
    const double sin_theta = std::sqrt(std::max(0.0, t * (2 - t)));
    return pdf_solid_angle(Vec3(sin_theta * std::cos(phi), sin_theta * std::sin(phi), 1 - t));
  };
  const auto t_edge = [&](int row) { return row == grid.t_bins ? grid.t_max : grid.t_max * row / grid.t_bins; };
  const auto phi_edge = [&](int col) { return col == grid.phi_bins ? kTwoPi : kTwoPi * col / grid.phi_bins; };
  probabilities_.resize(size_t(grid.t_bins) * size_t(grid.phi_bins));
  for (int row = 0; row < grid.t_bins; ++row)
    for (int col = 0; col < grid.phi_bins; ++col) {
      const double p = integrate_2d(pdf_at, t_edge(row), t_edge(row + 1), phi_edge(col), phi_edge(col + 1));
      probabilities_[size_t(row) * grid.phi_bins + col] = p;
      integral_ += p;
    }
}

long DirectionalChi2::cell_of(const Vec3& w) const { return spherical_cell_of(w, grid_); }

namespace {

// The directional test, with or without a bin of failed draws.
Chi2Result directional_test(const DirectionalChi2& chi2, const std::vector<Vec3>& samples,
                            std::optional<size_t> failures, double alpha_family, size_t n_tests, double power) {
  const SphericalGrid& grid = chi2.grid();
  const auto describe = [&](size_t c) {
    const size_t row = c / size_t(grid.phi_bins), col = c % size_t(grid.phi_bins);
    std::ostringstream s;
    s << "cell (t row " << row << ", phi column " << col << ") with 1 - cos(theta) in ["
      << grid.t_max * double(row) / grid.t_bins << ", " << grid.t_max * double(row + 1) / grid.t_bins << "]";
    return s.str();
  };
  return histogram_and_test(
      samples, chi2.cell_probabilities(), chi2.pdf_integral(), [&](const Vec3& w) { return chi2.cell_of(w); },
      describe, alpha_family, n_tests, power, failures);
}

}  // namespace

Chi2Result DirectionalChi2::test(const std::vector<Vec3>& samples, double alpha_family, size_t n_tests,
                                 double power) const {
  return directional_test(*this, samples, std::nullopt, alpha_family, n_tests, power);
}

Chi2Result DirectionalChi2::test_with_failures(const std::vector<Vec3>& samples, size_t failures,
                                               double alpha_family, size_t n_tests, double power) const {
  return directional_test(*this, samples, failures, alpha_family, n_tests, power);
}

Chi2Result chi2_test_directions(const std::vector<Vec3>& samples, const DirectionPdf& pdf_solid_angle,
                                const SphericalGrid& grid, double alpha_family, size_t n_tests, double power) {
  return DirectionalChi2(pdf_solid_angle, grid).test(samples, alpha_family, n_tests, power);
}

// ---------------------------------------------------------------------------

DirectionHistogram direction_histogram(const std::vector<Vec3>& samples, const SphericalGrid& grid) {
  if (grid.phi_bins < 1 || grid.phi_bins % 2 == 0 || grid.t_bins < 1 || !(grid.t_max > 0 && grid.t_max <= 2))
    throw std::invalid_argument("direction_histogram: odd phi_bins, positive t_bins and t_max in (0, 2] required.");
  DirectionHistogram h;
  h.counts.assign(size_t(grid.t_bins) * size_t(grid.phi_bins), 0.0);
  for (const Vec3& w : samples) {
    const long c = spherical_cell_of(w, grid);
    if (c < 0)
      ++h.outside;
    else
      h.counts[size_t(c)] += 1;
  }
  return h;
}

Chi2Result chi2_two_sample(const std::vector<double>& counts_a, const std::vector<double>& counts_b, double alpha,
                           double power) {
  if (counts_a.size() != counts_b.size())
    throw std::invalid_argument("chi2_two_sample: the histograms differ in size.");
  Chi2Result r;
  r.alpha = alpha;
  r.cells = counts_a.size();
  r.statistic = std::numeric_limits<double>::infinity();
  double n_a = 0, n_b = 0;
  for (size_t i = 0; i < counts_a.size(); ++i) {
    n_a += counts_a[i];
    n_b += counts_b[i];
  }
  r.samples = size_t(n_a + n_b);
  if (!(n_a > 0 && n_b > 0)) {
    r.message = "Both histograms need samples.";
    return r;
  }
  const double share_a = n_a / (n_a + n_b), share_b = n_b / (n_a + n_b);
  // Bins as (a, b) count pairs; cells with a small expected count are pooled.
  std::vector<std::pair<double, double>> bins;
  double pool_a = 0, pool_b = 0;
  for (size_t i = 0; i < counts_a.size(); ++i) {
    const double total = counts_a[i] + counts_b[i];
    if (total == 0) continue;
    if (std::min(share_a, share_b) * total < kMinExpectedCount) {
      pool_a += counts_a[i];
      pool_b += counts_b[i];
      ++r.pooled_cells;
    } else {
      bins.emplace_back(counts_a[i], counts_b[i]);
    }
  }
  if (r.pooled_cells > 0) {
    if (std::min(share_a, share_b) * (pool_a + pool_b) >= kMinExpectedCount || bins.empty()) {
      bins.emplace_back(pool_a, pool_b);
    } else {
      auto smallest = std::min_element(bins.begin(), bins.end(), [](const auto& x, const auto& y) {
        return x.first + x.second < y.first + y.second;
      });
      smallest->first += pool_a;
      smallest->second += pool_b;
    }
  }
  r.dof = int(bins.size()) - 1;
  if (r.dof < 1) {
    r.message = "Fewer than 2 bins reach the minimum expected count: draw more samples or use a coarser grid.";
    return r;
  }
  double chi2 = 0;
  for (const auto& [a, b] : bins) {
    const double total = a + b;
    const double e_a = share_a * total, e_b = share_b * total;
    chi2 += (a - e_a) * (a - e_a) / e_a + (b - e_b) * (b - e_b) / e_b;
  }
  finish_chi2(r, chi2, alpha, power, n_a * n_b / (n_a + n_b), "two-sample chi2");
  return r;
}

// ---------------------------------------------------------------------------

PlanarChi2::PlanarChi2(const PlanarPdf& pdf_area, const PlanarGrid& grid) : grid_(grid) {
  if (grid.x_bins < 1 || grid.y_bins < 1 || !(grid.x1 > grid.x0) || !(grid.y1 > grid.y0))
    throw std::invalid_argument("PlanarChi2: the grid needs positive bin counts and a non-empty rectangle.");
  const auto pdf_at = [&](double x, double y) { return pdf_area({x, y}); };
  const auto x_edge = [&](int i) { return i == grid.x_bins ? grid.x1 : grid.x0 + (grid.x1 - grid.x0) * i / grid.x_bins; };
  const auto y_edge = [&](int j) { return j == grid.y_bins ? grid.y1 : grid.y0 + (grid.y1 - grid.y0) * j / grid.y_bins; };
  probabilities_.resize(size_t(grid.x_bins) * size_t(grid.y_bins));
  for (int j = 0; j < grid.y_bins; ++j)
    for (int i = 0; i < grid.x_bins; ++i) {
      const double p = integrate_2d(pdf_at, x_edge(i), x_edge(i + 1), y_edge(j), y_edge(j + 1));
      probabilities_[size_t(j) * grid.x_bins + i] = p;
      integral_ += p;
    }
}

long PlanarChi2::cell_of(const std::array<double, 2>& p) const {
  if (!(p[0] >= grid_.x0 && p[0] <= grid_.x1 && p[1] >= grid_.y0 && p[1] <= grid_.y1)) return -1;  // also NaN
  const long i = std::min(long((p[0] - grid_.x0) / (grid_.x1 - grid_.x0) * grid_.x_bins), long(grid_.x_bins - 1));
  const long j = std::min(long((p[1] - grid_.y0) / (grid_.y1 - grid_.y0) * grid_.y_bins), long(grid_.y_bins - 1));
  return j * grid_.x_bins + i;
}

Chi2Result PlanarChi2::test(const std::vector<std::array<double, 2>>& samples, double alpha_family, size_t n_tests,
                            double power) const {
  const auto describe = [&](size_t c) {
    std::ostringstream s;
    s << "cell (x column " << c % size_t(grid_.x_bins) << ", y row " << c / size_t(grid_.x_bins) << ")";
    return s.str();
  };
  return histogram_and_test(
      samples, probabilities_, integral_, [&](const std::array<double, 2>& p) { return cell_of(p); }, describe,
      alpha_family, n_tests, power);
}

// ---------------------------------------------------------------------------

Chi2Result chi2_test_interval(const std::vector<double>& samples, const IntervalPdf& pdf, double a, double b,
                              int bins, double alpha_family, size_t n_tests, double power) {
  // A planar grid one bin high over y ∈ [0, 1], with a y-independent pdf.
  const PlanarChi2 chi2([&](const std::array<double, 2>& p) { return pdf(p[0]); }, PlanarGrid{a, b, 0, 1, bins, 1});
  std::vector<std::array<double, 2>> points;
  points.reserve(samples.size());
  for (double x : samples) points.push_back({x, 0.5});
  return chi2.test(points, alpha_family, n_tests, power);
}

}  // namespace furnace::stats
