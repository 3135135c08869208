#include <gtest/gtest.h>

#include <random>

#include <tbb/global_control.h>

#include "woven/sim/linear_solver.hpp"

namespace {

/// A 2-D Laplacian-like SPD matrix (n x n grid, 5-point stencil) plus `diagonal` on the diagonal.
Eigen::SparseMatrix<double> grid_matrix(int n, double diagonal)
{
    std::vector<Eigen::Triplet<double>> t;
    auto id = [n](int i, int j) { return i + n * j; };
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            t.emplace_back(id(i, j), id(i, j), 4.0 + diagonal);
            if (i + 1 < n) t.emplace_back(id(i, j), id(i + 1, j), -1.0), t.emplace_back(id(i + 1, j), id(i, j), -1.0);
            if (j + 1 < n) t.emplace_back(id(i, j), id(i, j + 1), -1.0), t.emplace_back(id(i, j + 1), id(i, j), -1.0);
        }
    Eigen::SparseMatrix<double> A(n * n, n * n);
    A.setFromTriplets(t.begin(), t.end());
    return A;
}

Eigen::VectorXd random_vector(int size)
{
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1, 1);
    Eigen::VectorXd v(size);
    for (int k = 0; k < size; ++k) v[k] = u(rng);
    return v;
}

}  // namespace

TEST(NewtonLinearSolver, FirstSolveFactorisesAndIsExact)
{
    const Eigen::SparseMatrix<double> A = grid_matrix(20, 0.01);
    const Eigen::VectorXd b = random_vector(400);
    woven::sim::NewtonLinearSolver solver;
    Eigen::VectorXd x;
    solver.solve(A, b, x);
    EXPECT_EQ(solver.factorizations(), 1);
    EXPECT_EQ(solver.cg_iterations(), 0);
    EXPECT_LT((A * x - b).norm(), 1e-10 * b.norm());
}

TEST(NewtonLinearSolver, NearbyMatrixReusesTheFactorisationThroughCG)
{
    const Eigen::VectorXd b = random_vector(400);
    woven::sim::NewtonLinearSolver solver;
    Eigen::VectorXd x;
    solver.solve(grid_matrix(20, 0.01), b, x);
    // A 5 % change of the diagonal: CG preconditioned by the old factor converges in a few
    // iterations to the requested relative residual (1e-6 by default).
    const Eigen::SparseMatrix<double> B = grid_matrix(20, 0.2);
    solver.solve(B, b, x);
    EXPECT_EQ(solver.factorizations(), 1);
    EXPECT_GT(solver.cg_iterations(), 0);
    EXPECT_LE(solver.cg_iterations(), 12);
    EXPECT_LT((B * x - b).norm(), 1e-6 * b.norm());
}

TEST(NewtonLinearSolver, FarMatrixIsFactorisedAfresh)
{
    const Eigen::VectorXd b = random_vector(400);
    woven::sim::NewtonLinearSolver solver;
    Eigen::VectorXd x;
    solver.solve(grid_matrix(20, 0.01), b, x);
    // Diagonal 0.01 -> 100: the old factor is a poor preconditioner; CG gives up after its
    // limit and the new matrix is factorised.
    const Eigen::SparseMatrix<double> C = grid_matrix(20, 100.0) * 1e3;
    solver.solve(C, b, x);
    EXPECT_EQ(solver.factorizations(), 2);
    EXPECT_LT((C * x - b).norm(), 1e-10 * b.norm());
    // It gave up at the rate check: three iterations in, the residual's mean rate could not
    // reach the tolerance by the cap.
    EXPECT_EQ(solver.cg_iterations(), woven::sim::NewtonLinearSolver::Options{}.cg_rate_check_after);
}

TEST(NewtonLinearSolver, WithoutTheRateCheckAFailingAttemptRunsToTheCap)
{
    const Eigen::VectorXd b = random_vector(400);
    woven::sim::NewtonLinearSolver::Options options;
    options.cg_rate_check_after = 0;
    woven::sim::NewtonLinearSolver solver(options);
    Eigen::VectorXd x;
    solver.solve(grid_matrix(20, 0.01), b, x);
    const Eigen::SparseMatrix<double> C = grid_matrix(20, 100.0) * 1e3;
    solver.solve(C, b, x);
    EXPECT_EQ(solver.factorizations(), 2);
    EXPECT_EQ(solver.cg_iterations(), options.max_cg_iterations);
    EXPECT_LT((C * x - b).norm(), 1e-10 * b.norm());
}

TEST(NewtonLinearSolver, TheRateCheckKeepsAnAttemptThatConvergesSlowly)
{
    // Diagonal 0.01 -> 0.05 on a 30 x 30 grid: the stale factor's CG needs 7 of its 12
    // iterations, and its rate is good enough from the third on. The same iterations with the
    // check and without it.
    const Eigen::VectorXd b = random_vector(900);
    const Eigen::SparseMatrix<double> A = grid_matrix(30, 0.01), B = grid_matrix(30, 0.05);
    woven::sim::NewtonLinearSolver::Options without;
    without.cg_rate_check_after = 0;
    woven::sim::NewtonLinearSolver checked, unchecked(without);
    Eigen::VectorXd x, y;
    checked.solve(A, b, x);
    unchecked.solve(A, b, y);
    checked.solve(B, b, x);
    unchecked.solve(B, b, y);
    EXPECT_EQ(unchecked.factorizations(), 1);
    EXPECT_GT(unchecked.cg_iterations(), woven::sim::NewtonLinearSolver::Options{}.cg_rate_check_after);
    EXPECT_EQ(checked.factorizations(), 1);
    EXPECT_EQ(checked.cg_iterations(), unchecked.cg_iterations());
    EXPECT_LT((B * x - b).norm(), 1e-6 * b.norm());
}

