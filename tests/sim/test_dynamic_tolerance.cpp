// The fast solver's dynamic-step move tolerance (FastSolverOptions::dynamic_step_cloth_fraction):
// a fraction of the spacing on coarse grids, a fraction of the cloth on fine ones.
#include <gtest/gtest.h>

#include "woven/sim/solvers.hpp"

namespace woven::sim {
namespace {

TEST(DynamicMoveTolerance, SpacingFractionUpToTheCubeGridThenClothFraction)
{
    const FastSolverOptions o;  // 0.03 sigma, or 5e-4 of the longer side
    // The paper's 1 m cloth: 0.03 sigma at 21 and 51 particles (0.6 mm at 51), 5e-4 m (half a
    // millimetre, 0.05 and 0.1 sigma) at 101 and 201.
    EXPECT_NEAR(detail::dynamic_move_tolerance(model::Grid{21, 21, 1.0 / 20}, o), 0.03 / 20, 1e-15);
    EXPECT_NEAR(detail::dynamic_move_tolerance(model::Grid{51, 51, 1.0 / 50}, o), 6e-4, 1e-15);
    EXPECT_NEAR(detail::dynamic_move_tolerance(model::Grid{101, 101, 1.0 / 100}, o), 5e-4, 1e-15);
    EXPECT_NEAR(detail::dynamic_move_tolerance(model::Grid{201, 201, 1.0 / 200}, o), 5e-4, 1e-15);
    // The longer side counts: a 2 m x 0.1 m strip at 1 cm spacing.
    EXPECT_NEAR(detail::dynamic_move_tolerance(model::Grid{201, 11, 0.01}, o), 1e-3, 1e-15);
    // The fraction 0 keeps the spacing's tolerance at every grid.
    FastSolverOptions spacing_only;
    spacing_only.dynamic_step_cloth_fraction = 0;
    EXPECT_NEAR(detail::dynamic_move_tolerance(model::Grid{201, 201, 1.0 / 200}, spacing_only), 0.03 / 200, 1e-15);
}

}  // namespace
}  // namespace woven::sim
