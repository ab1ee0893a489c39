// What the exporters' material tests share: over the built-in scenes, the
// reflecting objects of each material type an exporter writes and those its
// refusals name by their field, and the coverage those scenes must reach.
#pragma once

#include <gtest/gtest.h>

#include <cstdio>
#include <map>
#include <string>

#include <fmt/format.h>

#include "core/scene.h"
#include "export/scene_facts.h"

namespace furnace::exporter {

struct MaterialCoverage {
  std::map<std::string, int> written, refused;  // reflecting objects per material type (the scene file's word)

  // Counts the objects of `scene` whose material field the refusal names.
  void count_refusal(const Scene& scene, const std::string& refusal) {
    for (size_t i = 0; i < scene.objects.size(); ++i)
      if (refusal.find(fmt::format("objects[{}].material.type", i)) != std::string::npos)
        ++refused[bsdf_type_name(scene.objects[i].material.type())];
  }
  void count_written(const Object& o) {
    if (reflects(o.material)) ++written[bsdf_type_name(o.material.type())];
  }
  // The built-in scenes hold reflecting Lambertian, mirror and Phong
  // objects: both exporters write the first two and refuse Phong by name.
  void expect_built_in_coverage(const char* format) {
    EXPECT_GT(written["lambertian"], 0);
    EXPECT_GT(written["mirror"], 0);
    EXPECT_EQ(written["phong"], 0);
    EXPECT_GT(refused["phong"], 0);
    std::printf("%s: reflecting objects written: lambertian %d, mirror %d; refused by name: phong %d\n", format,
                written["lambertian"], written["mirror"], refused["phong"]);
  }
};

}  // namespace furnace::exporter
