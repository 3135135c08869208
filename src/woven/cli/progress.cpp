#include "woven/cli/progress.hpp"

#include <atomic>
#include <csignal>
#include <cstdio>
#include <string>

#include <unistd.h>

namespace woven::cli {

namespace {

std::atomic<bool> g_interrupted{false};
static_assert(std::atomic<bool>::is_always_lock_free);

extern "C" void on_sigint(int)
{
    if (g_interrupted.exchange(true)) {
        static const char msg[] = "\nwoven: interrupted again, exiting without writing outputs\n";
        [[maybe_unused]] auto n = ::write(STDERR_FILENO, msg, sizeof msg - 1);
        ::_exit(130);
    }
    static const char msg[] = "\nwoven: interrupt: stopping after this step and writing the state reached "
                              "(Ctrl-C again to quit at once)\n";
    [[maybe_unused]] auto n = ::write(STDERR_FILENO, msg, sizeof msg - 1);
}

}  // namespace

void install_interrupt_handler()
{
    struct sigaction sa {};
    sa.sa_handler = on_sigint;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART;
    sigaction(SIGINT, &sa, nullptr);
}

bool interrupt_requested() { return g_interrupted.load(); }

Progress::Progress(int max_steps)
    : tty_(::isatty(STDERR_FILENO) == 1), max_steps_(max_steps), start_(std::chrono::steady_clock::now()),
      last_(start_)
{
}

bool Progress::operator()(const sim::StepInfo& info)
{
    const auto now = std::chrono::steady_clock::now();
    const double since_last = std::chrono::duration<double>(now - last_).count();
    const double wall = std::chrono::duration<double>(now - start_).count();
    const bool draw = tty_ ? since_last >= 0.1 || info.step <= 1 : since_last >= 0.5;
    if (draw) {
        last_ = now;
        char line[256];
        std::string bar;
        if (tty_ && max_steps_ > 0) {
            const int width = 20;
            const int filled = std::min(width, info.step * width / max_steps_);
            bar = "[" + std::string(filled, '#') + std::string(width - filled, '.') + "] ";
        }
        std::snprintf(line, sizeof line, "step %d%s  t %.3f s  E %.6g J  residual %.3g m g  move %.3g m  wall %.1f s",
                      info.step, max_steps_ > 0 ? ("/" + std::to_string(max_steps_)).c_str() : "", info.time,
                      info.energy, info.max_residual_rel, info.max_move, wall);
        if (tty_) {
            std::fprintf(stderr, "\r%s%s\033[K", bar.c_str(), line);
            drawn_ = true;
        } else {
            std::fprintf(stderr, "%s\n", line);
        }
        std::fflush(stderr);
    }
    return !interrupt_requested();
}

void Progress::finish()
{
    if (tty_ && drawn_) std::fprintf(stderr, "\n");
    drawn_ = false;
}

}  // namespace woven::cli
