#pragma once
// A drape in progress, stepped by its user: the state of one solver (fast or paper, drape.hpp),
// built from a problem and a start. sim::drape is this loop:
//
//     const std::unique_ptr<sim::Solver> solver = sim::make_solver(problem, options);
//     while (!solver->converged() && solver->steps() < max_steps) {
//         if (!solver->step()) break;                 // false: an iteration callback said stop
//         std::printf("%d %g J\n", solver->steps(), solver->energy());
//         if (solver->steps() == 10) solver->set_obstacles(moved);  // between steps
//     }
//     const sim::Result result = solver->result();
//
// The solver keeps the problem's model, its obstacles (until set_obstacles replaces them) and
// pinned particles by reference or value as Problem holds them; the model must outlive it. It
// updates the slip states of an evolving model (ClothRef::evolving) after each step, and no
// one else does while it runs.
#include <memory>
#include <optional>

#include "woven/sim/drape.hpp"

namespace woven::sim {

class Solver {
public:
    virtual ~Solver();
    Solver(const Solver&) = delete;
    Solver& operator=(const Solver&) = delete;

    /// One step: fast, one backward-Euler step solved to its Newton tolerance (its size grows
    /// as the cloth settles); paper, the three phases of Sec. 3. `iteration` is called within
    /// the step (IterationCallback); when it returns false the step stops where it is and
    /// step() returns false (fast: the step is left unfinished and not counted; paper: the
    /// callback comes after the step). A step after convergence goes on from
    /// the state reached (a changed obstacle, say). With SolverOptions::threads > 0 the step
    /// runs on that many threads. Throws what the model throws.
    bool step(const IterationCallback& iteration = {});

    /// The particles' positions now (m).
    const Positions& positions() const { return x_; }
    /// The model's energy at positions() (J; computed on each call).
    double energy() const;
    /// Largest residual force on a free particle over its weight (Equilibrium::max_residual_rel).
    double residual() const;
    /// Largest particle move over the last step (m).
    double max_move() const { return max_move_; }
    /// Simulated time so far (s).
    double time() const { return time_; }
    /// Steps completed.
    int steps() const { return steps_; }
    /// At rest after the last step (fast: residual below tolerance on the cloth's own threads;
    /// paper: the movement test of Sec. 6). False again after set_obstacles.
    bool converged() const { return converged_; }
    /// Whether a progress display shows this step: every step (fast), every progress_every
    /// steps and at rest (paper).
    virtual bool report_due() const { return true; }
    /// The state as a StepInfo (x points at positions()).
    StepInfo step_info() const;

    const model::ClothModel& model() const { return *problem_.model; }
    const geometry::ObstacleSet& obstacles() const { return *problem_.obstacles; }
    const SolverOptions& options() const { return options_; }
    /// Replaces the obstacles between steps (the solver keeps its own). InputError on field
    /// "obstacles" when a free particle lies inside one of them (the solver keeps particles
    /// out of obstacles; it cannot take one from inside): move an obstacle in smaller steps.
    void set_obstacles(geometry::ObstacleSet obstacles);

    /// The run so far as a Result: positions, counters, equilibrium, energy terms; converged as
    /// converged(); interrupted when the last step() was stopped; wall_time the time spent in
    /// construction and steps.
    Result result() const;

protected:
    friend std::unique_ptr<Solver> make_solver(const Problem& problem, const SolverOptions& options);
    Solver(const Problem& problem, const SolverOptions& options);
    /// One step of the solver; false when `iteration` stopped it.
    virtual bool advance(const IterationCallback& iteration) = 0;
    /// Counters only the solver keeps (factorisations, CG iterations, softened steps).
    virtual void add_counters(Result&) const {}
    /// The friction the residual is measured with (the fast solver's obstacle friction).
    virtual double residual_friction() const { return 0.0; }
    /// Called after set_obstacles has replaced problem_.obstacles.
    virtual void obstacles_changed() {}
    /// Marks the residual as out of date (computed when next asked for).
    void residual_changed() const { residual_.reset(); }
    void set_residual(double r) const { residual_ = r; }
    void add_wall_time(double s) { wall_time_ += s; }

    Problem problem_;
    SolverOptions options_;
    std::vector<char> held_;  ///< pinned or inactive: held in place
    Positions x_;
    int steps_ = 0, iterations_ = 0;
    double time_ = 0, max_move_ = 0;
    bool converged_ = false, interrupted_ = false;

private:
    std::optional<geometry::ObstacleSet> own_obstacles_;  ///< set_obstacles's
    mutable std::optional<double> residual_;
    double wall_time_ = 0;
};

/// The solver of options.kind for the problem, at its start (the fast solver's start perturbed
/// as SolverOptions::perturbation says). InputError on a problem or option it cannot take.
std::unique_ptr<Solver> make_solver(const Problem& problem, const SolverOptions& options);

}  // namespace woven::sim
