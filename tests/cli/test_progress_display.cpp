// The command line's progress display (cli/progress_display.hpp) fed app's events: what a user
// sees on stderr, on a terminal and in a log, with the events' own times.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "woven/app/progress.hpp"
#include "woven/cli/progress_display.hpp"

using namespace woven;

namespace {

/// What a display writes, read back.
class Written {
public:
    Written() : file_(std::tmpfile()) {}
    ~Written() { std::fclose(file_); }
    std::FILE* file() const { return file_; }
    std::string text() const
    {
        std::fflush(file_);
        std::string s(static_cast<std::size_t>(std::ftell(file_)), '\0');
        std::rewind(file_);
        const std::size_t n = std::fread(s.data(), 1, s.size(), file_);
        s.resize(n);
        return s;
    }

private:
    std::FILE* file_;
};

app::ProgressEvent step(int step, double fraction, double wall_s)
{
    app::ProgressEvent e;
    e.event = "step";
    e.step = step;
    e.max_steps = 400;
    e.time_s = 0.01 * step;
    e.energy_J = -0.25;
    e.residual = 0.5;
    e.tolerance = 1e-3;
    e.move_m = 2e-4;
    e.fraction = fraction;
    e.wall_s = wall_s;
    return e;
}

app::ProgressEvent activity(const char* kind, int id, const char* label, double fraction, const char* detail, double wall_s)
{
    app::ProgressEvent e;
    e.event = kind;
    e.activity = id;
    e.label = label;
    e.detail = detail;
    e.fraction = fraction;
    e.wall_s = wall_s;
    return e;
}

}  // namespace

TEST(ProgressDisplay, StepsInALogArePlainLinesAboutEveryHalfSecond)
{
    const Written out;
    cli::ProgressDisplay d(out.file(), false, 2.0);
    EXPECT_TRUE(d(step(1, 0.0, 0.07)));
    d(step(2, 0.1, 0.3));  // within 0.5 s of the last line
    d(step(3, 0.2, 0.6));
    app::ProgressEvent it;
    it.event = "iteration";
    it.step = 4;
    it.iteration = 2;
    it.total_iterations = 9;
    it.time_step_s = 0.01;
    it.residual = 0.02;
    it.tolerance = 0.001;
    it.wall_s = 1.2;
    d(it);
    it.residual = std::nan("");  // the paper solver's phase 2
    it.wall_s = 1.8;
    d(it);
    app::ProgressEvent end;
    end.event = "steps-end";
    d(end);  // nothing on a log
    EXPECT_EQ(out.text(),
              "step 1/400  t 0.010 s  E -0.25 J  residual 0.5 m g (tolerance 0.001)  move 0.0002 m  wall 0.1 s\n"
              "step 3/400  t 0.030 s  E -0.25 J  residual 0.5 m g (tolerance 0.001)  move 0.0002 m  wall 0.6 s\n"
              "step 4  Newton iteration 2 (9 in all)  dt 0.01 s  step residual 0.02 m g (step tolerance 0.001)  wall 1.2 s\n"
              "step 4  sweep 2 (9 in all)  dt 0.01 s  wall 1.8 s\n");
}

TEST(ProgressDisplay, ATerminalsBarIsRedrawnWhenItGainsACellAndEndsWithTheLastStep)
{
    const Written out;
    cli::ProgressDisplay d(out.file(), true, 2.0, 79);
    d(step(1, 0.0, 0.00));
    d(step(2, 0.01, 0.02));  // same cell, within 0.1 s: not drawn
    d(step(3, 0.5, 0.04));   // ten cells more: drawn at once
    d(step(4, 0.52, 0.06));  // same cell, within 0.1 s: not drawn, but the end shows it
    app::ProgressEvent end;
    end.event = "steps-end";
    d(end);
    d(step(1, 0.0, 0.01));  // the next drape's bar starts afresh
    const std::string bar0 = "[....................] ", bar10 = "[##########..........] ";
    EXPECT_EQ(out.text(),
              "\r" + bar0 + "step 1/400  E -0.25 J  residual 0.5/0.001  0.0 s\033[K" +       //
                  "\r" + bar10 + "step 3/400  E -0.25 J  residual 0.5/0.001  0.0 s\033[K" +  //
                  "\r" + bar10 + "step 3/400  E -0.25 J  residual 0.5/0.001  0.0 s\033[K\n" + "\r" + bar0
                  + "step 1/400  E -0.25 J  residual 0.5/0.001  0.0 s\033[K");
    // Cut to the terminal's width.
    const Written narrow;
    cli::ProgressDisplay n(narrow.file(), true, 2.0, 30);
    n(step(1, 0.0, 0.0));
    EXPECT_EQ(narrow.text(), "\r" + cli::fit_line(bar0 + "step 1/400  E -0.25 J  residual 0.5/0.001  0.0 s", 30) + "\033[K");
    EXPECT_EQ(cli::fit_line(bar0 + "step 1/400  E -0.25 J", 30), "[....................] step...");
    EXPECT_EQ(cli::fit_line("short", 30), "short");
}

