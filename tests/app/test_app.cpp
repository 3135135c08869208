// The application floor called as a C++ program calls it: typed requests in, results with the
// numbers (and the JSON written) out, the command's one-line errors for values out of range,
// progress and interrupts through the request's Monitor.
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include <fcntl.h>
#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "woven/app/cusick.hpp"
#include "woven/app/drape.hpp"
#include "woven/app/drape_report.hpp"
#include "woven/app/fit.hpp"
#include "woven/app/kes_test.hpp"
#include "woven/app/progress.hpp"
#include "woven/common/error.hpp"

using namespace woven;
namespace fs = std::filesystem;

namespace {

/// A fresh folder under the system's temporary directory, removed at the end of the test.
struct TempDir {
    fs::path path;
    TempDir()
    {
        path = fs::temp_directory_path() / ("woven-app-test-" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "-" +
                                            ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(path);
    }
    ~TempDir()
    {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
};

/// File descriptor 2 sent to `file` while alive (what the C library or a stream writes on stderr).
class StderrToFile {
public:
    explicit StderrToFile(const fs::path& file) : file_(file)
    {
        std::fflush(stderr);
        saved_ = ::dup(STDERR_FILENO);
        const int fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
        ::dup2(fd, STDERR_FILENO);
        ::close(fd);
    }
    ~StderrToFile() { restore(); }
    /// Puts stderr back and returns what was written meanwhile.
    std::string restore()
    {
        if (saved_ >= 0) {
            std::fflush(stderr);
            ::dup2(saved_, STDERR_FILENO);
            ::close(saved_);
            saved_ = -1;
        }
        std::ifstream in(file_);
        return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    }

private:
    fs::path file_;
    int saved_ = -1;
};

/// The handler installed for `signal` now.
void (*handler_of(int signal))(int)
{
    struct sigaction now {};
    ::sigaction(signal, nullptr, &now);
    return now.sa_handler;
}

/// The message of the InputError `f` throws ("" when it throws none).
template <class F>
std::string input_error(F f)
{
    try {
        f();
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(AppRequests, ValuesOutOfRangeGetTheCommandLinesOneLineError)
{
    std::vector<std::string> warnings;
    app::DrapeValues drape;
    drape.grid = std::string("2");
    EXPECT_EQ(input_error([&] { app::drape_request(drape, app::Naming::OPTIONS); }),
              "command line: --grid: expected an integer in [3, 100000], got '2'");
    app::KesTestRequest kes;
    kes.fabric = "cotton";
    kes.sigma_cm = 5;
    EXPECT_EQ(input_error([&] { app::kes_test(kes); }), "command line: --sigma-cm: expected a number in [0.02, 2], got '5'");
    kes.sigma_cm.reset();
    kes.tests = app::KesTests::SHEAR;
    kes.convergence = true;
    EXPECT_EQ(input_error([&] { app::kes_test(kes); }),
              "command line: --convergence: expected --test cantilever or all (a study of the cantilever test)");
    app::CusickRequest cusick;
    cusick.fabric = "cotton";
    cusick.specimen_cm = 0;
    EXPECT_EQ(input_error([&] { app::cusick(cusick); }), "command line: --specimen-cm: expected a number in (0, 200], got '0'");
    cusick.specimen_cm = 30;
    cusick.seeds = 2;
    cusick.seed = std::numeric_limits<std::uint64_t>::max();
    EXPECT_EQ(input_error([&] { app::cusick(cusick); }),
              "command line: --seed: expected at most 18446744073709551614 with --seeds 2 (the runs' seeds are seed .. seed + 1), got "
              "'18446744073709551615'");
    app::FitRequest fit;
    fit.fabric = "cotton";
    fit.out = "";
    EXPECT_EQ(input_error([&] { app::fit(fit); }), "command line: --out: expected a directory path, got an empty string");
}

TEST(AppRequests, OneBuilderChecksADrapesValuesOnceAndNamesThemAsTheFrontEndDoes)
{
    // A value as text (the command line, a Python str) or typed (a Python int or float): the same
    // check, the same message, naming the option or the keyword.
    const auto error = [](const app::DrapeValues& v, app::Naming naming) { return input_error([&] { app::drape_request(v, naming); }); };
    for (const app::Given<long long>& grid : {app::Given<long long>(2LL), app::Given<long long>(std::string("2"))}) {
        app::DrapeValues v;
        v.grid = grid;
        EXPECT_EQ(error(v, app::Naming::OPTIONS), "command line: --grid: expected an integer in [3, 100000], got '2'");
        EXPECT_EQ(error(v, app::Naming::KEYWORDS), "grid: expected an integer in [3, 100000], got '2'");
    }
    app::DrapeValues v;
    v.max_steps = std::string("-5");
    EXPECT_EQ(error(v, app::Naming::KEYWORDS), "max_steps: expected an integer in [0, 1000000000], got '-5'");
    v = {};
    v.perturb_m = 0.5;
    EXPECT_EQ(error(v, app::Naming::KEYWORDS), "perturb: expected a number in [0, 0.01], got '0.5'");
    EXPECT_EQ(error(v, app::Naming::OPTIONS), "command line: --perturb: expected a number in [0, 0.01], got '0.5'");
    v = {};
    v.solver = "newton";
    EXPECT_EQ(error(v, app::Naming::OPTIONS), "command line: --solver: expected fast or paper, got 'newton'");
    v = {};
    v.seed = std::string("-1");
    EXPECT_EQ(error(v, app::Naming::KEYWORDS), "seed: expected an integer in [0, 18446744073709551615], got '-1'");
    v = {};
    v.threads = 4097LL;
    EXPECT_EQ(error(v, app::Naming::KEYWORDS), "threads: expected an integer in [0, 4096], got '4097'");
    v = {};
    v.bias = "twist";
    EXPECT_EQ(error(v, app::Naming::KEYWORDS), "bias: expected threads or fabric, got 'twist'");
    v = {};
    v.start = "";
    EXPECT_EQ(error(v, app::Naming::OPTIONS), "command line: --start: expected a directory path, got an empty string");

    // Good values read into the request, text and typed alike.
    v = {};
    v.grid = std::string("21");
    v.solver = "paper";
    v.seed = std::numeric_limits<std::uint64_t>::max();
    v.threads = 2LL;
    v.max_steps = std::string("7");
    v.perturb_m = std::string("0.001");
    v.hysteresis = "friction";
    v.bias = "fabric";
    app::DrapeRequest r = app::drape_request(v, app::Naming::KEYWORDS);
    EXPECT_EQ(r.grid, 21);
    EXPECT_EQ(r.solver, sim::SolverKind::PAPER);
    EXPECT_EQ(r.seed, std::numeric_limits<std::uint64_t>::max());
    EXPECT_EQ(r.threads, 2);
    EXPECT_EQ(r.max_steps, 7);
    EXPECT_EQ(r.perturb_m, 0.001);
    EXPECT_EQ(r.hysteresis, model::Hysteresis::FRICTION);
    EXPECT_EQ(r.bias, model::BiasBending::FABRIC);
    EXPECT_FALSE(r.start);
    EXPECT_EQ(r.naming, app::Naming::KEYWORDS);

    // What prepare_drape finds later is named as the request says: friction with the paper
    // solver, a grid too large for the scene's particle limit.
    std::vector<std::string> warnings;
    EXPECT_EQ(input_error([&] { app::prepare_drape(std::move(r), warnings); }),
              "hysteresis: expected loading-branch with the paper solver, or the fast solver with friction (friction inside the weave is "
              "the fast solver's)");
    for (const app::Naming naming : {app::Naming::OPTIONS, app::Naming::KEYWORDS}) {
        v = {};
        v.grid = 100000LL;
        const std::string message = input_error([&] { app::prepare_drape(app::drape_request(v, naming), warnings); });
        EXPECT_EQ(message.substr(0, message.find(" particles")),
                  std::string(naming == app::Naming::OPTIONS ? "command line: --grid" : "grid") + ": 100000 x 100000 = 10000000000")
            << message;
    }
}

TEST(AppDrape, ATypedRequestDrapesAndReportsTheSolversCounts)
{
    const TempDir dir;
    std::vector<std::string> warnings;
    app::DrapeRequest request;
    request.scene = "cube";
    request.fabric = "cotton";
    request.grid = 11;
    request.seed = 1;
    request.threads = 1;
    const auto setup = app::prepare_drape(std::move(request), warnings);
    EXPECT_EQ(setup->grid.nu, 11);
    EXPECT_EQ(setup->grid.nv, 11);
    int steps_seen = 0;
    sim::Result result = app::solve_drape(*setup, [&](const sim::StepInfo&) { return ++steps_seen > 0; }, {});
    const app::DrapeRun run = app::finish_drape(*setup, result, false);
    EXPECT_TRUE(run.result.converged);
    EXPECT_EQ(steps_seen, run.result.steps);
    app::DrapeWriteOptions write;
    write.no_render = true;
    const nlohmann::json report = app::write_drape_outputs(run, dir.path.string(), write);
    // The counters, written once (solver_result_json) into report.json.
    EXPECT_EQ(report.at("steps").get<int>(), run.result.steps);
    EXPECT_EQ(report.at("iterations").get<int>(), run.result.iterations);
    EXPECT_EQ(report.at("factorizations").get<int>(), run.result.factorizations);
    EXPECT_EQ(report.at("converged").get<bool>(), true);
    EXPECT_NEAR(report.at("energy").at("total_J").get<double>(), run.result.energy.total(), 1e-12 * std::abs(run.result.energy.total()));
    EXPECT_LT(run.result.energy.total(), setup->energy_initial);  // the cloth fell
    for (const char* f : {"drape.obj", "drape.ply", "drape.glb", "report.json"}) EXPECT_TRUE(fs::is_regular_file(dir.path / f)) << f;
    EXPECT_FALSE(fs::exists(dir.path / "drape.png"));
    EXPECT_EQ(report.at("files").size(), 3u);
}

TEST(AppReport, SolverResultJsonHoldsTheFastSolversCountsOnlyWhenAsked)
{
    sim::Result r;
    r.converged = true;
    r.steps = 7;
    r.iterations = 19;
    r.factorizations = 11;
    r.cg_iterations = 3;
    r.wall_time = 0.25;
    const nlohmann::json fast = app::solver_result_json(r, true);
    EXPECT_EQ(fast.at("steps"), 7);
    EXPECT_EQ(fast.at("iterations"), 19);
    EXPECT_EQ(fast.at("factorizations"), 11);
    EXPECT_EQ(fast.at("cg_iterations"), 3);
    EXPECT_EQ(fast.at("softened_steps"), 0);
    EXPECT_DOUBLE_EQ(fast.at("wall_time_s").get<double>(), 0.25);
    const nlohmann::json plain = app::solver_result_json(r, false);
    EXPECT_EQ(plain.size(), 4u);  // converged, steps, iterations, wall_time_s
    EXPECT_FALSE(plain.contains("factorizations"));
    r.wall_time = std::nan("");
    EXPECT_TRUE(app::solver_result_json(r, false).at("wall_time_s").is_null());
}

TEST(AppFit, TheResultCarriesTheReportWrittenAndTheSummary)
{
    const TempDir dir;
    app::FitRequest request;
    request.fabric = "cotton";
    request.sigma_cm = 1;
    request.out = dir.path;
    std::vector<std::string> warned;
    request.on_warnings = [&](const std::vector<std::string>& w) { warned.insert(warned.end(), w.begin(), w.end()); };
    const app::FitResult r = app::fit(request);
    EXPECT_TRUE(warned.empty());
    EXPECT_EQ(r.out_dir, dir.path.string());
    EXPECT_EQ(r.files, 10);  // 3 fits, 2 x 2 bending energies, 2 trellis, report.json
    EXPECT_EQ(r.report.at("files").size(), 9u);
    EXPECT_EQ(r.report.at("fabric"), "cotton");
    EXPECT_DOUBLE_EQ(r.report.at("sigma_cm").get<double>(), 1.0);
    EXPECT_NE(r.summary.find("fabric cotton: W "), std::string::npos);
    EXPECT_NE(r.summary.find("trellis: phi_e "), std::string::npos);
    EXPECT_TRUE(fs::is_regular_file(dir.path / "report.json"));
}

TEST(AppMonitor, AJobsMonitorGetsItsEventsAndInterruptsOnlyWhileItRuns)
{
    EXPECT_FALSE(app::interrupt_requested());
    std::vector<std::string> events;
    {
        app::Monitor m;
        m.progress = [&](const app::ProgressEvent& e) {
            events.push_back(std::string(e.event) + " " + e.label);
            return true;
        };
        m.interrupt = [] { return true; };
        const app::MonitorScope scope(m);
        app::Activity a("probe");
        a.update(0.5, "half");
        EXPECT_TRUE(app::interrupt_requested());
    }
    EXPECT_EQ(events, (std::vector<std::string>{"activity probe", "activity-end probe"}));
    EXPECT_FALSE(app::interrupt_requested());  // the poll went with the job
    app::Activity after("after");
    after.update(0.5);
    EXPECT_EQ(events.size(), 2u);  // the sink went too
}

TEST(AppMonitor, ADrapesStepsAndIterationsReachTheSinkWithTheirWayToTheToleranceAndEndOnce)
{
    std::vector<app::ProgressEvent> events;
    {
        app::Monitor m;
        m.progress = [&](const app::ProgressEvent& e) {
            events.push_back(e);
            return e.step != 3;  // stop at step 3
        };
        const app::MonitorScope scope(m);
        app::Progress p(400, 1e-3);
        sim::StepInfo s;
        s.step = 1;
        s.time = 0.01;
        s.energy = -0.5;
        s.max_move = 1e-3;
        s.max_residual_rel = 1.0;
        EXPECT_TRUE(p(s));
        sim::IterationInfo it;
        it.step = 2;
        it.iteration = 1;
        it.total_iterations = 4;
        it.time_step = 0.01;
        it.residual_rel = 0.05;
        it.tolerance = 1e-4;
        EXPECT_TRUE(p.iteration(it));
        s.step = 2;
        s.max_residual_rel = 0.1;
        EXPECT_TRUE(p(s));
        s.step = 3;
        s.max_residual_rel = 0.01;
        EXPECT_FALSE(p(s));  // the sink said stop
        EXPECT_TRUE(app::interrupt_requested());
        p.finish();
    }  // p's destructor ends nothing more
    EXPECT_FALSE(app::interrupt_requested());  // the stop went with the job's monitor
    ASSERT_EQ(events.size(), 5u);
    std::vector<std::string> kinds;
    for (const auto& e : events) kinds.push_back(e.event);
    EXPECT_EQ(kinds, (std::vector<std::string>{"step", "iteration", "step", "step", "steps-end"}));
    EXPECT_EQ(events[0].max_steps, 400);
    EXPECT_DOUBLE_EQ(events[0].time_s, 0.01);
    EXPECT_DOUBLE_EQ(events[0].energy_J, -0.5);
    EXPECT_DOUBLE_EQ(events[0].move_m, 1e-3);
    EXPECT_DOUBLE_EQ(events[0].tolerance, 1e-3);
    EXPECT_DOUBLE_EQ(events[0].fraction, 0.0);
    EXPECT_EQ(events[1].total_iterations, 4);
    EXPECT_DOUBLE_EQ(events[1].time_step_s, 0.01);
    EXPECT_DOUBLE_EQ(events[1].residual, 0.05);
    EXPECT_DOUBLE_EQ(events[1].tolerance, 1e-4);
    EXPECT_NEAR(events[2].fraction, 1.0 / 3.0, 1e-12);  // log(1 / 0.1) / log(1 / 1e-3)
    EXPECT_NEAR(events[3].fraction, 2.0 / 3.0, 1e-12);
    EXPECT_NEAR(events[4].fraction, 2.0 / 3.0, 1e-12);  // the bar as it ended
    for (const auto& e : events) EXPECT_GE(e.wall_s, 0.0);
}

TEST(AppMonitor, JobsWithAnEmptyMonitorPrintNothingAndInstallNoSignalHandlers)
{
    // A display that reads this would speak at once (it waits two seconds by default).
    ::setenv("WOVEN_PROGRESS_DELAY_S", "0", 1);
    // As the test was started (SIG_IGN under a shell's background job, else SIG_DFL).
    const auto on_sigint = handler_of(SIGINT), on_sigterm = handler_of(SIGTERM);
    const TempDir dir;
    fs::create_directories(dir.path);
    StderrToFile capture(dir.path / "stderr.txt");
    // A drape as the command runs it: the steps through the step adapter, drape.png rendered.
    std::vector<std::string> warnings;
    app::DrapeRequest request;
    request.scene = "cube";
    request.fabric = "cotton";
    request.grid = 7;
    request.seed = 1;
    request.threads = 1;
    const auto setup = app::prepare_drape(std::move(request), warnings);
    app::Progress progress(setup->max_steps, setup->scene.solver.residual_tolerance);
    sim::Result result = app::solve_drape(*setup, [&](const sim::StepInfo& s) { return progress(s); },
                                          [&](const sim::IterationInfo& i) { return progress.iteration(i); });
    progress.finish();
    const app::DrapeRun run = app::finish_drape(*setup, std::move(result), false);
    app::DrapeWriteOptions write;
    write.width = 64;
    write.height = 48;
    app::write_drape_outputs(run, (dir.path / "drape").string(), write);
    // A Cusick run (it installed the SIGINT and SIGTERM handlers itself).
    app::CusickRequest cusick;
    cusick.fabric = "cotton";
    cusick.spacing_cm = 2;
    cusick.max_steps = 5;
    cusick.threads = 1;
    cusick.out = dir.path / "cusick";
    cusick.render = false;  // 1024 x 768: seconds
    const app::CusickResult c = app::cusick(cusick);
    const std::string err = capture.restore();
    EXPECT_EQ(err, "");
    EXPECT_EQ(handler_of(SIGINT), on_sigint);
    EXPECT_EQ(handler_of(SIGTERM), on_sigterm);
    EXPECT_TRUE(run.result.converged);
    EXPECT_GT(run.result.steps, 1);
    EXPECT_EQ(c.runs.size(), 1u);
    EXPECT_TRUE(fs::is_regular_file(dir.path / "drape" / "drape.png"));
    EXPECT_TRUE(fs::is_regular_file(dir.path / "cusick" / "cusick.json"));
    ::unsetenv("WOVEN_PROGRESS_DELAY_S");
}

// Issue 53 item 5: a SIGTERM or SIGINT after cusick's solve, while its pictures were made, was
// forgotten: exit 0, "interrupted": false. The interrupt asked for during the run's files (here
// by the job's poll, set from on_run, which follows them) now marks the set interrupted.
TEST(AppCusick, AnInterruptDuringTheRunsPicturesMarksTheSetInterrupted)
{
    static bool stop = false;
    stop = false;
    const TempDir dir;
    fs::create_directories(dir.path);
    app::CusickRequest cusick;
    cusick.fabric = "silk";
    cusick.specimen_cm = 12;
    cusick.disc_cm = 6;
    cusick.spacing_cm = 1;
    cusick.max_steps = 3;
    cusick.threads = 1;
    cusick.out = dir.path / "cusick";
    cusick.render = false;
    cusick.monitor.interrupt = [] { return stop; };
    cusick.on_run = [](const app::CusickRunLine&) { stop = true; };
    const app::CusickResult c = app::cusick(cusick);
    EXPECT_TRUE(c.interrupted);
    EXPECT_TRUE(c.report.at("interrupted").get<bool>());
    EXPECT_TRUE(c.report.at("runs").at(0).at("interrupted").get<bool>());
    std::ifstream in(dir.path / "cusick" / "cusick.json");
    EXPECT_TRUE(nlohmann::json::parse(in).at("interrupted").get<bool>());
}
