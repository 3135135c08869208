// Drape solvers: rest states, symmetry, contact, reproducibility, agreement of the two solvers.
#include <gtest/gtest.h>

#include <cmath>

#include "sim/sim_fixtures.hpp"
#include "woven/common/error.hpp"
#include "woven/sim/contact.hpp"

namespace woven {
namespace {

using geometry::ObstacleSet;

sim::Result run(const model::ClothModel& m, const ObstacleSet& obstacles, const Positions& start, const std::vector<int>& pinned, const sim::SolverOptions& o)
{
    sim::Problem problem{&m, &obstacles, start, pinned};
    return sim::drape(problem, o);
}

/// The paper's Sec. 6 obstacles: a floor and a 0.5 m cube standing on it.
ObstacleSet floor_and_cube()
{
    ObstacleSet obstacles;
    obstacles.add(std::make_unique<geometry::Plane>(Vec3::Zero(), Vec3::UnitZ()));
    obstacles.add(std::make_unique<geometry::Box>(Vec3(0, 0, 0.25), Vec3(0.25, 0.25, 0.25)));
    return obstacles;
}

/// Largest distance between a particle and the image of its partner under a 90-degree rotation
/// about z (which maps particle (i, j) of a square grid to (n-1-j, i)), m.
double four_fold_asymmetry(const model::Grid& grid, const Positions& x)
{
    const int n = grid.nu;
    double worst = 0;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const Vec3& a = x[grid.index(i, j)];
            const Vec3& b = x[grid.index(n - 1 - j, i)];
            worst = std::max(worst, (Vec3(-a.y(), a.x(), a.z()) - b).norm());
        }
    return worst;
}

TEST(FastSolver, FreeSheetWithoutGravityStaysFlatAndAtRest)
{
    const model::Grid grid = test::square_grid(9, 0.4);
    model::ModelOptions mo;
    mo.gravity = 0.0;
    mo.C0 = 1000.0;  // the automatic C0 scales with gravity
    const model::ClothModel m = model::make_cloth_model(test::cotton_like(), grid, mo);
    const ObstacleSet none;
    const Positions start = model::flat_grid(grid, Vec3(0, 0, 1));
    sim::SolverOptions o;
    o.perturbation = 0;  // the flat start as given: exactly at rest
    const sim::Result r = run(m, none, start, {}, o);
    EXPECT_TRUE(r.converged);
    EXPECT_LT(sim::max_displacement(r.x, start), 1e-12);
    EXPECT_NEAR(r.energy.total(), 0.0, 1e-15);
}

TEST(FastSolver, SheetPinnedAtTwoCornersHangsSymmetrically)
{
    const model::Grid grid = test::square_grid(9, 0.4);
    const model::ClothModel m = model::make_cloth_model(test::cotton_like(), grid, {});
    const ObstacleSet none;
    const Positions start = model::flat_grid(grid, Vec3(0, 0, 1));
    const std::vector<int> pinned{grid.index(0, 8), grid.index(8, 8)};
    sim::SolverOptions o;
    o.perturbation = 0;  // a symmetric start (the default's 1e-5 m leaves up to 1e-5 m at rest)
    const sim::Result r = run(m, none, start, pinned, o);
    ASSERT_TRUE(r.converged);
    EXPECT_LT(r.equilibrium.max_residual_rel, 1e-3);
    // Mirror i -> 8 - i: x flips sign, y and z agree (tolerance 1e-6 m, far below sigma = 5 cm).
    for (int j = 0; j < 9; ++j)
        for (int i = 0; i < 9; ++i) {
            const Vec3& a = r.x[grid.index(i, j)];
            const Vec3& b = r.x[grid.index(8 - i, j)];
            EXPECT_NEAR(a.x(), -b.x(), 1e-6);
            EXPECT_NEAR(a.y(), b.y(), 1e-6);
            EXPECT_NEAR(a.z(), b.z(), 1e-6);
        }
    // It hangs: the free far edge is well below the pinned edge.
    EXPECT_LT(r.x[grid.index(4, 0)].z(), 1.0 - 0.2);
    EXPECT_LT(r.energy.total(), m.energy(start));
}

TEST(FastSolver, DrapeOverCentredSphereHasFourFoldSymmetryAndNoPenetration)
{
    const int n = 9;
    const model::Grid grid = test::square_grid(n, 0.3);
    // The paper's discretisation. With the convergent default this drape ends 3.3 cm from
    // four-fold symmetric, with projected Newton or Newton-CG alike: its energy is exactly
    // symmetric (tests/model/test_symmetry.cpp, to 1e-12), so the symmetric state of the
    // stiff-threaded cloth on a sphere is unstable and round-off decides which way it folds.
    const model::ClothModel m = model::make_cloth_model(test::balanced(), grid, test::paper_model());
    ObstacleSet obstacles;
    obstacles.add(std::make_unique<geometry::Plane>(Vec3::Zero(), Vec3::UnitZ()));
    obstacles.add(std::make_unique<geometry::Sphere>(Vec3(0, 0, 0.15), 0.15));
    const Positions start = model::flat_grid(grid, Vec3(0, 0, 0.31));
    sim::SolverOptions o;
    o.perturbation = 0;  // a symmetric start: the symmetric drape
    // Newton-CG on the exact Hessian follows negative curvature off the symmetric saddle (an
    // asymmetric rest state of lower energy exists without friction): this test is about the
    // symmetric state, so the static steps use the projected Newton matrix.
    o.fast.static_newton_cg = false;
    // The model has no friction (nor has the paper's): a cloth balanced on a sphere is an
    // unstable equilibrium, so the centre particle is held over the pole.
    const sim::Result r = run(m, obstacles, start, {grid.index(n / 2, n / 2)}, o);
    ASSERT_TRUE(r.converged);
    EXPECT_LT(r.equilibrium.max_residual_rel, o.residual_tolerance);
    EXPECT_LT(r.energy.total(), m.energy(start));
    // No particle inside an obstacle by more than 0.1 mm.
    EXPECT_GT(sim::min_obstacle_distance(obstacles, r.x), -1e-4);
    EXPECT_LT(four_fold_asymmetry(grid, r.x), 1e-4) << "m";
}

TEST(PaperSolver, DrapeOverCentredSphereIsFourFoldSymmetricUpToItsNoise)
{
    // The fast solver's sphere test with a 0.2 m cloth on a 7 x 7 grid. The paper solver's
    // seeded perturbation breaks the symmetry while the cloth falls, and a fold may form on one
    // side: its rest state is another local minimum near the symmetric one (on the 0.3 m cloth of
    // the fast test it even finds an asymmetric state of lower energy than the symmetric one).
    const int n = 7;
    const model::Grid grid = test::square_grid(n, 0.2);
    const model::ClothModel m = model::make_cloth_model(test::balanced(), grid, {});
    ObstacleSet obstacles;
    obstacles.add(std::make_unique<geometry::Plane>(Vec3::Zero(), Vec3::UnitZ()));
    obstacles.add(std::make_unique<geometry::Sphere>(Vec3(0, 0, 0.15), 0.15));
    const Positions start = model::flat_grid(grid, Vec3(0, 0, 0.31));
    const std::vector<int> pole{grid.index(n / 2, n / 2)};
    sim::SolverOptions o;
    o.kind = sim::SolverKind::PAPER;
    o.viscosity = 10.0;  // settles sooner; the equilibrium does not depend on it
    const sim::Result paper = run(m, obstacles, start, pole, o);
    const sim::Result fast = run(m, obstacles, start, pole, {});
    ASSERT_TRUE(paper.converged);
    EXPECT_GT(sim::min_obstacle_distance(obstacles, paper.x), -1e-4);
    // The pole pin leaves the cloth free to turn about z (no friction), and the noise may turn
    // it: compare heights and distances from the axis, which a turn keeps. Tolerance: 3 cm,
    // 15 % of the cloth's side (the noise's fold measured 1.9 cm with seed 1).
    double worst = 0;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const Vec3& a = paper.x[grid.index(i, j)];
            const Vec3& b = paper.x[grid.index(n - 1 - j, i)];
            worst = std::max({worst, std::abs(a.z() - b.z()), std::abs(a.head<2>().norm() - b.head<2>().norm())});
        }
    EXPECT_LT(worst, 0.03) << "m";
    // And its energy is that of the symmetric rest state within 5 % of the energy released
    // (the fold costs 3.7 % with seed 1).
    const double released = m.energy(start) - fast.energy.total();
    EXPECT_NEAR(paper.energy.total(), fast.energy.total(), 0.05 * released);
}

