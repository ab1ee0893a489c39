// The checks both Fresnel test files run, each on its own implementation
// (core/fresnel.h for the renderer, analytic/fresnel.h for the references):
// the function under test is a parameter, the 50-digit values and grids are
// tests/fresnel_50.h's. Each prints the worst relative error per class and
// holds it to `target` with EXPECT_LE.
#pragma once

#include <cmath>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tests/fresnel_50.h"

namespace furnace::testing_support {

inline void print_worst(const std::string& what, const WorstError& w, const char* a_name, const char* b_name) {
  std::cout << "  " << what << " worst rel err " << w.error << " at c = " << w.cos_i << ", " << a_name << " = " << w.a;
  if (b_name != nullptr) std::cout << ", " << b_name << " = " << w.b;
  std::cout << " (F = " << w.value << ", 50-digit " << w.reference << "; " << w.points << " points)\n";
}

// F(c, η) over kFresnelEtas × fresnel_cosines(), by class: η > 1, η < 1,
// |η − 1| ≤ 1e-3, grazing (c ≤ 1e-4).
template <class F>
void check_dielectric_grid(const std::string& name, F fresnel, double target) {
  WorstError outside, inside, near_one, grazing;
  for (double eta : kFresnelEtas)
    for (double c : fresnel_cosines()) {
      const double f = fresnel(c, eta);
      const Real50 ref = fresnel_dielectric_50(c, eta);
      const double e = relative_error(f, ref);
      ASSERT_GT(ref, 0) << "c " << c << " eta " << eta;
      if (std::fabs(eta - 1) <= 1e-3) near_one.add(e, c, eta, 0, f, ref);
      else if (eta > 1) outside.add(e, c, eta, 0, f, ref);
      else inside.add(e, c, eta, 0, f, ref);
      if (c <= 1e-4) grazing.add(e, c, eta, 0, f, ref);
      EXPECT_LE(e, target) << name << ": c " << c << " eta " << eta << " F " << f;
    }
  print_worst(name + " eta > 1", outside, "eta", nullptr);
  print_worst(name + " eta < 1", inside, "eta", nullptr);
  print_worst(name + " |eta - 1| <= 1e-3", near_one, "eta", nullptr);
  print_worst(name + " grazing c <= 1e-4", grazing, "eta", nullptr);
}

// θ = θc − dθ from inside (η < 1), dθ from 1e-10 to 1e-4 rad, on the
// transmitting side. F is ill-conditioned there: a relative perturbation δ
// of c moves F by about κ·δ, κ = |c F′/F| (printed beside the error: κ·ε/2
// is what one rounding of c² alone would cost, so an error well below it
// shows η² − 1 + c² formed without rounding its parts).
template <class F>
void check_near_critical_angle(const std::string& name, F fresnel, double target) {
  const std::vector<double> etas{0.25, 0.5, 1 / 1.5, 1 / 1.05, 0.999, 1 - 1e-6};
  for (double dtheta : {1e-10, 1e-8, 1e-6, 1e-4}) {
    WorstError w;
    double kappa_at_worst = 0;
    for (double eta : etas) {
      const double c = cos_near_critical(eta, -dtheta);
      const Real50 ref = fresnel_dielectric_50(c, eta);
      ASSERT_LT(ref, 1) << "not on the transmitting side: eta " << eta << " dtheta " << dtheta;
      const double f = fresnel(c, eta);
      const double e = relative_error(f, ref);
      if (e >= w.error) kappa_at_worst = fresnel_dielectric_condition(c, eta);
      w.add(e, c, eta, dtheta, f, ref);
      EXPECT_LE(e, target) << name << ": theta_c - " << dtheta << " rad, eta " << eta << ", c " << c << ": F " << f
                           << " vs 50-digit " << static_cast<double>(ref);
    }
    std::cout << "  " << name << " theta_c - " << dtheta << " rad: worst rel err " << w.error << " at eta = " << w.a
              << ", c = " << w.cos_i << " (condition number " << kappa_at_worst << ", kappa*eps/2 = "
              << kappa_at_worst * std::numeric_limits<double>::epsilon() / 2 << ")\n";
  }
}

// The points past the critical angle from inside (η < 1), grazing included,
// where the 50-digit F is exactly 1: `at_each(c, η)` checks the function
// under test there. Returns how many points.
template <class AtEach>
long for_each_total_internal_reflection(AtEach at_each) {
  long points = 0;
  for (double eta : kFresnelEtas) {
    if (!(eta < 1)) continue;
    std::vector<double> cosines{0.0};
    for (double dtheta : {1e-10, 1e-8, 1e-6, 1e-3, 0.1}) {
      const double c = cos_near_critical(eta, dtheta);
      if (c >= 0) cosines.push_back(c);  // θc + 0.1 is past grazing for η near 1
    }
    for (double c : fresnel_cosines())
      if (fresnel_dielectric_50(c, eta) == 1) cosines.push_back(c);
    for (double c : cosines) {
      EXPECT_EQ(fresnel_dielectric_50(c, eta), 1) << "not TIR: c " << c << " eta " << eta;
      ++points;
      at_each(c, eta);
    }
  }
  std::cout << "  " << points << " points past the critical angle\n";
  return points;
}

inline std::string index_name(const ComplexIndex& x) {
  return "(" + std::to_string(x.n).substr(0, 4) + ", " + std::to_string(x.k).substr(0, 4) + ")";
}

// F(c, n, k) over kConductors × fresnel_cosines(); for (1, 0), where F ≡ 0,
// the error is absolute.
template <class F>
void check_conductor_grid(const std::string& name, F fresnel, double target) {
  for (const ComplexIndex& x : kConductors) {
    WorstError w;
    for (double c : fresnel_cosines()) {
      const double f = fresnel(c, x.n, x.k);
      const Real50 ref = fresnel_conductor_50(c, x.n, x.k);
      const double e = relative_error(f, ref);
      w.add(e, c, x.n, x.k, f, ref);
      EXPECT_LE(e, target) << name << " " << index_name(x) << " c " << c << ": F " << f << " vs 50-digit "
                           << static_cast<double>(ref);
    }
    print_worst(name + " " + index_name(x) + (x.n == 1 && x.k == 0 ? " (absolute: F = 0)" : ""), w, "n", "k");
  }
}

}  // namespace furnace::testing_support
