#pragma once
// Progress and interruption as the jobs give them to a front end: events to the progress sink in
// force (the command line's display on stderr, a Python callable) and an interrupt flag that a
// front end raises (the command line's SIGINT / SIGTERM handlers, cli/progress_display.hpp) or a
// poll it sets. The first interrupt asks the solver to stop after the current step; the state
// reached is written as a complete set marked interrupted. With no sink set, app prints nothing;
// it installs no signal handler of its own (but the sweep's, while its children run).
#include <chrono>
#include <functional>
#include <mutex>
#include <string>

#include "woven/sim/drape.hpp"

namespace woven::app {

/// Asks the running job to stop as a signal does (async-signal-safe: a front end's handler calls
/// it). Returns false when one was asked for already (the first signal is the one kept).
bool request_interrupt(int signal);
/// True once an interrupt was asked for, the poll said stop or a sink returned false.
bool interrupt_requested();
/// An extra source of interrupts, polled by interrupt_requested() (the Python module: a Ctrl-C
/// the interpreter has seen). Once it returned true, interrupt_requested() stays true until the
/// poll is set again. Null: none.
void set_interrupt_poll(bool (*poll)());
/// 128 + the signal of the first request_interrupt (130 for SIGINT, 143 for SIGTERM); 130 when
/// there was none.
int interrupted_exit_code();
/// Installs `handler` for SIGINT and SIGTERM (system calls restarted): for a front end, and for
/// the sweep, which takes the signals over while its children run.
void install_signal_handlers(void (*handler)(int));

/// What a job reports of its progress, enough for a front end to draw it:
/// - "step" after each step of a drape, "iteration" before each Newton iteration (fast solver)
///   or after each phase 2 (paper solver), "steps-end" when the drape's steps are over (after
///   at least one step or iteration was reported);
/// - "activity" an update of a long wait other than a drape's steps (a picture, the testers'
///   static solves, a sweep's points), at most every 0.1 s; "activity-end" when it is over
///   (after at least one update was reported). Activities may nest: `activity` tells them apart.
struct ProgressEvent {
    const char* event = "";
    std::string label;         ///< activity: what is being waited for ("kes-test cotton")
    std::string detail;        ///< activity: what is being done now
    int activity = 0;          ///< activity: its number in the process
    double fraction = 0;       ///< of the way (0..1): the residual's way to the tolerance (log scale), or the activity's share done
    int step = 0;              ///< step, iteration: the step
    int max_steps = 0;         ///< step: the step limit (0: none)
    int iteration = 0;         ///< iteration: the Newton iteration (or the paper solver's sweep) in the step
    int total_iterations = 0;  ///< iteration: the iterations of the whole drape so far
    double time_s = 0;         ///< step: the simulated time
    double time_step_s = 0;    ///< iteration: the step's size (s)
    double energy_J = 0;       ///< step: the model's energy
    double residual = 0;       ///< step, iteration: the residual (m g; an iteration's is not finite for the paper solver)
    double tolerance = 0;      ///< step, iteration: its tolerance
    double move_m = 0;         ///< step: the largest particle move
    double wall_s = 0;         ///< since the drape's steps or the activity started
};
/// Receives each event while set; returning false stops a drape as an interrupt does. Called
/// from one thread at a time. Empty: none (the default; nothing is shown).
void set_progress_sink(std::function<bool(const ProgressEvent&)> sink);

/// How a front end follows a job (a member of each job's request): its progress events (instead
/// of the sink in force), an interrupt poll besides request_interrupt (the Python module: a Ctrl-C
/// the interpreter has seen), and quiet: no events to the sink in force while the job runs.
/// Empty: the sink and the interrupts in force.
struct Monitor {
    std::function<bool(const ProgressEvent&)> progress;  ///< false: stop the job as an interrupt does
    bool (*interrupt)() = nullptr;
    bool quiet = false;
};
/// A job's Monitor in force for its lifetime (a job installs its request's at its start); the
/// previous one is restored after. An empty Monitor changes nothing.
class MonitorScope {
public:
    explicit MonitorScope(const Monitor& monitor);
    ~MonitorScope();
    MonitorScope(const MonitorScope&) = delete;
    MonitorScope& operator=(const MonitorScope&) = delete;

private:
    bool active_ = false;
    bool (*poll_)() = nullptr;
    std::function<bool(const ProgressEvent&)> sink_;
};

/// A long wait other than a drape's steps, reported to the sink: "activity" events when the work
/// calls update() (the first at once, then at most every 0.1 s), "activity-end" when it ends (if
/// it reported anything). Thread-safe.
class Activity {
public:
    explicit Activity(std::string label);
    ~Activity();
    Activity(const Activity&) = delete;
    Activity& operator=(const Activity&) = delete;
    /// The fraction done (clamped to 0..1) and what is being done now.
    void update(double fraction, const std::string& detail = {});

private:
    std::mutex mutex_;
    std::string label_;
    int id_;
    double fraction_ = 0;
    bool reported_ = false;
    std::chrono::steady_clock::time_point start_, last_;
};

/// A drape's progress callbacks, reported to the sink as "step" and "iteration" events. The
/// fraction measures the residual's way down to the tolerance on a log scale,
/// log(r0 / r) / log(r0 / tolerance), r0 the largest seen, so that it moves as the cloth settles
/// whatever the step limit. Each returns false (stop) once an interrupt was asked for.
class Progress {
public:
    Progress(int max_steps, double residual_tolerance);
    ~Progress();  ///< finish()
    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;
    /// After each step (sim::ProgressCallback).
    bool operator()(const sim::StepInfo& info);
    /// Before each Newton iteration (fast solver) or after each phase 2 (paper solver), so that
    /// a display moves within a long step (sim::IterationCallback).
    bool iteration(const sim::IterationInfo& info);
    /// "steps-end" (once, if anything was reported).
    void finish();

    /// The "step" and "iteration" events of operator() and iteration(), made without sending
    /// them (a front end with its own callbacks: the Python module's woven.drape).
    ProgressEvent step_event(const sim::StepInfo& info);
    ProgressEvent iteration_event(const sim::IterationInfo& info) const;

    /// Fraction of the way from the largest residual seen to the tolerance, in [0, 1].
    double fraction(double residual);

private:
    int max_steps_;
    double tolerance_;
    double peak_residual_ = 0;
    double last_fraction_ = 0;  ///< the last step's way to the tolerance
    bool reported_ = false;
    std::chrono::steady_clock::time_point start_;
};

}  // namespace woven::app
