// SparseAssembly against an independent dense assembly of the same local terms: every value in
// its place, nothing outside the pattern, pinned rows as identity, and a repatterned assembly
// (self contact) equal to a freshly built one.
#include <gtest/gtest.h>

#include <random>

#include <Eigen/SparseCholesky>

#include "sim/sim_fixtures.hpp"
#include "woven/sim/assembly.hpp"
#include "woven/sim/linear_solver.hpp"

namespace woven {
namespace {

/// Adds every local gradient and Hessian into dense storage (a model::LocalSink).
struct DenseSink {
    Eigen::MatrixXd H;
    Eigen::VectorXd g;
    template <int N> void add(model::Term, const model::Stencil<N>& ids, const model::Local<N>& local, bool with_hessian)
    {
        for (int k = 0; k < N; ++k) g.segment<3>(3 * ids[k]) += local.gradient.template segment<3>(3 * k);
        if (!with_hessian) return;
        for (int a = 0; a < N; ++a)
            for (int b = 0; b < N; ++b) H.block<3, 3>(3 * ids[a], 3 * ids[b]) += local.hessian.template block<3, 3>(3 * a, 3 * b);
    }
};

/// A 6 x 6 cloth of 10 cm, its particles moved off the flat grid by up to 2 mm.
Positions crumpled(const model::Grid& grid)
{
    Positions x = model::flat_grid(grid, Vec3(0, 0, 0.2));
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-2e-3, 2e-3);
    for (Vec3& p : x) p += Vec3(u(rng), u(rng), u(rng));
    return x;
}

TEST(SparseAssembly, EqualsADenseAssemblyOfTheSameTerms)
{
    const model::Grid grid = test::square_grid(6, 0.1);
    const model::ClothModel m = model::make_cloth_model(test::cotton_like(), grid, {});
    const Positions x = crumpled(grid);
    const int n = grid.size();
    std::vector<char> pinned(n, 0);
    pinned[7] = 1;
    // One pair the stencils do not couple (opposite corners), as self contact adds.
    const std::vector<model::Stencil<2>> extra{{0, n - 1}};
    ASSERT_FALSE(m.stencils().coupled(0, n - 1));

    sim::SparseAssembly sparse(m.stencils(), pinned, extra);
    sparse.clear();
    m.evaluate(x, model::Derivatives::PROJECTED, sparse);
    const Mat3 contact = Vec3(1, 2, 3).asDiagonal();
    sparse.add_particle(0, contact, Vec3(0.5, 0, 0));
    sparse.finish();

    DenseSink dense{Eigen::MatrixXd::Zero(3 * n, 3 * n), Eigen::VectorXd::Zero(3 * n)};
    m.evaluate(x, model::Derivatives::PROJECTED, dense);
    dense.H.block<3, 3>(0, 0) += contact;
    dense.g.segment<3>(0) += Vec3(0.5, 0, 0);

    const Eigen::MatrixXd S = Eigen::MatrixXd(sparse.full_matrix());
    const double scale = dense.H.cwiseAbs().maxCoeff();
    ASSERT_GT(scale, 0);
    for (int p = 0; p < n; ++p)
        for (int q = 0; q < n; ++q) {
            const Mat3 got = S.block<3, 3>(3 * p, 3 * q);
            if (pinned[p] || pinned[q]) {
                const Mat3 expected = p == q ? Mat3(Mat3::Identity()) : Mat3(Mat3::Zero());
                EXPECT_EQ(got, expected) << p << ", " << q;
                continue;
            }
            // Every coupling of the terms lies in the pattern, and has its value there.
            const bool coupled = dense.H.block<3, 3>(3 * p, 3 * q).cwiseAbs().maxCoeff() > 0;
            EXPECT_TRUE(sparse.in_pattern(p, q) || !coupled) << p << ", " << q;
            EXPECT_LE((got - dense.H.block<3, 3>(3 * p, 3 * q)).cwiseAbs().maxCoeff(), 1e-12 * scale) << p << ", " << q;
        }
    EXPECT_TRUE(sparse.in_pattern(0, n - 1) && sparse.in_pattern(n - 1, 0));
    EXPECT_FALSE(sparse.in_pattern(1, n - 1));
    for (int p = 0; p < n; ++p) {
        const Vec3 expected = pinned[p] ? Vec3::Zero() : Vec3(dense.g.segment<3>(3 * p));
        EXPECT_LE((sparse.gradient().segment<3>(3 * p) - expected).norm(), 1e-12 * dense.g.cwiseAbs().maxCoeff()) << p;
    }
    // The stored matrix: compressed, rows ascending in every column and none above the
    // diagonal, and P H P^T for the order, a permutation of the unknowns.
    const Eigen::SparseMatrix<double>& A = sparse.matrix();
    EXPECT_TRUE(A.isCompressed());
    for (int c = 0; c < A.cols(); ++c) {
        for (int k = A.outerIndexPtr()[c] + 1; k < A.outerIndexPtr()[c + 1]; ++k) EXPECT_LT(A.innerIndexPtr()[k - 1], A.innerIndexPtr()[k]);
        if (A.outerIndexPtr()[c + 1] > A.outerIndexPtr()[c]) {
            EXPECT_GE(A.innerIndexPtr()[A.outerIndexPtr()[c]], c) << c;
        }
    }
    std::vector<int> order = sparse.order();
    ASSERT_EQ(order.size(), static_cast<size_t>(3 * n));
    std::sort(order.begin(), order.end());
    for (int k = 0; k < 3 * n; ++k) ASSERT_EQ(order[k], k);
    const Eigen::MatrixXd lower(A);
    for (int k = 0; k < 3 * n; ++k)
        for (int l = 0; l <= k; ++l) ASSERT_EQ(lower(k, l), S(sparse.order()[k], sparse.order()[l])) << k << ", " << l;
    // Vectors in and out of the matrix's order.
    Eigen::VectorXd v = Eigen::VectorXd::LinSpaced(3 * n, 1, 3 * n), w, back;
    sparse.to_matrix_order(v, w);
    sparse.from_matrix_order(w, back);
    for (int k = 0; k < 3 * n; ++k) EXPECT_EQ(w[k], v[sparse.order()[k]]);
    EXPECT_EQ(back, v);
}

TEST(SparseAssembly, NestedDissectionOrderHasLessFillThanTheGridOrder)
{
    // The order is what makes the factorisation affordable: nested dissection on a 20 x 20
    // cloth against the particles' own (row by row, a band of 2 rows of particles).
    const model::Grid grid = test::square_grid(20, 0.5);
    const model::ClothModel m = model::make_cloth_model(test::cotton_like(), grid, {});
    sim::SparseAssembly sparse(m.stencils(), std::vector<char>(grid.size(), 0));
    sparse.clear();
    m.evaluate(crumpled(grid), model::Derivatives::PROJECTED, sparse);
    for (int p = 0; p < grid.size(); ++p) sparse.add_particle(p, Mat3::Identity(), Vec3::Zero());
    sparse.finish();
    auto factor_nonzeros = [](const Eigen::SparseMatrix<double>& lower) {  // of L, in the order given
        Eigen::SimplicialLLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::NaturalOrdering<int>> llt(lower);
        EXPECT_EQ(llt.info(), Eigen::Success);
        return static_cast<double>(llt.matrixL().nestedExpression().nonZeros());
    };
    const Eigen::SparseMatrix<double> grid_order = sparse.full_matrix().triangularView<Eigen::Lower>();
    const double nested = factor_nonzeros(sparse.matrix()), banded = factor_nonzeros(grid_order);
    EXPECT_LT(nested, 0.8 * banded) << nested << " against " << banded;
}

TEST(SparseAssembly, SolvesInTheMatrixOrderEqualTheSolveOfH)
{
    // The fast solver's path: the right-hand side into the matrix's order, the Newton solver on
    // the stored triangle, the solution back; against an independent solve with H itself.
    const model::Grid grid = test::square_grid(9, 0.3);
    const model::ClothModel m = model::make_cloth_model(test::cotton_like(), grid, {});
    const int n = grid.size();
    std::vector<char> pinned(n, 0);
    pinned[4] = 1;
    sim::SparseAssembly system(m.stencils(), pinned, {{0, n - 1}});
    system.clear();
    m.evaluate(crumpled(grid), model::Derivatives::PROJECTED, system);
    for (int p = 0; p < n; ++p) system.add_particle(p, 1e3 * Mat3::Identity(), Vec3::Zero());  // inertia: definite
    system.finish();
    Eigen::VectorXd rhs = Eigen::VectorXd::LinSpaced(3 * n, -1, 1), in_order, solution, d;
    for (int a = 0; a < 3; ++a) rhs[3 * 4 + a] = 0;  // a pinned particle carries no force
    system.to_matrix_order(rhs, in_order);
    sim::NewtonLinearSolver linear;
    linear.solve(system.matrix(), in_order, solution);
    system.from_matrix_order(solution, d);
    const Eigen::SparseMatrix<double> H = system.full_matrix();
    const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> reference(H);
    ASSERT_EQ(reference.info(), Eigen::Success);
    const Eigen::VectorXd expected = reference.solve(rhs);
    EXPECT_LE((d - expected).norm(), 1e-10 * expected.norm());
    EXPECT_LE((H * d - rhs).norm(), 1e-10 * rhs.norm());
    EXPECT_EQ(linear.factorizations(), 1);
}

TEST(SparseAssembly, RepatternGivesTheFreshAssembly)
{
    const model::Grid grid = test::square_grid(6, 0.1);
    const model::ClothModel m = model::make_cloth_model(test::cotton_like(), grid, {});
    const Positions x = crumpled(grid);
    const std::vector<char> pinned(grid.size(), 0);
    const std::vector<model::Stencil<2>> extra{{2, 30}, {5, 33}};
    auto assembled = [&](sim::SparseAssembly& s) {
        s.clear();
        m.evaluate(x, model::Derivatives::PROJECTED, s);
        s.finish();
        return Eigen::MatrixXd(s.full_matrix());
    };
    sim::SparseAssembly fresh(m.stencils(), pinned, extra);
    sim::SparseAssembly changed(m.stencils(), pinned);
    const Eigen::MatrixXd before = assembled(changed);
    EXPECT_FALSE(changed.in_pattern(2, 30));
    changed.repattern(m.stencils(), extra);
    EXPECT_TRUE(changed.in_pattern(2, 30) && changed.in_pattern(33, 5));
    EXPECT_EQ(changed.matrix().nonZeros(), fresh.matrix().nonZeros());
    EXPECT_EQ(assembled(changed), assembled(fresh));
    EXPECT_EQ(changed.order(), fresh.order());
    // The extra pairs carry no term here, so the values are those of the plain pattern.
    EXPECT_EQ(assembled(changed), before);
}

/// The energy of `m` at x with its stretch term times w (the creep's softened threads).
double weighted_energy(const model::ClothModel& m, const Positions& x, double w)
{
    model::EnergyTerms e = m.evaluate(x);
    e.stretch *= w;
    return e.total();
}

TEST(WeightedStretchSink, GradientAndHessianAreThoseOfTheEnergyWithItsStretchWeighted)
{
    const model::Grid grid = test::square_grid(6, 0.1);
    const model::ClothModel m = model::make_cloth_model(test::cotton_like(), grid, {});
    const Positions x = crumpled(grid);
    const int n = grid.size();
    const double w = 0.01;  // threads 100 times softer
    sim::SparseAssembly system(m.stencils(), std::vector<char>(n, 0));
    system.clear();
    sim::WeightedStretchSink weighted{system, w};
    m.evaluate(x, model::Derivatives::HESSIAN, weighted);
    system.finish();
    const Eigen::VectorXd g = system.gradient();
    const Eigen::MatrixXd H = Eigen::MatrixXd(system.full_matrix());

    // Central differences of the weighted energy (gradient) and of the weighted gradient
    // (Hessian columns), step 1e-6 m: the stretch of the crumpled cloth is not negligible at
    // w = 0.01 (cotton's E_t 9.8 kN/m, strains ~1 %), so a wrong weight shows.
    const double step = 1e-6;
    auto gradient_at = [&](const Positions& y) {
        sim::SparseAssembly s(m.stencils(), std::vector<char>(n, 0));
        s.clear();
        sim::WeightedStretchSink ws{s, w};
        m.evaluate(y, model::Derivatives::GRADIENT, ws);
        return Eigen::VectorXd(s.gradient());
    };
    double g_scale = g.cwiseAbs().maxCoeff(), h_scale = H.cwiseAbs().maxCoeff();
    for (int k = 0; k < 3 * n; k += 5) {
        Positions plus = x, minus = x;
        plus[k / 3][k % 3] += step;
        minus[k / 3][k % 3] -= step;
        const double fd = (weighted_energy(m, plus, w) - weighted_energy(m, minus, w)) / (2 * step);
        EXPECT_NEAR(g[k], fd, 1e-6 * g_scale) << "gradient entry " << k;
        const Eigen::VectorXd column = (gradient_at(plus) - gradient_at(minus)) / (2 * step);
        EXPECT_LT((H.col(k) - column).cwiseAbs().maxCoeff(), 1e-5 * h_scale) << "Hessian column " << k;
    }
    // The weight matters here: the unweighted gradient differs by far more than the tolerance.
    sim::SparseAssembly full(m.stencils(), std::vector<char>(n, 0));
    full.clear();
    m.evaluate(x, model::Derivatives::GRADIENT, full);
    EXPECT_GT((full.gradient() - g).cwiseAbs().maxCoeff(), 0.1 * g_scale);
}

}  // namespace
}  // namespace woven
