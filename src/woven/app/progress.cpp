#include "woven/app/progress.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <optional>

#include <sys/ioctl.h>
#include <unistd.h>

namespace woven::app {

namespace {

std::atomic<int> g_signal{0};
static_assert(std::atomic<int>::is_always_lock_free);
std::atomic<bool (*)()> g_poll{nullptr};
std::atomic<bool> g_polled{false};  ///< the poll said stop
std::atomic<bool> g_shown{true};
std::mutex g_sink_mutex;                              ///< one event at a time
std::function<bool(const ProgressEvent&)> g_sink;    ///< set while a caller shows progress itself
std::atomic<bool> g_has_sink{false};

/// Sends `e` to the sink, if one is set; false (and the interrupt flag set) when it says stop.
/// Returns std::nullopt without a sink.
std::optional<bool> to_sink(const ProgressEvent& e)
{
    if (!g_has_sink.load()) return std::nullopt;
    const std::lock_guard lock(g_sink_mutex);
    if (!g_sink) return std::nullopt;
    const bool go = g_sink(e);
    if (!go) g_polled = true;
    return go;
}

/// "[#####...............]": `fraction` of `width` filled.
std::string bar(double fraction, int width)
{
    const int filled = static_cast<int>(std::lround(std::clamp(fraction, 0.0, 1.0) * width));
    return "[" + std::string(static_cast<std::size_t>(filled), '#') + std::string(static_cast<std::size_t>(width - filled), '.') + "]";
}

double seconds_since(std::chrono::steady_clock::time_point t)
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

std::string format(const char* fmt, double a, double b = 0)
{
    char buf[64];
    std::snprintf(buf, sizeof buf, fmt, a, b);
    return buf;
}

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

void install_interrupt_handler()
{
    // Not under an interrupt poll (the Python module): the interpreter keeps its own Ctrl-C
    // handling (woven.cusick replaced it for the rest of the process, and a second Ctrl-C then
    // exited the interpreter).
    if (g_poll.load() != nullptr) return;
    install_signal_handlers(on_signal);
}

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

void set_progress_sink(std::function<bool(const ProgressEvent&)> sink)
{
    const std::lock_guard lock(g_sink_mutex);
    g_sink = std::move(sink);
    g_has_sink = static_cast<bool>(g_sink);
}

MonitorScope::MonitorScope(const Monitor& m)
{
    active_ = m.progress || m.interrupt || m.quiet;
    if (!active_) return;
    poll_ = g_poll.load();
    shown_ = g_shown.load();
    {
        const std::lock_guard lock(g_sink_mutex);
        sink_ = g_sink;
    }
    if (m.interrupt) set_interrupt_poll(m.interrupt);
    if (m.quiet) set_progress_shown(false);
    if (m.progress) set_progress_sink(m.progress);
}

MonitorScope::~MonitorScope()
{
    if (!active_) return;
    set_progress_sink(std::move(sink_));
    set_interrupt_poll(poll_);
    set_progress_shown(shown_);
}

int interrupted_exit_code()
{
    const int s = g_signal.load();
    return 128 + (s != 0 ? s : SIGINT);
}

int progress_columns()
{
    if (::isatty(STDERR_FILENO) != 1) return 200;
    struct winsize w {};
    if (::ioctl(STDERR_FILENO, TIOCGWINSZ, &w) == 0 && w.ws_col >= 20) return w.ws_col - 1;
    return 79;
}

std::string fit_line(const std::string& line, int columns)
{
    if (columns < 4 || static_cast<int>(line.size()) <= columns) return line;
    return line.substr(0, static_cast<std::size_t>(columns - 3)) + "...";
}

Activity::Activity(std::string label)
    : label_(std::move(label)), tty_(::isatty(STDERR_FILENO) == 1), delay_s_(2.0), start_(std::chrono::steady_clock::now()),
      last_(start_)
{
    if (const char* d = std::getenv("WOVEN_PROGRESS_DELAY_S")) {
        char* end = nullptr;
        const double v = std::strtod(d, &end);
        if (end != d && *end == '\0' && v >= 0 && v < 1e6) delay_s_ = v;
    }
}

Activity::~Activity()
{
    const std::lock_guard lock(mutex_);
    if (!shown_ || g_has_sink.load() || !g_shown.load()) return;
    const std::string took = format("done in %.1f s", seconds_since(start_));
    if (tty_)
        std::fprintf(stderr, "\r%s\033[K\n", fit_line(bar(1, 20) + " " + label_ + ": " + took, progress_columns()).c_str());
    else
        std::fprintf(stderr, "woven: %s: %s\n", label_.c_str(), took.c_str());
    std::fflush(stderr);
}

void Activity::update(double fraction, const std::string& detail)
{
    const std::lock_guard lock(mutex_);
    if (std::isfinite(fraction)) fraction_ = std::clamp(fraction, 0.0, 1.0);
    const auto now = std::chrono::steady_clock::now();
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    if (g_has_sink.load()) {
        if (shown_ && std::chrono::duration<double>(now - last_).count() < 0.1) return;
        shown_ = true;
        last_ = now;
        ProgressEvent e;
        e.event = "activity";
        e.label = label_;
        e.detail = detail;
        e.fraction = fraction_;
        e.wall_s = elapsed;
        to_sink(e);
        return;
    }
    if (!g_shown.load()) return;
    if (elapsed < delay_s_) return;
    const double since = std::chrono::duration<double>(now - last_).count();
    if (shown_ && since < (tty_ ? 0.1 : 2.0)) return;
    shown_ = true;
    last_ = now;
    const std::string percent = format("%.0f %%", 100 * fraction_);
    const std::string time = format("%.1f s", elapsed);
    if (tty_) {
        const std::string line = bar(fraction_, 20) + " " + label_ + ": " + percent + (detail.empty() ? "" : " " + detail) + ", " + time;
        std::fprintf(stderr, "\r%s\033[K", fit_line(line, progress_columns()).c_str());
    } else {
        std::fprintf(stderr, "woven: %s: %s%s, %s\n", label_.c_str(), percent.c_str(), detail.empty() ? "" : (" (" + detail + ")").c_str(),
                     time.c_str());
    }
    std::fflush(stderr);
}

Progress::Progress(int max_steps, double residual_tolerance)
    : tty_(::isatty(STDERR_FILENO) == 1), max_steps_(max_steps), tolerance_(residual_tolerance),
      start_(std::chrono::steady_clock::now()), last_(start_)
{
}

double Progress::fraction(double residual)
{
    if (!(residual > 0) || !std::isfinite(residual)) return residual == 0 ? 1.0 : 0.0;
    // From the largest residual seen: a falling cloth's residual rises well above the first
    // step's before it settles (the bar stayed empty until the end when measured from the first).
    peak_residual_ = std::max(peak_residual_, residual);
    if (!(peak_residual_ > tolerance_)) return 1.0;
    const double f = std::log(peak_residual_ / residual) / std::log(peak_residual_ / tolerance_);
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

void Progress::show(const char* compact, const char* line)
{
    if (!g_shown.load()) return;
    if (tty_) {
        last_compact_ = compact;
        const std::string text = bar(last_fraction_, 20) + " " + compact;
        std::fprintf(stderr, "\r%s\033[K", fit_line(text, progress_columns()).c_str());
        drawn_ = true;
    } else {
        std::fprintf(stderr, "%s\n", line);
    }
    std::fflush(stderr);
}

bool Progress::operator()(const sim::StepInfo& info)
{
    const double before = last_fraction_;
    last_fraction_ = fraction(info.max_residual_rel);
    // A terminal's bar is redrawn whenever it gains or loses a cell, whatever the clock says.
    const bool cell_changed = tty_ && std::lround(before * 20) != std::lround(last_fraction_ * 20);
    if (cell_changed) any_ = false;
    if (g_has_sink.load()) {
        ProgressEvent e;
        e.event = "step";
        e.step = info.step;
        e.max_steps = max_steps_;
        e.energy_J = info.energy;
        e.residual = info.max_residual_rel;
        e.tolerance = tolerance_;
        e.fraction = last_fraction_;
        e.wall_s = seconds_since(start_);
        to_sink(e);
        return !interrupt_requested();
    }
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
        char compact[128];
        std::snprintf(compact, sizeof compact, "step %d%s  E %.4g J  residual %.2g/%.2g  %.1f s", info.step, limit, info.energy,
                      info.max_residual_rel, tolerance_, wall);
        show(compact, line);
    }
    return !interrupt_requested();
}

bool Progress::iteration(const sim::IterationInfo& info)
{
    if (g_has_sink.load()) {
        ProgressEvent e;
        e.event = "iteration";
        e.step = info.step;
        e.iteration = info.iteration;
        e.residual = info.residual_rel;
        e.tolerance = info.tolerance;
        e.fraction = last_fraction_;
        e.wall_s = seconds_since(start_);
        to_sink(e);
        return !interrupt_requested();
    }
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
        char compact[128];
        if (std::isfinite(info.residual_rel))
            std::snprintf(compact, sizeof compact, "step %d  Newton %d  residual %.2g/%.2g  %.1f s", info.step, info.iteration,
                          info.residual_rel, info.tolerance, wall);
        else
            std::snprintf(compact, sizeof compact, "step %d  sweep %d  %.1f s", info.step, info.iteration, wall);
        show(compact, line);
    }
    return !interrupt_requested();
}

void Progress::finish()
{
    if (!g_shown.load()) return;
    // The bar as it ended (the last step may have come between redraws).
    if (tty_ && drawn_)
        std::fprintf(stderr, "\r%s\033[K\n", fit_line(bar(last_fraction_, 20) + " " + last_compact_, progress_columns()).c_str());
    drawn_ = false;
}

}  // namespace woven::app
