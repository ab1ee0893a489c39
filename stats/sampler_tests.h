// Tests of a caller's direction sampler, given as callables, for a
// renderer's own test suite (furnace::stats in the installed package):
//  - chi2_test_sampler: do the directions sample(u) draws follow the density
//    pdf(w) claims? Pearson's chi-square on equal-solid-angle cells
//    (stats/chi2.h), with the per-test level, its correction and the
//    smallest detectable error in the result;
//  - check_sample_consistency: does every sample report pdf(direction) as
//    its pdf, and weight = eval·|cos θ|/pdf as its weight?
//
// Frame: directions are unit vectors in the sampler's local frame, z the
// shading normal; θ is measured from +z. Both tests are deterministic: the
// uniforms come from a UniformStream of a named seed (uniform_stream.h).
//
// The two tests see different bugs. A sampler whose sample() and pdf() agree
// with each other but not with the directions drawn (a warp that skips part of
// its support, a wrong Jacobian in both) passes the consistency test and fails
// chi-square; a weight computed from a stale pdf passes chi-square and fails
// the consistency test.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "core/vec3.h"
#include "stats/chi2.h"
#include "stats/statistics.h"
#include "stats/uniform_stream.h"

namespace furnace::stats {

// What sample(u) returns for one pair of uniforms; an empty optional means
// the sampler drew nothing (e.g. a BSDF sample below the horizon).
struct DirectionSample {
  Vec3 direction;             // unit vector, local frame
  double pdf_solid_angle = 0; // the density the sampler reports for `direction`, sr⁻¹
  // f·|cos θ|/pdf as the sampler returns it; only the consistency test reads
  // it, and only when it is given an eval callable.
  std::optional<double> weight;
  // A delta lobe's sample: pdf() is 0 there, so both tests leave it out (the
  // chi-square test counts it with the failed draws, see below).
  bool delta = false;
};

using DirectionSampler = std::function<std::optional<DirectionSample>(const std::array<double, 2>& u)>;
// The BSDF value f(wo, wi) for the caller's fixed wo, as a function of wi (sr⁻¹).
using DirectionEval = std::function<double(const Vec3& direction)>;
// DirectionPdf (chi2.h): density in solid angle, 0 outside the support.

// ---------------------------------------------------------------------------

struct SamplerChi2Options {
  // Cells: odd φ columns × rows of equal 1 − cos θ, all of one solid angle,
  // covering the sphere, the upper hemisphere or a cone around +z. Must cover
  // the pdf's support (chi2.h explains the grid rules).
  SphericalGrid grid = SphericalGrid::hemisphere(20);  // 41 × 20 cells
  size_t samples = 1'000'000;                           // draws of sample(u)
  uint64_t seed = kDefaultTestSeed;
  double alpha_family = 0.01;  // false-alarm probability of the caller's whole family of tests
  size_t n_tests = 1;          // tests in that family: each runs at the Šidák level
  double power = kDefaultPower;
};

struct SamplerChi2Result {
  // statistic, dof, p_value, alpha (the per-test level), pass, cells,
  // pooled_cells, pdf_integral, detectable_effect, message (chi2.h).
  Chi2Result chi2;
  size_t draws = 0;           // pairs u drawn
  size_t failed_draws = 0;    // sample(u) returned nothing
  size_t delta_samples = 0;   // sample(u) returned a delta sample
  uint64_t seed = 0;
  double alpha_family = 0;
  size_t n_tests = 0;
  double power = 0;
  std::string cells;       // the cell construction, one phrase
  std::string correction;  // e.g. "Sidak over 3 tests at family alpha 0.01"
  bool pass = false;
};

// Draws options.samples pairs u from the seeded stream, bins the directions
// on options.grid and runs Pearson's test against the expected counts
// N·∫cell pdf dΩ (nested adaptive Gauss–Kronrod quadrature of pdf; the pdf is
// not renormalised, so a wrong normalisation fails the test and shows in
// chi2.pdf_integral). Draws that return nothing or a delta sample form one
// more bin, of expected count N·(1 − ∫pdf): the probability a sampler
// leaves to failures and delta lobes is the mass its pdf lacks. Cells
// expected below kMinExpectedCount are pooled; a direction that is not a
// finite unit vector, lies outside the grid or falls where the pdf
// integrates to 0 fails the test at once (chi2.message names it).
//
// The test rejects at the Šidák level 1 − (1 − alpha_family)^(1/n_tests).
// chi2.detectable_effect is the Cohen's w it detects with probability
// `power`: w² = Σ (p'ᵢ − pᵢ)²/pᵢ over the cells, pᵢ the claimed and p'ᵢ the
// true cell probabilities, i.e. w is the probability-weighted RMS of the
// relative error of the cell probabilities.
//
// Throws std::invalid_argument for an invalid grid (chi2.h), samples < 1,
// alpha_family outside (0, 1) or n_tests < 1.
SamplerChi2Result chi2_test_sampler(const DirectionSampler& sample, const DirectionPdf& pdf_solid_angle,
                                    const SamplerChi2Options& options = {});

// One paragraph with every number of the result: verdict, statistic, dof,
// p-value, per-test α and its correction, cells, draws, pdf integral and the
// detectable effect.
std::string describe(const SamplerChi2Result& result);

// ---------------------------------------------------------------------------

// Default tolerance of check_sample_consistency, relative: the reported pdf
// and pdf(direction), or the weight and eval·|cos θ|/pdf, are the same
// quantity computed along two paths of a few double roundings each (the
// renderer's own strategies agree within 16 ε). 64 ε leaves room for a pdf
// recomputed from the direction instead of from u. A sampler computing in
// float needs a tolerance in float epsilons instead (64 of them are 7.6e-6).
inline constexpr double kDefaultConsistencyRelTolerance = 64 * 2.220446049250313e-16;

struct ConsistencyOptions {
  size_t samples = 100'000;
  uint64_t seed = kDefaultTestSeed;
  double relative_tolerance = kDefaultConsistencyRelTolerance;
};

struct ConsistencyResult {
  size_t draws = 0;
  size_t checked = 0;        // non-delta samples compared
  size_t failed_draws = 0;   // sample(u) returned nothing
  size_t delta_samples = 0;  // skipped
  // Samples whose direction is not a finite unit vector, whose pdf is not
  // finite and > 0, or that lack a weight although an eval was given.
  size_t invalid = 0;
  size_t pdf_mismatches = 0;     // |pdf_solid_angle − pdf(direction)| > tol·pdf(direction)
  size_t weight_mismatches = 0;  // |weight − eval·|cos θ|/pdf| > tol·|eval·|cos θ|/pdf|
  double max_pdf_relative_error = 0;
  double max_weight_relative_error = 0;
  double relative_tolerance = 0;
  bool weights_checked = false;  // an eval was given
  std::string message;           // the first offending sample, or a summary
  bool pass = false;             // checked > 0 and no invalid sample and no mismatch
};

// Draws options.samples pairs u and compares, for every non-delta sample,
// its pdf_solid_angle with pdf(direction) and, when `eval` is given (not
// empty), its weight with eval(direction)·|direction.z|/pdf(direction). The
// checks are exact identities up to round-off: a mismatch is a bug, so no
// statistics are involved. Throws std::invalid_argument for samples < 1 or a
// tolerance that is not finite and ≥ 0.
ConsistencyResult check_sample_consistency(const DirectionSampler& sample, const DirectionPdf& pdf_solid_angle,
                                           const DirectionEval& eval, const ConsistencyOptions& options = {});

std::string describe(const ConsistencyResult& result);

}  // namespace furnace::stats
