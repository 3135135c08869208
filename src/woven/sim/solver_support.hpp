#pragma once
// What both drape solvers (fast_solver.cpp, paper_solver.cpp) share, and what they measure:
// the start's perturbation, the held particles, the residual forces and the equilibrium test
// (and the step limit default_max_steps of drape.hpp, defined in solver_support.cpp).
#include <cstdint>
#include <vector>

#include "woven/common/types.hpp"
#include "woven/geometry/obstacle.hpp"
#include "woven/model/cloth_model.hpp"

namespace woven::sim {

struct Problem;  // drape.hpp

/// x with each coordinate of each particle not `held` moved by amplitude * u, u uniform in
/// [-1, 1] from a hash of (seed, particle, coordinate): the same bits on every machine and
/// thread count (SolverOptions::perturbation). `held`: one flag per particle, or empty.
Positions perturbed(const Positions& x, const std::vector<char>& held, double amplitude, std::uint64_t seed);

/// Largest |x_i - y_i| over particles (m).
double max_displacement(const Positions& x, const Positions& y);

/// The residual force on each particle (N): -dE/dx less what the obstacles can hold (see
/// Equilibrium: the inward normal part within the contact distance, and with friction mu a
/// tangential part up to mu times that reaction). Pinned particles are not treated apart.
Positions residual_forces(const model::ClothModel& model, const geometry::ObstacleSet& obstacles, const Positions& x,
                          double contact_distance, double friction = 0.0);

/// Largest residual force on a free particle relative to its weight (see Equilibrium). With
/// friction mu, an obstacle also holds a tangential force up to mu times its normal reaction.
double max_residual_relative(const model::ClothModel& model, const geometry::ObstacleSet& obstacles, const Positions& x,
                             const std::vector<int>& pinned, double contact_distance, double friction = 0.0);

namespace detail {

/// Pinned particles, and those not part of the cloth (inactive), as a mask: held in place.
std::vector<char> pinned_mask(const Problem& problem);

}  // namespace detail

}  // namespace woven::sim
