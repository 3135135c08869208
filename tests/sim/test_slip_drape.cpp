// Friction inside the weave in a drape (issue 33, model/slip.hpp): the fast solver updates the
// slip states after each step (sim::Problem::slip); the drape converges, differs from the
// loading branch's, leaves the states consistent with the state reached, and a fabric without
// a hysteresis width drapes exactly as the loading branch does.
#include <gtest/gtest.h>

#include <cmath>

#include "sim/sim_fixtures.hpp"
#include "woven/common/error.hpp"
#include "woven/sim/contact.hpp"

namespace woven {
namespace {

using geometry::ObstacleSet;

/// An 11 x 11, 0.6 m cloth over a 0.3 m cube on a floor: corners hang and fold.
struct CubeScene {
    model::Grid grid = test::square_grid(11, 0.6);
    ObstacleSet obstacles;
    Positions start;
    CubeScene()
    {
        obstacles.add(std::make_unique<geometry::Plane>(Vec3::Zero(), Vec3::UnitZ()));
        obstacles.add(std::make_unique<geometry::Box>(Vec3(0, 0, 0.15), Vec3(0.15, 0.15, 0.15)));
        start = model::flat_grid(grid, Vec3(0, 0, 0.31));
    }
};

model::ModelOptions with(model::Hysteresis h)
{
    model::ModelOptions o;
    o.hysteresis = h;
    return o;
}

sim::Result drape(model::ClothModel& m, const CubeScene& s, bool evolve = true)
{
    sim::Problem p{&m, &s.obstacles, s.start, {}};
    if (evolve) p.model = sim::ClothRef::evolving(m);
    return sim::drape(p, sim::SolverOptions{});
}

TEST(SlipDrape, FrictionConvergesAndDiffersFromTheLoadingBranch)
{
    const CubeScene s;
    // The fixture gives every curve by summary values with a width (2HB 0.04 / 0.08 gf.cm/cm,
    // 2HG 2, 2HG5 3 gf/cm): all three families carry friction elements.
    model::ClothModel loading = model::make_cloth_model(test::cotton_like(), s.grid, with(model::Hysteresis::LOADING_BRANCH));
    model::ClothModel friction = model::make_cloth_model(test::cotton_like(), s.grid, with(model::Hysteresis::FRICTION));
    ASSERT_FALSE(loading.has_slip());
    ASSERT_TRUE(friction.slip_laws().warp.active() && friction.slip_laws().weft.active() && friction.slip_laws().shear.active());
    const sim::Result a = drape(loading, s);
    const sim::Result b = drape(friction, s);
    ASSERT_TRUE(a.converged);
    ASSERT_TRUE(b.converged);
    EXPECT_LT(b.equilibrium.max_residual_rel, 1e-3);
    EXPECT_GT(sim::min_obstacle_distance(s.obstacles, b.x), -1e-4);
    // A different rest state: the corners hang at least 0.1 mm apart (the drapes differ by
    // millimetres; 0.1 mm is far above round-off, 1e-12 m).
    EXPECT_GT(sim::max_displacement(a.x, b.x), 1e-4) << "m";
    // The states moved off the virgin 0 somewhere.
    double largest = 0;
    for (const model::SlipState& st : friction.weft_slip())
        for (double v : st) largest = std::max(largest, std::abs(v));
    EXPECT_GT(largest, 0.0);
}

TEST(SlipDrape, StatesAreTheReturnMappingOfTheStateReached)
{
    const CubeScene s;
    model::ClothModel m = model::make_cloth_model(test::cotton_like(), s.grid, with(model::Hysteresis::FRICTION));
    const sim::Result r = drape(m, s);
    ASSERT_TRUE(r.converged);
    // The solver ended with update_slip at r.x: doing it again changes nothing (the return
    // mapping is idempotent), so the forces the residual was measured with are the model's.
    const std::vector<model::SlipState> warp = m.warp_slip(), weft = m.weft_slip(), shear = m.shear_slip();
    const Eigen::VectorXd g = m.gradient(r.x);
    m.update_slip(r.x);
    EXPECT_EQ(warp, m.warp_slip());
    EXPECT_EQ(weft, m.weft_slip());
    EXPECT_EQ(shear, m.shear_slip());
    EXPECT_EQ((m.gradient(r.x) - g).cwiseAbs().maxCoeff(), 0.0);
    // Without Problem::slip the states stay virgin: another drape.
    model::ClothModel frozen = model::make_cloth_model(test::cotton_like(), s.grid, with(model::Hysteresis::FRICTION));
    const sim::Result f = drape(frozen, s, false);
    for (const model::SlipState& st : frozen.weft_slip())
        for (double v : st) EXPECT_EQ(v, 0.0);
    EXPECT_GT(sim::max_displacement(f.x, r.x), 0.0);
}

TEST(SlipDrape, NoHysteresisWidthDrapesAsTheLoadingBranchBitForBit)
{
    const CubeScene s;
    kes::FabricData fabric = test::cotton_like();
    fabric.bending_warp.summary->two_HB = fabric.bending_weft.summary->two_HB = 0;
    fabric.shear.summary->two_HG = fabric.shear.summary->two_HG5 = 0;
    fabric.bending_warp.curve = kes::synthesize_bending_curve(*fabric.bending_warp.summary);
    fabric.bending_weft.curve = kes::synthesize_bending_curve(*fabric.bending_weft.summary);
    fabric.shear.curve = kes::synthesize_shear_curve(*fabric.shear.summary);
    model::ClothModel loading = model::make_cloth_model(fabric, s.grid, with(model::Hysteresis::LOADING_BRANCH));
    model::ClothModel friction = model::make_cloth_model(fabric, s.grid, with(model::Hysteresis::FRICTION));
    EXPECT_FALSE(friction.has_slip());
    const sim::Result a = drape(loading, s);
    const sim::Result b = drape(friction, s);
    ASSERT_TRUE(a.converged);
    EXPECT_EQ(a.steps, b.steps);
    EXPECT_EQ(sim::max_displacement(a.x, b.x), 0.0);
}

TEST(SlipDrape, OnlyAnEvolvingClothChangesItsSlipStates)
{
    const CubeScene s;
    model::ClothModel m = model::make_cloth_model(test::cotton_like(), s.grid, with(model::Hysteresis::FRICTION));
    const std::vector<model::SlipState> before = m.shear_slip();
    drape(m, s, false);
    EXPECT_TRUE(m.shear_slip() == before);
    drape(m, s, true);
    EXPECT_FALSE(m.shear_slip() == before);
}

}  // namespace
}  // namespace woven
