#pragma once
// Assembly of gradient and (projected) Hessian of the cloth energy into storage the solvers use:
// a sparse matrix with the fixed pattern of the grid stencils (so the symbolic factorisation is
// done once), or just the 3x3 diagonal blocks (the paper solver's per-particle steps).
#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include <Eigen/Sparse>

#include "woven/model/cloth_model.hpp"

namespace woven::sim {

/// Gradient and Hessian in a fixed sparsity pattern: each particle is coupled to the 12 grid
/// neighbours that share a stencil with it ((0,+-1), (+-1,0), (0,+-2), (+-2,0), (+-1,+-1)),
/// plus given extra pairs (repulsion between particles far apart on the grid: self contact).
/// A coupling outside the pattern keeps only its diagonal blocks. Pinned particles get identity
/// rows and zero gradient, so a Newton step leaves them in place.
class SparseAssembly : public model::StencilSink {
public:
    SparseAssembly(const model::Grid& grid, const std::vector<char>& pinned, const std::vector<std::pair<int, int>>& extra_pairs = {});

    /// Zeroes gradient and matrix values.
    void clear();
    void add(const int* particles, int n, const double* gradient, const double* hessian) override;
    /// Adds a 3x3 block on the diagonal and a gradient for particle p (inertia, contact).
    void add_particle(int p, const Mat3& hessian, const Vec3& gradient);
    /// Applies the pinned rows (identity, zero gradient); call after all adds.
    void finish();

    Eigen::VectorXd& gradient() { return gradient_; }
    const Eigen::SparseMatrix<double>& matrix() const { return matrix_; }

private:
    int block_slot(int p, int q) const;  ///< index into offsets_ of q relative to p, or -1
    model::Grid grid_;
    std::vector<char> pinned_;
    Eigen::SparseMatrix<double> matrix_;
    Eigen::VectorXd gradient_;
    /// For particle p and neighbour slot k: position in valuePtr() of row 3p in column 3q+b.
    std::vector<std::array<int, 3>> block_positions_;
    /// Extra pairs (p, q) in both orders -> positions as above.
    std::unordered_map<std::int64_t, std::array<int, 3>> extra_positions_;
    const std::array<int, 3>* block(int p, int q) const;
};

/// Gradient and 3x3 diagonal blocks of the Hessian only.
class DiagonalAssembly : public model::StencilSink {
public:
    explicit DiagonalAssembly(int particles);
    void clear();
    void add(const int* particles, int n, const double* gradient, const double* hessian) override;
    std::vector<Vec3, Eigen::aligned_allocator<Vec3>> gradient;
    std::vector<Mat3, Eigen::aligned_allocator<Mat3>> diagonal;
};

}  // namespace woven::sim
