#pragma once
// The command line's progress display on stderr (the sink of app's progress events) and its
// SIGINT / SIGTERM handling: the first signal asks the job to stop after the current step (the
// state reached is written as a complete set marked interrupted, exit 128 + the signal: 130,
// 143); a second exits at once without publishing anything (the previous output set stays as it
// was; the new run's temporaries are removed by the next run).
#include <chrono>
#include <cstdio>
#include <map>
#include <mutex>
#include <string>
#include <thread>

#include "woven/app/progress.hpp"

namespace woven::cli {

/// Columns a progress line may take on stderr: the terminal's width less one (80 when it does
/// not say), 200 when stderr is not a terminal.
int progress_columns();
/// `line` cut to `columns` characters (an ellipsis marks the cut).
std::string fit_line(const std::string& line, int columns);
/// Seconds an activity stays silent: the environment's WOVEN_PROGRESS_DELAY_S, else 2.
double activity_delay_s();

/// Draws app's progress events. A drape's steps: on a terminal a bar that measures the residual's
/// way to the tolerance, redrawn with '\r' within the terminal's width (at most every 0.1 s, and
/// whenever it gains or loses a cell), ended with a newline; otherwise a plain line at the first
/// event and then about every 0.5 s. An activity: nothing for its first `delay_s`, then on a
/// terminal a bar that fills with the fraction done, the label and the time, redrawn in place;
/// otherwise a line "woven: LABEL: 42 % (DETAIL), 3.1 s" at most every two seconds; it ends with
/// how long it took, if it said anything. Times are the events' own (wall_s).
///
/// With `heartbeat_s` > 0 a drape's steps or an activity that has drawn nothing for that long
/// (one Newton iteration of a large cusick, one static solve of kes-test: no event for minutes)
/// is drawn again from a thread of the display's own: the last state, the time since it and the
/// time in all ("woven: still working: ..."), so that the command speaks at least every
/// `heartbeat_s` seconds while it waits (issue 53).
class ProgressDisplay {
public:
    /// `columns` 0: progress_columns() at each line.
    ProgressDisplay(std::FILE* out, bool terminal, double delay_s, int columns = 0, double heartbeat_s = 0);
    ~ProgressDisplay();
    ProgressDisplay(const ProgressDisplay&) = delete;
    ProgressDisplay& operator=(const ProgressDisplay&) = delete;
    /// Draws `e` (nothing while quiet); true (the display never stops a job).
    bool operator()(const app::ProgressEvent& e);
    void set_quiet(bool quiet)
    {
        const std::lock_guard lock(mutex_);
        quiet_ = quiet;
    }

private:
    void on_step(const app::ProgressEvent& e);
    void on_iteration(const app::ProgressEvent& e);
    void on_steps_end();
    void on_activity(const app::ProgressEvent& e);
    void on_activity_end(const app::ProgressEvent& e);
    /// True (and the step clock set to `wall_s`) when a step line is due.
    bool due(double wall_s);
    /// `compact` after the bar on a terminal (cut to its width), else `line`.
    void show(const char* compact, const char* line);
    int columns() const;

    std::FILE* out_;
    bool tty_;
    double delay_s_;
    int columns_;
    bool quiet_ = false;
    // A drape's steps.
    std::string last_compact_;  ///< the last line drawn after the bar
    double last_fraction_ = 0;  ///< the bar: the last step's way to the tolerance
    bool drawn_ = false;
    bool any_ = false;
    double last_wall_ = 0;
    /// Activities that are going: when each last drew (absent: never).
    std::map<int, double> activities_;
    // The heartbeat.
    using Clock = std::chrono::steady_clock;
    /// The state drawn again: what is going ("" when nothing is), its time at the last event.
    struct Going {
        std::string what;
        double wall_s = 0;
        Clock::time_point at;
    };
    void wrote() { last_out_ = Clock::now(); }  ///< something was drawn
    void beat();                                ///< draws the state again when it is due
    double heartbeat_s_ = 0;
    bool steps_going_ = false;
    std::map<int, Going> going_;  ///< the activities going (key: activity), -1: the drape's steps
    Clock::time_point last_out_ = Clock::now();
    std::mutex mutex_;
    std::jthread heart_;  ///< last: started when everything else is
};

/// The display on stderr as app's progress sink (for the process).
void show_progress_on_stderr();
/// No progress on stderr from now on (--quiet).
void set_progress_quiet(bool quiet);
/// Installs the SIGINT and SIGTERM handlers (the commands that write the state reached on a
/// signal: drape, cusick, experiment map --reuse).
void install_interrupt_handler();

}  // namespace woven::cli
