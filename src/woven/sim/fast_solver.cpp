// The fast solver: backward-Euler steps, each the minimisation of the incremental potential
//   Phi(x) = sum_i m/(2 h^2) |x_i - (x_i^n + h v_i^n)|^2 + E(x) + sum_{i, obstacles} b(d(x_i))
// by projected Newton (per-stencil PSD Hessians in a fixed sparsity pattern; systems solved by
// CG preconditioned with a reused sparse Cholesky factorisation, see linear_solver.hpp) and a
// backtracking line search that starts inside the collision-free fraction of the step (no
// particle crosses an obstacle) and rejects any trial of infinite energy (trellis at 1.05 rad,
// a thread folded flat, contact). The step h doubles while Newton converges, so the
// cloth first falls and swings (a physical path) and then settles; the run ends when the
// largest residual force on a free particle is below the tolerance times its weight. With
// friction inside the weave (ClothRef::evolving) the slip states are updated between steps.
#include <algorithm>
#include <cmath>
#include <limits>

#include "woven/common/units.hpp"
#include "woven/model/pair_cache.hpp"
#include "woven/sim/assembly.hpp"
#include "woven/sim/contact.hpp"
#include "woven/sim/line_search.hpp"
#include "woven/sim/linear_solver.hpp"
#include "woven/sim/solver.hpp"
#include "woven/sim/solver_support.hpp"
#include "woven/sim/solvers.hpp"

namespace woven::sim::detail {

// The solver's fixed constants (docs/SOLVER.md "Every option": none was ever varied by a test, a
// scene or a benchmark drape).
constexpr double kMaxTimeStep = 20.0;           // s: the largest step, effectively static
constexpr double kMinTimeStep = 1e-4;           // s: the smallest step after halvings
constexpr double kStepShrink = 0.5;             // step factor after a Newton solve that did not converge
constexpr double kStaticToleranceFactor = 0.5;  // static Newton tolerance, times residual_tolerance (below the equilibrium test's, which lets obstacles push)
constexpr double kMinNewtonStep = 1e-10;        // m: a Newton step whose largest particle move is below this has converged
constexpr double kCollisionSafety = 0.8;        // fraction of the collision-free step taken (contact.hpp)
constexpr double kBarrierStiffness = 10.0;      // kappa = this m g / d^ (an interior particle's weight held at about 0.7 d^)
constexpr double kFrictionSlip = 1e-4;          // m: slip below which obstacle friction sticks (Coulomb smoothed)
constexpr double kCgTolerance = 1e-6;           // linear solves near rest: |H d + g| <= this |g| (linear_solver.hpp)
constexpr LineSearchOptions kLineSearch{};      // Armijo backtracking (line_search.hpp)

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

struct NoSink {
    template <int N> void add(model::Term, const model::Stencil<N>&, const model::Local<N>&, bool) { }
};

struct FastSolver {
    const model::ClothModel& model;
    const geometry::ObstacleSet* obstacles;  ///< the solver's current ones (Solver::set_obstacles)
    const SolverOptions& options;
    std::vector<char> pinned;  ///< pinned or inactive: held in place
    const std::vector<double>& mass;  ///< per particle (kg)
    std::vector<double> weight;  ///< m g per particle (N), g standard gravity when the model has none
    Barrier barrier;
    std::vector<FrictionContact> friction;  ///< frozen at the step's start
    /// Friction smoothing (m): a contact sticks (force below mu lambda) while it slips less
    /// than this over a step. Much smaller makes the potential too sharp for Newton.
    double slip_eps;
    /// The repulsion pairs as a Verlet list: line-search trials and Newton iterations filter it
    /// instead of hashing every particle (close_pairs was 10-13 % of the 51 x 51 cube's time).
    model::PairCache pairs;
    std::vector<double> distance;  ///< scratch: particle-obstacle distances (m)
    /// The stretch term's weight in Phi: 1 / the creep's softening (1: the cloth's own threads).
    double stretch_weight = 1.0;

    FastSolver(const Problem& problem, const SolverOptions& o)
        : model(*problem.model), obstacles(problem.obstacles), options(o), pinned(pinned_mask(problem)), mass(model.masses()),
          slip_eps(kFrictionSlip), pairs(model)
    {
        const double g = model.gravity() > 0 ? model.gravity() : units::kStandardGravity;
        for (double m : mass) weight.push_back(m * g);
        // An interior particle's weight is held at about 0.7 d^ above a surface; an edge carrying
        // a hanging flap comes closer but never touches.
        barrier = Barrier{options.contact_distance, kBarrierStiffness * (model.particle_mass() * g) / options.contact_distance};
    }