TEST(NewtonLinearSolver, AFailedStaleFactorIsNotRetriedAtOnce)
{
    // Matrices far apart in turn, so that no stale factor preconditions the next: after k
    // failed attempts in a row the next 2^k - 1 solves factorise without trying CG (each solve
    // stays exact), then the stale factor is tried again.
    const Eigen::VectorXd b = random_vector(400);
    woven::sim::NewtonLinearSolver::Options options;
    options.cg_rate_check_after = 0;  // every failed attempt runs to the cap
    const int cap = options.max_cg_iterations;
    woven::sim::NewtonLinearSolver solver(options);
    Eigen::VectorXd x;
    int k = 0;
    auto next = [&] {
        // As in FarMatrixIsFactorisedAfresh: neither factor preconditions the other.
        const Eigen::SparseMatrix<double> A = k % 2 ? Eigen::SparseMatrix<double>(grid_matrix(20, 100.0) * 1e3) : grid_matrix(20, 0.01);
        solver.solve(A, b, x);
        EXPECT_LT((A * x - b).norm(), 1e-10 * b.norm()) << "solve " << k;
        ++k;
    };
    next();  // the first: factorised
    EXPECT_EQ(solver.factorizations(), 1);
    next();  // attempt 1 fails (cap CG iterations), factorised
    EXPECT_EQ(solver.factorizations(), 2);
    EXPECT_EQ(solver.cg_iterations(), cap);
    next();  // skipped (2^1 - 1 = 1): factorised, no CG
    EXPECT_EQ(solver.factorizations(), 3);
    EXPECT_EQ(solver.cg_iterations(), cap);
    next();  // attempt 2 fails, then 3 solves skip it
    EXPECT_EQ(solver.cg_iterations(), 2 * cap);
    for (int s = 0; s < 3; ++s) next();
    EXPECT_EQ(solver.factorizations(), 7);
    EXPECT_EQ(solver.cg_iterations(), 2 * cap);
    next();  // attempt 3
    EXPECT_EQ(solver.cg_iterations(), 3 * cap);
    EXPECT_EQ(solver.factorizations(), 8);
}

TEST(NewtonLinearSolver, NearlySingularMatrixIsShiftedNotRejected)
{
    // A graph Laplacian (constant null vector) less 1e-12 on the diagonal: just short of
    // positive definite, as round-off can leave a Newton matrix. The first factorisation fails
    // and a shifted one succeeds; a consistent right-hand side is solved to a small residual.
    const int n = 10;
    std::vector<Eigen::Triplet<double>> t;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const int p = i + n * j;
            for (int q : {i + 1 < n ? p + 1 : -1, j + 1 < n ? p + n : -1}) {
                if (q < 0) continue;
                t.emplace_back(p, q, -1.0), t.emplace_back(q, p, -1.0);
                t.emplace_back(p, p, 1.0), t.emplace_back(q, q, 1.0);
            }
            t.emplace_back(p, p, -1e-12);
        }
    Eigen::SparseMatrix<double> A(n * n, n * n);
    A.setFromTriplets(t.begin(), t.end());
    Eigen::VectorXd b = random_vector(n * n);
    b.array() -= b.mean();
    woven::sim::NewtonLinearSolver solver;
    Eigen::VectorXd x;
    ASSERT_NO_THROW(solver.solve(A, b, x));
    EXPECT_GT(solver.factorizations(), 1);
    ASSERT_TRUE(x.allFinite());
    EXPECT_LT((A * x - b).norm(), 1e-3 * b.norm());
}

TEST(NewtonLinearSolver, SplitsALargeFactorisationOnAnyThreadCountInTheSameBits)
{
    // A 70 x 70 grid (4900 unknowns) in a nested-dissection order: two sides of about 2400.
    const Eigen::SparseMatrix<double> grid = grid_matrix(70, 0.01);
    Eigen::SparseMatrix<double> lower;
    {
        const Eigen::SparseMatrix<double> tri = grid.triangularView<Eigen::Lower>();
        const std::vector<int> starts(tri.outerIndexPtr(), tri.outerIndexPtr() + tri.outerSize() + 1);
        const std::vector<int> rows(tri.innerIndexPtr(), tri.innerIndexPtr() + tri.nonZeros());
        const std::vector<int> order = woven::sim::fill_reducing_order(static_cast<int>(grid.rows()), starts, rows);
        Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> P(static_cast<int>(order.size()));
        for (int k = 0; k < static_cast<int>(order.size()); ++k) P.indices()[order[k]] = k;
        Eigen::SparseMatrix<double> permuted;
        permuted = grid.selfadjointView<Eigen::Lower>().twistedBy(P);
        lower = permuted.triangularView<Eigen::Lower>();
    }
    const Eigen::VectorXd b = random_vector(4900);
    const Eigen::SparseMatrix<double> full = lower.selfadjointView<Eigen::Lower>();
    Eigen::VectorXd on_one;
    for (int threads : {1, 2}) {
        const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
        woven::sim::NewtonLinearSolver solver;
        Eigen::VectorXd x;
        solver.solve(lower, b, x);
        EXPECT_TRUE(solver.split_factorization()) << threads << " threads";
        EXPECT_LT((full * x - b).norm(), 1e-10 * b.norm()) << threads << " threads";
        if (threads == 1)
            on_one = x;
        else
            EXPECT_EQ((x - on_one).cwiseAbs().maxCoeff(), 0.0);  // the same bits
    }
}

