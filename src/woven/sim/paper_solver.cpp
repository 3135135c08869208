// The paper's three-phase step (Sec. 3, last paragraphs; House, Breen & Getto 1992):
//   1. each particle falls freely under gravity in a viscous medium, with collisions against
//      the obstacles (a particle stopped by a surface loses its inward normal velocity);
//   2. a stochastic energy minimisation enforces the inter-particle energies. Our reading: a few
//      sweeps that move every particle along its own (analytic, where the paper estimated it
//      numerically) preconditioned gradient of E_int(x) + sum_i m/(2 dt^2) |x_i - x_i^(1)|^2,
//      plus a seeded random perturbation proportional to the move (the paper's randomness,
//      which escapes local minima and breaks symmetry); a sweep is kept only if it lowers that
//      energy. The proximity term makes phase 2 a time step (its fixed point at rest is the
//      static equilibrium of E_int + gravity) rather than a projection onto E_int's minimum;
//   3. velocities are corrected by the motion of phase 2.
// Equilibrium (Sec. 6): the largest particle movement between successive steps below a
// threshold. Not fast: kept for reproduction and comparison.
#include <chrono>
#include <cmath>
#include <random>

#include <Eigen/Cholesky>

#include "woven/common/error.hpp"
#include "woven/sim/assembly.hpp"
#include "woven/sim/contact.hpp"
#include "woven/sim/solvers.hpp"