    /// Phi at x (inertia toward x_tilde with 1/h^2 = inv_h2); +inf if any term is singular.
    double incremental_potential(const Positions& x, const Positions& x_tilde, double inv_h2)
    {
        double phi = 0;
        for (size_t i = 0; i < x.size(); ++i) phi += 0.5 * mass[i] * inv_h2 * (x[i] - x_tilde[i]).squaredNorm();
        for (size_t o = 0; o < obstacles->size(); ++o) {
            obstacle_distances((*obstacles)[o], x, distance);
            for (size_t i = 0; i < x.size(); ++i) {
                if (distance[i] < barrier.d_hat) phi += barrier.value(distance[i]);
                if (!std::isfinite(phi)) return kInf;
            }
        }
        for (const FrictionContact& f : friction) phi += f.value(x[f.particle], slip_eps);
        NoSink none;
        model::EnergyTerms terms = model.evaluate(x, model::Derivatives::NONE, none, pairs.pairs(x));
        terms.stretch *= stretch_weight;
        phi += terms.total();
        return std::isfinite(phi) ? phi : kInf;
    }

    /// Gradient and Hessian of Phi: `what` PROJECTED (PSD, for the factorisation) or HESSIAN
    /// (the model's terms exact; barrier and friction keep their PSD forms).
    void assemble(SparseAssembly& system, const Positions& x, const Positions& x_tilde, double inv_h2,
                  model::Derivatives what = model::Derivatives::PROJECTED)
    {
        system.clear();
        if (stretch_weight == 1.0) {
            model.evaluate(x, what, system, pairs.pairs(x));
        } else {
            WeightedStretchSink weighted{system, stretch_weight};
            model.evaluate(x, what, weighted, pairs.pairs(x));
        }
        for (size_t i = 0; i < x.size(); ++i)
            system.add_particle(static_cast<int>(i), mass[i] * inv_h2 * Mat3::Identity(), mass[i] * inv_h2 * (x[i] - x_tilde[i]));
        for (const Contact& c : find_contacts(*obstacles, x, barrier.d_hat))
            system.add_particle(c.particle, barrier.d2(c.distance) * c.normal * c.normal.transpose(), barrier.d1(c.distance) * c.normal);
        for (const FrictionContact& f : friction) system.add_particle(f.particle, f.hessian(x[f.particle], slip_eps), f.gradient(x[f.particle], slip_eps));
        system.finish();
    }
};

/// Repulsion pairs whose particles share no stencil (self contact).
std::vector<model::Stencil<2>> off_pattern_pairs(const model::ClothModel& model, const std::vector<model::Stencil<2>>& close)
{
    std::vector<model::Stencil<2>> out;
    for (const model::Stencil<2>& pq : close)
        if (!model.stencils().coupled(pq[0], pq[1])) out.push_back(pq);
    return out;
}

}  // namespace

double dynamic_move_tolerance(const model::Grid& grid, const FastSolverOptions& options)
{
    const double side = (std::max(grid.nu, grid.nv) - 1) * grid.sigma;
    return std::max(options.dynamic_step_tolerance * grid.sigma, options.dynamic_step_cloth_fraction * side);
}

namespace {

/// The fast solver as a Solver: the state carried from one step to the next.
class FastStepper final : public Solver {
public:
    FastStepper(const Problem& problem, const SolverOptions& o)
        : Solver(problem, o), solver(problem_, options_), n(solver.model.grid().size()), sigma(solver.model.grid().sigma),
          move_tolerance(dynamic_move_tolerance(solver.model.grid(), o.fast)), v(n, Vec3::Zero()), x_tilde(n), trial(n), dx(n),
          system(solver.model.stencils(), solver.pinned), linear(NewtonLinearSolver::Options{kCgTolerance, o.fast.max_cg_iterations}),
          creep_started(o.fast.creep_softening <= 1.0), h(o.time_step)
    {
        // The seeded perturbation of the start (SolverOptions::perturbation); a particle it would
        // move into an obstacle's contact distance stays where it was.
        x_ = perturbed(problem.initial, solver.pinned, options_.perturbation, options_.seed);
        auto gap = [&](const Vec3& p) { return min_obstacle_distance(*solver.obstacles, Positions{p}); };
        for (int i = 0; i < n; ++i)
            if (x_[i] != problem.initial[i] && gap(x_[i]) < std::min(solver.barrier.d_hat, gap(problem.initial[i])))
                x_[i] = problem.initial[i];
    }

private:
    bool advance(const IterationCallback& on_iteration) override;
    void add_counters(Result& r) const override
    {
        r.factorizations = linear.factorizations();
        r.cg_iterations = linear.cg_iterations();
        r.softened_steps = softened_steps;
    }
    double residual_friction() const override { return options_.friction; }
    void obstacles_changed() override { solver.obstacles = problem_.obstacles; }

