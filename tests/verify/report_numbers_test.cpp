// The report's numbers, recomputed (label report): `furnace report` on
// disk_occluder with two strategies (4 to 64 spp), then, with code of its
// own, this test re-renders every point of every case (the report renders
// each spp independently with the report's seed, so render() with the same
// options gives the same image to the bit), takes the exact per-pixel
// reference from analytic::reference_image, and recomputes
//  - each point's RMSE and relative RMSE (RMSE over pixels / mean reference),
//  - the slope of log RMSE against log spp (centred least squares),
//  - the efficiency 1/(relative MSE × seconds) and the seconds to 1 %
//    (relative MSE × seconds / 1e-4) at the largest spp, from the report's
//    own wall time (a time cannot be re-measured),
//  - the relative RMSE of the equal-time image the report lists,
// and compares them with report.json (to 1e-12 relative: the same doubles
// by other arithmetic; the equal-time image, stored with 7 digits, to 1e-5)
// and with the numbers index.html and convergence.md print (to their last
// printed digit). A negative control: the mean absolute error and an RMSE
// over N − 1 pixels, measures a wrong report might use, are refused by the
// same comparison. Skipped (with the reason) without Python 3 and matplotlib,
// which the HTML page needs.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "analytic/reference.h"
#include "core/scene.h"
#include "core/strategy.h"
#include "renderer/render.h"
#include "tests/command.h"

