#pragma once
// Drape solvers: from a flat cloth above the obstacles to static equilibrium.
//   FAST  (default): implicit (backward-Euler) steps posed as minimisation of an incremental
//         potential, projected Newton with sparse Cholesky, a barrier for obstacle contact and a
//         line search that never crosses an energy singularity or an obstacle; steps grow as
//         the cloth settles, ending in a static solve.
//   PAPER: the paper's three-phase step (Sec. 3): free fall in a viscous medium with
//         collisions; stochastic energy minimisation; velocity correction. Kept for
//         reproduction and comparison.
#include <cstdint>
#include <functional>
#include <vector>

#include "woven/common/types.hpp"
#include "woven/geometry/obstacle.hpp"
#include "woven/model/cloth_model.hpp"

namespace woven::sim {

enum class SolverKind { FAST, PAPER };

/// Solver settings (SI). Defaults are those of `woven drape`.
struct SolverOptions {
    SolverKind kind = SolverKind::FAST;
    std::uint64_t seed = 1;         ///< random seed (the paper solver's stochastic phase)
    int max_steps = 0;              ///< 0: the solver's default (fast 400 steps, paper 200000)
    double residual_tolerance = 1e-3;  ///< equilibrium: largest residual force / (m g) on a free particle
    double move_tolerance = 1e-5;      ///< paper solver equilibrium: largest particle move per step (m)
    double time_step = 1.0 / 60.0;     ///< first time step (s); the fast solver grows it as the cloth settles, the paper solver caps it (see paper_solver.cpp)
    double contact_distance = 1e-3;    ///< barrier activation distance d^ (m)
    double viscosity = 2.0;            ///< paper solver: drag coefficient of the viscous medium (1/s)
    double friction = 0.0;             ///< fast solver: Coulomb friction coefficient cloth-obstacle (0: none, as the paper)
    int threads = 0;                   ///< 0: all cores
};

/// What to drape: the model, the obstacles, the start and the pinned particles.
struct Problem {
    const model::ClothModel* model = nullptr;
    const geometry::ObstacleSet* obstacles = nullptr;
    Positions initial;
    std::vector<int> pinned;  ///< particles held at their initial positions
};

/// Progress after each step; the callback returns false to stop (Ctrl-C): the state reached
/// is returned with converged = false.
struct StepInfo {
    int step = 0;
    double time = 0;              ///< simulated time (s)
    double energy = 0;            ///< model energy (J)
    double max_move = 0;          ///< largest particle movement over the step (m)
    double max_residual_rel = 0;  ///< largest residual force / (m g) over free particles
};
using ProgressCallback = std::function<bool(const StepInfo&)>;

/// Equilibrium measures of a state (MODEL-NOTES/issue: two numbers).
struct Equilibrium {
    double max_move = 0;          ///< m, over the last step
    double max_residual_rel = 0;  ///< largest |F_i| / (m g) over free particles (g: standard gravity when the
                                  ///< model has none); obstacles may push (a particle
                                  ///< within the contact distance may carry any outward normal reaction,
                                  ///< and with friction a tangential one up to mu times it)
};

struct Result {
    Positions x;
    bool converged = false;
    bool interrupted = false;
    int steps = 0;
    int iterations = 0;  ///< Newton iterations (fast) or minimisation sweeps (paper)
    int factorizations = 0;  ///< fast solver: sparse Cholesky factorisations
    int cg_iterations = 0;   ///< fast solver: preconditioned CG iterations
    double simulated_time = 0;
    double wall_time = 0;  ///< s
    Equilibrium equilibrium;
    model::EnergyTerms energy;
};

/// Runs the chosen solver to equilibrium (or max_steps, or until the callback says stop).
Result drape(const Problem& problem, const SolverOptions& options, const ProgressCallback& progress = {});

/// Largest |x_i - y_i| over particles (m).
double max_displacement(const Positions& x, const Positions& y);

/// Largest residual force on a free particle relative to its weight (see Equilibrium). With
/// friction mu, an obstacle also holds a tangential force up to mu times its normal reaction.
double max_residual_relative(const model::ClothModel& model, const geometry::ObstacleSet& obstacles, const Positions& x,
                             const std::vector<int>& pinned, double contact_distance, double friction = 0.0);

}  // namespace woven::sim