TEST(FastSolver, CubeDrapeRestsOnTheCubeWithoutPenetration)
{
    const model::Grid grid = test::square_grid(11, 1.0);
    const model::ClothModel m = model::make_cloth_model(test::cotton_like(), grid, {});
    const ObstacleSet obstacles = floor_and_cube();
    const Positions start = model::flat_grid(grid, Vec3(0, 0, 0.51));
    const sim::Result r = run(m, obstacles, start, {}, {});
    ASSERT_TRUE(r.converged);
    EXPECT_GT(sim::min_obstacle_distance(obstacles, r.x), -1e-4);
    EXPECT_LT(r.energy.total(), m.energy(start));
    // The centre rests on the top face (within the contact distance), the corners hang.
    EXPECT_NEAR(r.x[grid.index(5, 5)].z(), 0.5, 1.5e-3);
    EXPECT_LT(r.x[grid.index(0, 0)].z(), 0.45);
}

TEST(PaperSolver, PinnedSheetReachesTheFastSolversEquilibrium)
{
    const model::Grid grid = test::square_grid(5, 0.2);
    const model::ClothModel m = model::make_cloth_model(test::cotton_like(), grid, test::paper_model());
    const ObstacleSet none;
    const Positions start = model::flat_grid(grid, Vec3(0, 0, 1));
    const std::vector<int> pinned{grid.index(0, 4), grid.index(4, 4)};
    const sim::Result fast = run(m, none, start, pinned, {});
    sim::SolverOptions o;
    o.kind = sim::SolverKind::PAPER;
    o.max_steps = 20000;
    const sim::Result paper = run(m, none, start, pinned, o);
    ASSERT_TRUE(fast.converged);
    ASSERT_TRUE(paper.converged);
    // Tolerance: 2 % of the energy released by the drape (the paper solver's equilibrium test is
    // a movement threshold, not a force balance).
    const double released = m.energy(start) - fast.energy.total();
    EXPECT_NEAR(paper.energy.total(), fast.energy.total(), 0.02 * released);
}

