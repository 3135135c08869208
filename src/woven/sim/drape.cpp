#include "woven/sim/drape.hpp"

#include <cmath>
#include <optional>

#include <omp.h>
#include <tbb/global_control.h>

#include "woven/common/error.hpp"
#include "woven/sim/linear_solver.hpp"
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

Result drape(const Problem& problem, const SolverOptions& options, const ProgressCallback& progress, const IterationCallback& iteration)
{
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
    return options.kind == SolverKind::FAST ? detail::fast_drape(problem, options, progress, iteration)
                                            : detail::paper_drape(problem, options, progress, iteration);
}

}  // namespace woven::sim
