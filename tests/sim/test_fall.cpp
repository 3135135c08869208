// The fast solver's fall (FastSolverOptions::fall_duration): the steps stay at the first step's
// size until that much simulated time has passed, then grow; 0 lets them grow from the start.
#include <cmath>
#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include "sim/sim_fixtures.hpp"
#include "woven/sim/solver.hpp"

namespace woven {
namespace {

/// The simulated time after each of the first `steps` steps of an 11 x 11 cloth falling onto a box.
std::vector<double> times(double fall_duration, int steps)
{
    const model::Grid grid = test::square_grid(11, 1.0);
    const model::ClothModel model = model::make_cloth_model(test::cotton_like(), grid, {});
    geometry::ObstacleSet obstacles;
    obstacles.add(std::make_unique<geometry::Plane>(Vec3::Zero(), Vec3::UnitZ()));
    obstacles.add(std::make_unique<geometry::Box>(Vec3(0, 0, 0.25), Vec3(0.25, 0.25, 0.25)));
    const sim::Problem problem{&model, &obstacles, model::flat_grid(grid, Vec3(0.05, 0.02, 0.51), 0.3), {}};
    sim::SolverOptions o;
    o.fast.fall_duration = fall_duration;
    const std::unique_ptr<sim::Solver> solver = sim::make_solver(problem, o);
    std::vector<double> t;
    for (int k = 0; k < steps && solver->step(); ++k) t.push_back(solver->time());
    return t;
}

TEST(Fall, StepsStayAtTheFirstStepsSizeForTheFallThenGrow)
{
    const double h = sim::SolverOptions{}.time_step;  // 1/60 s
    // A fall of 0.09 s: six steps of h (the sixth starts at 5h = 0.083 s), then 2h, 4h, ...
    const std::vector<double> t = times(0.09, 9);
    ASSERT_EQ(t.size(), 9u);
    for (int k = 0; k < 6; ++k) EXPECT_NEAR(t[k], (k + 1) * h, 1e-12) << "step " << k + 1;
    EXPECT_NEAR(t[6] - t[5], 2 * h, 1e-12);
    EXPECT_NEAR(t[7] - t[6], 4 * h, 1e-12);
    // The default (0): the steps grow from the first.
    const std::vector<double> grow = times(0.0, 3);
    ASSERT_EQ(grow.size(), 3u);
    EXPECT_NEAR(grow[0], h, 1e-12);
    EXPECT_NEAR(grow[1] - grow[0], 2 * h, 1e-12);
    EXPECT_NEAR(grow[2] - grow[1], 4 * h, 1e-12);
}

}  // namespace
}  // namespace woven
