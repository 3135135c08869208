#include "woven/cli/progress_display.hpp"
#include "woven/common/format.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>

#include <sys/ioctl.h>
#include <unistd.h>

namespace woven::cli {

namespace {

/// "[#####...............]": `fraction` of `width` filled.
std::string bar(double fraction, int width)
{
    const int filled = static_cast<int>(std::lround(std::clamp(fraction, 0.0, 1.0) * width));
    return "[" + std::string(static_cast<std::size_t>(filled), '#') + std::string(static_cast<std::size_t>(width - filled), '.') + "]";
}

extern "C" void on_signal(int sig)
{
    if (!app::request_interrupt(sig)) {
        static const char msg[] = "\nwoven: interrupted again, exiting without writing outputs\n";
        [[maybe_unused]] auto n = ::write(STDERR_FILENO, msg, sizeof msg - 1);
        ::_exit(128 + sig);
    }
    static const char msg[] = "\nwoven: interrupt: stopping after this step and writing the state reached "
                              "(interrupt again to quit at once)\n";
    [[maybe_unused]] auto n = ::write(STDERR_FILENO, msg, sizeof msg - 1);
}

/// The process's display (show_progress_on_stderr); events reach it one at a time.
std::shared_ptr<ProgressDisplay> g_display;

}  // namespace

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

double activity_delay_s()
{
    if (const char* d = std::getenv("WOVEN_PROGRESS_DELAY_S")) {
        char* end = nullptr;
        const double v = std::strtod(d, &end);
        if (end != d && *end == '\0' && v >= 0 && v < 1e6) return v;
    }
    return 2.0;
}

ProgressDisplay::ProgressDisplay(std::FILE* out, bool terminal, double delay_s, int columns, double heartbeat_s)
    : out_(out), tty_(terminal), delay_s_(delay_s), columns_(columns), heartbeat_s_(heartbeat_s)
{
    if (heartbeat_s_ > 0)
        heart_ = std::jthread([this](std::stop_token stop) {
            while (!stop.stop_requested()) {
                std::this_thread::sleep_for(std::chrono::milliseconds(100));
                beat();
            }
        });
}

ProgressDisplay::~ProgressDisplay()
{
    if (heart_.joinable()) {
        heart_.request_stop();
        heart_.join();
    }
}

void ProgressDisplay::beat()
{
    const std::lock_guard lock(mutex_);
    if (quiet_ || going_.empty()) return;
    const auto now = Clock::now();
    if (std::chrono::duration<double>(now - last_out_).count() < heartbeat_s_) return;
    // The innermost state: the latest event's.
    const Going* g = nullptr;
    int which = 0;
    for (const auto& [k, v] : going_)
        if (!g || v.at > g->at) {
            g = &v;
            which = k;
        }
    const double since = std::chrono::duration<double>(now - g->at).count();
    if (which >= 0 && g->wall_s + since < delay_s_) return;  // an activity speaks only after its delay
    const std::string line = strf("still working: %s, %.1f s (%.1f s since the last update)", g->what.c_str(), g->wall_s + since, since);
    if (tty_)
        std::fprintf(out_, "\r%s\033[K", fit_line(line, columns()).c_str());
    else
        std::fprintf(out_, "woven: %s\n", line.c_str());
    std::fflush(out_);
    wrote();
}

int ProgressDisplay::columns() const { return columns_ > 0 ? columns_ : progress_columns(); }

bool ProgressDisplay::operator()(const app::ProgressEvent& e)
{
    const std::lock_guard lock(mutex_);
    if (quiet_) return true;
    const std::string kind = e.event;
    if (heartbeat_s_ > 0) {  // the state the heartbeat draws again
        char limit[16] = "";
        if (e.max_steps > 0) std::snprintf(limit, sizeof limit, "/%d", e.max_steps);
        if (kind == "step")
            going_[-1] = Going{strf("step %d%s, residual %.3g m g (tolerance %.3g)", e.step, limit, e.residual, e.tolerance), e.wall_s,
                               Clock::now()};
        else if (kind == "iteration")
            going_[-1] = Going{strf("step %d, Newton iteration %d", e.step, e.iteration), e.wall_s, Clock::now()};
        else if (kind == "steps-end")
            going_.erase(-1);
        else if (kind == "activity")
            going_[e.activity] = Going{e.label + ": " + strf("%.0f %%", 100 * e.fraction) + (e.detail.empty() ? "" : " (" + e.detail + ")"),
                                       e.wall_s, Clock::now()};
        else if (kind == "activity-end")
            going_.erase(e.activity);
    }
    if (kind == "step")
        on_step(e);
    else if (kind == "iteration")
        on_iteration(e);
    else if (kind == "steps-end")
        on_steps_end();
    else if (kind == "activity")
        on_activity(e);
    else if (kind == "activity-end")
        on_activity_end(e);
    return true;
}

bool ProgressDisplay::due(double wall_s)
{
    if (any_ && wall_s - last_wall_ < (tty_ ? 0.1 : 0.5)) return false;
    any_ = true;
    last_wall_ = wall_s;
    return true;
}

void ProgressDisplay::show(const char* compact, const char* line)
{
    if (tty_) {
        last_compact_ = compact;
        const std::string text = bar(last_fraction_, 20) + " " + compact;
        std::fprintf(out_, "\r%s\033[K", fit_line(text, columns()).c_str());
        drawn_ = true;
    } else {
        std::fprintf(out_, "%s\n", line);
    }
    std::fflush(out_);
    wrote();
}

void ProgressDisplay::on_step(const app::ProgressEvent& e)
{
    const double before = last_fraction_;
    last_fraction_ = e.fraction;
    // A terminal's bar is redrawn whenever it gains or loses a cell, whatever the clock says.
    if (tty_ && std::lround(before * 20) != std::lround(last_fraction_ * 20)) any_ = false;
    if (!due(e.wall_s)) return;
    // "/N" when there is a step limit, formatted here: ("/" + std::to_string(N)).c_str() made
    // GCC 12 warn falsely (-Wrestrict, in the inlined std::string concatenation).
    char limit[16] = "";
    if (e.max_steps > 0) std::snprintf(limit, sizeof limit, "/%d", e.max_steps);
    char line[256];
    std::snprintf(line, sizeof line, "step %d%s  t %.3f s  E %.6g J  residual %.3g m g (tolerance %.3g)  move %.3g m  wall %.1f s", e.step,
                  limit, e.time_s, e.energy_J, e.residual, e.tolerance, e.move_m, e.wall_s);
    char compact[128];
    std::snprintf(compact, sizeof compact, "step %d%s  E %.4g J  residual %.2g/%.2g  %.1f s", e.step, limit, e.energy_J, e.residual,
                  e.tolerance, e.wall_s);
    show(compact, line);
}

void ProgressDisplay::on_iteration(const app::ProgressEvent& e)
{
    last_fraction_ = e.fraction;
    if (!due(e.wall_s)) return;
    char line[256];
    char compact[128];
    if (std::isfinite(e.residual)) {
        std::snprintf(line, sizeof line,
                      "step %d  Newton iteration %d (%d in all)  dt %.3g s  step residual %.3g m g (step tolerance %.3g)  wall %.1f s",
                      e.step, e.iteration, e.total_iterations, e.time_step_s, e.residual, e.tolerance, e.wall_s);
        std::snprintf(compact, sizeof compact, "step %d  Newton %d  residual %.2g/%.2g  %.1f s", e.step, e.iteration, e.residual,
                      e.tolerance, e.wall_s);
    } else {
        std::snprintf(line, sizeof line, "step %d  sweep %d (%d in all)  dt %.3g s  wall %.1f s", e.step, e.iteration, e.total_iterations,
                      e.time_step_s, e.wall_s);
        std::snprintf(compact, sizeof compact, "step %d  sweep %d  %.1f s", e.step, e.iteration, e.wall_s);
    }
    show(compact, line);
}

void ProgressDisplay::on_steps_end()
{
    // The bar as it ended (the last step may have come between redraws).
    if (tty_ && drawn_) {
        std::fprintf(out_, "\r%s\033[K\n", fit_line(bar(last_fraction_, 20) + " " + last_compact_, columns()).c_str());
        std::fflush(out_);
    }
    // The next drape's bar starts afresh.
    last_compact_.clear();
    last_fraction_ = 0;
    drawn_ = false;
    any_ = false;
}

void ProgressDisplay::on_activity(const app::ProgressEvent& e)
{
    if (e.wall_s < delay_s_) return;
    const auto last = activities_.find(e.activity);
    if (last != activities_.end() && e.wall_s - last->second < (tty_ ? 0.1 : 2.0)) return;
    activities_[e.activity] = e.wall_s;
    const std::string percent = strf("%.0f %%", 100 * e.fraction);
    const std::string time = strf("%.1f s", e.wall_s);
    if (tty_) {
        const std::string line =
            bar(e.fraction, 20) + " " + e.label + ": " + percent + (e.detail.empty() ? "" : " " + e.detail) + ", " + time;
        std::fprintf(out_, "\r%s\033[K", fit_line(line, columns()).c_str());
    } else {
        std::fprintf(out_, "woven: %s: %s%s, %s\n", e.label.c_str(), percent.c_str(),
                     e.detail.empty() ? "" : (" (" + e.detail + ")").c_str(), time.c_str());
    }
    std::fflush(out_);
    wrote();
}

void ProgressDisplay::on_activity_end(const app::ProgressEvent& e)
{
    const auto drew = activities_.find(e.activity);
    if (drew == activities_.end()) return;
    activities_.erase(drew);
    const std::string took = strf("done in %.1f s", e.wall_s);
    if (tty_)
        std::fprintf(out_, "\r%s\033[K\n", fit_line(bar(1, 20) + " " + e.label + ": " + took, columns()).c_str());
    else
        std::fprintf(out_, "woven: %s: %s\n", e.label.c_str(), took.c_str());
    std::fflush(out_);
    wrote();
}

void show_progress_on_stderr()
{
    // The heartbeat: at least every 2 s while a drape or an activity waits (issue 53).
    g_display = std::make_shared<ProgressDisplay>(stderr, ::isatty(STDERR_FILENO) == 1, activity_delay_s(), 0, 2.0);
    app::set_progress_sink([display = g_display](const app::ProgressEvent& e) { return (*display)(e); });
}

void set_progress_quiet(bool quiet)
{
    if (g_display) g_display->set_quiet(quiet);
}

void install_interrupt_handler() { app::install_signal_handlers(on_signal); }

}  // namespace woven::cli
