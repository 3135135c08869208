// PairCache: its pairs equal close_pairs(x) (same set, same order) along a random walk of the
// particles, rebuilding only when a particle has moved more than half the skin; the energy
// evaluated with its pairs is bit-identical.
#include <random>

#include <gtest/gtest.h>

#include "model_test_support.hpp"
#include "woven/model/pair_cache.hpp"

namespace woven::test {
namespace {

using model::ClothModel;
using model::Grid;

std::vector<model::Stencil<2>> all_pairs_closer_than(const Positions& x, double r)
{
    std::vector<model::Stencil<2>> p;
    for (int i = 0; i < static_cast<int>(x.size()); ++i)
        for (int j = i + 1; j < static_cast<int>(x.size()); ++j)
            if ((x[i] - x[j]).squaredNorm() < r * r) p.push_back({i, j});
    return p;
}

struct NoSink {
    template <int N> void add(model::Term, const model::Stencil<N>&, const model::Local<N>&, bool) {}
};

TEST(PairCache, EqualsClosePairsAlongARandomWalk)
{
    const Grid grid{14, 12, 0.02};
    const ClothModel m = make_model(grid, Terms::all());
    model::PairCache cache(m, 0.5);
    Positions x = perturbed_grid(grid, 3, 0.2, 0.8);
    std::mt19937 rng(7);
    // Steps of 0.02 sigma per coordinate mostly (reuse), every 10th a jump of 0.6 sigma (rebuild).
    for (int k = 0; k < 60; ++k) {
        const double size = (k % 10 == 9 ? 0.6 : 0.02) * grid.sigma;
        std::uniform_real_distribution<double> u(-size, size);
        for (Vec3& p : x) p += Vec3(u(rng), u(rng), u(rng));
        const auto& got = cache.pairs(x);
        ASSERT_EQ(got, m.close_pairs(x)) << "step " << k;
        ASSERT_EQ(got, all_pairs_closer_than(x, grid.sigma)) << "step " << k;
    }
    // 6 jumps, and the small steps add up past skin/2 = 0.25 sigma only every few steps.
    EXPECT_GE(cache.rebuilds(), 7);
    EXPECT_LE(cache.rebuilds(), 30);
}

TEST(PairCache, EnergyWithCachedPairsIsBitIdentical)
{
    const Grid grid{10, 10, 0.02};
    const ClothModel m = make_model(grid, Terms::all());
    model::PairCache cache(m);
    const Positions x = perturbed_grid(grid, 5, 0.25, 0.7);
    NoSink none;
    const model::EnergyTerms a = m.evaluate(x);
    const model::EnergyTerms b = m.evaluate(x, model::Derivatives::NONE, none, cache.pairs(x));
    EXPECT_GT(a.repulsion, 0.0);
    EXPECT_EQ(a.repulsion, b.repulsion);
    EXPECT_EQ(a.total(), b.total());
}

}  // namespace
}  // namespace woven::test
