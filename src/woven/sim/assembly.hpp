#pragma once
// Assembly of the gradient and projected Hessian of the cloth energy into the fast solver's
// sparse matrix. Its pattern is the model's stencils (model::Stencils::coupled_with), so the
// symbolic factorisation is done once, plus the repulsion pairs the stencils do not couple
// (self contact). The matrix is stored as the factorisation reads it: its lower triangle, in a
// fill-reducing order of the unknowns (linear_solver.hpp), so that CHOLMOD factorises it as it
// is, without the permuted copies it would otherwise make at every factorisation.
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
///
/// The gradient is in particle order (particle p at 3p). The matrix is P H P^T, of which only
/// the lower triangle is stored, P the fill-reducing permutation `order()` (unknown order()[k]
/// of H is unknown k of the matrix): vectors go in and out with to_matrix_order and
/// from_matrix_order. Of each pair of mirrored entries of H the one below H's own diagonal is
/// the one assembled, so the factorised values are those of H's lower triangle.
class SparseAssembly {
public:
    SparseAssembly(const model::Stencils& stencils, const std::vector<char>& pinned,
                   const std::vector<model::Stencil<2>>& extra_pairs = {});

    /// Replaces the pattern (self contact changed `extra_pairs`), freeing the old one first.
    void repattern(const model::Stencils& stencils, const std::vector<model::Stencil<2>>& extra_pairs);
    /// Zeroes gradient and matrix values.
    void clear();
    /// Adds one stencil's local gradient and (with_hessian) Hessian; with `part` >= 0 only the
    /// values that part owns (model::PartitionedSink): the gradient of the particles and the
    /// Hessian blocks of the columns of its range of the matrix's order.
    template <int N> void add(model::Term, const model::Stencil<N>& ids, const model::Local<N>& local, bool with_hessian, int part = -1);
    /// Parts the adds are split into, one per oneTBB thread allowed at construction (at most 4).
    int parts() const { return parts_; }
    /// Adds a 3x3 block on the diagonal and a gradient for particle p (inertia, contact).
    void add_particle(int p, const Mat3& hessian, const Vec3& gradient);
    /// Applies the pinned rows (identity, zero gradient); call after all adds.
    void finish();

    /// Whether the pattern couples p and q (grid stencils or extra pairs).
    bool in_pattern(int p, int q) const;
    Eigen::VectorXd& gradient() { return gradient_; }
    /// The lower triangle of P H P^T (see the class comment).
    const Eigen::SparseMatrix<double>& matrix() const { return matrix_; }
    /// P: unknown order()[k] of H is unknown k of matrix().
    const std::vector<int>& order() const { return order_; }
    /// out[k] = v[order()[k]]: a vector of H's unknowns (3 per particle) in the matrix's order.
    void to_matrix_order(const Eigen::VectorXd& v, Eigen::VectorXd& out) const;
    /// The inverse: out[order()[k]] = v[k].
    void from_matrix_order(const Eigen::VectorXd& v, Eigen::VectorXd& out) const;
    /// H itself, both triangles, in particle order (a copy: for small problems and tests).
    Eigen::SparseMatrix<double> full_matrix() const;

private:
    void build(const model::Stencils& stencils, const std::vector<model::Stencil<2>>& extra_pairs);
    /// Block (p, q) for q <= p: positions in valuePtr() of its entries (3p + a, 3q + b) at
    /// [3 b + a], -1 above H's diagonal (a < b when q = p); nullptr outside the pattern or q > p.
    const std::array<int, 9>* lower_block(int p, int q) const;
    std::vector<char> pinned_;
    Eigen::SparseMatrix<double> matrix_;
    Eigen::VectorXd gradient_;
    std::vector<int> order_;
    /// Block row p: columns partners_[row_[p] .. row_[p+1]) ascending; those up to and
    /// including p, its lower blocks, have their value positions at positions_[lower_[p] ...].
    std::vector<int> row_, partners_, lower_;
    std::vector<std::array<int, 9>> positions_;
    int parts_ = 1;
    /// The part owning particle p's gradient and the Hessian blocks (p', p), p' >= p.
    std::vector<char> owner_;
};

template <int N> void SparseAssembly::add(model::Term, const model::Stencil<N>& ids, const model::Local<N>& local, bool with_hessian, int part)
{
    for (int k = 0; k < N; ++k)
        if (!pinned_[ids[k]] && (part < 0 || owner_[ids[k]] == part)) gradient_.segment<3>(3 * ids[k]) += local.gradient.template segment<3>(3 * k);
    if (!with_hessian) return;
    double* values = matrix_.valuePtr();
    for (int kq = 0; kq < N; ++kq) {
        if (pinned_[ids[kq]] || (part >= 0 && owner_[ids[kq]] != part)) continue;
        for (int kp = 0; kp < N; ++kp) {
            if (pinned_[ids[kp]] || ids[kp] < ids[kq]) continue;  // above the diagonal: its mirror is assembled
            const std::array<int, 9>* pos = lower_block(ids[kp], ids[kq]);
            if (!pos) continue;  // outside the pattern: the diagonal blocks carry it
            for (int b = 0; b < 3; ++b)
                for (int a = 0; a < 3; ++a)
                    if ((*pos)[3 * b + a] >= 0) values[(*pos)[3 * b + a]] += local.hessian(3 * kp + a, 3 * kq + b);
        }
    }
}

/// A sink adding to a SparseAssembly with the stretch term's local derivatives times
/// `stretch_weight`: the Newton system of the energy whose threads are `1 / stretch_weight`
/// times softer (the fast solver's creep continuation, FastSolverOptions::creep_softening).
struct WeightedStretchSink {
    SparseAssembly& system;
    double stretch_weight;
    int parts() const { return system.parts(); }
    template <int N> void add(model::Term term, const model::Stencil<N>& ids, const model::Local<N>& local, bool with_hessian, int part = -1)
    {
        if (term != model::Term::STRETCH) return system.template add<N>(term, ids, local, with_hessian, part);
        model::Local<N> scaled = local;
        model::scale_local(scaled, stretch_weight);
        system.template add<N>(term, ids, scaled, with_hessian, part);
    }
};

}  // namespace woven::sim