namespace woven::sim::detail {

namespace {

/// Moves particle positions by dx with collision handling: a particle whose path meets an
/// obstacle stops at the contact point lifted to `clearance` along the normal; a particle
/// that ends closer than `clearance` is lifted to it. Returns per-particle "stopped" flags.
std::vector<char> move_with_collisions(const geometry::ObstacleSet& obstacles, Positions& x, const Positions& dx, double clearance,
                                       std::vector<Vec3, Eigen::aligned_allocator<Vec3>>* normals)
{
    std::vector<char> stopped(x.size(), 0);
    for (size_t i = 0; i < x.size(); ++i) {
        Vec3 target = x[i] + dx[i];
        for (size_t o = 0; o < obstacles.size(); ++o) {
            const geometry::Obstacle& ob = obstacles[o];
            if (auto t = ob.first_contact(x[i], target)) target = x[i] + *t * (target - x[i]);
            const geometry::ClosestPoint c = ob.closest(target);
            if (c.distance < clearance) {
                target = c.point + clearance * c.normal;
                stopped[i] = 1;
                if (normals) (*normals)[i] = c.normal;
            }
        }
        x[i] = target;
    }
    return stopped;
}

}  // namespace

Result paper_drape(const Problem& problem, const SolverOptions& options, const ProgressCallback& progress)
{
    const auto start = std::chrono::steady_clock::now();
    const model::ClothModel& model = *problem.model;
    const geometry::ObstacleSet& obstacles = *problem.obstacles;
    const int n = model.grid().size();
    const std::vector<char> pinned = pinned_mask(problem);
    const double dt = options.time_step, mass = model.particle_mass(), g = model.gravity();
    const double inertia = mass / (dt * dt);
    const double clearance = 0.5 * options.contact_distance;
    const int max_steps = options.max_steps > 0 ? options.max_steps : 200000;
    constexpr int kMaxSweeps = 60;     // phase 2 stops earlier when a sweep moves no particle by more than kSweepTolerance
    const double kSweepTolerance = 0.02 * options.move_tolerance;
    constexpr double kNoise = 0.1;       // random perturbation relative to each particle's move
    constexpr int kCalmSteps = 10;       // equilibrium: movement below threshold this many steps in a row

    std::mt19937_64 rng(options.seed);
    std::normal_distribution<double> normal(0.0, 1.0 / std::sqrt(3.0));

    Result result;
    Positions x = problem.initial, v(n, Vec3::Zero()), x1(n), dx(n), step_dx(n), trial(n), x_prev;
    std::vector<Vec3, Eigen::aligned_allocator<Vec3>> normals(n);
    DiagonalAssembly diag(n);
    int calm = 0;

    // Phase-2 objective: inter-particle energy (no gravity) + proximity to the phase-1 positions.
    auto phase2_energy = [&](const Positions& y) {
        const model::EnergyTerms e = model.evaluate(y);
        double phi = e.total() - e.gravity;
        for (int i = 0; i < n; ++i) phi += 0.5 * inertia * (y[i] - x1[i]).squaredNorm();
        return phi;
    };

    for (int step = 1; step <= max_steps; ++step) {
        x_prev = x;
        // Phase 1: free fall in a viscous medium, with collisions.
        const double drag = std::exp(-options.viscosity * dt);
        for (int i = 0; i < n; ++i) {
            v[i] = pinned[i] ? Vec3::Zero() : Vec3(drag * v[i] + Vec3(0, 0, -g * dt));
            dx[i] = v[i] * dt;
        }
        x1 = x;
        const std::vector<char> stopped = move_with_collisions(obstacles, x1, dx, clearance, &normals);
        for (int i = 0; i < n; ++i)
            if (stopped[i]) v[i] -= std::min(0.0, v[i].dot(normals[i])) * normals[i];

        // Phase 2: stochastic minimisation of the inter-particle energy.
        Positions x2 = x1;
        double phi = phase2_energy(x2);
        int sweeps = 0;
        for (int sweep = 0; sweep < kMaxSweeps; ++sweep, ++sweeps) {
            diag.clear();
            model.evaluate(x2, model::Derivatives::PROJECTED, &diag);
            for (int i = 0; i < n; ++i) {
                if (pinned[i]) {
                    dx[i].setZero();
                    continue;
                }
                const Vec3 grad = diag.gradient[i] - Vec3(0, 0, mass * g) + inertia * (x2[i] - x1[i]);
                const Mat3 H = diag.diagonal[i] + inertia * Mat3::Identity();
                dx[i] = -H.ldlt().solve(grad);
                if (sweep == 0) {  // the random perturbation; later sweeps settle it
                    const double len = dx[i].norm();
                    dx[i] += kNoise * len * Vec3(normal(rng), normal(rng), normal(rng));
                }
            }
            bool accepted = false;
            double sweep_move = 0;
            for (double alpha = 1.0; alpha > 1e-3; alpha *= 0.5) {
                trial = x2;
                for (int i = 0; i < n; ++i) step_dx[i] = alpha * dx[i];
                move_with_collisions(obstacles, trial, step_dx, clearance, nullptr);
                const double phi_trial = phase2_energy(trial);
                if (phi_trial < phi) {
                    sweep_move = max_displacement(trial, x2);
                    x2.swap(trial);
                    phi = phi_trial;
                    accepted = true;
                    break;
                }
            }
            if (!accepted || sweep_move < kSweepTolerance) break;
        }
        // Phase 3: velocity correction for the motion of phase 2.
        for (int i = 0; i < n; ++i) v[i] = pinned[i] ? Vec3::Zero() : Vec3(v[i] + (x2[i] - x1[i]) / dt);
        x.swap(x2);

        result.steps = step;
        result.iterations += sweeps;
        result.simulated_time += dt;
        result.equilibrium.max_move = max_displacement(x, x_prev);
        calm = result.equilibrium.max_move < options.move_tolerance ? calm + 1 : 0;
        const bool report = progress && (step % 50 == 0 || calm >= kCalmSteps);
        if (report || calm >= kCalmSteps)
            result.equilibrium.max_residual_rel = max_residual_relative(model, obstacles, x, problem.pinned, options.contact_distance);
        if (report) {
            const StepInfo info{step, result.simulated_time, model.energy(x), result.equilibrium.max_move, result.equilibrium.max_residual_rel};
            if (!progress(info)) {
                result.interrupted = true;
                break;
            }
        }
        if (calm >= kCalmSteps) {
            result.converged = true;
            break;
        }
    }
    result.equilibrium.max_residual_rel = max_residual_relative(model, obstacles, x, problem.pinned, options.contact_distance);
    result.x = std::move(x);
    result.energy = model.evaluate(result.x);
    result.wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
}

}  // namespace woven::sim::detail
