#include "woven/testers/static_solve.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/SparseCholesky>

#include "woven/common/error.hpp"
#include "woven/common/units.hpp"
#include "woven/sim/assembly.hpp"

namespace woven::testers {

namespace {

/// Repulsion pairs the grid's sparsity pattern does not couple (self contact of a specimen).
std::vector<model::Stencil<2>> off_pattern_pairs(const model::ClothModel& model, const Positions& x)
{
    std::vector<model::Stencil<2>> out;
    for (const model::Stencil<2>& pq : model.close_pairs(x))
        if (!model.stencils().coupled(pq[0], pq[1])) out.push_back(pq);
    return out;
}

double free_residual(const Eigen::VectorXd& g, const std::vector<char>& fixed)
{
    double r = 0;
    for (size_t i = 0; i < fixed.size(); ++i)
        if (!fixed[i]) r = std::max(r, g.segment<3>(3 * static_cast<Eigen::Index>(i)).norm());
    return r;
}

}  // namespace

StaticResult solve_static(const model::ClothModel& model, const Positions& x0, const std::vector<char>& fixed, const StaticOptions& options)
{
    const int n = model.grid().size();
    if (static_cast<int>(x0.size()) != n || static_cast<int>(fixed.size()) != n)
        throw InputError("static solve", "x0", "needs one position and one flag per particle");
    const double reference = options.reference_force > 0 ? options.reference_force : model.particle_mass() * units::kStandardGravity;
    const double sigma = model.grid().sigma;

    StaticResult result;
    result.x = x0;
    Positions& x = result.x;
    double energy = model.energy(x);
    if (!std::isfinite(energy)) throw RuntimeError("static solve: the start has infinite energy");

    std::vector<model::Stencil<2>> extra = off_pattern_pairs(model, x);
    sim::SparseAssembly system(model.stencils(), fixed, extra);
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt;
    bool analysed = false;
    int stalled = 0;
    double best = std::numeric_limits<double>::infinity(), best_energy = energy;
    double mu = 0;  // Levenberg-Marquardt shift relative to the Hessian's diagonal
    Positions trial(n);
    Eigen::VectorXd delta;

    for (int it = 0; it < options.max_iterations; ++it) {
        std::vector<model::Stencil<2>> now = off_pattern_pairs(model, x);
        if (now != extra) {
            extra = std::move(now);
            system.repattern(model.stencils(), extra);
            analysed = false;
        }
        if (options.on_iteration) options.on_iteration();
        system.clear();
        model.evaluate(x, model::Derivatives::HESSIAN, system);
        system.finish();
        const Eigen::VectorXd g = system.gradient();
        result.max_residual_rel = free_residual(g, fixed) / reference;
        result.iterations = it;
        if (result.max_residual_rel < options.residual_tolerance) {
            result.converged = true;
            return result;
        }
        // No progress for several iterations: the forces' round-off floor is reached.
        const bool progress = result.max_residual_rel < 0.9 * best || energy < best_energy - 1e-14 * std::abs(best_energy);
        stalled = progress ? 0 : stalled + 1;
        best = std::min(best, result.max_residual_rel);
        best_energy = std::min(best_energy, energy);
        if (stalled >= 6) break;
        // Newton on the exact Hessian where it is positive definite; else the projected
        // (per-term PSD) Hessian, which stays definite where a specimen is held but its exact
        // Hessian is not (a sheet sheared in plane would buckle out of it: the in-plane
        // problem is well posed, the out-of-plane directions carry no force), shifted
        // Levenberg-Marquardt style (mu diag |H|) only if that fails too.
        auto try_factor = [&](const Eigen::SparseMatrix<double>& H, double shift) {
            Eigen::SparseMatrix<double> A = H;
            if (shift > 0)
                for (int k = 0; k < 3 * n; ++k)
                    if (!fixed[k / 3]) A.coeffRef(k, k) += shift * std::max(std::abs(H.coeff(k, k)), 1e-300);
            if (!analysed) {
                ldlt.analyzePattern(A);
                analysed = true;
            }
            ldlt.factorize(A);
            if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().array() > 0).all()) return false;
            delta = ldlt.solve(-g);
            return delta.allFinite() && delta.dot(g) < 0;
        };
        bool factored = mu == 0 && try_factor(system.full_matrix(), 0.0);
        if (!factored) {
            system.clear();
            model.evaluate(x, model::Derivatives::PROJECTED, system);
            system.finish();
            const Eigen::SparseMatrix<double> projected = system.full_matrix();
            factored = try_factor(projected, mu);
            for (int attempt = 0; !factored && attempt < 40; ++attempt) {
                mu = std::max(10.0 * mu, 1e-10);
                factored = try_factor(projected, mu);
            }
        }
        if (!factored) break;

        double step_max = 0;
        for (int i = 0; i < n; ++i) step_max = std::max(step_max, delta.segment<3>(3 * i).norm());
        if (step_max < 1e-15 * sigma) {  // at round-off: stationary
            result.converged = result.max_residual_rel < 1e3 * options.residual_tolerance;
            return result;
        }
        double alpha = std::min(1.0, sigma / step_max);
        const double slope = g.dot(delta);
        bool accepted = false;
        for (int ls = 0; ls < 50; ++ls, alpha *= 0.5) {
            for (int i = 0; i < n; ++i) trial[i] = fixed[i] ? x[i] : Vec3(x[i] + alpha * delta.segment<3>(3 * i));
            const double e = model.energy(trial);
            if (std::isfinite(e) && e <= energy + 1e-4 * alpha * slope) {
                x.swap(trial);
                energy = e;
                accepted = true;
                break;
            }
        }
        if (!accepted) {
            // Near the minimum the energy's change is below its round-off: accept the largest
            // step (of a few) that lowers the largest residual force instead.
            const double r0 = result.max_residual_rel;
            alpha = std::min(1.0, sigma / step_max);
            for (int ls = 0; ls < 8 && !accepted; ++ls, alpha *= 0.5) {
                for (int i = 0; i < n; ++i) trial[i] = fixed[i] ? x[i] : Vec3(x[i] + alpha * delta.segment<3>(3 * i));
                const double e = model.energy(trial);
                if (!std::isfinite(e)) continue;
                if (free_residual(model.gradient(trial), fixed) / reference < r0) {
                    x.swap(trial);
                    energy = e;
                    accepted = true;
                }
            }
        }
        if (!accepted) {
            mu = std::max(100.0 * mu, 1e-6);  // no descent: a shorter, more gradient-like step
            continue;
        }
        mu = alpha == 1.0 ? (mu < 1e-9 ? 0.0 : mu / 10.0) : mu;
    }
    // Final residual; a solve stopped at the round-off floor counts as converged when that
    // floor is within floor_factor of the tolerance.
    const Eigen::VectorXd g = model.gradient(x);
    result.max_residual_rel = free_residual(g, fixed) / reference;
    result.converged = result.max_residual_rel < options.floor_factor * options.residual_tolerance;
    return result;
}

}  // namespace woven::testers
