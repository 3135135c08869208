#pragma once
// Static equilibrium of a specimen with prescribed (pinned) particles: the loading step of
// every virtual instrument. Newton's method on the model's energy with its exact Hessian,
// regularised Levenberg-Marquardt style (H + mu D, D the Hessian's diagonal scale) where the
// Hessian is not positive definite (a flat, unloaded specimen: the stretch well is flat at
// rest), a backtracking line search that rejects infinite energy, and a trust region of
// sigma per iteration. No inertia, no obstacles: what is not pinned is free.
#include <functional>
#include <vector>

#include "woven/common/types.hpp"
#include "woven/model/cloth_model.hpp"

namespace woven::testers {

/// Settings of the static solve.
struct StaticOptions {
    /// Converged when the largest force on a free particle is below this times a reference
    /// force: the particle's weight in standard gravity (W sigma^2 g0). Far below what any
    /// measurement needs (a displacement error of about this fraction of a weight over the
    /// bending stiffness).
    double residual_tolerance = 1e-7;
    /// The forces' own round-off is 1e-8 .. 2e-4 of a weight (stiff threads' tension summed
    /// against the bending terms): a solve that stops improving (neither residual nor energy
    /// for 6 iterations) below floor_factor times the tolerance has converged as far as the
    /// arithmetic allows.
    double floor_factor = 1e4;
    /// The reference force (N); 0: a particle's weight. Specimens held by forces much larger
    /// than their weight (the shear test's pre-tension) measure the residual against those.
    double reference_force = 0.0;
    int max_iterations = 300;
    /// Called after each Newton iteration (a caller's word on a long test); may be empty.
    std::function<void()> on_iteration;
};

/// The equilibrium reached.
struct StaticResult {
    Positions x;
    bool converged = false;
    int iterations = 0;
    double max_residual_rel = 0;  ///< largest free-particle force / reference force
};

/// Minimises the model's energy over the particles whose `fixed` flag is 0, starting at x0
/// (fixed particles stay where x0 puts them). Throws RuntimeError if the start has infinite
/// energy.
StaticResult solve_static(const model::ClothModel& model, const Positions& x0, const std::vector<char>& fixed,
                          const StaticOptions& options = {});

}  // namespace woven::testers
