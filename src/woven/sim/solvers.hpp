#pragma once
// Internal: the two solvers behind sim::drape (the helpers they share: solver_support.hpp).
#include "woven/sim/drape.hpp"

namespace woven::sim::detail {

Result fast_drape(const Problem& problem, const SolverOptions& options, const ProgressCallback& progress,
                  const IterationCallback& iteration);
Result paper_drape(const Problem& problem, const SolverOptions& options, const ProgressCallback& progress,
                   const IterationCallback& iteration);

/// The fast solver's move tolerance of a dynamic step's Newton (m): dynamic_step_tolerance
/// sigma, or dynamic_step_cloth_fraction of the grid's longer side where that is more.
double dynamic_move_tolerance(const model::Grid& grid, const FastSolverOptions& options);

}  // namespace woven::sim::detail
