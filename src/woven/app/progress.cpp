#include "woven/app/progress.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <csignal>

namespace woven::app {

namespace {

std::atomic<int> g_signal{0};
static_assert(std::atomic<int>::is_always_lock_free);
std::atomic<bool (*)()> g_poll{nullptr};
std::atomic<bool> g_polled{false};                 ///< the poll or a sink said stop
std::mutex g_sink_mutex;                           ///< one event at a time
std::function<bool(const ProgressEvent&)> g_sink;  ///< set while a front end shows progress
std::atomic<bool> g_has_sink{false};
std::atomic<int> g_activities{0};  ///< activities numbered so far

/// Sends `e` to the sink, if one is set; a sink that says stop raises the interrupt flag.
void to_sink(const ProgressEvent& e)
{
    if (!g_has_sink.load()) return;
    const std::lock_guard lock(g_sink_mutex);
    if (g_sink && !g_sink(e)) g_polled = true;
}

double seconds_since(std::chrono::steady_clock::time_point t)
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace

bool request_interrupt(int signal)
{
    int none = 0;
    return g_signal.compare_exchange_strong(none, signal);
}

void install_signal_handlers(void (*handler)(int))
{
    struct sigaction sa {};
    sa.sa_handler = handler;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART;
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);
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
    {
        const std::lock_guard lock(g_sink_mutex);
        sink_ = g_sink;
    }
    if (m.interrupt) set_interrupt_poll(m.interrupt);
    if (m.progress || m.quiet) set_progress_sink(m.progress);
}

MonitorScope::~MonitorScope()
{
    if (!active_) return;
    set_progress_sink(std::move(sink_));
    set_interrupt_poll(poll_);
}

int interrupted_exit_code()
{
    const int s = g_signal.load();
    return 128 + (s != 0 ? s : SIGINT);
}

Activity::Activity(std::string label)
    : label_(std::move(label)), id_(++g_activities), start_(std::chrono::steady_clock::now()), last_(start_)
{}

Activity::~Activity()
{
    const std::lock_guard lock(mutex_);
    if (!reported_) return;
    ProgressEvent e;
    e.event = "activity-end";
    e.label = label_;
    e.activity = id_;
    e.fraction = fraction_;
    e.wall_s = seconds_since(start_);
    to_sink(e);
}

void Activity::update(double fraction, const std::string& detail)
{
    const std::lock_guard lock(mutex_);
    if (std::isfinite(fraction)) fraction_ = std::clamp(fraction, 0.0, 1.0);
    if (!g_has_sink.load()) return;
    const auto now = std::chrono::steady_clock::now();
    if (reported_ && std::chrono::duration<double>(now - last_).count() < 0.1) return;
    reported_ = true;
    last_ = now;
    ProgressEvent e;
    e.event = "activity";
    e.label = label_;
    e.detail = detail;
    e.activity = id_;
    e.fraction = fraction_;
    e.wall_s = std::chrono::duration<double>(now - start_).count();
    to_sink(e);
}

Progress::Progress(int max_steps, double residual_tolerance)
    : max_steps_(max_steps), tolerance_(residual_tolerance), start_(std::chrono::steady_clock::now())
{}

Progress::~Progress() { finish(); }

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

ProgressEvent Progress::step_event(const sim::StepInfo& info)
{
    last_fraction_ = fraction(info.max_residual_rel);
    ProgressEvent e;
    e.event = "step";
    e.step = info.step;
    e.max_steps = max_steps_;
    e.time_s = info.time;
    e.energy_J = info.energy;
    e.residual = info.max_residual_rel;
    e.tolerance = tolerance_;
    e.move_m = info.max_move;
    e.fraction = last_fraction_;
    e.wall_s = seconds_since(start_);
    return e;
}

ProgressEvent Progress::iteration_event(const sim::IterationInfo& info) const
{
    ProgressEvent e;
    e.event = "iteration";
    e.step = info.step;
    e.iteration = info.iteration;
    e.total_iterations = info.total_iterations;
    e.time_step_s = info.time_step;
    e.residual = info.residual_rel;
    e.tolerance = info.tolerance;
    e.fraction = last_fraction_;
    e.wall_s = seconds_since(start_);
    return e;
}

bool Progress::operator()(const sim::StepInfo& info)
{
    const ProgressEvent e = step_event(info);
    if (g_has_sink.load()) {
        reported_ = true;
        to_sink(e);
    }
    return !interrupt_requested();
}

bool Progress::iteration(const sim::IterationInfo& info)
{
    if (g_has_sink.load()) {
        reported_ = true;
        to_sink(iteration_event(info));
    }
    return !interrupt_requested();
}

void Progress::finish()
{
    if (!reported_) return;
    reported_ = false;
    ProgressEvent e;
    e.event = "steps-end";
    e.step = 0;
    e.max_steps = max_steps_;
    e.tolerance = tolerance_;
    e.fraction = last_fraction_;
    e.wall_s = seconds_since(start_);
    to_sink(e);
}

}  // namespace woven::app
