#pragma once
// Internal: the two solvers behind sim::drape, and helpers they share.
#include "woven/sim/drape.hpp"

namespace woven::sim::detail {

Result fast_drape(const Problem& problem, const SolverOptions& options, const ProgressCallback& progress,
                  const IterationCallback& iteration);
Result paper_drape(const Problem& problem, const SolverOptions& options, const ProgressCallback& progress,
                   const IterationCallback& iteration);

/// The fast solver's move tolerance of a dynamic step's Newton (m): dynamic_step_tolerance
/// sigma, or dynamic_step_cloth_fraction of the grid's longer side where that is more.
double dynamic_move_tolerance(const model::Grid& grid, const FastSolverOptions& options);

/// Pinned particles, and those not part of the cloth (inactive), as a mask: held in place.
std::vector<char> pinned_mask(const Problem& problem);

}  // namespace woven::sim::detail
