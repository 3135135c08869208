#include "woven/sim/drape.hpp"

#include <chrono>
#include <cmath>
#include <optional>
#include <string>

#include <omp.h>
#include <tbb/global_control.h>

#include "woven/common/error.hpp"
#include "woven/sim/linear_solver.hpp"
#include "woven/sim/solver.hpp"
#include "woven/sim/solvers.hpp"
#include "woven/sim/thread_count.hpp"

namespace woven::sim {

struct ThreadCount::State {
    int omp = 0, blas = 0;
    bool set = false, blas_set = false;
    std::optional<tbb::global_control> tbb;
};

// The drape sets the BLAS to one thread (its only BLAS work is CHOLMOD's, each factorisation on
// one thread, linear_solver.cpp: set once here, not switched at every solve).
ThreadCount::ThreadCount(int threads, int blas) : state_(std::make_unique<State>())
{
    State& s = *state_;
    s.omp = omp_get_max_threads();
    s.blas = blas_threads();
    s.set = threads > 0;
    if (s.set) {
        omp_set_num_threads(threads);
        s.tbb.emplace(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
    }
    s.blas_set = blas > 0 && s.blas > 0 && s.blas != blas;
    if (s.blas_set) set_blas_threads(blas);
}

ThreadCount::~ThreadCount()
{
    if (state_->set) omp_set_num_threads(state_->omp);
    if (state_->blas_set) set_blas_threads(state_->blas);
}

const char* to_string(SolverKind kind) { return name_of(kSolverKindNames, kind); }

std::optional<SolverKind> solver_kind_from_string(std::string_view name) { return value_named(kSolverKindNames, name); }

Solver::Solver(const Problem& problem, const SolverOptions& options)
    : problem_(problem), options_(options), held_(detail::pinned_mask(problem))
{}

Solver::~Solver() = default;

bool Solver::step(const IterationCallback& iteration)
{
    const auto start = std::chrono::steady_clock::now();
    const ThreadCount threads(options_.threads, 1);
    interrupted_ = !advance(iteration);
    if (interrupted_) converged_ = false;
    add_wall_time(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    return !interrupted_;
}

double Solver::energy() const { return problem_.model->energy(x_); }

double Solver::residual() const
{
    if (!residual_)
        residual_ = max_residual_relative(*problem_.model, *problem_.obstacles, x_, problem_.pinned, options_.contact_distance,
                                          residual_friction());
    return *residual_;
}

StepInfo Solver::step_info() const { return StepInfo{steps_, time_, energy(), max_move_, residual(), &x_}; }

void Solver::set_obstacles(geometry::ObstacleSet obstacles)
{
    for (std::size_t i = 0; i < x_.size(); ++i) {
        if (held_[i]) continue;
        const double d = obstacles.distance(x_[i]);
        if (!(d > 0))
            throw InputError("", "obstacles",
                             "particle " + std::to_string(i) + " lies inside an obstacle (distance " + std::to_string(d)
                                 + " m); the cloth is kept out of obstacles, not pushed out of them: move an obstacle in smaller steps");
    }
    own_obstacles_.reset();  // the old set goes first: the new one is not built beside a third
    own_obstacles_.emplace(std::move(obstacles));
    problem_.obstacles = &*own_obstacles_;
    obstacles_changed();
    residual_changed();
    converged_ = false;
}

Result Solver::result() const
{
    Result r;
    r.x = x_;
    r.converged = converged_;
    r.interrupted = interrupted_;
    r.steps = steps_;
    r.iterations = iterations_;
    add_counters(r);
    r.simulated_time = time_;
    r.wall_time = wall_time_;
    r.equilibrium.max_move = max_move_;
    r.equilibrium.max_residual_rel = residual();
    r.energy = problem_.model->evaluate(x_);
    return r;
}

std::unique_ptr<Solver> make_solver(const Problem& problem, const SolverOptions& options)
{
    const auto start = std::chrono::steady_clock::now();
    if (!problem.model || !problem.obstacles) throw InputError("", "problem", "needs a model and an obstacle set");
    if (static_cast<int>(problem.initial.size()) != problem.model->grid().size())
        throw InputError("", "initial", "needs one position per particle");
    for (const Vec3& p : problem.initial)
        if (!p.allFinite()) throw InputError("", "initial", "positions must be finite");
    for (int p : problem.pinned)
        if (p < 0 || p >= problem.model->grid().size()) throw InputError("", "pinned", "particle index out of range");
    const FastSolverOptions& fo = options.fast;
    if (!(fo.creep_softening > 0) || !std::isfinite(fo.creep_softening))
        throw InputError("", "fast.creep_softening", "must be a finite number above 0 (1 or less: off)");
    if (fo.creep_softening > 1 && !(fo.creep_stage_ratio > 1 && std::isfinite(fo.creep_stage_ratio)))
        throw InputError("", "fast.creep_stage_ratio", "must be a finite number above 1 while creep_softening is above 1");
    const ThreadCount threads(options.threads, 1);
    std::unique_ptr<Solver> solver =
        options.kind == SolverKind::FAST ? detail::make_fast_solver(problem, options) : detail::make_paper_solver(problem, options);
    solver->add_wall_time(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    return solver;
}

Result drape(const Problem& problem, const SolverOptions& options, const ProgressCallback& progress, const IterationCallback& iteration)
{
    const ThreadCount threads(options.threads, 1);  // once for the run (each step sets the same)
    const std::unique_ptr<Solver> solver = make_solver(problem, options);
    const int max_steps = options.max_steps > 0 ? options.max_steps : default_max_steps(options.kind);
    bool stopped = false;
    while (solver->steps() < max_steps && !solver->converged()) {
        if (!solver->step(iteration)) break;
        if (progress && solver->report_due() && !progress(solver->step_info())) {
            stopped = true;
            break;
        }
    }
    Result r = solver->result();
    if (stopped) {
        r.interrupted = true;
        r.converged = false;
    }
    return r;
}

}  // namespace woven::sim