TEST(PaperSolver, CubeDrapeReachesTheFastSolversEnergyWithoutPenetration)
{
    // Threads wrapping the cube's edges: particles in contact must slide along the faces.
    const model::Grid grid = test::square_grid(7, 0.3);
    const model::ClothModel m = model::make_cloth_model(test::cotton_like(), grid, test::paper_model());
    ObstacleSet obstacles;
    obstacles.add(std::make_unique<geometry::Plane>(Vec3::Zero(), Vec3::UnitZ()));
    obstacles.add(std::make_unique<geometry::Box>(Vec3(0, 0, 0.075), Vec3(0.075, 0.075, 0.075)));
    const Positions start = model::flat_grid(grid, Vec3(0, 0, 0.16));
    const sim::Result fast = run(m, obstacles, start, {}, {});
    sim::SolverOptions o;
    o.kind = sim::SolverKind::PAPER;
    o.viscosity = 10.0;  // settles sooner; the equilibrium does not depend on it
    const sim::Result paper = run(m, obstacles, start, {}, o);
    ASSERT_TRUE(fast.converged);
    ASSERT_TRUE(paper.converged);
    EXPECT_GT(sim::min_obstacle_distance(obstacles, paper.x), 0.0);
    const double released = m.energy(start) - fast.energy.total();
    EXPECT_NEAR(paper.energy.total(), fast.energy.total(), 0.02 * released);
}

