// The stateful solver (sim::Solver): a user's step loop gives sim::drape's bits, the state is
// readable between steps, obstacles are replaceable (and refused where a particle would start
// inside one), and the paper solver has the same shape.
#include <cmath>
#include <memory>

#include <gtest/gtest.h>

#include "sim/sim_fixtures.hpp"
#include "woven/common/error.hpp"
#include "woven/sim/contact.hpp"
#include "woven/sim/solver.hpp"

namespace woven {
namespace {

geometry::ObstacleSet floor_and_box(double half_side)
{
    geometry::ObstacleSet o;
    o.add(std::make_unique<geometry::Plane>(Vec3::Zero(), Vec3::UnitZ()));
    o.add(std::make_unique<geometry::Box>(Vec3(0, 0, half_side), Vec3(half_side, half_side, half_side)));
    return o;
}

struct Scene {
    model::Grid grid = test::square_grid(11, 1.0);
    model::ClothModel model = model::make_cloth_model(test::cotton_like(), grid, {});
    geometry::ObstacleSet obstacles = floor_and_box(0.25);
    sim::Problem problem{&model, &obstacles, model::flat_grid(grid, Vec3(0.05, 0.02, 0.51), 0.3), {}};
};

TEST(Solver, AStepLoopGivesTheDrapesBitsAndState)
{
    const Scene s;
    sim::SolverOptions o;
    o.friction = 0.3;  // every path of the fast solver
    const sim::Result expected = sim::drape(s.problem, o);
    ASSERT_TRUE(expected.converged);

    const std::unique_ptr<sim::Solver> solver = sim::make_solver(s.problem, o);
    EXPECT_EQ(solver->steps(), 0);
    EXPECT_EQ(solver->time(), 0.0);
    EXPECT_FALSE(solver->converged());
    double last_energy = solver->energy();
    int energy_drops = 0;
    while (!solver->converged() && solver->steps() < 400) {
        ASSERT_TRUE(solver->step());
        energy_drops += solver->energy() < last_energy;
        last_energy = solver->energy();
    }
    const sim::Result r = solver->result();
    EXPECT_EQ(r.steps, expected.steps);
    EXPECT_EQ(r.iterations, expected.iterations);
    EXPECT_EQ(r.factorizations, expected.factorizations);
    EXPECT_EQ(sim::max_displacement(r.x, expected.x), 0.0);  // bit for bit
    EXPECT_EQ(solver->energy(), s.model.energy(expected.x));
    EXPECT_EQ(r.energy.total(), expected.energy.total());
    EXPECT_EQ(solver->time(), expected.simulated_time);
    EXPECT_LT(solver->residual(), o.residual_tolerance);
    EXPECT_EQ(solver->residual(), expected.equilibrium.max_residual_rel);
    // The cloth falls: the energy drops on most steps (gravity's part dominates).
    EXPECT_GE(energy_drops, expected.steps / 2);
}

TEST(Solver, ObstaclesAreReplaceableBetweenSteps)
{
    const Scene s;
    const std::unique_ptr<sim::Solver> solver = sim::make_solver(s.problem, sim::SolverOptions{});
    while (!solver->converged() && solver->steps() < 400) ASSERT_TRUE(solver->step());
    ASSERT_TRUE(solver->converged());
    const double on_the_box = solver->energy();
    const double top = [&] {
        double z = -1;
        for (const Vec3& p : solver->positions()) z = std::max(z, p.z());
        return z;
    }();
    // A lower box (0.4 m): the cloth falls 0.1 m further and rests on it, lower in energy.
    solver->set_obstacles(floor_and_box(0.2));
    EXPECT_FALSE(solver->converged());
    const int before = solver->steps();
    while (!solver->converged() && solver->steps() < before + 400) ASSERT_TRUE(solver->step());
    ASSERT_TRUE(solver->converged());
    double new_top = -1;
    for (const Vec3& p : solver->positions()) new_top = std::max(new_top, p.z());
    EXPECT_NEAR(top - new_top, 0.1, 0.01) << "m";
    EXPECT_LT(solver->energy(), on_the_box);
    EXPECT_GT(sim::min_obstacle_distance(solver->obstacles(), solver->positions()), 0.0);

    // A box that would swallow the resting cloth is refused, naming the field; the set in
    // force stays.
    try {
        solver->set_obstacles(floor_and_box(0.3));
        FAIL() << "a particle inside an obstacle was accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("obstacles"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("inside an obstacle"), std::string::npos) << e.what();
    }
    EXPECT_TRUE(solver->converged());
    EXPECT_GT(sim::min_obstacle_distance(solver->obstacles(), solver->positions()), 0.0);
}

TEST(Solver, TheIterationCallbackStopsAStep)
{
    const Scene s;
    const std::unique_ptr<sim::Solver> solver = sim::make_solver(s.problem, sim::SolverOptions{});
    ASSERT_TRUE(solver->step());
    int calls = 0;
    EXPECT_FALSE(solver->step([&](const sim::IterationInfo& info) {
        EXPECT_EQ(info.step, 2);
        return ++calls < 2;
    }));
    EXPECT_EQ(calls, 2);
    EXPECT_EQ(solver->steps(), 1);  // the stopped step is not counted
    EXPECT_TRUE(solver->result().interrupted);
    EXPECT_TRUE(solver->step());  // and the run goes on
    EXPECT_EQ(solver->steps(), 2);
}

TEST(Solver, ThePaperSolverHasTheSameShape)
{
    const model::Grid grid = test::square_grid(7, 0.5);
    const model::ClothModel m = model::make_cloth_model(test::cotton_like(), grid, test::paper_model());
    const geometry::ObstacleSet obstacles = floor_and_box(0.1);
    const sim::Problem problem{&m, &obstacles, model::flat_grid(grid, Vec3(0, 0, 0.25), 0.0), {}};
    sim::SolverOptions o;
    o.kind = sim::SolverKind::PAPER;
    o.max_steps = 300;
    const sim::Result expected = sim::drape(problem, o);
    const std::unique_ptr<sim::Solver> solver = sim::make_solver(problem, o);
    while (!solver->converged() && solver->steps() < 300) ASSERT_TRUE(solver->step());
    const sim::Result r = solver->result();
    EXPECT_EQ(r.steps, expected.steps);
    EXPECT_EQ(r.converged, expected.converged);
    EXPECT_EQ(sim::max_displacement(r.x, expected.x), 0.0);
    EXPECT_EQ(r.equilibrium.max_residual_rel, expected.equilibrium.max_residual_rel);
    EXPECT_TRUE(std::isfinite(solver->energy()));
}

}  // namespace
}  // namespace woven
