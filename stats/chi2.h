// Pearson chi-square goodness-of-fit tests for samplers: do samples drawn by
// a warp follow the density its pdf() claims?
//
// Recipe (the idea of Mitsuba's chi2.py and Nori's chi2test):
//  - histogram the samples on a grid of equal-area cells; on the sphere the
//    cells are equal steps in φ (an odd number of them) and in t = 1 − cos θ
//    (dΩ = dφ·dt, so equal steps are equal solid angles);
//  - expected count of a cell = N · ∫cell pdf, by nested adaptive
//    Gauss–Kronrod quadrature in the same (t, φ) parametrisation;
//  - cells expected to hold fewer than kMinExpectedCount samples are pooled
//    into one bin; a sample in a cell of zero expectation, or outside the
//    grid, is an immediate failure;
//  - p-value from Boost's chi_squared, compared with the Šidák level derived
//    from the caller's family-wise α and number of tests;
//  - power: the effect size w = √(Σ(p'ᵢ − pᵢ)²/pᵢ) (Cohen's w, the
//    χ²-distance between the true and the claimed cell probabilities) that
//    the test detects with probability kDefaultPower, from Boost's
//    non-central chi-square.
//
// The grid must cover the pdf's support, and should have cell edges along
// its boundary (a hemisphere or cone grid for a hemisphere or cone; the
// shape's own coordinates for a spherical triangle): quadrature cannot see a
// sliver of support that falls between its nodes, and a sample there would
// read as a sample in a zero-expectation cell. The pdf is not renormalised:
// a wrong normalisation enters the statistic, and pdf_integral reports it.
//
// Also here: the same test for points in a rectangle (PlanarChi2) or on an
// interval, and a two-sample (homogeneity) test of two samplers' histograms
// when no pdf is available.
#pragma once

#include <array>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "core/vec3.h"
#include "stats/statistics.h"

namespace furnace::stats {

// Cochran's rule: below ~5 expected counts the χ² approximation of the
// Pearson statistic's distribution breaks down.
inline constexpr double kMinExpectedCount = 5;

// Sample directions must be unit vectors; warps produce them to a few ulps.
// 1e-9 is ~10⁷ ulps (no round-off reaches it) yet catches a missing normalisation.
inline constexpr double kUnitLengthTolerance = 1e-9;

// A sample on the grid's outer rim (e.g. a cone sample with u1 → 1) may have
// t = 1 − cos θ a few ulps above t_max; this relative slack bins it into the
// last row instead of failing it as "outside the grid".
inline constexpr double kGridRimSlack = 1e-9;

// Quadrature of the expected counts: nested adaptive Gauss–Kronrod
// (core/adaptive_quadrature.h) on Boost's 15-point rule. An error δE in an
// expected count E matters only against its Poisson noise √E (≥ 2 for
// E ≥ 5), so a relative tolerance of 1e-8 per cell is ample. The inner
// integral must be far more accurate than the outer tolerance, or the outer
// bisection chases the inner one's noise: smooth inner integrands reach 1e-11
// with one or two rule applications; where a pdf jumps inside a cell (a
// disk's rim across a square cell) each bisection halves the error, so the
// piece holding the jump is bisected down to kQuadratureMaxDepth.
inline constexpr double kQuadratureRelTolerance = 1e-8;        // outer integral
inline constexpr double kQuadratureInnerRelTolerance = 1e-11;  // inner integral
inline constexpr unsigned kQuadraturePoints = 15;
// A jump left in a piece of 2^−40 ≈ 9e-13 of a quarter cell errs by less
// than the inner tolerance; each jump costs 2·40 rule applications.
inline constexpr int kQuadratureMaxDepth = 40;
// Per integral: caps the cost of a pathological pdf (a support test
// flickering with round-off along a rim that lies inside a cell) at 800
// pieces, room for 10 jumps at full depth. Measured on the spherical
// triangle tests, whose cells the hypotenuse cuts: at 400 the pdf integrals
// agree with Ω_true/Ω_claimed to ≤ 3.7e-7 (the tests allow 1e-6); 800 gives
// ≤ 2.6e-7 in twice the time, 200 gives ≤ 5e-7.
inline constexpr size_t kQuadratureMaxBisections = 400;
// No error estimate sees a feature that falls between all nodes (a sliver of
// the support in a cell corner); starting from 4 pieces puts nodes ≤ ~5 % of
// a cell apart. Grids whose cell edges follow the support's boundary avoid
// the problem altogether (the disk test bins (r², φ), not (x, y)).
inline constexpr int kQuadratureInitialPieces = 4;

struct Chi2Result {
  double statistic = 0;
  int dof = 0;               // bins after pooling − 1
  double p_value = 0;
  double alpha = 0;          // per-test level (Šidák)
  bool pass = false;
  size_t samples = 0;
  size_t cells = 0;          // grid cells
  size_t pooled_cells = 0;   // cells with 0 < expected < kMinExpectedCount, pooled into one bin
  double pdf_integral = 0;   // ∫ pdf over the grid (quadrature); 1 for a normalised pdf covered by the grid; 0 when no pdf (two-sample)
  double detectable_effect = 0;  // Cohen's w detected with kDefaultPower (or the power passed)
  std::string message;       // why it failed, or a one-line summary
};

// The Pearson test on counts already binned; expected[i] is the expected
// count of bin i (not renormalised). Samples in bins with expected == 0 fail
// the test immediately. `alpha` is the per-test level.
Chi2Result chi2_from_counts(const std::vector<double>& observed, const std::vector<double>& expected, double alpha,
                            double power = kDefaultPower);

// ---------------------------------------------------------------------------
// Directions on the sphere, a hemisphere or a cone around +z.

struct SphericalGrid {
  int phi_bins = 41;  // odd: no cell edge on the symmetry planes φ = 0, π/2, π
  int t_bins = 20;    // rows of equal height in t = 1 − cos θ ∈ [0, t_max]
  double t_max = 2;   // 2 sphere, 1 upper hemisphere, 1 − cos θmax a cone (pass it accurately for tiny cones)