    FastSolver solver;
    const int n;
    const double sigma;
    const double move_tolerance;
    Positions v, x_tilde, x_prev, trial, dx;
    SparseAssembly system;
    NewtonLinearSolver linear;
    Eigen::VectorXd delta, rhs, solution;  // delta in particle order; rhs, solution in the matrix's (assembly.hpp)
    std::vector<model::Stencil<2>> extra_pairs;
    // The creep's continuation (FastSolverOptions::creep_softening): the tensile stiffness is
    // divided by `softening` while it is above 1.
    int capped_static_steps = 0;
    double softening = 1.0;
    bool creep_started;
    int softened_steps = 0;
    double h;  ///< the next step's size (s)
};

bool FastStepper::advance(const IterationCallback& on_iteration)
{
    const FastSolverOptions& fo = options_.fast;
    const SolverOptions& options = options_;
    const model::ClothModel& model = solver.model;
    Positions& x = x_;
    const int step = steps_ + 1;
    // The step: inertia toward x_tilde = x + h v, friction frozen at its start.
    x_prev = x;
    const double inv_h2 = 1.0 / (h * h);
    for (int i = 0; i < n; ++i) x_tilde[i] = solver.pinned[i] ? x[i] : Vec3(x[i] + h * v[i]);
    if (options.friction > 0) {
        solver.friction = friction_contacts(find_contacts(*solver.obstacles, x, solver.barrier.d_hat), x, solver.barrier, options.friction);
    }
    // Dynamic steps need much less accuracy than the final static solve (its tolerance
    // is below the equilibrium test's, which lets obstacles push).
    const bool static_step = h >= fo.static_time_step;
    if (static_step && !creep_started && capped_static_steps >= fo.creep_capped_steps) {
        creep_started = true;
        softening = fo.creep_softening;
        solver.stretch_weight = 1.0 / softening;
    }
    double newton_tolerance =
        !static_step ? std::max(fo.dynamic_tolerance, options.residual_tolerance) : kStaticToleranceFactor * options.residual_tolerance;
    if (static_step && softening > 1.0) newton_tolerance = std::max(newton_tolerance, fo.creep_tolerance);

    // Newton on Phi.
    double phi = solver.incremental_potential(x, x_tilde, inv_h2);
    int iterations = 0;
    bool newton_converged = false;
    for (; iterations < fo.max_newton_iterations; ++iterations) {
        // Self contact: pairs closer than sigma that the stencils do not couple get their
        // own blocks (a changed set means a new symbolic factorisation).
        std::vector<model::Stencil<2>> extra = off_pattern_pairs(model, solver.pairs.pairs(x));
        if (extra != extra_pairs) {
            extra_pairs = std::move(extra);
            linear.release();  // its factor of the old pattern would coexist with the new pattern's ordering
            system.repattern(model.stencils(), extra_pairs);
        }
        solver.assemble(system, x, x_tilde, inv_h2);
        const Eigen::VectorXd g = system.gradient();  // kept: the Newton-CG branch reassembles `system`
        double g_max = 0;                             // largest |g_i| / (m_i g) over free particles
        for (int i = 0; i < n; ++i)
            if (!solver.pinned[i]) g_max = std::max(g_max, g.segment<3>(3 * i).norm() / solver.weight[i]);
        if (on_iteration && !on_iteration(IterationInfo{step, iterations, iterations_ + iterations, h, g_max, newton_tolerance})) {
            iterations_ += iterations;
            return false;
        }
        if (g_max < newton_tolerance) {
            newton_converged = true;
            break;
        }
        // Dynamic steps, and static ones far from rest: projected Newton. Static steps near
        // rest: truncated Newton-CG on the exact Hessian preconditioned by the projected
        // one's factor. Near rest the projected
        // terms' dropped negative parts made projected Newton converge linearly (0.92 per
        // iteration on the 51 x 51 cube of d519f62, whose static steps took 104 iterations;
        // 16 with Newton-CG, the same energy to 1e-8).
        if (static_step && fo.static_newton_cg && g_max < fo.static_newton_cg_below) {
            // One matrix for both: the exact Hessian is assembled into `system`, and the
            // projected one again only when it is factorised.
            bool holds_exact = false;
            auto matrix = [&](bool exact) -> const Eigen::SparseMatrix<double>& {
                if (holds_exact != exact)
                    solver.assemble(system, x, x_tilde, inv_h2, exact ? model::Derivatives::HESSIAN : model::Derivatives::PROJECTED);
                holds_exact = exact;
                return system.matrix();
            };
            system.to_matrix_order(-g, rhs);
            linear.solve_exact(matrix, rhs, solution, kCgTolerance);
        } else {
            linear.set_tolerance(static_step ? fo.static_projected_cg_tolerance : fo.dynamic_cg_tolerance);
            system.to_matrix_order(-g, rhs);
            linear.solve(system.matrix(), rhs, solution);
        }
        system.from_matrix_order(solution, delta);
        double step_max = 0;
        for (int i = 0; i < n; ++i) {
            dx[i] = delta.segment<3>(3 * i);
            step_max = std::max(step_max, dx[i].norm());
        }
        // A dynamic step needs its path, not its forces, resolved: with stiff threads the
        // residual force falls slowly (a step across the cloth of 1 % sigma leaves a
        // second-order stretch of hundreds of m g) while the positions have settled.
        if (step_max < kMinNewtonStep || (!static_step && step_max < move_tolerance)) {
            newton_converged = true;
            break;
        }
        // Accept: inside the trust region (no particle moves more than trust_region sigma)
        // and the collision-free fraction, the Armijo line search on Phi.
        double alpha = std::min(1.0, fo.trust_region * sigma / step_max);
        alpha = std::min(alpha, collision_free_fraction(*solver.obstacles, x, dx, kCollisionSafety));
        const LineSearchResult ls = line_search(
            [&](double a) {
                for (int i = 0; i < n; ++i) trial[i] = x[i] + a * dx[i];
                return solver.incremental_potential(trial, x_tilde, inv_h2);
            },
            phi, g.dot(delta), alpha, kLineSearch);
        if (!ls.accepted) break;  // no descent left at round-off level
        x.swap(trial);
        phi = ls.value;
    }
    iterations_ += iterations;
    // Friction inside the weave: the return mapping at the step's end state (slip.hpp). It
    // leaves each element's force at x as it is (so the residual below is the step's), and
    // the next step minimises with the new states (an elastoplastic solver's update).
    if (model::ClothModel* evolving = problem_.model.evolving_model(); evolving && model.has_slip()) evolving->update_slip(x);
    if (static_step && softening == 1.0 && iterations >= fo.max_newton_iterations) ++capped_static_steps;

    for (int i = 0; i < n; ++i) v[i] = solver.pinned[i] ? Vec3::Zero() : Vec3((x[i] - x_prev[i]) / h / (1.0 + fo.damping * h));
    time_ += h;
    steps_ = step;
    max_move_ = max_displacement(x, x_prev);
    const double residual = max_residual_relative(model, *solver.obstacles, x, problem_.pinned, options.contact_distance, options.friction);
    set_residual(residual);
    bool at_rest = residual < options.residual_tolerance;
    if (softening > 1.0) {
        // Softened threads: not the cloth's rest; a converged step takes the next stage.
        at_rest = false;
        ++softened_steps;
        if (newton_converged) {
            softening /= fo.creep_stage_ratio;
            if (softening <= 1.0 + 1e-12) softening = 1.0;
            solver.stretch_weight = 1.0 / softening;
        }
    }
    converged_ = at_rest;
    // Grow the step while Newton converges, shrink it when it does not: the cloth falls in
    // short steps, and the steps lengthen (and damp more) as it settles. Growing only
    // after easy solves (<= 15 iterations) took 2.5 times the Newton iterations on the
    // 51 x 51 cube.
    // During the fall (FastSolverOptions::fall_duration) a converged step is followed by one
    // of the first step's size, not a longer one.
    if (newton_converged)
        h = time_ < fo.fall_duration ? options.time_step : std::min(fo.step_growth * h, kMaxTimeStep);
    else
        h = std::max(kStepShrink * h, kMinTimeStep);
    return true;
}

}  // namespace

std::unique_ptr<Solver> make_fast_solver(const Problem& problem, const SolverOptions& options)
{
    return std::make_unique<FastStepper>(problem, options);
}

}  // namespace woven::sim::detail
