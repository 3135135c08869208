// The convergent discretisation (model/stencils.hpp, Discretization): the cloth weighs W times
// its area on any grid and outline, the term weights add up to the cloth's extent, and the
// paper's convention is kept as an option.
#include <cmath>
#include <numeric>

#include <gtest/gtest.h>

#include "woven/common/units.hpp"
#include "woven/model/cloth_model.hpp"

namespace woven::model {
namespace {

kes::FabricData plain_fabric(double W)
{
    kes::FabricData f;
    f.name = "plain";
    f.areal_density_mg_cm2 = W;
    for (int k = 0; k <= 25; ++k) {
        f.bending_warp.curve.x.push_back(0.1 * k);
        f.bending_warp.curve.y.push_back(0.1 * 0.1 * k);
    }
    f.bending_weft.curve = f.bending_warp.curve;
    for (int k = 0; k <= 16; ++k) {
        f.shear.curve.x.push_back(0.5 * k);
        f.shear.curve.y.push_back(0.5 * k);
    }
    return f;
}

double total_mass(const ClothModel& m) { return std::accumulate(m.masses().begin(), m.masses().end(), 0.0); }

TEST(Discretization, ClothMassIsWTimesItsArea)
{
    const kes::FabricData f = plain_fabric(12.0);
    const double W = 12.0 * units::kMgPerCm2ToKgPerM2;
    for (const auto& [nu, nv, sigma] :
         {std::tuple{51, 51, 0.02}, std::tuple{2, 2, 0.01}, std::tuple{7, 3, 0.005}, std::tuple{26, 11, 0.04}}) {
        const Grid g{nu, nv, sigma};
        const ClothModel m = make_cloth_model(f, g, ModelOptions{});
        const double area = (nu - 1) * sigma * (nv - 1) * sigma;
        EXPECT_NEAR(total_mass(m), W * area, 1e-12 * W * area) << nu << " x " << nv;
        // The paper's convention: a full patch per particle, nu nv sigma^2 (1 m at 51 x 51: 4 % heavy).
        ModelOptions paper;
        paper.discretization = Discretization::PAPER;
        const ClothModel p = make_cloth_model(f, g, paper);
        EXPECT_NEAR(total_mass(p), W * nu * nv * sigma * sigma, 1e-12 * W * area);
    }
    // 1 m at 51 x 51 (the paper's cube cloth): 1.0000 m^2 of cloth, not 1.0404.
    const ClothModel cube = make_cloth_model(f, Grid{51, 51, 0.02}, ModelOptions{});
    EXPECT_NEAR(total_mass(cube) / W, 1.0, 1e-12);
    EXPECT_NEAR(cube.mass(0), cube.particle_mass() / 4, 1e-15);  // corner
    EXPECT_NEAR(cube.mass(1), cube.particle_mass() / 2, 1e-15);  // edge
    EXPECT_NEAR(cube.mass(52), cube.particle_mass(), 1e-15);     // interior
}

TEST(Discretization, MaskedClothMassIsWTimesTheCellsItCovers)
{
    // A 6 x 6 grid with a hole at (2, 2) and a missing corner (5, 5): the cloth is the grid
    // cells whose four corners are present.
    const Grid g{6, 6, 0.01};
    std::vector<char> active(g.size(), 1);
    active[g.index(2, 2)] = 0;
    active[g.index(5, 5)] = 0;
    int cells = 0;
    for (int j = 0; j + 1 < 6; ++j)
        for (int i = 0; i + 1 < 6; ++i)
            cells += active[g.index(i, j)] && active[g.index(i + 1, j)] && active[g.index(i, j + 1)] && active[g.index(i + 1, j + 1)];
    EXPECT_EQ(cells, 25 - 4 - 1);
    const kes::FabricData f = plain_fabric(10.0);
    const ClothModel m = make_cloth_model(f, g, ModelOptions{}, active);
    const double W = 10.0 * units::kMgPerCm2ToKgPerM2;
    EXPECT_NEAR(total_mass(m), W * cells * 1e-4, 1e-15);
    EXPECT_EQ(m.mass(g.index(2, 2)), 0.0);
}

TEST(Discretization, WeightsAddUpToTheCloth)
{
    // Bends: one thread line per column at its share of width (1/2 at the sides); crossings:
    // every particle at its dual-cell share, summing to the cloth's area in sigma^2; segments:
    // the width beside them.
    const Grid g{5, 4, 0.01};
    const ClothModel m = make_cloth_model(plain_fabric(10.0), g, ModelOptions{});
    const Stencils& s = m.stencils();
    auto sum = [](const std::vector<double>& v) { return std::accumulate(v.begin(), v.end(), 0.0); };
    EXPECT_EQ(s.crossings.size(), 20u);  // one per particle, one-sided at the edges
    EXPECT_NEAR(sum(s.crossing_weights), 4.0 * 3.0, 1e-12);
    EXPECT_NEAR(sum(s.warp_weights), 4.0 * 2.0, 1e-12);      // (nu - 1) widths x (nv - 2) bends
    EXPECT_NEAR(sum(s.weft_weights), 3.0 * 3.0, 1e-12);      // (nv - 1) widths x (nu - 2) bends
    EXPECT_NEAR(sum(s.edge_weights), 4.0 * 3.0 * 2, 1e-12);  // each cell's two threads
    // The flat cloth at rest has no energy but its weight, however it is weighted.
    const Positions x = flat_grid(g, Vec3(0, 0, 0));
    const EnergyTerms e = m.evaluate(x);
    EXPECT_NEAR(e.stretch, 0.0, 1e-25);  // (r - sigma)^2 of rounding
    EXPECT_NEAR(e.bending_warp + e.bending_weft + e.trellis, 0.0, 1e-25);
}

TEST(Discretization, GradientMatchesFiniteDifferences)
{
    // The weighted sum with one-sided edge and corner crossings, on a perturbed 4 x 3 grid:
    // every coordinate's derivative against a central difference of the total energy.
    const Grid g{4, 3, 0.01};
    kes::FabricData f = plain_fabric(12.0);
    for (std::size_t k = 0; k < f.bending_warp.curve.y.size(); ++k)
        f.bending_warp.curve.y[k] += 0.02 * (1 - std::exp(-f.bending_warp.curve.x[k] / 0.3));
    const ClothModel m = make_cloth_model(f, g, ModelOptions{});
    Positions x = flat_grid(g, Vec3(0, 0, 0.1));
    unsigned seed = 7;
    auto noise = [&] {
        seed = seed * 1103515245u + 12345u;
        return ((seed >> 8) % 2001) / 1000.0 - 1.0;
    };
    for (Vec3& p : x) p += 0.15 * g.sigma * Vec3(noise(), noise(), noise());
    const Eigen::VectorXd grad = m.gradient(x);
    const double h = 1e-7;
    for (int k = 0; k < 3 * g.size(); ++k) {
        Positions a = x, b = x;
        a[k / 3][k % 3] += h;
        b[k / 3][k % 3] -= h;
        const double fd = (m.energy(a) - m.energy(b)) / (2 * h);
        EXPECT_NEAR(grad[k], fd, 1e-5 * grad.cwiseAbs().maxCoeff()) << "coordinate " << k;
    }
}

TEST(Discretization, DefaultsAreConvergentAndWork)
{
    const ModelOptions o;
    EXPECT_EQ(o.discretization, Discretization::CONVERGENT);
    EXPECT_EQ(o.bending_form, BendingForm::WORK);
    // The thread stiffness from KES EMT: 500 gf/cm at 5 % is 10^4 gf/cm per unit strain.
    EXPECT_NEAR(tensile_stiffness_from_emt(5.0, units::GramForce::PAPER), 1e4 * 978.80e-5 / 1e-2, 1e-9);
}

}  // namespace
}  // namespace woven::model
