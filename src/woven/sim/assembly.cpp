#include "woven/sim/assembly.hpp"

#include <algorithm>
#include <cassert>
#include <limits>

#include <tbb/global_control.h>

#include "woven/common/error.hpp"
#include "woven/sim/linear_solver.hpp"

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
    std::vector<int>().swap(lower_);
    std::vector<int>().swap(order_);
    std::vector<std::array<int, 9>>().swap(positions_);
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
    lower_.assign(n + 1, 0);
    for (int p = 0; p < n; ++p) {
        std::sort(rows[p].begin(), rows[p].end());
        rows[p].erase(std::unique(rows[p].begin(), rows[p].end()), rows[p].end());
        row_[p + 1] = row_[p] + static_cast<int>(rows[p].size());
        lower_[p + 1] = lower_[p] + static_cast<int>(std::upper_bound(rows[p].begin(), rows[p].end(), p) - rows[p].begin());
    }
    partners_.reserve(row_[n]);
    for (const auto& r : rows) partners_.insert(partners_.end(), r.begin(), r.end());
    std::vector<std::vector<int>>().swap(rows);

    // H's lower triangle, compressed columns: column 3q + b holds rows 3p + a >= 3q + b of each
    // partner p >= q of q, ascending (the pattern is symmetric: q is p's partner when p is q's).
    const int size = 3 * n;
    const long long lower_blocks = lower_[n];
    if (9 * lower_blocks > std::numeric_limits<int>::max()) throw RuntimeError("fast solver: the Newton matrix is too large for 32-bit indices");
    std::vector<int> starts(size + 1, 0), entries;
    entries.reserve(static_cast<size_t>(9 * lower_blocks));
    for (int q = 0; q < n; ++q)
        for (int b = 0; b < 3; ++b) {
            starts[3 * q + b] = static_cast<int>(entries.size());
            for (int k = row_[q]; k < row_[q + 1]; ++k)
                for (int a = 0; a < 3; ++a)
                    if (3 * partners_[k] + a >= 3 * q + b) entries.push_back(3 * partners_[k] + a);
        }
    starts[size] = static_cast<int>(entries.size());

    // The fill-reducing order, and the lower triangle of P H P^T written directly in it (no
    // triplets: at 201 x 201 the triplets and setFromTriplets' transposed copy were 75 + 56 MB
    // on top of the matrix, the drape's peak when self contact changed it).
    order_ = fill_reducing_order(size, starts, entries);
    std::vector<int> rank(size);
    for (int k = 0; k < size; ++k) rank[order_[k]] = k;
    const int nonzeros = starts[size];
    matrix_ = Eigen::SparseMatrix<double>(size, size);
    matrix_.resizeNonZeros(nonzeros);
    int* outer = matrix_.outerIndexPtr();
    int* inner = matrix_.innerIndexPtr();
    std::fill(outer, outer + size + 1, 0);
    for (int c = 0; c < size; ++c)
        for (int e = starts[c]; e < starts[c + 1]; ++e) ++outer[std::min(rank[entries[e]], rank[c]) + 1];
    for (int c = 0; c < size; ++c) outer[c + 1] += outer[c];
    std::vector<int> next(outer, outer + size), slot_entry(nonzeros), entry_slot(nonzeros);
    for (int c = 0; c < size; ++c)
        for (int e = starts[c]; e < starts[c + 1]; ++e) {
            const int r = rank[entries[e]], cc = rank[c];
            const int slot = next[std::min(r, cc)]++;
            inner[slot] = std::max(r, cc);
            slot_entry[slot] = e;
        }
    for (int c = 0; c < size; ++c)  // rows ascending in each column (a column holds a few dozen)
        for (int i = outer[c] + 1; i < outer[c + 1]; ++i)
            for (int j = i; j > outer[c] && inner[j - 1] > inner[j]; --j) {
                std::swap(inner[j - 1], inner[j]);
                std::swap(slot_entry[j - 1], slot_entry[j]);
            }
    for (int slot = 0; slot < nonzeros; ++slot) entry_slot[slot_entry[slot]] = slot;
    std::fill(matrix_.valuePtr(), matrix_.valuePtr() + nonzeros, 0.0);
    gradient_ = Eigen::VectorXd::Zero(size);

    // Owners for the parallel adds: the parts' ranges of the matrix's order (so each part
    // writes mostly its own columns' values).
    parts_ = static_cast<int>(std::clamp<std::size_t>(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism), 1, 4));
    owner_.assign(n, 0);
    for (int p = 0; p < n; ++p) owner_[p] = static_cast<char>(static_cast<long long>(rank[3 * p]) * parts_ / size);

    // Lower block (p, q): the slot of each entry (3p + a, 3q + b) on or below H's diagonal.
    positions_.resize(lower_[n]);
    for (int p = 0; p < n; ++p)
        for (int k = row_[p]; k < row_[p] + (lower_[p + 1] - lower_[p]); ++k) {
            const int q = partners_[k];
            std::array<int, 9>& pos = positions_[lower_[p] + (k - row_[p])];
            for (int b = 0; b < 3; ++b)
                for (int a = 0; a < 3; ++a) {
                    const int r = 3 * p + a, c = 3 * q + b;
                    if (r < c) {
                        pos[3 * b + a] = -1;
                        continue;
                    }
                    const int* first = entries.data() + starts[c];
                    const int* last = entries.data() + starts[c + 1];
                    const int* it = std::lower_bound(first, last, r);
                    assert(*it == r);
                    pos[3 * b + a] = entry_slot[it - entries.data()];
                }
        }
}

