// `furnace analytic --json` carries an error bound beside every value it
// computes: on every built-in scene, at the point a few camera rays hit, each
// number of the answer other than the query's own inputs (point, normal,
// albedo) has a sibling "<name>_error_bound" that is a finite number ≥ 0, and
// every estimator is either unsupported (with its reason) or carries all four
// of second moment, variance and their bounds.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "analytic/reference.h"
#include "core/error.h"
#include "core/scene.h"
#include "verify/analytic_query.h"

namespace furnace::verify {
namespace {

// The query's inputs, echoed back: not computed, so no bound.
const std::set<std::string> kInputs{"point", "normal", "albedo"};

// Checks every numeric member of `object` (not an input) against its bound;
// returns how many values were checked.
int check_bounds(const nlohmann::json& object, const std::string& where) {
  int checked = 0;
  for (const auto& [key, value] : object.items()) {
    if (!value.is_number() || kInputs.count(key) || (key.size() > 12 && key.substr(key.size() - 12) == "_error_bound"))
      continue;
    const std::string bound_key = key + "_error_bound";
    EXPECT_TRUE(object.contains(bound_key)) << where << ": '" << key << "' has no '" << bound_key << "'";
    if (!object.contains(bound_key)) continue;
    const nlohmann::json& bound = object[bound_key];
    EXPECT_TRUE(bound.is_number() && std::isfinite(bound.get<double>()) && bound.get<double>() >= 0)
        << where << ": '" << bound_key << "' is " << bound.dump();
    ++checked;
  }
  return checked;
}

TEST(AnalyticQueryJson, EveryValueCarriesAnErrorBound) {
  int scenes = 0, queries = 0, values = 0;
  for (const auto& entry : std::filesystem::directory_iterator(FURNACE_SCENE_DIR)) {
    if (entry.path().extension() != ".json") continue;
    const Scene scene = load_scene(entry.path());
    ++scenes;
    const int w = scene.camera.width_px, h = scene.camera.height_px;
    for (const auto& [px, py] : {std::pair{w / 2, h / 2}, std::pair{w / 4, h / 4}, std::pair{3 * w / 4, 3 * h / 4}}) {
      const Camera::Ray ray = scene.camera.pixel_center_ray(px, py);
      const auto hit = analytic::intersect(scene, ray.origin, ray.direction);
      if (!hit) continue;
      AnalyticQuery q;
      q.point = hit->point;
      q.normal = dot(hit->normal, ray.direction) < 0 ? hit->normal : -hit->normal;
      const std::string where = scene.name + " pixel (" + std::to_string(px) + ", " + std::to_string(py) + ")";
      nlohmann::json answer;
      try {
        answer = nlohmann::json::parse(answer_analytic_query(scene, q, true));
      } catch (const Error&) {
        continue;  // the irradiance itself is outside what analytic/ solves here
      }
      ++queries;
      values += check_bounds(answer, where);
      ASSERT_TRUE(answer.contains("estimators")) << where;
      for (const auto& [name, estimator] : answer["estimators"].items()) {
        if (estimator.contains("unsupported")) {
          EXPECT_TRUE(estimator["unsupported"].is_string()) << where << " " << name;
          continue;
        }
        for (const char* key : {"second_moment", "variance"})
          EXPECT_TRUE(estimator.contains(key)) << where << " " << name << " has no " << key;
        values += check_bounds(estimator, where + " " + name);
      }
    }
  }
  std::printf("[ analytic --json ] %d scenes, %d queries, %d values, each with a finite error bound\n", scenes, queries,
              values);
  EXPECT_GT(queries, 20);
}

}  // namespace
}  // namespace furnace::verify
