#include "woven/sim/assembly.hpp"

#include <algorithm>

namespace woven::sim {

SparseAssembly::SparseAssembly(const model::Stencils& stencils, const std::vector<char>& pinned,
                               const std::vector<model::Stencil<2>>& extra_pairs)
    : pinned_(pinned)
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

    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(static_cast<size_t>(row_[n]) * 9);
    for (int p = 0; p < n; ++p)
        for (int k = row_[p]; k < row_[p + 1]; ++k)
            for (int a = 0; a < 3; ++a)
                for (int b = 0; b < 3; ++b) triplets.emplace_back(3 * p + a, 3 * partners_[k] + b, 0.0);
    matrix_.resize(3 * n, 3 * n);
    matrix_.setFromTriplets(triplets.begin(), triplets.end());
    matrix_.makeCompressed();
    gradient_ = Eigen::VectorXd::Zero(3 * n);

    positions_.resize(partners_.size());
    const int* outer = matrix_.outerIndexPtr();
    const int* inner = matrix_.innerIndexPtr();
    for (int p = 0; p < n; ++p)
        for (int k = row_[p]; k < row_[p + 1]; ++k)
            for (int b = 0; b < 3; ++b) {
                const int col = 3 * partners_[k] + b;
                positions_[k][b] = static_cast<int>(std::lower_bound(inner + outer[col], inner + outer[col + 1], 3 * p) - inner);
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
