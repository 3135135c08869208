#include "woven/sim/assembly.hpp"

#include <algorithm>

namespace woven::sim {

namespace {
// Grid offsets (di, dj) of the particles sharing a stencil with a particle, itself first.
constexpr int kSlots = 13;
constexpr int kOffsets[kSlots][2] = {{0, 0}, {1, 0}, {-1, 0}, {0, 1}, {0, -1}, {2, 0}, {-2, 0}, {0, 2}, {0, -2}, {1, 1}, {1, -1}, {-1, 1}, {-1, -1}};
}  // namespace

namespace {
std::int64_t pair_key(int p, int q) { return (static_cast<std::int64_t>(p) << 32) | static_cast<std::uint32_t>(q); }
}  // namespace

SparseAssembly::SparseAssembly(const model::Grid& grid, const std::vector<char>& pinned, const std::vector<std::pair<int, int>>& extra_pairs)
    : grid_(grid), pinned_(pinned)
{
    const int n = grid.size();
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(static_cast<size_t>(n) * kSlots * 9);
    for (int j = 0; j < grid.nv; ++j)
        for (int i = 0; i < grid.nu; ++i)
            for (const auto& off : kOffsets) {
                const int qi = i + off[0], qj = j + off[1];
                if (qi < 0 || qj < 0 || qi >= grid.nu || qj >= grid.nv) continue;
                const int p = grid.index(i, j), q = grid.index(qi, qj);
                for (int a = 0; a < 3; ++a)
                    for (int b = 0; b < 3; ++b) triplets.emplace_back(3 * p + a, 3 * q + b, 0.0);
            }
    for (const auto& [p, q] : extra_pairs)
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b) {
                triplets.emplace_back(3 * p + a, 3 * q + b, 0.0);
                triplets.emplace_back(3 * q + a, 3 * p + b, 0.0);
            }
    matrix_.resize(3 * n, 3 * n);
    matrix_.setFromTriplets(triplets.begin(), triplets.end());
    matrix_.makeCompressed();
    gradient_ = Eigen::VectorXd::Zero(3 * n);

    block_positions_.assign(static_cast<size_t>(n) * kSlots, {-1, -1, -1});
    const int* outer = matrix_.outerIndexPtr();
    const int* inner = matrix_.innerIndexPtr();
    for (int p = 0; p < n; ++p)
        for (int k = 0; k < kSlots; ++k) {
            const int qi = p % grid.nu + kOffsets[k][0], qj = p / grid.nu + kOffsets[k][1];
            if (qi < 0 || qj < 0 || qi >= grid.nu || qj >= grid.nv) continue;
            const int q = grid.index(qi, qj);
            for (int b = 0; b < 3; ++b) {
                const int col = 3 * q + b;
                const int* it = std::lower_bound(inner + outer[col], inner + outer[col + 1], 3 * p);
                block_positions_[static_cast<size_t>(p) * kSlots + k][b] = static_cast<int>(it - inner);
            }
        }
    auto locate = [&](int p, int q) {
        std::array<int, 3> pos;
        for (int b = 0; b < 3; ++b) {
            const int col = 3 * q + b;
            pos[b] = static_cast<int>(std::lower_bound(inner + outer[col], inner + outer[col + 1], 3 * p) - inner);
        }
        return pos;
    };
    for (const auto& [p, q] : extra_pairs) {
        extra_positions_[pair_key(p, q)] = locate(p, q);
        extra_positions_[pair_key(q, p)] = locate(q, p);
    }
}

const std::array<int, 3>* SparseAssembly::block(int p, int q) const
{
    const int slot = block_slot(p, q);
    if (slot >= 0) return &block_positions_[static_cast<size_t>(p) * kSlots + slot];
    if (extra_positions_.empty()) return nullptr;
    auto it = extra_positions_.find(pair_key(p, q));
    return it == extra_positions_.end() ? nullptr : &it->second;
}

int SparseAssembly::block_slot(int p, int q) const
{
    const int di = q % grid_.nu - p % grid_.nu, dj = q / grid_.nu - p / grid_.nu;
    for (int k = 0; k < kSlots; ++k)
        if (kOffsets[k][0] == di && kOffsets[k][1] == dj) return k;
    return -1;
}

void SparseAssembly::clear()
{
    std::fill(matrix_.valuePtr(), matrix_.valuePtr() + matrix_.nonZeros(), 0.0);
    gradient_.setZero();
}

void SparseAssembly::add(const int* particles, int n, const double* gradient, const double* hessian)
{
    const int stride = 3 * n;
    for (int k = 0; k < n; ++k)
        if (!pinned_[particles[k]])
            for (int c = 0; c < 3; ++c) gradient_[3 * particles[k] + c] += gradient[3 * k + c];
    if (!hessian) return;
    double* values = matrix_.valuePtr();
    for (int kq = 0; kq < n; ++kq) {
        const int q = particles[kq];
        if (pinned_[q]) continue;
        for (int kp = 0; kp < n; ++kp) {
            const int p = particles[kp];
            if (pinned_[p]) continue;
            const std::array<int, 3>* block_pos = block(p, q);
            if (!block_pos) continue;  // outside the pattern: the diagonal blocks carry it
            const auto& pos = *block_pos;
            for (int b = 0; b < 3; ++b)
                for (int a = 0; a < 3; ++a) values[pos[b] + a] += hessian[(3 * kq + b) * stride + 3 * kp + a];
        }
    }
}

void SparseAssembly::add_particle(int p, const Mat3& hessian, const Vec3& gradient)
{
    if (pinned_[p]) return;
    gradient_.segment<3>(3 * p) += gradient;
    const auto& pos = block_positions_[static_cast<size_t>(p) * kSlots];
    double* values = matrix_.valuePtr();
    for (int b = 0; b < 3; ++b)
        for (int a = 0; a < 3; ++a) values[pos[b] + a] += hessian(a, b);
}

void SparseAssembly::finish()
{
    // Pinned rows and columns received nothing (see add): identity on their diagonal blocks.
    double* values = matrix_.valuePtr();
    for (int p = 0; p < grid_.size(); ++p) {
        if (!pinned_[p]) continue;
        const auto& pos = block_positions_[static_cast<size_t>(p) * kSlots];
        for (int b = 0; b < 3; ++b) values[pos[b] + b] = 1.0;
    }
}

DiagonalAssembly::DiagonalAssembly(int particles) : gradient(particles), diagonal(particles) { clear(); }

void DiagonalAssembly::clear()
{
    for (auto& g : gradient) g.setZero();
    for (auto& d : diagonal) d.setZero();
}

void DiagonalAssembly::add(const int* particles, int n, const double* g, const double* hessian)
{
    const int stride = 3 * n;
    for (int k = 0; k < n; ++k) {
        const int p = particles[k];
        gradient[p] += Eigen::Map<const Vec3>(g + 3 * k);
        if (!hessian) continue;
        for (int b = 0; b < 3; ++b)
            for (int a = 0; a < 3; ++a) diagonal[p](a, b) += hessian[(3 * k + b) * stride + 3 * k + a];
    }
}

}  // namespace woven::sim
