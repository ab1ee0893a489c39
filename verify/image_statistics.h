// The statistics `furnace check` (verify/check.h) and `furnace compare`
// (verify/compare.h) share on images: how a pixel's spread is floored and
// when its values are too few to estimate it, the detectable bias of a t- or
// z-test at a stated power with the spread at its upper confidence bound,
// and the search for the image or render count the advice quotes.
#pragma once

#include <functional>
#include <vector>

namespace furnace::verify {

// Confidence of the upper bound on the spread that the detectable bias uses
// (Browne 1995, "On the use of a pilot sample for sample size determination",
// Stat. Med. 14:1933): with few images the observed spread is itself noisy,
// and two images whose means happen to lie close together would otherwise
// claim a power they lack. The bound is s·√(ν/χ²_{1−c, ν}): 7.96·s at ν = 1,
// 1.57·s at ν = 7, 1.16·s at ν = 63; 1 for the z-test of one furnace EXR.
inline constexpr double kSpreadConfidence = 0.9;

// A pixel's K values repeat when at most K / kFewValuesDivisor of them are
// distinct (and not all are equal: that is the zero-spread case); tested only
// from kFewValuesMinImages images on (below, two equal values of three are
// not evidence of a discrete render).
inline constexpr int kFewValuesDivisor = 2;
inline constexpr int kFewValuesMinImages = 4;
// True when `values` (one pixel's K values) take so few distinct values that
// their spread does not estimate the error (ChannelCheck::pixels_few_values).
bool has_few_distinct_values(std::vector<double> values);

// Images store 32-bit floats: a spread below kZeroVarianceRelTolerance (64
// float steps) of the mean is round-off, not noise. Such a spread is floored
// there, so that values that coincide to round-off by chance (two images of
// 1 % noise agree to 7.6e-6 at some pixel of 1024 about one check in three)
// do not make t explode. Exactly no spread (every value equal) stays 0: the
// pixel must then match the reference exactly.
double floored_variance(double sample_variance, double mean);

// The smallest count k ≥ 2 with enough(k), for a predicate that stays true
// once true (more images or renders never lose power); 0 when none up to
// max_count. Doubling, then bisection: O(log k) calls.
int smallest_sufficient_count(const std::function<bool(int)>& enough, int max_count);

// The noncentrality λ = bias/SE at which a two-sided level-α t-test with
// `dof` d.o.f. (+inf: the z-test) rejects with probability `power`.
double detectable_noncentrality(double dof, double alpha, double power);
// √(ν/χ²_{1−confidence, ν}): the one-sided upper confidence bound of σ over s
// from ν d.o.f.; 1 for ν = +inf.
double spread_upper_bound_factor(double dof, double confidence);
// √(ν/χ²_{confidence, ν}): the one-sided lower confidence bound of σ over s
// from ν d.o.f. (0.76 at ν = 7 and confidence 0.9); 1 for ν = +inf.
double spread_lower_bound_factor(double dof, double confidence);
// The critical |statistic| of a two-sided level-α test: Student's t with
// `dof` d.o.f., the normal quantile for dof = +inf.
double critical_statistic(double dof, double alpha);

// The rare-event guards' floor (compare.h, check.h): a variance of the mean
// `variance_of_mean` estimated from `dof` d.o.f. over `samples` samples,
// taken per sample at the lower kSpreadConfidence bound of its spread and
// spread over `floored_samples` samples: b²·variance_of_mean·samples/floored_samples.
double rare_event_variance_floor(double variance_of_mean, double dof, double samples, double floored_samples);
// The factor on the samples at which a held test's floored statistic
// `guarded_statistic` (`dof` d.o.f.) reaches the noncentrality a level-α
// test detects with probability `power`: (λ/|t|)², as the floored variance
// falls as 1/samples; +inf for t = 0.
double held_spp_factor(double guarded_statistic, double dof, double alpha, double power);

}  // namespace furnace::verify
