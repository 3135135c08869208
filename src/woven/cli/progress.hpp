#pragma once
// Progress of a drape on stderr, and the handling of SIGINT (Ctrl-C) and SIGTERM (batch
// schedulers): the first signal asks the solver to stop after the current step; the state
// reached is written as a complete set marked interrupted, and woven exits with 128 + the
// signal (130, 143). A second signal exits at once without publishing anything: the previous
// output set stays as it was (the new run's temporaries are removed by the next run).
#include <chrono>

#include "woven/sim/drape.hpp"

namespace woven::cli {

/// Installs `handler` for SIGINT and SIGTERM (system calls restarted).
void install_signal_handlers(void (*handler)(int));
/// Installs the SIGINT and SIGTERM handlers (idempotent).
void install_interrupt_handler();
/// True once SIGINT or SIGTERM was received.
bool interrupt_requested();
/// An extra source of interrupts, polled by interrupt_requested() (the Python module: a Ctrl-C
/// the interpreter has seen). Once it returned true, interrupt_requested() stays true until the
/// poll is set again. Null: none.
void set_interrupt_poll(bool (*poll)());
/// false: Progress draws nothing (the Python module, whose progress goes to a callable).
void set_progress_shown(bool shown);
/// 128 + the first signal received (130 for SIGINT, 143 for SIGTERM); 130 when none was.
int interrupted_exit_code();

/// The progress callback: a bar redrawn with '\r' when stderr is a terminal, plain lines about
/// every 0.5 s otherwise (and always the first call). The bar measures the residual's way down
/// to the tolerance on a log scale, log(r0 / r) / log(r0 / tolerance), so it moves as the
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

    /// Fraction of the way from the first residual seen to the tolerance, in [0, 1].
    double fraction(double residual);

private:
    /// True (and the clock reset) when a line is due.
    bool due();
    void show(const char* line);

    bool tty_;
    int max_steps_;
    double tolerance_;
    double first_residual_ = 0;
    double last_fraction_ = 0;  ///< the bar: the last step's way to the tolerance
    bool drawn_ = false;
    bool any_ = false;
    std::chrono::steady_clock::time_point start_, last_;
};

}  // namespace woven::cli
