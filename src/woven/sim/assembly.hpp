#pragma once
// Assembly of the gradient and projected Hessian of the cloth energy into the fast solver's
// sparse matrix. Its pattern is the model's stencils (model::Stencils::coupled_with), so the
// symbolic factorisation is done once, plus the repulsion pairs the stencils do not couple
// (self contact).
#include <array>
#include <vector>

#include <Eigen/Sparse>

#include "woven/model/stencils.hpp"
#include "woven/model/terms.hpp"

namespace woven::sim {

/// Gradient and Hessian in a fixed sparsity pattern: particle p is coupled to the particles
/// sharing a stencil with it, and to its partners in `extra_pairs`. A coupling outside the
/// pattern keeps only its diagonal blocks. Pinned particles get identity rows and zero
/// gradient, so a Newton step leaves them in place. A model::LocalSink.
class SparseAssembly {
public:
    SparseAssembly(const model::Stencils& stencils, const std::vector<char>& pinned,
                   const std::vector<model::Stencil<2>>& extra_pairs = {});

    /// Replaces the pattern (self contact changed `extra_pairs`), freeing the old one first.
    void repattern(const model::Stencils& stencils, const std::vector<model::Stencil<2>>& extra_pairs);
    /// Zeroes gradient and matrix values.
    void clear();
    /// Adds one stencil's local gradient and (with_hessian) Hessian.
    template <int N> void add(model::Term, const model::Stencil<N>& ids, const model::Local<N>& local, bool with_hessian);
    /// Adds a 3x3 block on the diagonal and a gradient for particle p (inertia, contact).
    void add_particle(int p, const Mat3& hessian, const Vec3& gradient);
    /// Applies the pinned rows (identity, zero gradient); call after all adds.
    void finish();

    /// Whether the pattern couples p and q (grid stencils or extra pairs).
    bool in_pattern(int p, int q) const { return block(p, q) != nullptr; }
    Eigen::VectorXd& gradient() { return gradient_; }
    const Eigen::SparseMatrix<double>& matrix() const { return matrix_; }

private:
    void build(const model::Stencils& stencils, const std::vector<model::Stencil<2>>& extra_pairs);
    /// Positions in valuePtr() of row 3p of columns 3q, 3q+1, 3q+2; nullptr outside the pattern.
    const std::array<int, 3>* block(int p, int q) const;
    std::vector<char> pinned_;
    Eigen::SparseMatrix<double> matrix_;
    Eigen::VectorXd gradient_;
    /// Block row p: columns partners_[row_[p] .. row_[p+1]) ascending, value positions positions_.
    std::vector<int> row_, partners_;
    std::vector<std::array<int, 3>> positions_;
};

template <int N> void SparseAssembly::add(model::Term, const model::Stencil<N>& ids, const model::Local<N>& local, bool with_hessian)
{
    for (int k = 0; k < N; ++k)
        if (!pinned_[ids[k]]) gradient_.segment<3>(3 * ids[k]) += local.gradient.template segment<3>(3 * k);
    if (!with_hessian) return;
    double* values = matrix_.valuePtr();
    for (int kq = 0; kq < N; ++kq) {
        if (pinned_[ids[kq]]) continue;
        for (int kp = 0; kp < N; ++kp) {
            if (pinned_[ids[kp]]) continue;
            const std::array<int, 3>* pos = block(ids[kp], ids[kq]);
            if (!pos) continue;  // outside the pattern: the diagonal blocks carry it
            for (int b = 0; b < 3; ++b)
                for (int a = 0; a < 3; ++a) values[(*pos)[b] + a] += local.hessian(3 * kp + a, 3 * kq + b);
        }
    }
}

}  // namespace woven::sim
