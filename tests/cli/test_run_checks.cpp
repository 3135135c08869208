// Unit tests of the run checks of the application floor (issue 13 defects 2, 9, 12, 14).
#include <cmath>
#include <limits>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "woven/app/progress.hpp"
#include "woven/io/output_checks.hpp"
#include "woven/sim/resources.hpp"
#include "woven/app/run_checks.hpp"
#include "woven/common/error.hpp"

using namespace woven;

TEST(RunChecks, NoReportWithANonFiniteNumber)
{
    // a report claiming convergence with null energies was written; now the run fails.
    nlohmann::json r = {{"converged", true}, {"energy", {{"total_J", 0.5}}}, {"folds", nullptr}};
    EXPECT_NO_THROW(io::require_finite(r, "the drape", {"folds"}));
    r["energy"]["total_J"] = nullptr;  // what a non-finite number becomes in JSON
    try {
        io::require_finite(r, "the drape", {"folds"});
        FAIL();
    } catch (const RuntimeError& e) {
        EXPECT_STREQ(e.what(), "the drape ended with a non-finite number (energy.total_J); no outputs written");
    }
    r["energy"]["total_J"] = std::numeric_limits<double>::infinity();
    EXPECT_THROW(io::require_finite(r, "the drape", {"folds"}), RuntimeError);
    r["energy"]["total_J"] = 0.5;
    r["bbox"] = {{"min_m", {0.0, std::nan(""), 0.0}}};
    EXPECT_THROW(io::require_finite(r, "the drape", {"folds"}), RuntimeError);
    r.erase("bbox");
    EXPECT_THROW(io::require_finite(r, "the drape"), RuntimeError);  // folds: null, not optional here
}

TEST(RunChecks, ThreadsNeverExceedTheCoresAvailable)
{
    // the request is capped at the cores of the affinity mask (and cgroup quota).
    const int cores = sim::available_cores();
    EXPECT_GE(cores, 1);
    EXPECT_EQ(sim::threads_to_use(0), cores);
    EXPECT_EQ(sim::threads_to_use(1), 1);
    EXPECT_EQ(sim::threads_to_use(cores + 5), cores);
}

TEST(RunChecks, MemoryEstimateFollowsTheMeasuredPeaks)
{
    // the fits through the peak RSS measured with /usr/bin/time (docs/RELIABILITY.md,
    // `woven drape cube --grid N --threads T --max-steps 2 --no-render`, kB of 1024 bytes): one
    // thread 51x51 33,264 kB, 101x101 95,936, 151x151 219,584, 201x201 385,032, 251x251 617,428;
    // two threads 35,984, 108,152, 243,012, 420,800, 677,316. The estimate carries a 25 % margin.
    const double margin = 1.25;
    const int sides[] = {51, 101, 151, 201, 251};
    const double one_thread_kB[] = {33264, 95936, 219584, 385032, 617428};
    const double two_threads_kB[] = {35984, 108152, 243012, 420800, 677316};
    for (int k = 0; k < 5; ++k) {
        const long long n = static_cast<long long>(sides[k]) * sides[k];
        const double one = one_thread_kB[k] * 1024, two = two_threads_kB[k] * 1024;
        EXPECT_NEAR(sim::estimate_drape_memory(n, 1).resident_bytes / margin, one, 0.03 * one) << sides[k];
        EXPECT_NEAR(sim::estimate_drape_memory(n, 2).resident_bytes / margin, two, 0.03 * two) << sides[k];
        EXPECT_GT(sim::estimate_drape_memory(n, 4).resident_bytes, 1.05 * two) << sides[k];  // never under, margin included
    }
    const auto e = sim::estimate_drape_memory(4'000'000, 2);
    EXPECT_GT(e.address_space_bytes, e.resident_bytes);
    EXPECT_GT(e.resident_bytes, 50e9);  // --grid 2000 cannot run in 4 GB
}

