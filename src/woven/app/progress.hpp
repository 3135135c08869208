#pragma once
// Progress of a drape on stderr, and the handling of SIGINT (Ctrl-C) and SIGTERM (batch
// schedulers): the first signal asks the solver to stop after the current step; the state
// reached is written as a complete set marked interrupted, and woven exits with 128 + the
// signal (130, 143). A second signal exits at once without publishing anything: the previous
// output set stays as it was (the new run's temporaries are removed by the next run).
#include <chrono>
#include <functional>
#include <mutex>
#include <string>

#include "woven/sim/drape.hpp"

namespace woven::app {

/// Installs `handler` for SIGINT and SIGTERM (system calls restarted).
void install_signal_handlers(void (*handler)(int));
/// Installs the SIGINT and SIGTERM handlers (idempotent); nothing while an interrupt poll is set
/// (the Python module: the interpreter's handlers stay).
void install_interrupt_handler();
/// True once SIGINT or SIGTERM was received.
bool interrupt_requested();
/// An extra source of interrupts, polled by interrupt_requested() (the Python module: a Ctrl-C
/// the interpreter has seen). Once it returned true, interrupt_requested() stays true until the
/// poll is set again. Null: none.
void set_interrupt_poll(bool (*poll)());
/// false: Progress draws nothing (the Python module, whose progress goes to a callable).
void set_progress_shown(bool shown);

/// What the progress display shows, for a caller that shows it another way (the Python
/// module's progress=): a drape's step ("step") or Newton iteration ("iteration"), or a long
/// wait's update ("activity": label, fraction, detail).
struct ProgressEvent {
    const char* event = "";
    std::string label;       ///< activity: what is being waited for ("kes-test cotton")
    std::string detail;      ///< activity: what is being done now
    double fraction = 0;     ///< of the way (0..1): the residual's way to the tolerance, or the activity's share done
    int step = 0;            ///< step, iteration: the step
    int max_steps = 0;       ///< step: the step limit (0: none)
    int iteration = 0;       ///< iteration: the Newton iteration in the step
    double energy_J = 0;     ///< step: the model's energy
    double residual = 0;     ///< step, iteration: the residual (m g)
    double tolerance = 0;    ///< step, iteration: its tolerance
    double wall_s = 0;       ///< since the display started
};
/// Receives each event (instead of stderr) while set; returning false stops a drape as an
/// interrupt does. From one thread at a time. Empty: none (the default).
void set_progress_sink(std::function<bool(const ProgressEvent&)> sink);
/// 128 + the first signal received (130 for SIGINT, 143 for SIGTERM); 130 when none was.
int interrupted_exit_code();

/// How a front end follows a job (a member of each job's request): its progress events instead
/// of the progress display on stderr, an interrupt poll besides SIGINT and SIGTERM (the Python
/// module: a Ctrl-C the interpreter has seen; while one is set the signal handlers are not
/// installed), and whether the display draws at all. Empty: the display on stderr, signals only.
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
    bool shown_ = true;
    std::function<bool(const ProgressEvent&)> sink_;
};

/// Columns a progress line may take on stderr: the terminal's width less one (80 when it does
/// not say), 200 when stderr is not a terminal.
int progress_columns();
/// `line` cut to `columns` characters (an ellipsis marks the cut).
std::string fit_line(const std::string& line, int columns);

/// Word on a long wait other than a drape's steps (a picture, the testers' static solves, a
/// sweep's points), on stderr: nothing for its first two seconds (the environment's
/// WOVEN_PROGRESS_DELAY_S sets another delay), then, when the work calls update(), on a terminal
/// a bar that fills with the fraction done, the label and the time, redrawn in place within the
/// terminal's width; otherwise a line "woven: LABEL: 42 % (DETAIL), 3.1 s" at most every two
/// seconds. It ends with how long it took, if it said anything. Thread-safe. Silent where
/// set_progress_shown(false).
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
    bool tty_;
    double delay_s_;
    double fraction_ = 0;
    bool shown_ = false;
    std::chrono::steady_clock::time_point start_, last_;
};

/// The progress callback: a bar redrawn with '\r' when stderr is a terminal, plain lines about
/// every 0.5 s otherwise (and always the first call). The bar measures the residual's way down
/// to the tolerance on a log scale, log(r0 / r) / log(r0 / tolerance), r0 the largest seen, so it moves as the
/// cloth settles whatever the step limit. Returns false (stop) once a signal was received.
class Progress {
public:
    Progress(int max_steps, double residual_tolerance);
    /// After each step (sim::ProgressCallback).
    bool operator()(const sim::StepInfo& info);
    /// Before each Newton iteration (fast solver) or after each phase 2 (paper solver), so that
    /// the display moves within a long step (sim::IterationCallback).
    bool iteration(const sim::IterationInfo& info);
    /// Ends the bar line (when one was drawn).
    void finish();

    /// Fraction of the way from the largest residual seen to the tolerance, in [0, 1].
    double fraction(double residual);

private:
    /// True (and the clock reset) when a line is due.
    bool due();
    /// `compact` after the bar on a terminal (cut to its width), else `line`.
    void show(const char* compact, const char* line);

    bool tty_;
    int max_steps_;
    double tolerance_;
    double peak_residual_ = 0;
    std::string last_compact_;  ///< the last line drawn after the bar
    double last_fraction_ = 0;  ///< the bar: the last step's way to the tolerance
    bool drawn_ = false;
    bool any_ = false;
    std::chrono::steady_clock::time_point start_, last_;
};

}  // namespace woven::app