TEST(ProgressDisplay, AnActivityWaitsForItsDelaySpeaksEveryTwoSecondsAndSaysHowLongItTook)
{
    const Written out;
    cli::ProgressDisplay d(out.file(), false, 2.0);
    d(activity("activity", 1, "quick", 0.5, "", 0.1));  // under the delay
    d(activity("activity-end", 1, "quick", 1.0, "", 0.3));
    d(activity("activity", 2, "kes-test cotton", 0.25, "bending warp", 2.1));
    d(activity("activity", 3, "rendering a.png (64 x 48)", 0.5, "", 2.2));    // nested: its own clock
    d(activity("activity", 2, "kes-test cotton", 0.3, "bending warp", 3.0));  // under two seconds
    d(activity("activity", 2, "kes-test cotton", 0.5, "", 4.2));
    d(activity("activity-end", 3, "rendering a.png (64 x 48)", 1.0, "", 2.6));
    d(activity("activity-end", 2, "kes-test cotton", 1.0, "", 5.04));
    EXPECT_EQ(out.text(),
              "woven: kes-test cotton: 25 % (bending warp), 2.1 s\n"
              "woven: rendering a.png (64 x 48): 50 %, 2.2 s\n"
              "woven: kes-test cotton: 50 %, 4.2 s\n"
              "woven: rendering a.png (64 x 48): done in 2.6 s\n"
              "woven: kes-test cotton: done in 5.0 s\n");
    // On a terminal: a bar redrawn in place, a full one at the end.
    const Written tty;
    cli::ProgressDisplay t(tty.file(), true, 0.0, 79);
    t(activity("activity", 7, "drawing", 0.5, "cotton, side", 0.0));
    t(activity("activity-end", 7, "drawing", 0.5, "", 1.24));
    EXPECT_EQ(tty.text(),
              "\r[##########..........] drawing: 50 % cotton, side, 0.0 s\033[K"
              "\r[####################] drawing: done in 1.2 s\033[K\n");
}

TEST(ProgressDisplay, QuietDrawsNothing)
{
    const Written out;
    cli::ProgressDisplay d(out.file(), false, 0.0);
    d.set_quiet(true);
    d(step(1, 0.0, 0.0));
    d(activity("activity", 1, "x", 0.5, "", 1.0));
    d(activity("activity-end", 1, "x", 1.0, "", 1.5));
    EXPECT_EQ(out.text(), "");
}

// Issue 53 item 9: kes-test sat at 67 % for 163 s and cusick was silent for 14 s (one static
// solve, one Newton iteration: no event). The display's heartbeat draws the last state again
// when nothing was drawn for heartbeat_s; nothing when nothing is going or an activity is within
// its delay.
TEST(ProgressDisplay, AWaitWithoutEventsIsDrawnAgainEveryHeartbeat)
{
    const Written out;
    {
        cli::ProgressDisplay d(out.file(), false, 2.0, 0, 0.3);
        d(activity("activity", 1, "kes-test cotton", 0.67, "", 0.1));  // within its 2 s delay
        std::this_thread::sleep_for(std::chrono::milliseconds(700));
        d(step(1, 0.0, 0.05));
        std::this_thread::sleep_for(std::chrono::milliseconds(1100));  // no event: beats at about 0.3, 0.6, 0.9 s
        app::ProgressEvent end;
        end.event = "steps-end";
        d(end);
        d(activity("activity-end", 1, "kes-test cotton", 1, "", 0.2));
        std::this_thread::sleep_for(std::chrono::milliseconds(700));  // nothing going: silent
    }
    const std::string text = out.text();
    const std::string beat = "woven: still working: step 1/400, residual 0.5 m g (tolerance 0.001), ";
    int beats = 0;
    for (std::size_t at = text.find(beat); at != std::string::npos; at = text.find(beat, at + 1)) ++beats;
    EXPECT_GE(beats, 2) << text;
    EXPECT_LE(beats, 4) << text;
    EXPECT_EQ(text.find("kes-test"), std::string::npos) << text;
    EXPECT_EQ(text.rfind("woven: still working: step 1/400"), text.rfind("woven: still working")) << text;
    EXPECT_EQ(text.find("step 1/400  t 0.010 s"), 0u) << text;
}
