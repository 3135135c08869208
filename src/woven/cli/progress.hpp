#pragma once
// Progress of a drape on stderr, and Ctrl-C handling: the first SIGINT asks the solver to stop
// after the current step (the state reached is written, exit code 130); a second exits at once.
#include <chrono>

#include "woven/sim/drape.hpp"

namespace woven::cli {

/// Installs the SIGINT handler (idempotent).
void install_interrupt_handler();
/// True once SIGINT was received.
bool interrupt_requested();

/// The progress callback: a bar redrawn with '\r' when stderr is a terminal, plain lines about
/// every 0.5 s otherwise. Returns false (stop) once Ctrl-C was pressed.
class Progress {
public:
    explicit Progress(int max_steps);
    bool operator()(const sim::StepInfo& info);
    /// Ends the bar line (when one was drawn).
    void finish();

private:
    bool tty_;
    int max_steps_;
    bool drawn_ = false;
    std::chrono::steady_clock::time_point start_, last_;
};

}  // namespace woven::cli
