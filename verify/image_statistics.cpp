#include "verify/image_statistics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <exception>
#include <limits>
#include <map>
#include <mutex>

#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/non_central_t.hpp>
#include <boost/math/distributions/normal.hpp>
#include <boost/math/distributions/students_t.hpp>
#include <boost/math/tools/roots.hpp>

#include "stats/statistics.h"

namespace furnace::verify {

namespace {

// Bits of the noncentrality the root finder resolves (λ to ~1e-9 relative).
constexpr int kNoncentralityBits = 30;

// Two-sided level-α rejection probability of the t-test with `dof` d.o.f.
// when the statistic is noncentral t with noncentrality λ.
double t_test_power(double dof, double critical_t, double lambda) {
  const boost::math::non_central_t_distribution<double> t(dof, lambda);
  return boost::math::cdf(boost::math::complement(t, critical_t)) + boost::math::cdf(t, -critical_t);
}

// detectable_noncentrality's root solve (about 1–10 ms; a check needs a few,
// and the simulation of its power thousands).
double solve_detectable_noncentrality(double dof, double alpha, double power) {
  const boost::math::normal_distribution<double> normal;
  if (!std::isfinite(dof))  // z-test: the far tail's share of the power is below 1e-9 at the levels used
    return boost::math::quantile(boost::math::complement(normal, alpha / 2)) +
           boost::math::quantile(boost::math::complement(normal, 1 - power));
  const boost::math::students_t_distribution<double> student(dof);
  const double critical_t = boost::math::quantile(boost::math::complement(student, alpha / 2));
  try {
    // The additive (t_{1−α/2} + t_power) is a lower bound: start there, double until the power is reached.
    double low = 0, high = critical_t + boost::math::quantile(boost::math::complement(student, 1 - power));
    while (t_test_power(dof, critical_t, high) < power) low = high, high *= 2;
    std::uintmax_t iterations = 200;
    const auto root = boost::math::tools::toms748_solve(
        [&](double lambda) { return t_test_power(dof, critical_t, lambda) - power; }, low, high,
        boost::math::tools::eps_tolerance<double>(kNoncentralityBits), iterations);
    return 0.5 * (root.first + root.second);
  } catch (const std::exception&) {
    // Boost's series overflow at one d.o.f. and per-pixel levels (critical t
    // ~1e5). There the statistic (Z + λ)/|W| exceeds t essentially when
    // |W| < λ/t (Z is negligible next to λ), so power = 2Φ(λ/t) − 1.
    return critical_t * boost::math::quantile(normal, (1 + power) / 2);
  }
}

}  // namespace

double detectable_noncentrality(double dof, double alpha, double power) {
  // Memoised: the same few (d.o.f., level) pairs recur in every check of a process.
  static std::mutex mutex;
  static std::map<std::array<double, 3>, double> solved;
  const std::array<double, 3> key = {dof, alpha, power};
  {
    const std::lock_guard<std::mutex> lock(mutex);
    if (const auto it = solved.find(key); it != solved.end()) return it->second;
  }
  const double lambda = solve_detectable_noncentrality(dof, alpha, power);
  const std::lock_guard<std::mutex> lock(mutex);
  return solved.emplace(key, lambda).first->second;
}

bool has_few_distinct_values(std::vector<double> values) {
  const size_t k = values.size();
  if (k < size_t(kFewValuesMinImages)) return false;
  std::sort(values.begin(), values.end());
  const size_t distinct = size_t(std::unique(values.begin(), values.end()) - values.begin());
  return distinct > 1 && distinct * kFewValuesDivisor <= k;
}

double floored_variance(double sample_variance, double mean) {
  if (sample_variance == 0) return 0;
  const double floor = stats::kZeroVarianceRelTolerance * std::fabs(mean);
  return std::max(sample_variance, floor * floor);
}

int smallest_sufficient_count(const std::function<bool(int)>& enough, int max_count) {
  if (enough(2)) return 2;
  int low = 2, high = 4;  // enough(low) is false; doubling until enough(high)
  while (!enough(high)) {
    if (high >= max_count) return 0;
    low = high;
    high = std::min(2 * high, max_count);
  }
  while (high - low > 1) {
    const int mid = low + (high - low) / 2;
    (enough(mid) ? high : low) = mid;
  }
  return high;
}

double spread_upper_bound_factor(double dof, double confidence) {
  if (!std::isfinite(dof)) return 1.0;
  const boost::math::chi_squared_distribution<double> chi2(dof);
  return std::sqrt(dof / boost::math::quantile(chi2, 1 - confidence));
}

double spread_lower_bound_factor(double dof, double confidence) {
  if (!std::isfinite(dof)) return 1.0;
  const boost::math::chi_squared_distribution<double> chi2(dof);
  return std::sqrt(dof / boost::math::quantile(chi2, confidence));
}

double critical_statistic(double dof, double alpha) {
  if (!std::isfinite(dof)) return stats::normal_upper_quantile(alpha / 2);
  return boost::math::quantile(boost::math::complement(boost::math::students_t_distribution<double>(dof), alpha / 2));
}

double rare_event_variance_floor(double variance_of_mean, double dof, double samples, double floored_samples) {
  const double b = spread_lower_bound_factor(dof, kSpreadConfidence);
  return b * b * variance_of_mean * samples / floored_samples;
}

double held_spp_factor(double guarded_statistic, double dof, double alpha, double power) {
  const double ratio = detectable_noncentrality(dof, alpha, power) / std::fabs(guarded_statistic);
  return std::isfinite(ratio) ? ratio * ratio : std::numeric_limits<double>::infinity();
}

}  // namespace furnace::verify