TEST(FastSolver, CreepContinuationEndsAtRestOnTheClothsOwnThreads)
{
    // The 21 x 21 cube (the convergent model's stiff threads) with the creep's continuation
    // forced from the first static step (no capped step needed), threads 100 then 10 times softer.
    const model::Grid grid = test::square_grid(21, 1.0);
    const model::ClothModel m = model::make_cloth_model(test::cotton_like(), grid, {});
    const ObstacleSet obstacles = floor_and_cube();
    const Positions start = model::flat_grid(grid, Vec3(0, 0, 0.51));
    sim::SolverOptions direct;
    sim::SolverOptions softened = direct;
    softened.fast.creep_capped_steps = 0;
    softened.fast.creep_stage_ratio = 10;
    const sim::Result a = run(m, obstacles, start, {}, direct);
    const sim::Result b = run(m, obstacles, start, {}, softened);
    ASSERT_TRUE(a.converged);
    ASSERT_TRUE(b.converged);
    // The default does not creep at this size: no softened step.
    EXPECT_EQ(a.softened_steps, 0);
    // Two stages (E_t / 100, E_t / 10), each at least one step.
    EXPECT_GE(b.softened_steps, 2);
    // At rest on the cloth's own energy (the residual of the unsoftened model, as the run's end
    // test), outside the obstacles, and its thread strains those of the stiff threads: the
    // largest stretch of a warp or weft segment at most twice the direct drape's (softened
    // 100 times it would be about 100 times it).
    EXPECT_LT(sim::max_residual_relative(m, obstacles, b.x, {}, softened.contact_distance), softened.residual_tolerance);
    EXPECT_GT(sim::min_obstacle_distance(obstacles, b.x), 0.0);
    double strain_a = 0, strain_b = 0;
    for (const model::Stencil<2>& e : m.stencils().edges) {
        strain_a = std::max(strain_a, (a.x[e[0]] - a.x[e[1]]).norm() / grid.sigma - 1);
        strain_b = std::max(strain_b, (b.x[e[0]] - b.x[e[1]]).norm() / grid.sigma - 1);
    }
    EXPECT_LT(strain_b, 2 * strain_a + 1e-5);
    // Not a higher drape (to 2e-4 relative), and the same kind of drape (within 0.2 %): the
    // softened path may settle another fold, and here it settles a lower one (0.461576 J
    // against 0.461748 J).
    EXPECT_LT(b.energy.total(), a.energy.total() * (1 + 2e-4));
    EXPECT_GT(b.energy.total(), a.energy.total() * (1 - 2e-3));
    // Softening 1 is off: with the trigger forced as above, the default's bits.
    sim::SolverOptions off = softened;
    off.fast.creep_softening = 1;
    const sim::Result c = run(m, obstacles, start, {}, off);
    EXPECT_EQ(c.energy.total(), a.energy.total());
    EXPECT_EQ(c.iterations, a.iterations);
}

TEST(Drape, RejectsInconsistentProblems)
{
    const model::Grid grid = test::square_grid(5, 0.2);
    const model::ClothModel m = model::make_cloth_model(test::cotton_like(), grid, {});
    const ObstacleSet none;
    Positions start = model::flat_grid(grid, Vec3(0, 0, 1));
    start[3].x() = std::nan("");
    EXPECT_THROW(run(m, none, start, {}, {}), InputError);
    start = model::flat_grid(grid, Vec3(0, 0, 1));
    EXPECT_THROW(run(m, none, start, {99}, {}), InputError);
    start.pop_back();
    EXPECT_THROW(run(m, none, start, {}, {}), InputError);
    // A creep continuation that would never end its softened stages, or soften by nothing.
    start = model::flat_grid(grid, Vec3(0, 0, 1));
    sim::SolverOptions never_stiff;
    never_stiff.fast.creep_stage_ratio = 1.0;
    EXPECT_THROW(run(m, none, start, {}, never_stiff), InputError);
    sim::SolverOptions no_softening;
    no_softening.fast.creep_softening = std::nan("");
    EXPECT_THROW(run(m, none, start, {}, no_softening), InputError);
}

TEST(Contact, BarrierIsSmoothAtTheActivationDistanceAndInfiniteAtContact)
{
    const sim::Barrier b{1e-3, 2.0};
    EXPECT_EQ(b.value(1e-3), 0.0);
    EXPECT_NEAR(b.d1(1e-3 * (1 - 1e-9)), 0.0, 1e-9);
    EXPECT_TRUE(std::isinf(b.value(0.0)));
    const double d = 4e-4, h = 1e-9;
    EXPECT_NEAR(b.d1(d), (b.value(d + h) - b.value(d - h)) / (2 * h), 1e-6 * std::abs(b.d1(d)));
    EXPECT_NEAR(b.d2(d), (b.d1(d + h) - b.d1(d - h)) / (2 * h), 1e-5 * std::abs(b.d2(d)));
    EXPECT_LT(b.d1(d), 0.0);
}

}  // namespace
}  // namespace woven
