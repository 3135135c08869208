#pragma once
// Internal: the two solvers behind sim::make_solver (the helpers they share: solver_support.hpp).
#include "woven/sim/solver.hpp"

namespace woven::sim::detail {

std::unique_ptr<Solver> make_fast_solver(const Problem& problem, const SolverOptions& options);
std::unique_ptr<Solver> make_paper_solver(const Problem& problem, const SolverOptions& options);

/// The fast solver's move tolerance of a dynamic step's Newton (m): dynamic_step_tolerance
/// sigma, or dynamic_step_cloth_fraction of the grid's longer side where that is more.
double dynamic_move_tolerance(const model::Grid& grid, const FastSolverOptions& options);

}  // namespace woven::sim::detail
