// The model's energy knows no direction of the grid it was not given: mirrored, or turned by a
// quarter (for a fabric whose warp and weft are alike), a configuration has the same energy,
// in both discretisations, edges and corners included.
#include <gtest/gtest.h>

#include <random>

#include "model_test_support.hpp"
#include "woven/model/cloth_model.hpp"

namespace woven::model {
namespace {

kes::FabricData alike_warp_and_weft()
{
    kes::FabricData f;
    f.name = "balanced";
    f.areal_density_mg_cm2 = 15;
    f.bending_warp.summary = test::cotton_warp();
    f.bending_warp.curve = kes::synthesize_bending_curve(test::cotton_warp());
    f.bending_weft = f.bending_warp;
    f.shear.summary = test::cotton_shear();
    f.shear.curve = kes::synthesize_shear_curve(test::cotton_shear());
    return f;
}

/// x_(i,j) = grid position + noise of 0.1 sigma (seeded), the cloth 0.3 m square, n x n.
Positions noisy_grid(const Grid& g, unsigned seed)
{
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-0.1 * g.sigma, 0.1 * g.sigma);
    Positions x(g.size());
    for (int j = 0; j < g.nv; ++j)
        for (int i = 0; i < g.nu; ++i) x[g.index(i, j)] = Vec3(i * g.sigma + u(rng), j * g.sigma + u(rng), 0.3 + u(rng));
    return x;
}

class Symmetry : public ::testing::TestWithParam<Discretization> {};

TEST_P(Symmetry, MirrorAndQuarterTurnKeepEveryTerm)
{
    const int n = 9;
    const Grid g{n, n, 0.3 / (n - 1)};
    ModelOptions o;
    o.discretization = GetParam();
    const ClothModel m = make_cloth_model(alike_warp_and_weft(), g, o);
    for (unsigned seed : {1u, 2u, 3u}) {
        const Positions x = noisy_grid(g, seed);
        Positions mirrored(g.size()), turned(g.size());
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const Vec3& p = x[g.index(i, j)];
                mirrored[g.index(n - 1 - i, j)] = Vec3(-p.x(), p.y(), p.z());     // i -> n - 1 - i, x -> -x
                turned[g.index(n - 1 - j, i)] = Vec3(-p.y(), p.x(), p.z());       // a quarter turn about z
            }
        const EnergyTerms e = m.evaluate(x), em = m.evaluate(mirrored), et = m.evaluate(turned);
        for (Term t : {Term::STRETCH, Term::REPULSION, Term::BENDING_WARP, Term::BENDING_WEFT, Term::TRELLIS, Term::GRAVITY}) {
            EXPECT_NEAR(em[t], e[t], 1e-12 * std::abs(e.total())) << "mirror, term " << static_cast<int>(t) << ", seed " << seed;
        }
        // The quarter turn swaps warp and weft (alike here): compare the sums.
        EXPECT_NEAR(et.bending_warp + et.bending_weft, e.bending_warp + e.bending_weft, 1e-12 * std::abs(e.total())) << seed;
        for (Term t : {Term::STRETCH, Term::REPULSION, Term::TRELLIS, Term::GRAVITY})
            EXPECT_NEAR(et[t], e[t], 1e-12 * std::abs(e.total())) << "turn, term " << static_cast<int>(t) << ", seed " << seed;
    }
}

INSTANTIATE_TEST_SUITE_P(BothDiscretizations, Symmetry, ::testing::Values(Discretization::PAPER, Discretization::CONVERGENT));

}  // namespace
}  // namespace woven::model
