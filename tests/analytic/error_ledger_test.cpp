// The error bounds `furnace analytic` prints (analytic/error_ledger.h): how a
// ledger composes the quadratures' own error estimates, and that the bound of
// a sum is not swamped by a negligible, poorly resolved term.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>

#include <gtest/gtest.h>

#include "analytic/error_ledger.h"
#include "analytic/moments.h"
#include "analytic/reference.h"
#include "core/scene.h"
#include "core/strategy.h"

namespace furnace::analytic {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

TEST(ErrorLedger, NestedLedgersAddRelativeErrorsOutward) {
  const ErrorLedger outer;
  {
    const ErrorLedger inner;
    ErrorLedger::report(1e-12, 1.0);
    EXPECT_DOUBLE_EQ(inner.relative_quadrature_error(), 1e-12);
  }
  ErrorLedger::report(3e-12, 2.0);
  EXPECT_DOUBLE_EQ(outer.relative_quadrature_error(), 2.5e-12);
  EXPECT_DOUBLE_EQ(outer.bound(4.0), 4.0 * (2.5e-12 + kRoundoffUlps * kEps));
}

TEST(ErrorLedger, ZeroScaleWithAnErrorIsInfinitelyWrong) {
  const ErrorLedger ledger;
  ErrorLedger::report(1e-20, 0.0);
  EXPECT_TRUE(std::isinf(ledger.relative_quadrature_error()));
}

// A sum's bound weighs each term's relative error by the term's size: a term
// of 1e-12 known only to 100 % adds 1e-12, not 1, to the sum's relative error.
TEST(ErrorSum, WeighsEachTermsRelativeErrorByItsSize) {
  const ErrorLedger outer;
  ErrorSum errors;
  double sum = 0;
  sum += errors.term([] { ErrorLedger::report(1e-15, 1.0); return 1.0; });
  sum += errors.term([] { ErrorLedger::report(1e-12, 1e-12); return 1e-12; });
  errors.report(sum);
  EXPECT_NEAR(outer.relative_quadrature_error(), (1e-15 + 1e-12) / (1 + 1e-12), 1e-27);
}

// Negative control of the composition: summing the terms' relative errors
// (what the ledger does without ErrorSum) gives the useless bound.
TEST(ErrorSum, PlainNestingOfTheSameTermsSumsRelativeErrors) {
  const ErrorLedger outer;
  ErrorLedger::report(1e-15, 1.0);
  ErrorLedger::report(1e-12, 1e-12);
  EXPECT_GT(outer.relative_quadrature_error(), 0.99);
}

// near_contact has three tiny square lights 1e-5 to 1e-3 above the receiver:
// seen from receiver points far from them, their contour integrals cancel to
// a tiny fraction of their edge terms, so their own relative errors are large
// while their contributions are negligible. The bounds of E and of every
// supported second moment must stay small relative to the value.
TEST(ErrorSum, BoundsStaySmallBesideNegligibleTinyLights) {
  const Scene scene = load_scene(std::filesystem::path(FURNACE_SCENE_DIR) / "near_contact.json");
  const Vec3 n{0, 0, 1};
  size_t receiver = 0;
  ASSERT_EQ(scene.objects[receiver].name, "receiver");
  for (const Vec3& p : {Vec3{-0.8125, 0.4375, 0}, Vec3{-1.0, 0.1, 0}, Vec3{0.3, 0.3, 0}}) {
    {
      const ErrorLedger ledger;
      const double e = irradiance(scene, p, n, receiver);
      std::printf("(%g, %g): E %.17g, relative bound %.3g\n", p.x, p.y, e, ledger.bound(e) / e);
      EXPECT_LT(ledger.bound(e) / e, 1e-10);
    }
    for (const Strategy s : {Strategy::kUniformHemisphere, Strategy::kCosineHemisphere}) {
      const ErrorLedger ledger;
      const double m2 = second_moment(s, scene, p, n, receiver);
      std::printf("(%g, %g): %s E[Y^2] %.17g, relative bound %.3g\n", p.x, p.y, strategy_name(s).c_str(), m2,
                  ledger.bound(m2) / m2);
      EXPECT_LT(ledger.bound(m2) / m2, 1e-10);
    }
  }
}

// white_furnace's ball rests on the floor: seen from the floor its cone meets
// the horizon exactly where the cone ends, so the cos² integral has a piece
// one ulp wide, whose tanh–sinh error Boost 1.74 states unscaled (1e-5). The
// bound of the uniform-hemisphere second moment must stay small.
TEST(ErrorLedger, BoundStaysSmallForASphereTouchingTheHorizon) {
  const Scene scene = load_scene(std::filesystem::path(FURNACE_SCENE_DIR) / "white_furnace.json");
  size_t floor = 0;
  while (scene.objects[floor].name != "floor") ++floor;
  for (const Vec3& p : {Vec3{-0.9, 0.9, 0}, Vec3{-0.29, 0, 0}, Vec3{-0.5, 0, 0}}) {
    const ErrorLedger ledger;
    const double m2 = second_moment(Strategy::kUniformHemisphere, scene, p, Vec3{0, 0, 1}, floor);
    std::printf("(%g, %g): uniform_hemisphere E[Y^2] %.17g, relative bound %.3g\n", p.x, p.y, m2, ledger.bound(m2) / m2);
    EXPECT_LT(ledger.bound(m2) / m2, 1e-10);
  }
}

}  // namespace
}  // namespace furnace::analytic
