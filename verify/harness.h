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
#include "verify/resources.h"  // scene_dir(), which the suite's cases and tests use

namespace furnace::verify {

// The family-wise false-alarm probability of one `furnace verify` run (all
// scenes × strategies × pixels together). Stated once; every test's own
// level is derived from it by the Šidák correction.
inline constexpr double kDefaultFamilyAlpha = 0.01;
// Power at which the minimum detectable bias is quoted: the bias the test
// would catch with probability 1 − β. 0.9 is the usual design power.
inline constexpr double kReportedPower = 0.9;
// The smallest spp at which the built-in suite's false-alarm rate has been
// measured to stay within its stated α, per strategy: `furnace sweep
// --strategy NAME` found no case rejecting significantly more often than its
// per-case α there and at every larger spp measured (README "Low spp" gives
// the counts). Below it the per-pixel tests' normal approximations (Hall's
// statistic, Cochran's rule, the fourth-moment standard error of s²) are not
// calibrated for that strategy's most skewed cases: verify and sweep still
// run but print low_spp_warning().
int min_calibrated_spp(Strategy strategy);
// The smallest and largest min_calibrated_spp over all strategies (--help).
int lowest_min_calibrated_spp();
int highest_min_calibrated_spp();


// Each pixel's mean is tested with Hall's skewness-corrected t statistic
// against Student's t quantile (stats::pixel_mean_test, stats/pixel_tests.h).
// A pixel's test is only valid when its sample mean is close to normal:
// pixels that fail Cochran's rule (N ≥ 25·G1², stats::clt_adequate) are not
// tested but counted and reported as `px skip`; they still enter the
// image-mean test, whose mean over all pixels is close to normal. A pixel
// whose samples are all equal (s = 0) must match its reference exactly; if it
// does not, it is skipped the same way unless every pixel of the case is
// constant (a zero-variance estimator, which must be exact everywhere).

struct Case {
  std::string scene_path;
  RenderOptions options;
};

// One sentence naming each strategy among `cases` whose case spp is below its
// min_calibrated_spp, with that spp; empty when every case is at or above its
// strategy's.
std::string low_spp_warning(const std::vector<Case>& cases);

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
  double detectable_rel_bias = 0;   // smallest relative bias of the image mean found with power kReportedPower
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
  double variance_detectable_rel_error = 0;  // of the aggregate, at kReportedPower
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
};

// What a verdict says, keeping the two kinds of failure apart: a failed mean
// test means the estimator is biased; a failed variance test with passing
// mean tests means it converges to the right answer but is not the estimator
// its name claims (its variance is another estimator's: a power heuristic
// with another exponent, a different sampling density).
enum class VerdictKind { kPass, kBiased, kVarianceMismatch };
VerdictKind verdict_kind(const Verdict& v);
// One line: "pass", "biased: …" or "unbiased, but variance differs from its
// model (not the estimator it claims to be)".
std::string verdict_explanation(VerdictKind kind);

// The verdict table's cells that its JSON and HTML twins (verdict_export.h)
// print too, so the three cannot drift apart:
// the verdict column: "pass", "FAIL biased" or "FAIL variance";
const char* verdict_label(VerdictKind kind);
// the strategy column: the strategy, with "+defect" when one is injected;
std::string strategy_label(const Verdict& v);
// the "var detect" column: "-" when not tested, "exact" for a zero predicted
// variance (tested for exact agreement), else the detectable error in %;
std::string variance_detect_cell(const Verdict& v);
// the "weakest" lines: the `count` verdicts with the largest finite `detect`
// among those `applies` selects, largest first (an exact case, tested for
// exact agreement, quotes no relative error and is left out).
std::vector<const Verdict*> weakest_cases(const std::vector<Verdict>& verdicts, double Verdict::*detect,
                                          bool (*applies)(const Verdict&), size_t count);

// The analytic side of cases (per-pixel references and predicted
// variances), computed once per scene file and kept for every later case
// that needs the same values: the direct-lighting strategies of a scene share
// one reference, the path tracers one per max_depth, and a strategy's
// variances (under one light selection) do not depend on the seed or spp, so
// a sweep over seeds computes them once. A value is a pure function of the
// scene file and those keys, so a run's results are the same with or without
// the cache. Thread-safe: concurrent cases may share one (two cases that
// miss the same key at once both compute it; the values are equal).
class AnalyticCache {
 public:
  // reference_for(scene, options), from the cache when this scene file's was computed before.
  const std::vector<double>& reference(const Case& c, const Scene& scene);
  // The predicted per-pixel variances E[Y²] − E[Y]² of c's strategy, or empty
  // when analytic/ does not model them on this scene (see run_case).
  const std::vector<double>& predicted_variance(const Case& c, const Scene& scene,
                                                const std::vector<double>& reference);

 private:
  std::mutex mutex_;  // guards the maps; values are computed outside it
  // std::map: references to its values stay valid as keys are added.
  std::map<std::string, std::vector<double>> references_;
  std::map<std::string, std::vector<double>> variances_;
};

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

// The built-in suite `furnace verify` runs when no scene is given: each
// built-in scene with the strategies whose reference it has (direct-lighting
// strategies against analytic::reference_image, path tracers against
// analytic::global_reference_image), at `spp` samples per pixel.
std::vector<Case> default_suite(int spp, uint64_t seed, int threads);

// The reference a case's render must converge to, per pixel centre; a
// non-finite value is bad input (require_finite_reference).
std::vector<double> reference_for(const Scene& scene, const RenderOptions& options);

// Throws furnace::Error naming the scene file, the pixel and the value if any
// per-pixel reference (row-major, the scene camera's width) is not finite: a
// scene whose exact answer overflows double precision cannot be verified.
void require_finite_reference(const std::vector<double>& reference, const Scene& scene);

// How many of the least powerful cases the table's summary names, per test.
inline constexpr size_t kWeakestCasesListed = 5;

// Formats the verdict table: one row per case with the smallest relative bias
// its image-mean test detects (`detect`), the median of the same per pixel
// (`px detect`) and the smallest relative error of the summed variance its
// variance test detects (`var detect`; "-" when not tested, "exact" when the
// predicted variance is 0 and the test is one of exact agreement), each at power
// kReportedPower; a line per failed case saying which kind of failure it is;
// and a summary naming the kWeakestCasesListed cases with the largest
// `detect` and `var detect`.
std::string format_table(const std::vector<Verdict>& verdicts, double family_alpha);

}  // namespace furnace::verify
