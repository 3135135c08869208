// Micro benchmarks of the model and the fast solver's pieces on n x n grids (n = 51, 101, 201;
// the argument of each benchmark): energy, gradient, projected Hessian assembly, the neighbour
// search, one Newton linear solve (analysis + factorisation + solve, the numeric factorisation
// alone, and a solve reusing the factor), and
// an obstacle query on a triangle mesh (the chair). Times per call; "per particle" counters
// divide by n^2. Run: make bench, or build/bench/bench_model --benchmark_filter=...
#include <memory>
#include <random>
#include <string>

#include <Eigen/CholmodSupport>
#include <omp.h>
#include <tbb/global_control.h>
#include <benchmark/benchmark.h>

#include "sim/sim_fixtures.hpp"
#include "woven/common/embedded.hpp"
#include "woven/geometry/mesh_obstacle.hpp"
#include "woven/io/embedded_data.hpp"
#include "woven/io/mesh_file.hpp"
#include "woven/sim/assembly.hpp"
#include "woven/sim/linear_solver.hpp"
#include "woven/sim/split_cholesky.hpp"

namespace {

using namespace woven;

/// oneTBB limited to `threads` for a benchmark's lifetime: the model's local terms run on
/// oneTBB's threads, and these benchmarks measure one (the split ones their argument). The BLAS
/// runs on its caller's thread, as in a drape (sim/drape.cpp): a threaded OpenBLAS called from
/// both sides of the split at once made newton_solve_split/201/2 take 102 ms instead of 26.6.
struct TbbThreads {
    explicit TbbThreads(int threads) : limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads))
    {
        sim::set_blas_threads(1);
    }
    tbb::global_control limit;
};

/// The paper's 1 m cloth on an n x n grid, flat at 0.5 m with a 5 % sigma jitter (so that every
/// term, repulsion included, is active).
struct Setup {
    model::Grid grid;
    model::ClothModel model;
    Positions x;
    explicit Setup(int n) : grid(test::square_grid(n, 1.0)), model(model::make_cloth_model(test::cotton_like(), grid, {}))
    {
        x = model::flat_grid(grid, Vec3(0, 0, 0.5));
        std::mt19937 rng(1);
        std::normal_distribution<double> noise(0.0, 0.05 * grid.sigma);
        for (Vec3& p : x) p += Vec3(noise(rng), noise(rng), noise(rng));
    }
    /// The Newton matrix of a dynamic step (h = 1/60 s) at x.
    sim::SparseAssembly newton_system() const
    {
        sim::SparseAssembly system(model.stencils(), std::vector<char>(grid.size(), 0));
        system.clear();
        model.evaluate(x, model::Derivatives::PROJECTED, system);
        const double h = 1.0 / 60.0;
        const Mat3 inertia = model.particle_mass() / (h * h) * Mat3::Identity();
        for (int p = 0; p < grid.size(); ++p) system.add_particle(p, inertia, Vec3::Zero());
        system.finish();
        return system;
    }
};

