// The verification harness: render a scene with one strategy, compare every
// pixel and the image mean with the exact reference by hypothesis tests, and
// summarise the verdict in one row of the table `furnace verify` prints.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "core/scene.h"
#include "renderer/render.h"
#include "stats/test_design.h"
#include "verify/analytic_cache.h"
#include "verify/calibration.h"
#include "verify/suite.h"

namespace furnace::verify {

// Each pixel's mean is tested by stats::pixel_mean_test (stats/pixel_tests.h):
// where the strategy's second moment is modelled on the scene, with the exact
// variance (Bernstein's bound below the reference, valid at any spp; above
// it, Hall's t and the exact-variance z must both reject); elsewhere with
// Hall's skewness-corrected t against Student's t quantile. A t test is only
// valid when the sample mean is close to normal: pixels that fail Cochran's
// rule (N ≥ 25·G1², stats::clt_adequate) are not t-tested but counted and
// reported as `px skip`; they still enter the image-mean test. A pixel whose
// samples are all equal (s = 0) must match its reference exactly (or, with a
// modelled variance, pass the exact-variance tests); if it does not, it is
// skipped the same way unless every pixel of the case is constant (a
// zero-variance estimator, which must be exact everywhere). A rejection in a
// case without a modelled variance below its strategy's calibrated spp makes
// the case INCONCLUSIVE (Verdict::calibrated_from_spp).

struct Verdict {
  std::string scene;
  std::string strategy;
  std::string defect;
  int spp = 0;
  int pixels = 0;
  // Image-mean test: mean over pixels of the estimates against the mean of
  // the references, standard error from the per-pixel sample variances.
  double image_mean = 0;
  double reference_mean = 0;
  double z = 0;
  double threshold = 0;             // |z| above this fails the image-mean test
  double detectable_rel_bias = 0;   // smallest relative bias of the image mean found with power stats::kReportedPower
  // Per-pixel tests (each at the Šidák-corrected level).
  int pixel_failures = 0;
  int pixels_untested = 0;          // not mean-tested: too skewed at this spp, or constant and off (stats::PixelStatus)
  double worst_pixel_t = 0;
  // The pixel with the largest |t| (a failing zero-variance pixel counts as
  // infinite): where to look first when a case fails.
  int worst_px = 0, worst_py = 0;
  double worst_pixel_mean = 0, worst_pixel_reference = 0, worst_pixel_sample_variance = 0;
  double median_pixel_detectable_rel_bias = 0;
  // Variance test against the analytic second moment (strategies that
  // analytic/moments.h models, on scenes it solves) for the sum over pixels
  // of s² − σ²; per-pixel outliers are counted for information only.
  bool variance_tested = false;
  // Why a modelled variance was not tested (empty when it was, or when the
  // strategy has no model): too few samples per pixel for the test
  // (stats::kMinVarianceTestSamples). The verdict rests on the mean tests.
  std::string variance_skipped;
  double measured_variance = 0;    // mean over pixels of the per-sample s²
  double predicted_variance = 0;   // mean over pixels of E[Y²] − E[Y]²
  double variance_z = 0;           // aggregate (Σ s² − Σ σ²)/√(Σ Var s²)
  double variance_detectable_rel_error = 0;  // of the aggregate, at stats::kReportedPower
  int variance_pixel_failures = 0;
  bool variance_pass = true;       // the aggregate variance test (true when not tested)
  double rmse = 0;                  // √(mean over pixels of (estimate − reference)²)
  uint64_t nonfinite_samples = 0;
  double seconds = 0;               // render wall time
  double samples_per_second = 0;
  bool pass = false;
  // The mean tests alone: every pixel test, the image-mean test, no
  // non-finite sample.
  bool mean_pass = false;
  // Whether the mean tests used the exact variance per sample (the strategy's
  // second moment is modelled on this scene): a pixel or image mean below its
  // reference is then tested by Bernstein's bound, valid at any spp.
  bool exact_variance = false;
  // The spp from which a rejection by this case's mean tests is calibrated;
  // 0 when it is at this spp. Set for a case without the exact variance
  // below its strategy's min_calibrated_spp: its tests rest on the sample
  // variance, which a rare contribution missed by the run shrinks, so a
  // rejection there makes the case INCONCLUSIVE, not FAIL.
  int calibrated_from_spp = 0;
};

// What a verdict says, keeping the two kinds of failure apart: a failed mean
// test means the estimator is biased; a failed variance test with passing
// mean tests means it converges to the right answer but is not the estimator
// its name claims (its variance is another estimator's: a power heuristic
// with another exponent, a different sampling density).
// A mean-test rejection that the spp cannot support (Verdict::
// calibrated_from_spp) is neither: the case is inconclusive, and says the
// spp that would judge it.
enum class VerdictKind { kPass, kBiased, kVarianceMismatch, kInconclusive };
VerdictKind verdict_kind(const Verdict& v);
// One line: "pass", "biased: …", "unbiased, but variance differs from its
// model (not the estimator it claims to be)" or "inconclusive: …".
std::string verdict_explanation(VerdictKind kind);
// verdict_explanation, with the spp an inconclusive case needs.
std::string verdict_explanation(const Verdict& v);

// A run's outcome: FAIL when any case is biased or fails its variance test,
// else INCONCLUSIVE when any case is, else PASS (the CLI maps these to exit
// codes 1, 3 and 0).
enum class RunOutcome { kPass, kFail, kInconclusive };
RunOutcome run_outcome(const std::vector<Verdict>& verdicts);
// "PASS", "FAIL" or "INCONCLUSIVE".
const char* run_outcome_word(RunOutcome outcome);

// Runs one case. `per_case_alpha` is the family-wise level of this case's
// P + 1 mean tests (P pixel tests and the image-mean test) and, where the
// strategy's variance is modelled, its aggregate variance test. `cache`,
// when given, keeps the analytic values between cases (AnalyticCache).
Verdict run_case(const Case& c, double per_case_alpha, AnalyticCache* cache = nullptr);

// run_case for every case, sharing one AnalyticCache, several cases at a time
// (as many as TBB's workers: `threads`, 0 for all; each case's pixels are
// split among the workers too). Every case's verdict is the one run_case
// gives it alone, bit for bit, except its render time (it shares the machine
// with the cases running beside it); verdicts come back in case order.
// `case_done` is called (serialised) after each case.
std::vector<Verdict> run_cases(const std::vector<Case>& cases, double per_case_alpha, int threads,
                               const std::function<void()>& case_done = {});

}  // namespace furnace::verify