namespace furnace {
namespace {

namespace fs = std::filesystem;

const std::string kScene = std::string(FURNACE_SCENE_DIR) + "/disk_occluder.json";

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

struct Errors {
  double rmse = 0, relative_rmse = 0, relative_mae = 0, rmse_n_minus_1 = 0;
};
Errors errors(const std::vector<double>& image, const std::vector<double>& reference) {
  double sum_sq = 0, sum_abs = 0, sum_ref = 0;
  for (size_t i = 0; i < image.size(); ++i) {
    const double e = image[i] - reference[i];
    sum_sq += e * e;
    sum_abs += std::fabs(e);
    sum_ref += reference[i];
  }
  const double n = double(image.size()), mean_ref = sum_ref / n;
  Errors r;
  r.rmse = std::sqrt(sum_sq / n);
  r.relative_rmse = r.rmse / mean_ref;
  r.relative_mae = sum_abs / n / mean_ref;
  r.rmse_n_minus_1 = std::sqrt(sum_sq / (n - 1));
  return r;
}

// Slope of y against x by centred least squares.
double slope(const std::vector<double>& x, const std::vector<double>& y) {
  double mx = 0, my = 0;
  for (size_t i = 0; i < x.size(); ++i) mx += x[i], my += y[i];
  mx /= double(x.size());
  my /= double(y.size());
  double sxy = 0, sxx = 0;
  for (size_t i = 0; i < x.size(); ++i) sxy += (x[i] - mx) * (y[i] - my), sxx += (x[i] - mx) * (x[i] - mx);
  return sxy / sxx;
}

bool near(double a, double b, double rel) { return std::fabs(a - b) <= rel * std::fabs(b); }

// The number a page printed with `digits` significant digits (or `decimals`
// fixed) agrees with `value` to half its last digit (and round-off).
bool prints_as(double printed, double value, int significant) {
  const double unit = std::pow(10.0, std::floor(std::log10(std::fabs(value))) - (significant - 1));
  return std::fabs(printed - value) <= 0.5 * unit * (1 + 1e-9) + 1e-15;
}
bool prints_fixed(double printed, double value, int decimals) {
  return std::fabs(printed - value) <= 0.5 * std::pow(10.0, -decimals) * (1 + 1e-9);
}

// The cells of the row of `strategy` in the convergence table of `text` (the
// first table after its "rel. RMSE at max spp" header; HTML <td> or Markdown |).
std::vector<double> row_numbers(const std::string& text, const std::string& strategy, bool html) {
  const std::string start = html ? "<tr><td class=l>" + strategy + "</td>" : "| " + strategy + " |";
  const size_t table = text.find("rel. RMSE at max spp");
  if (table == std::string::npos) return {};
  const size_t at = text.find(start, table);
  if (at == std::string::npos) return {};
  const size_t end = text.find(html ? "</tr>" : "\n", at);
  const std::string row = text.substr(at + start.size(), end - at - start.size());
  std::vector<double> out;
  const std::regex number(R"([-+]?[0-9]*\.?[0-9]+(?:[eE][-+]?[0-9]+)?)");
  for (auto it = std::sregex_iterator(row.begin(), row.end(), number); it != std::sregex_iterator(); ++it)
    out.push_back(std::stod(it->str()));
  return out;
}

class ReportNumbers : public testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("furnace_report_numbers_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(ReportNumbers, RecomputedFromTheImagesAgreeWithReportJsonAndThePage) {
  const fs::path out = dir_ / "report";
  const testing_support::CommandResult run = testing_support::run_command(
      std::string(FURNACE_CLI) + " report --scene " + kScene +
      " --strategy uniform_hemisphere --strategy light_area --min-spp 4 --max-spp 64 --threads 2 --output-dir " +
      out.string() + " 2>&1");
  if (run.exit_code == 2 && run.output.find("matplotlib") != std::string::npos)
    GTEST_SKIP() << "skipped: the HTML report needs Python 3 with matplotlib: " << run.output;
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const nlohmann::json j = nlohmann::json::parse(read_text(out / "report.json"));
  const std::string page = read_text(out / "index.html"), markdown = read_text(out / "convergence.md");
  const Scene scene = load_scene(kScene);
  const std::vector<double> reference = analytic::reference_image(scene);
  ASSERT_EQ(j["cases"].size(), 2u);
  for (const nlohmann::json& c : j["cases"]) {
    const std::string strategy = c["strategy"];
    SCOPED_TRACE(strategy);
    std::vector<double> log_spp, log_rmse;
    Errors last;
    for (const nlohmann::json& p : c["points"]) {
      RenderOptions options;
      options.strategy = parse_strategy(strategy);
      options.spp = p["spp"];
      options.seed = j["seed"];
      const Image image = render(scene, options);
      std::vector<double> mean;
      for (const PixelMoments& m : image.pixels) mean.push_back(m.mean);
      last = errors(mean, reference);
      EXPECT_TRUE(near(p["rmse"], last.rmse, 1e-12)) << p["spp"] << " spp: " << p["rmse"] << " vs " << last.rmse;
      EXPECT_TRUE(near(p["relative_rmse"], last.relative_rmse, 1e-12)) << p["spp"] << " spp";
      // Negative control: other error measures are refused by this comparison.
      EXPECT_FALSE(near(p["relative_rmse"], last.relative_mae, 1e-12)) << p["spp"] << " spp";
      EXPECT_FALSE(near(p["rmse"], last.rmse_n_minus_1, 1e-12)) << p["spp"] << " spp";
      log_spp.push_back(std::log(double(p["spp"])));
      log_rmse.push_back(std::log(last.rmse));
    }
    const double seconds = c["points"].back()["seconds"];
    const double slope_recomputed = slope(log_spp, log_rmse);
    const double mse = last.relative_rmse * last.relative_rmse;
    const double efficiency = 1 / (mse * seconds), to_one_percent = mse * seconds / 1e-4;
    EXPECT_NEAR(double(c["slope"]), slope_recomputed, 1e-12);
    EXPECT_TRUE(near(c["efficiency"], efficiency, 1e-12)) << c["efficiency"] << " vs " << efficiency;
    EXPECT_TRUE(near(c["seconds_to_one_percent"], to_one_percent, 1e-12));
    // The equal-time image the report lists (7 significant digits per pixel).
    const std::vector<double> equal_time = c["equal_time"]["mean"];
    const double relative_equal_time = errors(equal_time, reference).relative_rmse;
    // The page and the Markdown table: slope, rel. RMSE, seconds, efficiency, s to 1 % (and, on the page,
    // equal-time spp and its rel. RMSE).
    for (const bool html : {true, false}) {
      SCOPED_TRACE(html ? "index.html" : "convergence.md");
      const std::vector<double> row = row_numbers(html ? page : markdown, strategy, html);
      ASSERT_GE(row.size(), 5u) << "no table row for " << strategy;
      EXPECT_TRUE(prints_fixed(row[0], slope_recomputed, 3)) << row[0] << " vs " << slope_recomputed;
      EXPECT_TRUE(prints_as(row[1], last.relative_rmse, 4)) << row[1] << " vs " << last.relative_rmse;
      EXPECT_TRUE(prints_fixed(row[2], seconds, 3)) << row[2] << " vs " << seconds;
      EXPECT_TRUE(prints_as(row[3], efficiency, 3)) << row[3] << " vs " << efficiency;
      EXPECT_TRUE(prints_as(row[4], to_one_percent, 3)) << row[4] << " vs " << to_one_percent;
      if (html) {
        ASSERT_EQ(row.size(), 7u);
        EXPECT_EQ(row[5], double(c["equal_time"]["spp"]));
        EXPECT_TRUE(prints_as(row[6], relative_equal_time, 4) || near(row[6], relative_equal_time, 1e-5))
            << row[6] << " vs " << relative_equal_time;
      }
    }
  }
}

}  // namespace
}  // namespace furnace
