// The exact cantilever elastica (testers/elastica.hpp) against known values.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "woven/common/error.hpp"
#include "woven/testers/elastica.hpp"

namespace woven::testers {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

TEST(Elastica, SmallDeflectionTipDropIsWL4Over8EI)
{
    // lambda = w L^3 / EI = 1e-4: tip drop w L^4 / (8 EI) to first order in lambda.
    const double L = 0.1, w = 1.0, EI = w * L * L * L / 1e-4;
    const ElasticaSolution s = cantilever_elastica_linear(L, w, EI);
    const double linear = w * std::pow(L, 4) / (8 * EI);
    EXPECT_NEAR(s.tip_drop / linear, 1.0, 1e-3);
    // The root moment is the straight strip's w L^2 / 2 to the same order.
    EXPECT_NEAR(s.root_moment / (0.5 * w * L * L), 1.0, 1e-3);
}

TEST(Elastica, PeirceChordAngleAtTwoBendingLengths)
{
    // ASTM D1388 / Peirce: at L/c = 2 (lambda = 8) the chord angle is 41.5 degrees.
    const ElasticaSolution s = cantilever_elastica_linear(2.0, 1.0, 1.0);
    EXPECT_NEAR(s.chord_angle / kDeg, 41.5, 0.1);
    // and the inverse: the overhang of the 41.5 degree chord is 2 c, within the rule's
    // rounding of the angle.
    EXPECT_NEAR(overhang_ratio_for_chord_angle(kPeirceChordAngle), 2.0, 0.01);
}

TEST(Elastica, ScalesWithTheBendingLength)
{
    // Same L/c, different units: the same shape scaled.
    const ElasticaSolution a = cantilever_elastica_linear(1.5, 1.0, 1.0);
    const double c = 0.02;  // m: EI / w = c^3
    const ElasticaSolution b = cantilever_elastica_linear(1.5 * c, 2.0, 2.0 * c * c * c);
    EXPECT_NEAR(b.tip_drop / c, a.tip_drop, 1e-9);
    EXPECT_NEAR(b.chord_angle, a.chord_angle, 1e-9);
}

TEST(Elastica, InextensibleAndConverged)
{
    // The tip lies within L of the clamp, the end moment is zero (shooting converged), and the
    // 4th-order integration agrees with a 4x finer one.
    const ElasticaSolution s = cantilever_elastica_linear(3.0, 1.0, 1.0, 500);
    const ElasticaSolution f = cantilever_elastica_linear(3.0, 1.0, 1.0, 2000);
    EXPECT_LT(std::hypot(s.tip_x, s.tip_drop), 3.0);
    EXPECT_NEAR(s.tip_drop, f.tip_drop, 1e-9);
    EXPECT_GT(s.chord_angle, 41.5 * kDeg);
    ASSERT_EQ(f.theta.size(), 2001u);
    // theta' (L) = 0: the last two slopes agree to O(h^2).
    EXPECT_NEAR(f.theta[2000], f.theta[1999], 1e-6);
}

TEST(Elastica, NonlinearLawStifferThanItsInitialSlopeDroopsLess)
{
    // K(M) = M / (1 + M): stiffening; less drop than the linear law of slope 1.
    const ElasticaSolution lin = cantilever_elastica_linear(2.0, 1.0, 1.0);
    const ElasticaSolution stiff = cantilever_elastica(2.0, 1.0, [](double M) { return M / (1.0 + std::abs(M)); });
    EXPECT_LT(stiff.tip_drop, lin.tip_drop);
    EXPECT_GT(stiff.tip_drop, 0.0);
}

TEST(Elastica, RejectsBadInput)
{
    EXPECT_THROW(cantilever_elastica_linear(0.0, 1.0, 1.0), InputError);
    EXPECT_THROW(cantilever_elastica_linear(1.0, -1.0, 1.0), InputError);
    EXPECT_THROW(cantilever_elastica_linear(1.0, 1.0, 0.0), InputError);
    EXPECT_THROW(elastica_overhang_for_chord_angle(2.0, 1.0, [](double M) { return M; }), InputError);
}

}  // namespace
}  // namespace woven::testers
