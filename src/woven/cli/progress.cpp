#include "woven/cli/progress.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdio>

#include <unistd.h>

namespace woven::cli {

namespace {

std::atomic<int> g_signal{0};
static_assert(std::atomic<int>::is_always_lock_free);
std::atomic<bool (*)()> g_poll{nullptr};
std::atomic<bool> g_polled{false};  ///< the poll said stop
std::atomic<bool> g_shown{true};

extern "C" void on_signal(int sig)
{
    int none = 0;
    if (!g_signal.compare_exchange_strong(none, sig)) {
        static const char msg[] = "\nwoven: interrupted again, exiting without writing outputs\n";
        [[maybe_unused]] auto n = ::write(STDERR_FILENO, msg, sizeof msg - 1);
        ::_exit(128 + sig);
    }
    static const char msg[] = "\nwoven: interrupt: stopping after this step and writing the state reached "
                              "(interrupt again to quit at once)\n";
    [[maybe_unused]] auto n = ::write(STDERR_FILENO, msg, sizeof msg - 1);
}

}  // namespace

void install_signal_handlers(void (*handler)(int))
{
    struct sigaction sa {};
    sa.sa_handler = handler;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART;
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);
}

void install_interrupt_handler() { install_signal_handlers(on_signal); }

bool interrupt_requested()
{
    if (g_signal.load() != 0 || g_polled.load()) return true;
    bool (*poll)() = g_poll.load();
    if (poll && poll()) g_polled = true;
    return g_polled.load();
}

void set_interrupt_poll(bool (*poll)())
{
    g_poll = poll;
    g_polled = false;
}

void set_progress_shown(bool shown) { g_shown = shown; }

int interrupted_exit_code()
{
    const int s = g_signal.load();
    return 128 + (s != 0 ? s : SIGINT);
}

Progress::Progress(int max_steps, double residual_tolerance)
    : tty_(::isatty(STDERR_FILENO) == 1), max_steps_(max_steps), tolerance_(residual_tolerance),
      start_(std::chrono::steady_clock::now()), last_(start_)
{
}

double Progress::fraction(double residual)
{
    if (!(residual > 0) || !std::isfinite(residual)) return residual == 0 ? 1.0 : 0.0;
    if (first_residual_ <= 0) first_residual_ = residual;
    if (!(first_residual_ > tolerance_)) return 1.0;
    const double f = std::log(first_residual_ / residual) / std::log(first_residual_ / tolerance_);
    return std::clamp(f, 0.0, 1.0);
}

bool Progress::due()
{
    const auto now = std::chrono::steady_clock::now();
    const double since_last = std::chrono::duration<double>(now - last_).count();
    if (any_ && since_last < (tty_ ? 0.1 : 0.5)) return false;
    any_ = true;
    last_ = now;
    return true;
}

void Progress::show(const char* line)
{
    if (!g_shown.load()) return;
    if (tty_) {
        const int width = 20;
        const int filled = static_cast<int>(std::lround(last_fraction_ * width));
        char bar[width + 1];
        std::fill(bar, bar + filled, '#');
        std::fill(bar + filled, bar + width, '.');
        bar[width] = '\0';
        std::fprintf(stderr, "\r[%s] %s\033[K", bar, line);
        drawn_ = true;
    } else {
        std::fprintf(stderr, "%s\n", line);
    }
    std::fflush(stderr);
}

bool Progress::operator()(const sim::StepInfo& info)
{
    last_fraction_ = fraction(info.max_residual_rel);
    if (due()) {
        const double wall = std::chrono::duration<double>(last_ - start_).count();
        // "/N" when there is a step limit, formatted here: ("/" + std::to_string(N)).c_str() made
        // GCC 12 warn falsely (-Wrestrict, in the inlined std::string concatenation).
        char limit[16] = "";
        if (max_steps_ > 0) std::snprintf(limit, sizeof limit, "/%d", max_steps_);
        char line[256];
        std::snprintf(line, sizeof line,
                      "step %d%s  t %.3f s  E %.6g J  residual %.3g m g (tolerance %.3g)  move %.3g m  wall %.1f s",
                      info.step, limit, info.time, info.energy, info.max_residual_rel, tolerance_, info.max_move, wall);
        show(line);
    }
    return !interrupt_requested();
}

bool Progress::iteration(const sim::IterationInfo& info)
{
    if (due()) {
        const double wall = std::chrono::duration<double>(last_ - start_).count();
        char line[256];
        if (std::isfinite(info.residual_rel))
            std::snprintf(line, sizeof line,
                          "step %d  Newton iteration %d (%d in all)  dt %.3g s  step residual %.3g m g (step tolerance "
                          "%.3g)  wall %.1f s",
                          info.step, info.iteration, info.total_iterations, info.time_step, info.residual_rel,
                          info.tolerance, wall);
        else
            std::snprintf(line, sizeof line, "step %d  sweep %d (%d in all)  dt %.3g s  wall %.1f s", info.step,
                          info.iteration, info.total_iterations, info.time_step, wall);
        show(line);
    }
    return !interrupt_requested();
}

void Progress::finish()
{
    if (!g_shown.load()) return;
    if (tty_ && drawn_) std::fprintf(stderr, "\n");
    drawn_ = false;
}

}  // namespace woven::cli
