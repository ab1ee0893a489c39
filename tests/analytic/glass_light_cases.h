// The geometries of the disk light behind rough glass, shared by its two
// checks: tests/analytic/glass_light_test.cpp (an independent integral in
// double) and tests/analytic/glass_light_precision_test.cpp (50-digit
// values). Glass in z = 0 (front normal +z, η 1.5), a one-sided disk light
// parallel to it on the far side facing it, a point p on the glass and the
// view ωo in the plane x = const (its azimuth −y); each test builds its own
// scene and integrand from these numbers.
#pragma once

#include <string>
#include <vector>

#include "core/material.h"

namespace furnace::analytic::glass_light_cases {

struct Case {
  std::string name;
  double alpha;
  MicrofacetShadowing shadowing;
  double view_degrees;  // θo from the normal on the viewer's side
  bool from_inside;     // viewer behind the glass's front normal (η′ = 1/1.5), light in front
  double depth;         // the disk's distance from the glass's plane
  double offset;        // the disk centre's y (the view's azimuth is −y)
  double radius;
};

inline constexpr MicrofacetShadowing kSeparable = MicrofacetShadowing::kSeparable;
inline constexpr MicrofacetShadowing kHeightCorrelated = MicrofacetShadowing::kHeightCorrelated;

// Disks wholly inside the BTDF's support for their point and view (each
// test checks it): α 0.1, 0.3, 1, both Smith forms, views 10°–70° from
// outside and 20°–30° from inside, centred near the lobe's peak unless
// named Tail.
inline const std::vector<Case>& inside_support() {
  static const std::vector<Case> all = {
      {"A01HcOut45", 0.1, kHeightCorrelated, 45, false, 0.6, 0.27, 0.25},
      {"A03HcOut45", 0.3, kHeightCorrelated, 45, false, 0.6, 0.27, 0.25},
      {"A03SepOut45", 0.3, kSeparable, 45, false, 0.6, 0.27, 0.25},
      {"A1HcOut45", 1.0, kHeightCorrelated, 45, false, 0.6, 0.27, 0.25},
      {"A03HcOut70Tail", 0.3, kHeightCorrelated, 70, false, 0.5, 0.6, 0.15},  // peak off the disk
      {"A01SepOut10", 0.1, kSeparable, 10, false, 1.0, 0.0, 0.5},
      {"A03HcIn30", 0.3, kHeightCorrelated, 30, true, 0.6, 0.63, 0.3},  // η′ = 1/1.5
      {"A1SepIn20", 1.0, kSeparable, 20, true, 0.5, 0.3, 0.2},
  };
  return all;
}

// Disks the support's edges cross (the receiver model cuts there:
// receiver_integrals.h, plane_integral): η 1.5 from outside at 45°, the
// cone −ωo·ωi = 1/η crossing a wide disk's rim and the microfacets' rim
// μi = μo/η (a circle inside it) meeting the cone on the disk; at 70° the
// cone alone across a disk off the peak; from inside at 30° (η′ = 1/1.5:
// the cone −ωo·ωi = η′ is total internal reflection of ωi, the rim
// outside the far hemisphere).
inline const std::vector<Case>& crossing_support() {
  static const std::vector<Case> all = {
      {"A03HcOut45Wide", 0.3, kHeightCorrelated, 45, false, 0.6, 0.0, 1.5},
      {"A1SepOut70Edge", 1.0, kSeparable, 70, false, 0.5, 0.9, 0.8},
      {"A03HcIn30Wide", 0.3, kHeightCorrelated, 30, true, 0.6, 0.3, 1.2},
  };
  return all;
}

}  // namespace furnace::analytic::glass_light_cases
