#include "woven/sim/assembly.hpp"

#include <algorithm>
#include <cassert>
#include <limits>

#include "woven/common/error.hpp"

namespace woven::sim {

SparseAssembly::SparseAssembly(const model::Stencils& stencils, const std::vector<char>& pinned,
                               const std::vector<model::Stencil<2>>& extra_pairs)
    : pinned_(pinned)
{
    build(stencils, extra_pairs);
}

void SparseAssembly::repattern(const model::Stencils& stencils, const std::vector<model::Stencil<2>>& extra_pairs)
{
    // The old pattern's storage goes first: the drape's peak is where two matrices coexist.
    matrix_ = Eigen::SparseMatrix<double>();
    std::vector<int>().swap(row_);
    std::vector<int>().swap(partners_);
    std::vector<std::array<int, 3>>().swap(positions_);
    build(stencils, extra_pairs);
}

void SparseAssembly::build(const model::Stencils& stencils, const std::vector<model::Stencil<2>>& extra_pairs)
{
    const int n = static_cast<int>(stencils.active.size());
    std::vector<std::vector<int>> rows(n);
    for (int p = 0; p < n; ++p) {
        const auto coupled = stencils.coupled_with(p);
        rows[p].assign(coupled.begin(), coupled.end());
    }
    for (const auto& [p, q] : extra_pairs) {
        rows[p].push_back(q);
        rows[q].push_back(p);
    }
    row_.assign(n + 1, 0);
    for (int p = 0; p < n; ++p) {
        std::sort(rows[p].begin(), rows[p].end());
        rows[p].erase(std::unique(rows[p].begin(), rows[p].end()), rows[p].end());
        row_[p + 1] = row_[p] + static_cast<int>(rows[p].size());
    }
    partners_.reserve(row_[n]);
    for (const auto& r : rows) partners_.insert(partners_.end(), r.begin(), r.end());

    // The pattern is symmetric (q is p's partner when p is q's), so column 3q + b holds rows 3p,
    // 3p + 1, 3p + 2 of each partner p of q, ascending: the compressed structure is written
    // directly, without triplets (at 201 x 201 the triplets and setFromTriplets' transposed copy
    // were 75 + 56 MB on top of the matrix, the drape's peak when self contact changed it).
    const long long blocks = row_[n];
    if (9 * blocks > std::numeric_limits<int>::max()) throw RuntimeError("fast solver: the Newton matrix is too large for 32-bit indices");
    matrix_ = Eigen::SparseMatrix<double>(3 * n, 3 * n);
    matrix_.resizeNonZeros(static_cast<Eigen::Index>(9 * blocks));
    int* outer = matrix_.outerIndexPtr();
    int* inner = matrix_.innerIndexPtr();
    int next = 0;
    for (int q = 0; q < n; ++q)
        for (int b = 0; b < 3; ++b) {
            outer[3 * q + b] = next;
            for (int k = row_[q]; k < row_[q + 1]; ++k)
                for (int a = 0; a < 3; ++a) inner[next++] = 3 * partners_[k] + a;
        }
    outer[3 * n] = next;
    std::fill(matrix_.valuePtr(), matrix_.valuePtr() + next, 0.0);
    gradient_ = Eigen::VectorXd::Zero(3 * n);

    // Block (p, q): in column 3q + b, p's place among q's partners.
    positions_.resize(partners_.size());
    for (int p = 0; p < n; ++p)
        for (int k = row_[p]; k < row_[p + 1]; ++k) {
            const int q = partners_[k];
            const int place = static_cast<int>(std::lower_bound(partners_.begin() + row_[q], partners_.begin() + row_[q + 1], p) - (partners_.begin() + row_[q]));
            assert(partners_[row_[q] + place] == p);
            for (int b = 0; b < 3; ++b) positions_[k][b] = outer[3 * q + b] + 3 * place;
        }
}

const std::array<int, 3>* SparseAssembly::block(int p, int q) const
{
    const int* begin = partners_.data() + row_[p];
    const int* end = partners_.data() + row_[p + 1];
    const int* it = std::lower_bound(begin, end, q);
    return it != end && *it == q ? &positions_[it - partners_.data()] : nullptr;
}

void SparseAssembly::clear()
{
    std::fill(matrix_.valuePtr(), matrix_.valuePtr() + matrix_.nonZeros(), 0.0);
    gradient_.setZero();
}

void SparseAssembly::add_particle(int p, const Mat3& hessian, const Vec3& gradient)
{
    if (pinned_[p]) return;
    gradient_.segment<3>(3 * p) += gradient;
    const auto& pos = *block(p, p);
    double* values = matrix_.valuePtr();
    for (int b = 0; b < 3; ++b)
        for (int a = 0; a < 3; ++a) values[pos[b] + a] += hessian(a, b);
}

void SparseAssembly::finish()
{
    // Pinned rows and columns received nothing (see add): identity on their diagonal blocks.
    double* values = matrix_.valuePtr();
    for (int p = 0; p < static_cast<int>(pinned_.size()); ++p) {
        if (!pinned_[p]) continue;
        const auto& pos = *block(p, p);
        for (int b = 0; b < 3; ++b) values[pos[b] + b] = 1.0;
    }
}

}  // namespace woven::sim
