// The two-sided factorisation of the Newton matrix (sim/split_cholesky.hpp) against an
// independent LDLT solve of the same matrix, its split against the elimination tree's
// definition, and its bits on one thread against two.
#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include <Eigen/SparseCholesky>

#include "sim/sim_fixtures.hpp"
#include "woven/sim/assembly.hpp"
#include "woven/sim/linear_solver.hpp"
#include "woven/sim/split_cholesky.hpp"

namespace woven {
namespace {

/// The Newton matrix (projected Hessian plus the inertia of a 1/60 s step) of an n x n cloth of
/// 30 cm crumpled by up to 2 mm, two particles pinned, one self-contact pair: its stored
/// triangle in the nested-dissection order.
Eigen::SparseMatrix<double> newton_matrix(int n)
{
    const model::Grid grid = test::square_grid(n, 0.3);
    const model::ClothModel m = model::make_cloth_model(test::cotton_like(), grid, {});
    Positions x = model::flat_grid(grid, Vec3(0, 0, 0.2));
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-2e-3, 2e-3);
    for (Vec3& p : x) p += Vec3(u(rng), u(rng), u(rng));
    std::vector<char> pinned(grid.size(), 0);
    pinned[0] = pinned[n - 1] = 1;
    sim::SparseAssembly system(m.stencils(), pinned, {{n + 1, grid.size() - n - 2}});
    system.clear();
    m.evaluate(x, model::Derivatives::PROJECTED, system);
    const double h = 1.0 / 60.0;
    for (int p = 0; p < grid.size(); ++p) system.add_particle(p, m.particle_mass() / (h * h) * Mat3::Identity(), Vec3::Zero());
    system.finish();
    return system.matrix();
}

Eigen::VectorXd random_vector(int size, unsigned seed)
{
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    Eigen::VectorXd v(size);
    for (int k = 0; k < size; ++k) v[k] = u(rng);
    return v;
}

Eigen::SparseMatrix<double> full(const Eigen::SparseMatrix<double>& lower)
{
    return lower.selfadjointView<Eigen::Lower>();
}

TEST(SplitCholesky, SplitsTheClothAtItsTopSeparator)
{
    const Eigen::SparseMatrix<double> A = newton_matrix(25);
    const int n = static_cast<int>(A.cols());
    const auto split = sim::SplitCholesky::find(A, 200, 1000);
    ASSERT_TRUE(split.has_value());
    const int side1 = split->side_end, side2 = split->separator_begin - split->side_end, separator = n - split->separator_begin;
    // A nested dissection of a 25 x 25 grid: a separator of about two rows of particles (its
    // stencils reach two particles away), the rest halved.
    EXPECT_GE(separator, 3 * 25);
    EXPECT_LE(separator, 3 * 4 * 25);
    EXPECT_GE(std::min(side1, side2), 0.4 * (side1 + side2));
    // No entry couples the sides.
    for (int j = 0; j < side1; ++j)
        for (Eigen::SparseMatrix<double>::InnerIterator it(A, j); it; ++it)
            EXPECT_TRUE(it.row() < side1 || it.row() >= split->separator_begin) << it.row() << ", " << j;
}

TEST(SplitCholesky, FindsNoSplitWhereThereIsNone)
{
    const Eigen::SparseMatrix<double> A = newton_matrix(25);
    // Too small for the sides asked for.
    EXPECT_FALSE(sim::SplitCholesky::find(A, static_cast<int>(A.cols()) / 2, 1000).has_value());
    // A separator longer than allowed.
    EXPECT_FALSE(sim::SplitCholesky::find(A, 200, 20).has_value());
    // A tridiagonal matrix: its elimination tree is a chain, with no sides.
    const int n = 500;
    Eigen::SparseMatrix<double> chain(n, n);
    for (int k = 0; k < n; ++k) {
        chain.insert(k, k) = 4;
        if (k + 1 < n) chain.insert(k + 1, k) = -1;
    }
    chain.makeCompressed();
    EXPECT_FALSE(sim::SplitCholesky::find(chain, 10, n).has_value());
}

TEST(SplitCholesky, SolvesAsAnIndependentLdlt)
{
    const Eigen::SparseMatrix<double> A = newton_matrix(25);
    const auto split = sim::SplitCholesky::find(A, 200, 1000);
    ASSERT_TRUE(split.has_value());
    sim::SplitCholesky factor(A, *split);
    ASSERT_TRUE(factor.factorize(A, 0, false));
    EXPECT_EQ(factor.corners_in_place(), 2);  // the separator is each side's last supernode
    const Eigen::SparseMatrix<double> H = full(A);
    const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> reference(H);
    ASSERT_EQ(reference.info(), Eigen::Success);
    for (unsigned seed : {1u, 2u}) {
        const Eigen::VectorXd b = random_vector(static_cast<int>(A.cols()), seed);
        const Eigen::VectorXd x = factor.solve(b, false), expected = reference.solve(b);
        EXPECT_LE((x - expected).norm(), 1e-10 * expected.norm());
        // The residual of a backward-stable solve: no larger than the reference's own, within 4.
        EXPECT_LE((H * x - b).norm(), 4 * (H * expected - b).norm()) << (H * expected - b).norm();
    }
    // With a diagonal shift: (A + s I)^-1.
    const double shift = 0.5 * A.diagonal().maxCoeff();
    ASSERT_TRUE(factor.factorize(A, shift, false));
    Eigen::SparseMatrix<double> I(A.rows(), A.cols());
    I.setIdentity();
    const Eigen::SparseMatrix<double> shifted = H + shift * I;
    const Eigen::VectorXd b = random_vector(static_cast<int>(A.cols()), 3);
    const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> shifted_reference(shifted);
    const Eigen::VectorXd expected = shifted_reference.solve(b);
    EXPECT_LE((factor.solve(b, false) - expected).norm(), 1e-10 * expected.norm());
}

TEST(SplitCholesky, KeepsDecoupledUnknownsAfterTheClothInTheSeparator)
{
    // Pinned particles' unknowns couple to nothing: trees of their own in the elimination
    // forest. Six of them after the cloth's unknowns join the separator; the sides stay.
    const Eigen::SparseMatrix<double> cloth = newton_matrix(25);
    const int n = static_cast<int>(cloth.cols()), extra = 6;
    std::vector<Eigen::Triplet<double>> t;
    for (int j = 0; j < n; ++j)
        for (Eigen::SparseMatrix<double>::InnerIterator it(cloth, j); it; ++it) t.emplace_back(it.row(), j, it.value());
    for (int k = 0; k < extra; ++k) t.emplace_back(n + k, n + k, 1.0);
    Eigen::SparseMatrix<double> A(n + extra, n + extra);
    A.setFromTriplets(t.begin(), t.end());
    const auto split = sim::SplitCholesky::find(A, 200, 1000);
    ASSERT_TRUE(split.has_value());
    EXPECT_EQ(split->side_end, sim::SplitCholesky::find(cloth, 200, 1000)->side_end);
    EXPECT_EQ(n + extra - split->separator_begin, n - sim::SplitCholesky::find(cloth, 200, 1000)->separator_begin + extra);
    sim::SplitCholesky factor(A, *split);
    ASSERT_TRUE(factor.factorize(A, 0, true));
    EXPECT_LT(factor.corners_in_place(), 2);  // the decoupled unknowns are supernodes of their own: copied
    const Eigen::SparseMatrix<double> H = full(A);
    const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> reference(H);
    const Eigen::VectorXd b = random_vector(n + extra, 6), expected = reference.solve(b);
    EXPECT_LE((factor.solve(b, true) - expected).norm(), 1e-10 * expected.norm());
}

TEST(SplitCholesky, TwoThreadsGiveTheBitsOfOne)
{
    const Eigen::SparseMatrix<double> A = newton_matrix(31);
    const auto split = sim::SplitCholesky::find(A, 200, 1000);
    ASSERT_TRUE(split.has_value());
    sim::SplitCholesky serial(A, *split), parallel(A, *split);
    ASSERT_TRUE(serial.factorize(A, 0, false));
    ASSERT_TRUE(parallel.factorize(A, 0, true));
    const Eigen::VectorXd b = random_vector(static_cast<int>(A.cols()), 4);
    const Eigen::VectorXd x1 = serial.solve(b, false), x2 = parallel.solve(b, true);
    EXPECT_EQ(0, std::memcmp(x1.data(), x2.data(), sizeof(double) * x1.size()));
}

TEST(SplitCholesky, MultipliesAsTheWholeSymmetricMatrixInTheSameBitsOnTwoThreads)
{
    const Eigen::SparseMatrix<double> A = newton_matrix(31);
    const auto split = sim::SplitCholesky::find(A, 200, 1000);
    ASSERT_TRUE(split.has_value());
    const Eigen::VectorXd p = random_vector(static_cast<int>(A.cols()), 7);
    const Eigen::VectorXd expected = full(A) * p;
    Eigen::VectorXd serial, parallel;
    sim::SplitCholesky::symmetric_product(A, *split, p, serial, false);
    sim::SplitCholesky::symmetric_product(A, *split, p, parallel, true);
    // The reference sums in another order: equal to round-off of the largest term.
    const double scale = Eigen::Map<const Eigen::VectorXd>(A.valuePtr(), A.nonZeros()).cwiseAbs().maxCoeff() * 30;
    ASSERT_EQ(expected.size(), serial.size());
    EXPECT_LE((serial - expected).cwiseAbs().maxCoeff(), 1e-14 * scale);
    EXPECT_GT(serial.norm(), 0.1 * expected.norm());  // not a product that vanishes
    EXPECT_EQ(0, std::memcmp(serial.data(), parallel.data(), sizeof(double) * serial.size()));
}

TEST(SplitCholesky, RefusesAMatrixThatIsNotPositiveDefinite)
{
    Eigen::SparseMatrix<double> A = newton_matrix(25);
    const auto split = sim::SplitCholesky::find(A, 200, 1000);
    ASSERT_TRUE(split.has_value());
    sim::SplitCholesky factor(A, *split);
    // Indefinite in one side, then only in the separator's Schur complement.
    for (int column : {split->side_end / 2, static_cast<int>(A.cols()) - 1}) {
        Eigen::SparseMatrix<double> B = A;
        B.coeffRef(column, column) = -B.coeffRef(column, column);
        EXPECT_FALSE(factor.factorize(B, 0, true)) << column;
    }
    EXPECT_TRUE(factor.factorize(A, 0, true));
}

}  // namespace
}  // namespace woven