  // The (2k+1)·k grids of the recipe.
  static SphericalGrid sphere(int k) { return {2 * k + 1, k, 2.0}; }
  static SphericalGrid hemisphere(int k) { return {2 * k + 1, k, 1.0}; }
  static SphericalGrid cone(int k, double one_minus_cos_theta_max) { return {2 * k + 1, k, one_minus_cos_theta_max}; }
};

// Density in solid angle (sr⁻¹).
using DirectionPdf = std::function<double(const Vec3& w)>;

// Integrates the pdf over every cell once, then tests any number of sample
// sets against it (the calibration sweeps reuse one instance).
class DirectionalChi2 {
 public:
  // Throws std::invalid_argument for an even phi_bins, t_bins < 1 or t_max ∉ (0, 2].
  DirectionalChi2(const DirectionPdf& pdf_solid_angle, const SphericalGrid& grid);

  // Per-test level = sidak_alpha(alpha_family, n_tests).
  Chi2Result test(const std::vector<Vec3>& samples, double alpha_family, size_t n_tests,
                  double power = kDefaultPower) const;

  // The test of a sampler that may draw no direction (a failed or a delta
  // sample): `failures` such draws, N = samples.size() + failures. Expected
  // counts are N·∫cell pdf, and the failures form one more bin of expected
  // count N·(1 − ∫pdf) (the mass the pdf leaves outside the grid; pooled
  // like a cell when below kMinExpectedCount, and then counted in
  // pooled_cells); a failure when the pdf integrates to 1 or more is an
  // immediate failure.
  Chi2Result test_with_failures(const std::vector<Vec3>& samples, size_t failures, double alpha_family,
                                size_t n_tests, double power = kDefaultPower) const;

  const SphericalGrid& grid() const { return grid_; }
  // ∫cell pdf dΩ, row-major (t row, then φ column).
  const std::vector<double>& cell_probabilities() const { return probabilities_; }
  double pdf_integral() const { return integral_; }
  // Cell of a direction; −1 if it is not a finite unit vector or lies outside the grid.
  long cell_of(const Vec3& w) const;

 private:
  SphericalGrid grid_;
  std::vector<double> probabilities_;
  double integral_ = 0;
};

// One-shot convenience.
Chi2Result chi2_test_directions(const std::vector<Vec3>& samples, const DirectionPdf& pdf_solid_angle,
                                const SphericalGrid& grid, double alpha_family, size_t n_tests,
                                double power = kDefaultPower);

// ---------------------------------------------------------------------------
// Two samplers compared without a pdf (homogeneity test): is the distribution
// of sample set A the same as that of B (e.g. Malley's cosine sampler vs the
// inversion one, or a sampler before and after an optimisation)?

// Counts per cell of `grid` (row-major, t row then φ column); samples that
// are not finite unit vectors inside the grid are counted in `outside`.
struct DirectionHistogram {
  std::vector<double> counts;
  size_t outside = 0;
};
DirectionHistogram direction_histogram(const std::vector<Vec3>& samples, const SphericalGrid& grid);

// Pearson's chi-square for the 2 × K table of two histograms over the same
// cells: expected count of A in cell i is N_A·(a_i + b_i)/(N_A + N_B). Cells
// whose smaller expected count is below kMinExpectedCount are pooled (as
// above); dof = bins − 1. `alpha` is the per-test level. The detectable
// effect is w = √(Σ (P_A,i − P_B,i)²/P̄_i), P the cell probabilities of each
// sampler and P̄ their pooled mean; the non-centrality of the test is then
// λ = w²·N_A·N_B/(N_A + N_B).
Chi2Result chi2_two_sample(const std::vector<double>& counts_a, const std::vector<double>& counts_b, double alpha,
                           double power = kDefaultPower);

// ---------------------------------------------------------------------------
// Points in a rectangle of the plane ([0,1]², or [−1,1]² around a unit disk).

struct PlanarGrid {
  double x0 = 0, x1 = 1, y0 = 0, y1 = 1;
  int x_bins = 21, y_bins = 21;  // odd: no cell edge on the centre lines
};

// Density in area.
using PlanarPdf = std::function<double(const std::array<double, 2>& p)>;

class PlanarChi2 {
 public:
  PlanarChi2(const PlanarPdf& pdf_area, const PlanarGrid& grid);
  Chi2Result test(const std::vector<std::array<double, 2>>& samples, double alpha_family, size_t n_tests,
                  double power = kDefaultPower) const;
  const std::vector<double>& cell_probabilities() const { return probabilities_; }
  double pdf_integral() const { return integral_; }
  long cell_of(const std::array<double, 2>& p) const;

 private:
  PlanarGrid grid_;
  std::vector<double> probabilities_;
  double integral_ = 0;
};

// ---------------------------------------------------------------------------
// Points on an interval [a, b] (a 1-D sampler, e.g. a distance or a CDF
// inversion), `bins` equal-width bins; the pdf is a density in length.
using IntervalPdf = std::function<double(double x)>;
Chi2Result chi2_test_interval(const std::vector<double>& samples, const IntervalPdf& pdf, double a, double b,
                              int bins, double alpha_family, size_t n_tests, double power = kDefaultPower);

}  // namespace furnace::stats
