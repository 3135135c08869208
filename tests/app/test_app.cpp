// The application floor called as a C++ program calls it: typed requests in, results with the
// numbers (and the JSON written) out, the command's one-line errors for values out of range,
// progress and interrupts through the request's Monitor.
#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

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
    app::DrapeRequest drape;
    drape.grid = 2;
    EXPECT_EQ(input_error([&] { app::prepare_drape(std::move(drape), warnings); }),
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
    EXPECT_EQ(events, std::vector<std::string>{"activity probe"});
    EXPECT_FALSE(app::interrupt_requested());  // the poll went with the job
    app::Activity after("after");
    after.update(0.5);
    EXPECT_EQ(events.size(), 1u);  // the sink went too
}