TEST(RunChecks, ProgressBarFollowsTheResidualDownToTheTolerance)
{
    // the bar measures log(r0 / r) / log(r0 / tolerance), whatever the step limit.
    app::Progress p(400, 1e-3);
    EXPECT_DOUBLE_EQ(p.fraction(1.0), 0.0);  // the first residual seen
    EXPECT_NEAR(p.fraction(0.1), 1.0 / 3.0, 1e-12);
    EXPECT_NEAR(p.fraction(0.01), 2.0 / 3.0, 1e-12);
    EXPECT_DOUBLE_EQ(p.fraction(1e-3), 1.0);
    EXPECT_DOUBLE_EQ(p.fraction(1e-5), 1.0);
    EXPECT_DOUBLE_EQ(p.fraction(10.0), 0.0);
    EXPECT_DOUBLE_EQ(p.fraction(std::nan("")), 0.0);
}

TEST(RunChecks, FittingErrorsNameTheFabricFile)
{
    // "fabric 'probe': bending.warp: ..." from the fitting stage names the file.
    try {
        app::with_fabric_source("probe.toml", [] { throw InputError("fabric 'probe'", "bending.warp", "cannot fit"); });
        FAIL();
    } catch (const InputError& e) {
        EXPECT_STREQ(e.what(), "probe.toml: bending.warp: cannot fit");
    }
    EXPECT_EQ(app::fabric_source("cotton"), "built-in fabric 'cotton'");
    EXPECT_EQ(app::fabric_source("a/b.toml"), "a/b.toml");
}

// Every table a command writes is checked finite before it is published.
TEST(RunChecks, NoTableWithANonFiniteNumber)
{
    EXPECT_NO_THROW(io::require_finite_csv("a,b\n1,2\nsimulated,3e-5\n", "t.csv", "fit"));
    EXPECT_NO_THROW(io::require_finite_csv("nan,inf\n1,2\n", "t.csv", "fit"));  // a header is text
    for (const char* bad : {"a,b\n1,2\n3,-nan\n", "a,b\n1,2\n3,nan\n", "a,b\n1,2\ninf,4\n", "a,b\n1,2\n3,-inf\n"}) {
        try {
            io::require_finite_csv(bad, "t.csv", "fit");
            ADD_FAILURE() << bad;
        } catch (const RuntimeError& e) {
            EXPECT_STREQ(e.what(), "fit ended with a non-finite number (t.csv, line 3); no outputs written");
        }
    }
}

TEST(MemoryCheck, ShortOfFreeMemoryNowIsARuntimeFailureNotBadInput)
{
    // Within the lasting limits (none here) but above what is free at this moment: exit 1,
    // "not enough memory now" (a dip in MemAvailable refused a default drape as bad input).
    const sim::MemoryEstimate e = sim::estimate_drape_memory(51 * 51, 1);
    try {
        app::check_memory_estimate(e, sim::MemoryLimit{}, 1e6, 2601, "scene.toml", "cloth.grid", "use a smaller grid");
        FAIL();
    } catch (const RuntimeError& err) {
        EXPECT_THAT(std::string(err.what()), ::testing::HasSubstr("not enough memory now: 2601 particles need about"));
    }
    // Above a lasting limit: bad input, naming the field.
    EXPECT_THROW(app::check_memory_estimate(e, sim::MemoryLimit{1e6, "cgroup memory.max", false}, 1e12, 2601, "scene.toml", "cloth.grid",
                                            "use a smaller grid"),
                 InputError);
    EXPECT_NO_THROW(app::check_memory_estimate(e, sim::MemoryLimit{1e12, "cgroup memory.max", false}, 1e12, 2601, "scene.toml",
                                               "cloth.grid", "use a smaller grid"));
    // The machine's memory is a lasting limit; MemAvailable is not one.
    EXPECT_NE(sim::memory_limit().what, "MemAvailable");
}
