#pragma once
// Internal: the two solvers behind sim::drape, and helpers they share.
#include "woven/sim/drape.hpp"

namespace woven::sim::detail {

Result fast_drape(const Problem& problem, const SolverOptions& options, const ProgressCallback& progress,
                  const IterationCallback& iteration);
Result paper_drape(const Problem& problem, const SolverOptions& options, const ProgressCallback& progress,
                   const IterationCallback& iteration);

/// Pinned particles, and those not part of the cloth (inactive), as a mask: held in place.
std::vector<char> pinned_mask(const Problem& problem);

}  // namespace woven::sim::detail
