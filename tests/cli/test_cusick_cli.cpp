// woven cusick on the command line: help, every bad option gives the one-line error and exit 2
// with nothing written, and a small specimen's run writes its outputs and a complete cusick.json.
#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include "cli_support.hpp"
#include "process_support.hpp"

namespace fs = std::filesystem;
using ::testing::HasSubstr;

namespace {

using Ran = woven::test::Outcome;
using CusickCli = woven::test::SpawningProcessTest;

}  // namespace

TEST_F(CusickCli, HelpAndBadOptions)
{
    const Ran h = woven("cusick --help");
    EXPECT_EQ(h.code, 0);
    EXPECT_THAT(h.out, HasSubstr("--specimen-cm"));
    EXPECT_THAT(h.out, HasSubstr("--seeds"));
    struct Bad {
        const char* args;
        const char* what;
    };
    for (const Bad b :
         {Bad{"cusick cotton --disc-cm 40", "command line: --disc-cm:"},
          Bad{"cusick cotton --specimen-cm -3", "command line: --specimen-cm:"},
          Bad{"cusick cotton --spacing-cm 4", "command line: --spacing-cm:"}, Bad{"cusick cotton --seeds 0", "command line: --seeds:"},
          Bad{"cusick cotton --clamp glue", "command line: --clamp:"},
          Bad{"cusick cotton --clamp discs --clamp-margin 1", "command line: --clamp-margin:"},
          Bad{"cusick cotton --clamp-margin 3", "command line: --clamp-margin:"},
          Bad{"cusick nosuchfabric", "nosuchfabric"}, Bad{"cusick cotton --spacing-cm abc", "command line: --spacing-cm:"}}) {
        SCOPED_TRACE(b.args);
        const Ran r = woven(std::string(b.args) + " --out o");
        EXPECT_EQ(r.code, 2);
        EXPECT_THAT(r.err, HasSubstr(b.what));
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_FALSE(fs::exists(dir_ / "o"));
    }
}

TEST_F(CusickCli, ASmallSpecimenWritesEveryOutput)
{
    // A 12 cm specimen on a 6 cm disc at 1 cm: about 110 particles, two seeds.
    const Ran r = woven("cusick silk --specimen-cm 12 --disc-cm 6 --spacing-cm 1 --seeds 2 --no-render --threads 1 --out o");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_THAT(r.out, HasSubstr("run 1/2 seed 1: DC "));
    EXPECT_THAT(r.out, HasSubstr("run 2/2 seed 2: DC "));
    for (const char* f : {"shadow-seed1.png", "shadow-seed2.png", "cusick.obj", "cusick.json"})
        EXPECT_TRUE(fs::exists(dir_ / "o" / f)) << f;
    EXPECT_FALSE(fs::exists(dir_ / "o" / "drape.png"));
    std::ifstream in(dir_ / "o" / "cusick.json");
    const auto j = nlohmann::json::parse(in);
    EXPECT_NEAR(j.at("specimen_area_m2").get<double>(), 3.14159265358979 * 0.06 * 0.06, 1e-12);
    EXPECT_DOUBLE_EQ(j.at("spacing_m").get<double>(), 0.01);
    EXPECT_EQ(j.at("clamp").get<std::string>(), "pinned");
    EXPECT_DOUBLE_EQ(j.at("clamp_radius_m").get<double>(), 0.03 + 0.005);  // r_d + sigma / 2
    EXPECT_DOUBLE_EQ(j.at("pinned_radius_m").get<double>(), 0.03 + 0.005);
    EXPECT_EQ(j.at("sandwiched_particles").get<int>(), 0);
    EXPECT_DOUBLE_EQ(j.at("perturbation_m").get<double>(), 0.001);
    ASSERT_EQ(j.at("runs").size(), 2u);
    for (const char* k : {"drape_coefficient_percent", "nodes", "node_angles_deg", "node_depths_m", "converged", "drape_coefficient_mean",
                          "drape_coefficient_std", "nodes_per_run", "runs_per_node_count"})
        EXPECT_TRUE(j.contains(k)) << k;
    const double dc = j.at("drape_coefficient_percent").get<double>();
    EXPECT_GT(dc, 0.0);
    EXPECT_LT(dc, 100.5);
    EXPECT_EQ(j.at("node_angles_deg").size(), j.at("nodes").get<size_t>());
    for (const auto& a : j.at("node_angles_deg")) {
        EXPECT_GE(a.get<double>(), 0.0);
        EXPECT_LT(a.get<double>(), 360.0);
    }
    // One output set: cusick.json names every file with its size and SHA-256, and nothing else
    // (no temporaries) is left in the directory.
    ASSERT_TRUE(j.contains("files"));
    EXPECT_EQ(j.at("files").size(), 4u);
    for (const char* f : {"shadow-seed1.png", "shadow-seed2.png", "cusick.obj", "cusick.glb"}) {
        ASSERT_TRUE(j.at("files").contains(f)) << f;
        EXPECT_EQ(j.at("files").at(f).at("bytes").get<std::uint64_t>(), fs::file_size(dir_ / "o" / f)) << f;
        EXPECT_EQ(j.at("files").at(f).at("sha256").get<std::string>().size(), 64u) << f;
    }
    int entries = 0;
    for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir_ / "o")) ++entries;
    EXPECT_EQ(entries, 5);
}

TEST_F(CusickCli, TheDiscsClampIsWrittenInTheReport)
{
    const Ran r = woven("cusick silk --specimen-cm 12 --disc-cm 6 --spacing-cm 1 --clamp discs --no-render --threads 1 --out o");
    ASSERT_EQ(r.code, 0) << r.err;
    std::ifstream in(dir_ / "o" / "cusick.json");
    const auto j = nlohmann::json::parse(in);
    EXPECT_EQ(j.at("clamp").get<std::string>(), "discs");
    EXPECT_DOUBLE_EQ(j.at("clamp_radius_m").get<double>(), 0.03);          // the discs' rim
    EXPECT_DOUBLE_EQ(j.at("pinned_radius_m").get<double>(), 0.03 - 0.015);  // r_d - 1.5 sigma
    EXPECT_GT(j.at("sandwiched_particles").get<int>(), 8);
    EXPECT_TRUE(j.at("converged").get<bool>());
}

// Ctrl-C during a run (the command line's handler, installed as the runs begin): the run stops
// after the current step, the runs done are written with interrupted: true, exit 130.
TEST_F(CusickCli, AnInterruptWritesTheRunsDone)
{
    const pid_t pid = spawn({"cusick", "cotton", "--spacing-cm", "0.7", "--threads", "1", "--no-render", "--out", "c"});
    ASSERT_GT(pid, 0);
    // Wait for the first step's line, then press Ctrl-C.
    int status = 0;
    bool exited = false;
    if (wait_for(pid, "\nstep ", status, exited)) {
        ::kill(pid, SIGINT);
        ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    }
    if (exited && WIFEXITED(status) && WEXITSTATUS(status) == 0) GTEST_SKIP() << "the run finished before its first step's line";
    const std::string said = woven::test::slurp(dir_ / "err.txt");
    ASSERT_TRUE(WIFEXITED(status)) << said;
    EXPECT_EQ(WEXITSTATUS(status), 130) << said;
    EXPECT_THAT(said, HasSubstr("woven: interrupt: stopping after this step"));
    EXPECT_THAT(said, HasSubstr("woven: interrupted; the outputs hold the runs done (not converged)\n"));
    const auto j = nlohmann::json::parse(woven::test::slurp(dir_ / "c" / "cusick.json"));
    EXPECT_TRUE(j.at("interrupted").get<bool>());
}