const std::array<int, 9>* SparseAssembly::lower_block(int p, int q) const
{
    if (q > p) return nullptr;
    const int* begin = partners_.data() + row_[p];
    const int* end = begin + (lower_[p + 1] - lower_[p]);
    const int* it = std::lower_bound(begin, end, q);
    return it != end && *it == q ? &positions_[lower_[p] + (it - begin)] : nullptr;
}

bool SparseAssembly::in_pattern(int p, int q) const
{
    return std::binary_search(partners_.begin() + row_[p], partners_.begin() + row_[p + 1], q);
}

void SparseAssembly::to_matrix_order(const Eigen::VectorXd& v, Eigen::VectorXd& out) const
{
    out.resize(v.size());
    for (Eigen::Index k = 0; k < v.size(); ++k) out[k] = v[order_[k]];
}

void SparseAssembly::from_matrix_order(const Eigen::VectorXd& v, Eigen::VectorXd& out) const
{
    out.resize(v.size());
    for (Eigen::Index k = 0; k < v.size(); ++k) out[order_[k]] = v[k];
}

Eigen::SparseMatrix<double> SparseAssembly::full_matrix() const
{
    // H(order[k], order[l]) = M(k, l): the permutation sends k to order[k].
    Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> to_particles(static_cast<int>(order_.size()));
    std::copy(order_.begin(), order_.end(), to_particles.indices().data());
    Eigen::SparseMatrix<double> full(matrix_.rows(), matrix_.cols());
    full = matrix_.selfadjointView<Eigen::Lower>().twistedBy(to_particles);
    return full;
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
    const auto& pos = *lower_block(p, p);
    double* values = matrix_.valuePtr();
    for (int b = 0; b < 3; ++b)
        for (int a = b; a < 3; ++a) values[pos[3 * b + a]] += hessian(a, b);
}

void SparseAssembly::finish()
{
    // Pinned rows and columns received nothing (see add): identity on their diagonal blocks.
    double* values = matrix_.valuePtr();
    for (int p = 0; p < static_cast<int>(pinned_.size()); ++p) {
        if (!pinned_[p]) continue;
        const auto& pos = *lower_block(p, p);
        for (int b = 0; b < 3; ++b) values[pos[4 * b]] = 1.0;
    }
}

}  // namespace woven::sim
