// The fast solver's backtracking line search (sim/line_search.hpp).
#include <gtest/gtest.h>

#include <cmath>

#include "woven/sim/line_search.hpp"

namespace woven::sim {
namespace {

// phi(alpha) = c + (alpha - 1)^2 along d, slope -2 at 0: the full step is the minimum.
TEST(LineSearch, AcceptsTheFullNewtonStepOfAQuadratic)
{
    const double c = 3.0;
    const LineSearchResult r = line_search([&](double a) { return c + (a - 1) * (a - 1); }, c + 1, -2.0, 1.0);
    ASSERT_TRUE(r.accepted);
    EXPECT_EQ(r.fraction, 1.0);
    EXPECT_DOUBLE_EQ(r.value, c);
}

// A singular trial (+inf) is rejected and the step halved.
TEST(LineSearch, RejectsInfiniteTrials)
{
    const LineSearchResult r = line_search([](double a) { return a > 0.3 ? INFINITY : 1.0 - a; }, 1.0, -1.0, 1.0);
    ASSERT_TRUE(r.accepted);
    EXPECT_EQ(r.fraction, 0.25);
}

// Near a minimum the promised decrease (1e-17 J) is below the round-off of phi (0.47 J to
// 1e-16 relative). Here phi at the full step comes out one ulp above phi0, which Armijo alone
// rejects at every fraction: the search must accept the full step within the round-off band.
TEST(LineSearch, AcceptsTheFullStepWhenTheDecreaseIsBelowRoundOff)
{
    const double phi0 = 0.4696;
    const double slope = -2e-17;
    const double ulp_above = std::nextafter(phi0, 1.0);
    const LineSearchResult r = line_search([&](double) { return ulp_above; }, phi0, slope, 1.0);
    ASSERT_TRUE(r.accepted);
    EXPECT_EQ(r.fraction, 1.0);

    // Without the band (roundoff 0) the same search shrinks to nothing and fails.
    LineSearchOptions strict;
    strict.roundoff = 0;
    EXPECT_FALSE(line_search([&](double) { return ulp_above; }, phi0, slope, 1.0, strict).accepted);
}

// A resolvable decrease is still held to Armijo: an increase of phi is never accepted there.
TEST(LineSearch, KeepsArmijoWhereTheDecreaseIsResolved)
{
    const double phi0 = 1.0;
    const LineSearchResult r = line_search([&](double a) { return phi0 + 1e-3 * a; }, phi0, -1e-2, 1.0);
    EXPECT_FALSE(r.accepted);
}

}  // namespace
}  // namespace woven::sim
