#include "woven/sim/solver_support.hpp"

#include <algorithm>

#include <Eigen/Dense>

#include "woven/common/units.hpp"
#include "woven/sim/contact.hpp"
#include "woven/sim/drape.hpp"

namespace woven::sim {

int default_max_steps(SolverKind kind) { return kind == SolverKind::FAST ? 400 : 200000; }

namespace detail {

std::vector<char> pinned_mask(const Problem& problem)
{
    std::vector<char> mask(problem.initial.size(), 0);
    for (int p : problem.pinned) mask.at(p) = 1;
    for (size_t p = 0; p < mask.size(); ++p)
        if (!problem.model->active(static_cast<int>(p))) mask[p] = 1;  // not part of the cloth
    return mask;
}

}  // namespace detail

namespace {

/// SplitMix64 (Steele, Lea & Flood 2014): a well-mixed 64-bit hash of its input.
std::uint64_t splitmix64(std::uint64_t z)
{
    z += 0x9E3779B97F4A7C15ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

}  // namespace

Positions perturbed(const Positions& x, const std::vector<char>& held, double amplitude, std::uint64_t seed)
{
    Positions y = x;
    if (amplitude == 0) return y;
    const std::uint64_t s = splitmix64(seed);
    for (size_t i = 0; i < y.size(); ++i) {
        if (!held.empty() && held[i]) continue;
        for (int c = 0; c < 3; ++c) {
            const std::uint64_t h = splitmix64(s ^ splitmix64(3 * i + c));
            const double u = static_cast<double>(h >> 11) * 0x1.0p-52 - 1.0;  // [-1, 1)
            y[i][c] += amplitude * u;
        }
    }
    return y;
}

double max_displacement(const Positions& x, const Positions& y)
{
    double m = 0;
    for (size_t i = 0; i < x.size(); ++i) m = std::max(m, (x[i] - y[i]).norm());
    return m;
}

Positions residual_forces(const model::ClothModel& model, const geometry::ObstacleSet& obstacles, const Positions& x,
                          double contact_distance, double friction)
{
    const Eigen::VectorXd g = model.gradient(x);
    Positions force(x.size());
    for (size_t i = 0; i < x.size(); ++i) force[i] = -g.segment<3>(3 * i);
    // An obstacle can push: a particle within the contact distance carries any outward normal
    // reaction, so the inward normal part of its force is not a residual; with friction, nor is
    // a tangential part up to mu times that reaction.
    std::vector<double> distance;
    std::vector<std::vector<Vec3>> normals(x.size());
    for (size_t o = 0; o < obstacles.size(); ++o) {
        obstacle_distances(obstacles[o], x, distance);
        for (size_t i = 0; i < x.size(); ++i)
            if (distance[i] < contact_distance) normals[i].push_back(obstacles[o].closest(x[i]).normal);
    }
    for (size_t i = 0; i < x.size(); ++i) {
        if (normals[i].empty()) continue;
        if (normals[i].size() == 1) {
            const Vec3& n = normals[i][0];
            const double fn = force[i].dot(n);
            if (fn >= 0) continue;
            force[i] -= fn * n;
            // Friction holds up to mu times the normal reaction -fn.
            const double ft = force[i].norm();
            force[i] *= ft > 0 ? std::max(0.0, ft + friction * fn) / ft : 0.0;
            continue;
        }
        // Several obstacles at once (a particle held between two discs, a corner): the
        // reactions lambda_k >= 0 along their normals that leave the least force, a small
        // non-negative least squares solved exactly over the subsets of (at most 4) contacts;
        // friction then holds up to mu times the reactions' sum.
        const std::vector<Vec3>& N = normals[i];
        const int k = static_cast<int>(std::min<size_t>(N.size(), 4));
        Vec3 best = force[i];
        double best_reaction = 0;
        for (int subset = 1; subset < (1 << k); ++subset) {
            int idx[4], m = 0;
            for (int j = 0; j < k; ++j)
                if (subset & (1 << j)) idx[m++] = j;
            Eigen::MatrixXd A(3, m);
            for (int c = 0; c < m; ++c) A.col(c) = N[idx[c]];
            const Eigen::VectorXd lambda = A.colPivHouseholderQr().solve(-force[i]);
            if ((lambda.array() < 0).any() || !lambda.allFinite()) continue;
            const Vec3 rest = force[i] + A * lambda;
            if (rest.norm() < best.norm()) {
                best = rest;
                best_reaction = lambda.sum();
            }
        }
        const double ft = best.norm();
        force[i] = ft > 0 ? Vec3(best * (std::max(0.0, ft - friction * best_reaction) / ft)) : Vec3::Zero();
    }
    return force;
}

double max_residual_relative(const model::ClothModel& model, const geometry::ObstacleSet& obstacles, const Positions& x,
                             const std::vector<int>& pinned, double contact_distance, double friction)
{
    const Positions force = residual_forces(model, obstacles, x, contact_distance, friction);
    std::vector<char> is_pinned(x.size(), 0);
    for (int p : pinned) is_pinned.at(p) = 1;
    // Each particle against its own weight; without gravity, its weight in standard gravity.
    const double gravity = model.gravity() > 0 ? model.gravity() : units::kStandardGravity;
    double r = 0;
    for (size_t i = 0; i < x.size(); ++i)
        if (!is_pinned[i] && model.active(static_cast<int>(i))) r = std::max(r, force[i].norm() / (model.mass(static_cast<int>(i)) * gravity));
    return r;
}

}  // namespace woven::sim
