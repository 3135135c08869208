#include "woven/sim/drape.hpp"

#include <cmath>
#include <optional>

#include <omp.h>
#include <tbb/global_control.h>

#include "woven/common/error.hpp"
#include "woven/sim/linear_solver.hpp"
#include "woven/sim/solvers.hpp"

namespace woven::sim {

namespace {

/// Sets the thread count of oneTBB (the solvers' threads) and OpenMP for its lifetime
/// (threads > 0) and the BLAS's to one (the solvers' only BLAS work is CHOLMOD's, each
/// factorisation on one thread, linear_solver.cpp: set once here, not switched at every solve),
/// restoring both after.
class ThreadCount {
public:
    explicit ThreadCount(int threads) : omp_(omp_get_max_threads()), blas_(blas_threads()), set_(threads > 0)
    {
        if (set_) {
            omp_set_num_threads(threads);
            tbb_.emplace(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
        }
        if (blas_ > 1) set_blas_threads(1);
    }
    ~ThreadCount()
    {
        if (set_) omp_set_num_threads(omp_);
        if (blas_ > 1) set_blas_threads(blas_);
    }
    ThreadCount(const ThreadCount&) = delete;
    ThreadCount& operator=(const ThreadCount&) = delete;

private:
    int omp_, blas_;
    bool set_;
    std::optional<tbb::global_control> tbb_;
};

}  // namespace

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
    if (problem.slip && problem.slip != problem.model)
        throw InputError("", "slip", "must be the problem's model (its friction states evolve with the drape)");
    const FastSolverOptions& fo = options.fast;
    if (!(fo.creep_softening > 0) || !std::isfinite(fo.creep_softening))
        throw InputError("", "fast.creep_softening", "must be a finite number above 0 (1 or less: off)");
    if (fo.creep_softening > 1 && !(fo.creep_stage_ratio > 1 && std::isfinite(fo.creep_stage_ratio)))
        throw InputError("", "fast.creep_stage_ratio", "must be a finite number above 1 while creep_softening is above 1");
    const ThreadCount threads(options.threads);
    return options.kind == SolverKind::FAST ? detail::fast_drape(problem, options, progress, iteration)
                                            : detail::paper_drape(problem, options, progress, iteration);
}

}  // namespace woven::sim
