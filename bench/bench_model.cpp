// Micro benchmarks of the model on the paper's 51 x 51 grid: energy, gradient, projected
// Hessian assembly, and one factorisation of the Newton matrix. Run: make bench.
#include <benchmark/benchmark.h>

#include <random>

#include <Eigen/SparseCholesky>

#include "sim/sim_fixtures.hpp"
#include "woven/sim/assembly.hpp"

namespace {

using namespace woven;

struct Setup {
    model::Grid grid = test::square_grid(51, 1.0);
    model::ClothModel model = model::make_cloth_model(test::cotton_like(), grid, {});
    Positions x;
    Setup()
    {
        x = model::flat_grid(grid, Vec3(0, 0, 0.5));
        std::mt19937 rng(1);
        std::normal_distribution<double> noise(0.0, 0.05 * grid.sigma);
        for (Vec3& p : x) p += Vec3(noise(rng), noise(rng), noise(rng));
    }
};

void energy(benchmark::State& state)
{
    Setup s;
    for (auto _ : state) benchmark::DoNotOptimize(s.model.energy(s.x));
}
BENCHMARK(energy)->Unit(benchmark::kMillisecond);

void gradient(benchmark::State& state)
{
    Setup s;
    for (auto _ : state) benchmark::DoNotOptimize(s.model.gradient(s.x));
}
BENCHMARK(gradient)->Unit(benchmark::kMillisecond);

void projected_hessian_assembly(benchmark::State& state)
{
    Setup s;
    sim::SparseAssembly system(s.model.stencils(), std::vector<char>(s.grid.size(), 0));
    for (auto _ : state) {
        system.clear();
        s.model.evaluate(s.x, model::Derivatives::PROJECTED, system);
        system.finish();
    }
}
BENCHMARK(projected_hessian_assembly)->Unit(benchmark::kMillisecond);

void newton_factorisation(benchmark::State& state)
{
    Setup s;
    sim::SparseAssembly system(s.model.stencils(), std::vector<char>(s.grid.size(), 0));
    system.clear();
    s.model.evaluate(s.x, model::Derivatives::PROJECTED, system);
    const Mat3 inertia = 1e3 * Mat3::Identity();
    for (int p = 0; p < s.grid.size(); ++p) system.add_particle(p, inertia, Vec3::Zero());
    system.finish();
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower> ldlt;
    ldlt.analyzePattern(system.matrix());
    for (auto _ : state) ldlt.factorize(system.matrix());
}
BENCHMARK(newton_factorisation)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