void per_particle(benchmark::State& state, int particles)
{
    state.counters["per_particle"] =
        benchmark::Counter(static_cast<double>(particles), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void energy(benchmark::State& state)
{
    const TbbThreads one(1);
    const Setup s(static_cast<int>(state.range(0)));
    for (auto _ : state) benchmark::DoNotOptimize(s.model.energy(s.x));
    per_particle(state, s.grid.size());
}

void gradient(benchmark::State& state)
{
    const TbbThreads one(1);
    const Setup s(static_cast<int>(state.range(0)));
    for (auto _ : state) benchmark::DoNotOptimize(s.model.gradient(s.x));
    per_particle(state, s.grid.size());
}

void projected_hessian_assembly(benchmark::State& state)
{
    const TbbThreads one(1);
    const Setup s(static_cast<int>(state.range(0)));
    sim::SparseAssembly system(s.model.stencils(), std::vector<char>(s.grid.size(), 0));
    for (auto _ : state) {
        system.clear();
        s.model.evaluate(s.x, model::Derivatives::PROJECTED, system);
        system.finish();
    }
    per_particle(state, s.grid.size());
}

void close_pairs(benchmark::State& state)
{
    const TbbThreads one(1);
    const Setup s(static_cast<int>(state.range(0)));
    for (auto _ : state) benchmark::DoNotOptimize(s.model.close_pairs(s.x));
    per_particle(state, s.grid.size());
}

/// One Newton linear solve from scratch: symbolic analysis, factorisation and solve (the
/// nested-dissection order is the assembly's, made once per pattern).
void newton_solve_factorise(benchmark::State& state)
{
    const TbbThreads one(1);
    const Setup s(static_cast<int>(state.range(0)));
    const sim::SparseAssembly system = s.newton_system();
    Eigen::VectorXd rhs = Eigen::VectorXd::Ones(system.matrix().rows()), d;
    for (auto _ : state) {
        sim::NewtonLinearSolver linear;
        linear.solve(system.matrix(), rhs, d);
        benchmark::DoNotOptimize(d.data());
    }
    per_particle(state, s.grid.size());
}

/// The numeric factorisation alone, the symbolic analysis done once, as in a drape (which
/// analyses again only when the self-contact pattern changes). CHOLMOD supernodal on the
/// assembly's matrix as it is stored: its lower triangle in the nested-dissection order
/// (assembly.hpp, linear_solver.cpp).
void newton_refactorise(benchmark::State& state)
{
    const TbbThreads one(1);
    const Setup s(static_cast<int>(state.range(0)));
    const sim::SparseAssembly system = s.newton_system();
    const Eigen::SparseMatrix<double>& lower = system.matrix();
    Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> llt;
    llt.cholmod().nmethods = 1;
    llt.cholmod().method[0].ordering = CHOLMOD_NATURAL;
    llt.cholmod().postorder = 0;
    llt.analyzePattern(lower);
    // CHOLMOD's supernodal loops would start their own OpenMP threads: one thread, as in the
    // drape (linear_solver.cpp's SerialOpenMP).
    const int levels = omp_get_max_active_levels();
    omp_set_max_active_levels(0);
    for (auto _ : state) {
        llt.factorize(lower);
        if (llt.info() != Eigen::Success) state.SkipWithError("not positive definite");
    }
    omp_set_max_active_levels(levels);
    per_particle(state, s.grid.size());
    state.counters["factor_nonzeros"] = llt.cholmod().lnz;  // of L, from the analysis
    state.counters["factor_flops"] = llt.cholmod().fl;
    state.counters["matrix_nonzeros"] = static_cast<double>(lower.nonZeros());
}

/// The Newton matrix of an n x n grid (arg 0) and its split factor, or nullptr (the benchmark
/// skipped) when it does not split.
struct SplitSetup {
    Setup setup;
    sim::SparseAssembly system;
    std::unique_ptr<sim::SplitCholesky> factor;
    explicit SplitSetup(benchmark::State& state) : setup(static_cast<int>(state.range(0))), system(setup.newton_system())
    {
        const auto split = sim::SplitCholesky::find(system.matrix(), 1000, 4096);
        if (split)
            factor = std::make_unique<sim::SplitCholesky>(system.matrix(), *split);
        else
            state.SkipWithError("no split");
    }
};

/// The same numeric factorisation split at the top separator (sim/split_cholesky.hpp), its two
/// sides on two threads (as the drape factorises with two threads or more), or on one (arg 1):
/// against newton_refactorise, the separator's dense work and the threads' gain.
void newton_refactorise_split(benchmark::State& state)
{
    const TbbThreads threads(static_cast<int>(state.range(1)));
    const SplitSetup s(state);
    if (!s.factor) return;
    const bool parallel = state.range(1) == 2;
    const Eigen::SparseMatrix<double>& lower = s.system.matrix();
    const int levels = omp_get_max_active_levels();
    omp_set_max_active_levels(0);
    for (auto _ : state)
        if (!s.factor->factorize(lower, 0, parallel)) state.SkipWithError("not positive definite");
    omp_set_max_active_levels(levels);
    per_particle(state, s.setup.grid.size());
    const sim::SplitCholesky::Split& split = s.factor->split();
    state.counters["separator"] = static_cast<double>(lower.cols() - split.separator_begin);
    state.counters["sides"] = static_cast<double>(split.side_end) / split.separator_begin;
}

/// A solve with the split factor (one CG iteration's preconditioner), on `arg 1` threads.
void newton_solve_split(benchmark::State& state)
{
    const TbbThreads threads(static_cast<int>(state.range(1)));
    const SplitSetup s(state);
    if (!s.factor) return;
    const bool parallel = state.range(1) == 2;
    const Eigen::VectorXd rhs = Eigen::VectorXd::Ones(s.system.matrix().rows());
    if (!s.factor->factorize(s.system.matrix(), 0, parallel)) state.SkipWithError("not positive definite");
    for (auto _ : state) benchmark::DoNotOptimize(s.factor->solve(rhs, parallel).data());
    per_particle(state, s.setup.grid.size());
}

/// The CG's product y = H p with the Newton matrix (its stored lower triangle): Eigen's
/// symmetric product on one thread (arg 1 = 1), the split's on two (arg 1 = 2).
void newton_product(benchmark::State& state)
{
    const TbbThreads threads(static_cast<int>(state.range(1)));
    const SplitSetup s(state);
    if (!s.factor) return;
    const Eigen::SparseMatrix<double>& lower = s.system.matrix();
    const Eigen::VectorXd p = Eigen::VectorXd::Ones(lower.rows());
    Eigen::VectorXd y(lower.rows());
    for (auto _ : state) {
        if (state.range(1) == 1) y.noalias() = lower.selfadjointView<Eigen::Lower>() * p;
        else sim::SplitCholesky::symmetric_product(lower, s.factor->split(), p, y, true);
        benchmark::DoNotOptimize(y.data());
    }
    per_particle(state, s.setup.grid.size());
}

/// One Newton linear solve reusing the last factorisation (the common case: CG preconditioned
/// by the factor of a nearby matrix; here the same matrix).
void newton_solve_reuse(benchmark::State& state)
{
    const TbbThreads one(1);
    const Setup s(static_cast<int>(state.range(0)));
    const sim::SparseAssembly system = s.newton_system();
    Eigen::VectorXd rhs = Eigen::VectorXd::Ones(system.matrix().rows()), d;
    sim::NewtonLinearSolver linear;
    linear.solve(system.matrix(), rhs, d);
    for (auto _ : state) {
        linear.solve(system.matrix(), rhs, d);
        benchmark::DoNotOptimize(d.data());
    }
    per_particle(state, s.grid.size());
}

/// Closest-point queries on the chair mesh (Embree BVH) for the particles of an n x n cloth
/// spread over the chair's bounding box.
void mesh_obstacle_closest(benchmark::State& state)
{
    const TbbThreads one(1);
    const int n = static_cast<int>(state.range(0));
    std::string_view obj;
    for (const EmbeddedFile& f : io::data::embedded_files())
        if (f.path == "assets/chair.obj") obj = f.data;
    if (obj.empty()) {
        state.SkipWithError("assets/chair.obj is not embedded");
        return;
    }
    const geometry::MeshObstacle chair(io::parse_obj_mesh(obj, "assets/chair.obj"));
    const geometry::Aabb box = chair.bounds();
    Positions x;
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int k = 0; k < n * n; ++k) x.push_back(box.lo + Vec3(u(rng), u(rng), u(rng)).cwiseProduct(box.hi - box.lo));
    for (auto _ : state)
        for (const Vec3& p : x) benchmark::DoNotOptimize(chair.closest(p));
    per_particle(state, n * n);
}

#define WOVEN_GRIDS ->Arg(51)->Arg(101)->Arg(201)->Unit(benchmark::kMillisecond)
BENCHMARK(energy) WOVEN_GRIDS;
BENCHMARK(gradient) WOVEN_GRIDS;
BENCHMARK(projected_hessian_assembly) WOVEN_GRIDS;
BENCHMARK(close_pairs) WOVEN_GRIDS;
BENCHMARK(newton_solve_factorise) WOVEN_GRIDS;
BENCHMARK(newton_refactorise) WOVEN_GRIDS;
BENCHMARK(newton_solve_reuse) WOVEN_GRIDS;
#define WOVEN_SPLIT_GRIDS ->Args({51, 1})->Args({51, 2})->Args({101, 1})->Args({101, 2})->Args({201, 1})->Args({201, 2})->Unit(benchmark::kMillisecond)
BENCHMARK(newton_refactorise_split) WOVEN_SPLIT_GRIDS;
BENCHMARK(newton_solve_split) WOVEN_SPLIT_GRIDS;
BENCHMARK(newton_product) WOVEN_SPLIT_GRIDS;
BENCHMARK(mesh_obstacle_closest) WOVEN_GRIDS;

}  // namespace

BENCHMARK_MAIN();
