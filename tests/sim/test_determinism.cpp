// Determinism, pinned (box2d's test/test_determinism.c): the final positions and step count of
// small drapes hash to recorded values, the fast solver's at 1, 2 and 4 threads (every thread
// count gives the same bits: the model's threads sum in the stencils' order, the
// factorisation's BLAS runs on one thread, linear_solver.cpp, and a large grid's factorisation
// is split the same way on any count) and the paper solver's at a fixed seed. Also the seeded perturbation of the fast solver's start.
//
// The hashes change whenever the physics or the discretisation does on purpose (a new mass
// rule, a new fit, a solver setting). Then: run this test under ctest (which sets OpenBLAS's
// kernels, tests/CMakeLists.txt), check that the drape still converges and looks right, and
// replace the expected value by the one printed ("got").
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <cstdio>
#include <string>

#include "sim/sim_fixtures.hpp"
#include "woven/sim/drape.hpp"

namespace woven {
namespace {

/// FNV-1a over the bits of every coordinate, then the step count.
std::uint64_t drape_hash(const sim::Result& r)
{
    std::uint64_t h = 14695981039346656037ull;
    auto mix = [&](std::uint64_t v) {
        for (int b = 0; b < 8; ++b) {
            h ^= (v >> (8 * b)) & 0xFF;
            h *= 1099511628211ull;
        }
    };
    for (const Vec3& p : r.x)
        for (int c = 0; c < 3; ++c) mix(std::bit_cast<std::uint64_t>(p[c]));
    mix(static_cast<std::uint64_t>(r.steps));
    return h;
}

std::string hex(std::uint64_t h)
{
    char buf[32];
    std::snprintf(buf, sizeof buf, "0x%016llx", static_cast<unsigned long long>(h));
    return buf;
}

const char* kHowToUpdate = "if the physics, the discretisation or a solver setting changed on purpose, replace the expected value in "
                           "tests/sim/test_determinism.cpp by the one printed under ctest (OPENBLAS_CORETYPE=Prescott, tests/CMakeLists.txt; see this file's header)";

/// The paper's Sec. 6 obstacles at a small scale: a floor and a 0.5 m cube.
geometry::ObstacleSet floor_and_cube()
{
    geometry::ObstacleSet obstacles;
    obstacles.add(std::make_unique<geometry::Plane>(Vec3::Zero(), Vec3::UnitZ()));
    obstacles.add(std::make_unique<geometry::Box>(Vec3(0, 0, 0.25), Vec3(0.25, 0.25, 0.25)));
    return obstacles;
}

// A 15 x 15 cloth of 1 m over the cube, off centre and turned (with friction: every code path of
// the fast solver), the default perturbation of the start.
constexpr std::uint64_t kFastCube = 0xfc241f0878f60e8cull;
constexpr int kFastCubeSteps = 12;

TEST(Determinism, FastSolverCubeDrapeIsPinnedAtOneTwoAndFourThreads)
{
    const model::Grid grid = test::square_grid(15, 1.0);
    const model::ClothModel m = model::make_cloth_model(test::cotton_like(), grid, {});
    const geometry::ObstacleSet obstacles = floor_and_cube();
    const sim::Problem problem{&m, &obstacles, model::flat_grid(grid, Vec3(0.05, 0.02, 0.51), 0.3), {}};
    for (int threads : {1, 2, 4}) {
        sim::SolverOptions o;
        o.friction = 0.3;
        o.threads = threads;
        const sim::Result r = sim::drape(problem, o);
        ASSERT_TRUE(r.converged) << threads << " threads";
        EXPECT_EQ(r.steps, kFastCubeSteps) << threads << " threads";
        EXPECT_EQ(hex(drape_hash(r)), hex(kFastCube)) << threads << " threads, " << r.steps << " steps, " << r.iterations
                                                        << " Newton iterations; got " << hex(drape_hash(r)) << ": " << kHowToUpdate;
    }
}

// A 41 x 41 cloth, large enough that its Newton matrix is factorised in two sides split at its
// top separator (sim/split_cholesky.hpp), at once from two threads and one after the other on
// one: the same bits at 1, 2 and 4 threads and on a second run. (Before, one thread factorised
// the matrix whole and its drape differed from two threads' by round-off: 1e-9 m.)
TEST(Determinism, SplitFactorisationGivesTheSameBitsAtOneTwoAndFourThreads)
{
    const model::Grid grid = test::square_grid(41, 1.0);
    const model::ClothModel m = model::make_cloth_model(test::cotton_like(), grid, {});
    const geometry::ObstacleSet obstacles = floor_and_cube();
    const sim::Problem problem{&m, &obstacles, model::flat_grid(grid, Vec3(0.05, 0.02, 0.51), 0.3), {}};
    const auto run = [&](int threads) {
        sim::SolverOptions o;
        o.threads = threads;
        o.max_steps = 3;
        return sim::drape(problem, o);
    };
    const sim::Result two = run(2), four = run(4), again = run(2), one = run(1);
    EXPECT_EQ(hex(drape_hash(two)), hex(drape_hash(four)));
    EXPECT_EQ(hex(drape_hash(two)), hex(drape_hash(again)));
    EXPECT_EQ(hex(drape_hash(one)), hex(drape_hash(two)));
    EXPECT_EQ(one.iterations, two.iterations);
    EXPECT_EQ(one.energy.total(), two.energy.total());
}

// The paper solver: a 7 x 7 cloth of 0.3 m falling on a sphere, 60 steps, seed 7.
constexpr std::uint64_t kPaperSphere = 0x573939dccd97a938ull;

TEST(Determinism, PaperSolverIsPinnedAtAFixedSeed)
{
    const model::Grid grid = test::square_grid(7, 0.3);
    const model::ClothModel m = model::make_cloth_model(test::cotton_like(), grid, {});
    geometry::ObstacleSet obstacles;
    obstacles.add(std::make_unique<geometry::Sphere>(Vec3(0, 0, 0.1), 0.1));
    const sim::Problem problem{&m, &obstacles, model::flat_grid(grid, Vec3(0, 0, 0.21)), {}};
    sim::SolverOptions o;
    o.kind = sim::SolverKind::PAPER;
    o.max_steps = 60;
    o.seed = 7;
    const sim::Result a = sim::drape(problem, o);
    EXPECT_EQ(hex(drape_hash(a)), hex(kPaperSphere)) << "got " << hex(drape_hash(a)) << ": " << kHowToUpdate;
}

TEST(Perturbation, SeededUniformWithinTheAmplitudeHeldParticlesFixed)
{
    const Positions x = model::flat_grid(test::square_grid(6, 0.5), Vec3(0, 0, 1));
    std::vector<char> held(x.size(), 0);
    held[3] = 1;
    const double a = 1e-5;
    const Positions y = sim::perturbed(x, held, a, 42);
    EXPECT_EQ(y[3], x[3]);
    double largest = 0, sum = 0;
    int n = 0;
    for (size_t i = 0; i < x.size(); ++i) {
        if (held[i]) continue;
        for (int c = 0; c < 3; ++c) {
            const double d = y[i][c] - x[i][c];
            EXPECT_LE(std::abs(d), a);
            largest = std::max(largest, std::abs(d));
            sum += d;
            ++n;
        }
    }
    EXPECT_GT(largest, 0.8 * a);                    // 105 uniform draws: the largest is above 0.8 a (probability 1 - 0.8^105)
    EXPECT_LT(std::abs(sum / n), 0.2 * a);          // mean near 0 (its standard deviation a / sqrt(3 n) = 0.06 a)
    EXPECT_EQ(sim::perturbed(x, held, a, 42), y);   // the same seed, the same bits
    EXPECT_NE(sim::perturbed(x, held, a, 43), y);   // another seed, another perturbation
    EXPECT_EQ(sim::perturbed(x, held, 0.0, 42), x); // amplitude 0: the start as given
}

TEST(Perturbation, OnlyMovesTheStartAndDependsOnTheSeed)
{
    // A perturbed drape is the unperturbed solver started from the perturbed positions, bit for
    // bit; another seed gives another drape.
    const model::Grid grid = test::square_grid(9, 1.0);
    const model::ClothModel m = model::make_cloth_model(test::cotton_like(), grid, {});
    const geometry::ObstacleSet obstacles = floor_and_cube();
    const Positions start = model::flat_grid(grid, Vec3(0, 0, 0.51));
    sim::SolverOptions o;
    o.perturbation = 1e-4;
    o.seed = 3;
    const sim::Result a = sim::drape(sim::Problem{&m, &obstacles, start, {}}, o);
    sim::SolverOptions plain = o;
    plain.perturbation = 0;
    const sim::Result b = sim::drape(sim::Problem{&m, &obstacles, sim::perturbed(start, {}, 1e-4, 3), {}}, plain);
    ASSERT_TRUE(a.converged);
    EXPECT_EQ(a.steps, b.steps);
    EXPECT_EQ(drape_hash(a), drape_hash(b));
    o.seed = 4;
    EXPECT_GT(sim::max_displacement(sim::drape(sim::Problem{&m, &obstacles, start, {}}, o).x, a.x), 0.0);
}

// Seeds give genuinely different drapes, as the paper's stochastic solver does: on the default
// (convergent) model the fall amplifies the 1e-5 m start perturbation into another fold pattern
// (the 15 x 15 cube: seeds 1 and 2 differ by about 0.1 m at a corner), while each seed's drape
// is reproduced bit for bit.
TEST(Perturbation, DifferentSeedsFoldDifferently)
{
    const model::Grid grid = test::square_grid(15, 1.0);
    const model::ClothModel m = model::make_cloth_model(test::cotton_like(), grid, {});
    const geometry::ObstacleSet obstacles = floor_and_cube();
    const sim::Problem problem{&m, &obstacles, model::flat_grid(grid, Vec3(0, 0, 0.51)), {}};
    sim::SolverOptions o;
    o.seed = 1;
    const sim::Result a = sim::drape(problem, o);
    o.seed = 2;
    const sim::Result b = sim::drape(problem, o);
    ASSERT_TRUE(a.converged);
    ASSERT_TRUE(b.converged);
    EXPECT_GT(sim::max_displacement(a.x, b.x), 0.01);  // m: another fold, not round-off
    EXPECT_EQ(drape_hash(sim::drape(problem, o)), drape_hash(b));
}

}  // namespace
}  // namespace woven
