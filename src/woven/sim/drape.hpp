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
#include <optional>
#include <string_view>
#include <vector>

#include "woven/common/choice.hpp"
#include "woven/common/types.hpp"
#include "woven/geometry/obstacle.hpp"
#include "woven/model/cloth_model.hpp"
#include "woven/sim/solver_support.hpp"  // the equilibrium measures (residual_forces, ...)

namespace woven::sim {

enum class SolverKind { FAST, PAPER };

/// The solvers' names: "fast", "paper" (scene files, the command line, reports).
inline constexpr std::array<Named<SolverKind>, 2> kSolverKindNames{{{SolverKind::FAST, "fast"}, {SolverKind::PAPER, "paper"}}};
/// Its name in kSolverKindNames.
const char* to_string(SolverKind kind);
/// The kind named in kSolverKindNames; nullopt for any other name.
std::optional<SolverKind> solver_kind_from_string(std::string_view name);
/// The step limit when SolverOptions::max_steps is 0: fast 400 steps, paper 200000.
int default_max_steps(SolverKind kind);

/// The backtracking (Armijo) line search of the fast solver's Newton iterations (line_search.hpp).
struct LineSearchOptions {
    double armijo = 1e-4;      ///< sufficient decrease: Phi(alpha) <= Phi(0) + armijo alpha slope
    double shrink = 0.5;       ///< step factor per rejected trial
    int max_trials = 40;       ///< trials before giving up
    double min_fraction = 1e-12;  ///< smallest step fraction tried
    /// Relative round-off of the objective: below a predicted decrease of this times |phi0| the
    /// energy cannot tell two trials apart, and a finite trial within that band is accepted.
    double roundoff = 1e-13;
};

/// Settings of the fast solver (fast_solver.cpp) beyond the shared ones, with their units; each
/// field's measured effect: docs/SOLVER.md "Every option" (which also lists the solver's fixed
/// constants: step limits, floors, the barrier, the line search).
struct FastSolverOptions {
    int max_newton_iterations = 120;  ///< per step; a step that needs more is halved
    double static_time_step = 1.0;    ///< s: from this step on, Newton is solved to the final tolerance
    double step_growth = 2.0;         ///< step factor after a converged Newton solve (after the fall)
    /// s: the fall. Until this much simulated time has passed the steps stay at the first step's
    /// size (SolverOptions::time_step), then they grow by step_growth; 0 (the default): they grow
    /// from the first step. Backward Euler's numerical damping grows with the step, so this
    /// chooses how much of the falling cloth's swing survives, and with it which of the cube's
    /// nearly equal rest states a drape lands in; measured in docs/SOLVER.md "The fall", where
    /// no step size gave the paper's cotton/wool/polyester-cotton contrast.
    double fall_duration = 0.0;
    double damping = 2.0;             ///< 1/s: viscous medium, v <- v / (1 + damping h)
    double dynamic_tolerance = 0.1;   ///< Newton tolerance of dynamic steps, residual force / (m g)
    /// a dynamic step's Newton has also converged when no particle moves more than this, in
    /// sigma, in an iteration (0.03 on the 51 x 51 cube: 1305 -> 371 Newton iterations, 0.01: 701)
    double dynamic_step_tolerance = 0.03;
    /// ... or more than this times the cloth's longer side, where that is more: the fall's path
    /// needs resolving to a fraction of the cloth, not of the spacing (the 51 x 51 cube's 0.03
    /// sigma is 6e-4 of its side; on the 101 x 101 cube 0.05 sigma took 568 -> 403 Newton
    /// iterations and a lower drape; 201 x 201 was not faster, bench/NOTES.md "the fall's path tolerance")
    double dynamic_step_cloth_fraction = 5e-4;
    double trust_region = 1.0;        ///< largest particle move per Newton iteration, in sigma
    double dynamic_cg_tolerance = 1e-6;  ///< linear solves of dynamic steps: |H d + g| <= this |g| (an inexact Newton forcing term; 0.1 saves factorisations but moves the drape)
    /// ... and in the static steps' projected Newton (far from rest, above static_newton_cg_below):
    /// a stale factor then preconditions CG to this often enough to skip a factorisation. The
    /// same drapes; 201 x 201 1554 -> 927 factorisations, 12 % less CPU; 101 x 101 3-4 %;
    /// 51 x 51 no change (bench/NOTES.md "a forcing term for the static steps' projected Newton")
    double static_projected_cg_tolerance = 0.1;
    int max_cg_iterations = 12;       ///< beyond this the Newton matrix is factorised afresh
    bool static_newton_cg = true;     ///< static steps: CG on the exact Hessian preconditioned by the projected one's factor (linear_solver.hpp)
    /// ... once the residual is below this (residual force / (m g)); above it, projected Newton.
    /// Far from rest the exact Hessian's CG stops at negative curvature or its iteration cap
    /// with poor steps: the 51 x 51 cube's first static step took 94 iterations of up to 48 CG
    /// iterations each (3356 in all); with projected Newton down to 1 m g, 785 CG iterations
    /// and 23 % fewer seconds for the whole drape (bench/NOTES.md "Stiff linear threads and Newton").
    double static_newton_cg_below = 1.0;
    /// The static creep's continuation (bench/NOTES.md "the creep's continuation"). On a fine grid the hanging
    /// flaps refold in static steps that each run into the Newton cap: a straight Newton move of
    /// a turning flap lengthens its stiff threads with the square of the turn, so each iteration
    /// moves it a fraction of a millimetre. Once `creep_capped_steps` static steps have run into
    /// the cap, Phi's stretch term is divided by `creep_softening` (threads that much softer),
    /// and each step that converges divides the softening by `creep_stage_ratio`, down to the
    /// cloth's own threads; a softened static step ends at `creep_tolerance` (residual force /
    /// (m g)), and the run ends only at rest on the cloth's own energy. 201 x 201 cube, two
    /// threads: 1831 -> 1024 Newton iterations, 1302 -> 773 factorisations, 0.4704828 ->
    /// 0.4704300 J (a lower drape); the sphere scene 3354 -> 1101. The 21, 51 and 101 x 101
    /// cubes do not creep (at most one capped step) and keep their bits. creep_softening 1: off.
    double creep_softening = 100.0;
    double creep_stage_ratio = 10.0;  ///< 100 (one stage) took 1531 iterations: the stiff threads crept again
    int creep_capped_steps = 2;       ///< 101 x 101 runs into the cap once, near rest
    double creep_tolerance = 0.1;
};

/// Settings of the paper solver (paper_solver.cpp) beyond the shared ones, with their units.
struct PaperSolverOptions {
    int max_sweeps = 60;                ///< phase-2 sweeps per step at most
    double sweep_tolerance = 0.02;      ///< a sweep moving no particle more than this times move_tolerance ends phase 2
    double noise = 0.1;                 ///< random perturbation, relative to the particle's movement over the last step
    double noise_fade = 0.01;           ///< in sigma: below this movement per step the perturbation fades (quadratically)
    double pair_margin = 1.1;           ///< repulsion partners: pairs closer than this times sigma at the start of phase 2
    double stiffness_strain = 0.01;     ///< the time step is capped at sqrt(m / (dt_cap k)), k = S'' at this strain
    double dt_cap = 4.0;                ///< see stiffness_strain
    double clearance = 0.5;             ///< particles are kept this times contact_distance off obstacles
    double min_move_fraction = 1e-3;    ///< a particle's move is halved down to this fraction before it is dropped
    int calm_steps = 10;                ///< equilibrium: movement below move_tolerance this many steps in a row ...
    double calm_time = 0.1;             ///< s: ... and over at least this time
    int progress_every = 50;            ///< steps between progress reports
};

/// Solver settings (SI). Defaults are those of `woven drape`.
struct SolverOptions {
    SolverKind kind = SolverKind::FAST;
    std::uint64_t seed = 1;            ///< random seed (the paper solver's stochastic phase; the fast solver's perturbation)
    int max_steps = 0;                 ///< 0: default_max_steps(kind)
    double residual_tolerance = 1e-3;  ///< equilibrium: largest residual force / (m g) on a free particle
    double move_tolerance = 1e-5;      ///< paper solver equilibrium: largest particle move per step (m)
    double time_step = 1.0 / 60.0;     ///< first time step (s); the fast solver grows it as the cloth settles, the paper solver caps it (see paper_solver.cpp)
    double contact_distance = 1e-3;    ///< barrier activation distance d^ (m)
    double viscosity = 2.0;            ///< paper solver: drag coefficient of the viscous medium (1/s)
    double friction = 0.0;             ///< fast solver: Coulomb friction coefficient cloth-obstacle (0: none, as the paper)
    int threads = 0;                   ///< oneTBB and OpenMP threads during the drape; 0: leave the count as it is (all cores); restored on return
    /// Fast solver: amplitude (m) of a seeded perturbation of the start, each coordinate of each
    /// free particle moved by up to this (uniform, from `seed`), so that the start is never
    /// exactly symmetric (the paper's stochastic solver never drapes the same twice); 0 keeps
    /// the start as given. The default 1e-5 m (5e-4 sigma at the paper's 2 cm) is far above
    /// round-off and far below anything a drape resolves. On the convergent model (stiff
    /// threads) the fall amplifies it: the 51 x 51 cotton cube at seeds 1..5 gives five
    /// different drapes, 0.46884-0.46917 J, with different corner folds (docs/EXPERIMENTS.md),
    /// as the paper's stochastic solver does. (On d519f62's paper-convention model the same
    /// perturbation left a stable symmetric drape: mirror asymmetry 9e-8 m, energy change 4e-12 J.)
    double perturbation = 1e-5;
    FastSolverOptions fast;
    PaperSolverOptions paper;
};

/// The cloth of a problem, held once: read-only (a model with friction inside the weave keeps
/// its slip states as they are) or evolving (`evolving`: the fast solver updates its slip states
/// by the return mapping after each step, ClothModel::update_slip, so that each step minimises
/// an energy with its states fixed and the path is remembered; the states are not reset, so a
/// protocol of several drapes carries them on).
class ClothRef {
public:
    ClothRef() = default;
    ClothRef(const model::ClothModel* model) : model_(model) {}  // NOLINT(google-explicit-constructor): read as a pointer
    static ClothRef evolving(model::ClothModel& model)
    {
        ClothRef r(&model);
        r.writable_ = &model;
        return r;
    }
    const model::ClothModel* get() const { return model_; }
    const model::ClothModel& operator*() const { return *model_; }
    const model::ClothModel* operator->() const { return model_; }
    explicit operator bool() const { return model_ != nullptr; }
    /// The model whose slip states the solver updates; null when read-only.
    model::ClothModel* evolving_model() const { return writable_; }

private:
    const model::ClothModel* model_ = nullptr;
    model::ClothModel* writable_ = nullptr;  ///< only `evolving`, from a writable model, sets it
};

/// What to drape: the model, the obstacles, the start and the pinned particles.
struct Problem {
    ClothRef model;
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
    const Positions* x = nullptr; ///< the state after the step (valid during the callback)
};
using ProgressCallback = std::function<bool(const StepInfo&)>;

/// Progress within a step, for a display that moves while a long step is solved: the fast
/// solver reports before each Newton iteration, the paper solver after each step's phase 2.
/// The callback returns false to stop, as ProgressCallback's.
struct IterationInfo {
    int step = 0;               ///< the step being solved (from 1)
    int iteration = 0;          ///< Newton iteration within it (fast), or phase-2 sweeps (paper)
    int total_iterations = 0;   ///< over the run so far
    double time_step = 0;       ///< s
    double residual_rel = 0;    ///< fast: largest |grad Phi_i| / (m_i g) over free particles (Phi the step's incremental potential); paper: NaN
    double tolerance = 0;       ///< fast: the Newton tolerance of this step on residual_rel; paper: NaN
};
using IterationCallback = std::function<bool(const IterationInfo&)>;

/// Equilibrium measures of a state: two numbers.
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
    int softened_steps = 0;  ///< fast solver: steps solved with the creep's softened threads (FastSolverOptions::creep_softening)
    double simulated_time = 0;
    double wall_time = 0;  ///< s
    Equilibrium equilibrium;
    model::EnergyTerms energy;
};

/// Adds the counters of a further run to `total`: steps, iterations, factorisations, CG
/// iterations, softened steps, simulated and wall time (a drape in stages, a drape resumed).
inline void add_counters(Result& total, const Result& more)
{
    total.steps += more.steps;
    total.iterations += more.iterations;
    total.factorizations += more.factorizations;
    total.cg_iterations += more.cg_iterations;
    total.softened_steps += more.softened_steps;
    total.simulated_time += more.simulated_time;
    total.wall_time += more.wall_time;
}

/// Runs the chosen solver (sim::Solver, solver.hpp: this is a loop over its step()) to equilibrium (or max_steps, or until a callback says stop). With
/// options.threads > 0, oneTBB and OpenMP run on that many threads during the call; the BLAS on
/// one; the process-wide counts are restored on return. Threads evaluate the model's local
/// terms (the same bits on any count) and, on a large grid, the two sides of the Newton
/// matrix's top separator are factorised apart (sim/split_cholesky.hpp; at once from two
/// threads, one after the other on one): every thread count gives the same bits.
Result drape(const Problem& problem, const SolverOptions& options, const ProgressCallback& progress = {},
             const IterationCallback& iteration = {});

}  // namespace woven::sim
