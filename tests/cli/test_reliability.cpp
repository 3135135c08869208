// Reliability, run on the real binary (WOVEN_BINARY) in a temporary directory: no input crashes it, no bad input reports success, no run leaves a
// mixed or partial result. Tiny grids and few steps: the suite also runs under the sanitizers.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "woven/io/sha256.hpp"

#include "process_support.hpp"

namespace fs = std::filesystem;

namespace {

using woven::test::Outcome;
using woven::test::quote;
using woven::test::slurp;
using woven::test::write;

using woven::test::kTinyScene;
using woven::test::documented_form;
using woven::test::one_line;
using woven::test::replace;

const std::string kFabric = R"(name = "probe"
source = "test"
areal_density_mg_cm2 = 15
[bending.warp]
B = 0.05
2HB = 0.02
[bending.weft]
B = 0.04
2HB = 0.02
[shear]
G = 0.5
2HG = 0.5
2HG5 = 1.0
)";

class Reliability : public woven::test::SpawningProcessTest {};

nlohmann::json report(const fs::path& p) { return nlohmann::json::parse(slurp(p)); }

}  // namespace

// a 50,000-part dotted header overflowed toml++'s stack (SIGSEGV).
TEST_F(Reliability, DeepTomlKeysAreOneLineExitTwo)
{
    std::string deep = "[a";
    for (int k = 0; k < 50000; ++k) deep += ".a";
    write(dir_ / "deep.toml", deep + "]\n");
    for (const char* cmd : {"fit deep.toml", "drape deep.toml --no-render"}) {
        const Outcome r = woven(cmd);
        EXPECT_EQ(r.code, 2) << cmd;
        EXPECT_EQ(r.err, "woven: error: deep.toml:1: TOML: a key or table header of more than 32 dotted parts\n") << cmd;
    }
    EXPECT_FALSE(fs::exists(dir_ / "out"));
}

// implausible scene numbers are bad input naming the field, never a run.
TEST_F(Reliability, ImplausibleSceneNumbersAreBadInput)
{
    const std::vector<std::pair<std::string, std::string>> cases = {
        {replace(kTinyScene, "size_m = [0.3, 0.3]", "size_m = [1e300, 1e300]"), "cloth.size_m"},
        {replace(kTinyScene, "size_m = [0.3, 0.3]", "size_m = [1e-300, 1e-300]"), "cloth.size_m"},
        {replace(kTinyScene, "height_m = 0.12", "height_m = 9.2e18"), "cloth.height_m"},
        {kTinyScene + "[solver]\ncontact_distance_m = 1e300\n", "solver.contact_distance_m"},
        {kTinyScene + "[[obstacle]]\ntype = \"mesh\"\nfile = \"assets/chair.obj\"\ntranslate_m = [1e308, 0, 0]\n",
         "obstacle[3].translate_m"},
    };
    for (const auto& [text, field] : cases) {
        write(dir_ / "s.toml", text);
        const Outcome r = woven("drape s.toml --no-render --out res");
        EXPECT_EQ(r.code, 2) << field << ": " << r.err;
        EXPECT_EQ(r.err.rfind("woven: error: s.toml: " + field + ": expected ", 0), 0u) << r.err;
        EXPECT_TRUE(one_line(r.err)) << r.err;
        EXPECT_FALSE(fs::exists(dir_ / "res")) << field;
    }
}

// OBJ numbers are checked; the message names the mesh file and line.
TEST_F(Reliability, ObjNumbersAreChecked)
{
    const std::string scene = kTinyScene + "[[obstacle]]\ntype = \"mesh\"\nfile = \"m.obj\"\ntranslate_m = [0.5, 0.5, 0]\n";
    write(dir_ / "s.toml", scene);
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"v 0 0 0\nv nan 0 0\nv 0 0.1 0\nf 1 2 3\n", "m.obj:2: v: expected a number"},
        {"v 0 0 0\nv 0.1 0 0\nv 0 inf 0\nf 1 2 3\n", "m.obj:3: v: expected a number"},
        {"v 0 0 0\nv 0.1 0 0\nv 0 zz 0\nf 1 2 3\n", "m.obj:3: v: expected a number"},
        {"v 0 0 0\nv 0.1 0 0\nv 0 0.1 0\nf 1 2 4294967299\n", "m.obj:4: f: expected a vertex index"},
    };
    for (const auto& [obj, expected] : cases) {
        write(dir_ / "m.obj", obj);
        const Outcome r = woven("drape s.toml --no-render --out res");
        EXPECT_EQ(r.code, 2) << r.err;
        EXPECT_NE(r.err.find("s.toml: obstacle[3].file: ./" + expected), std::string::npos) << r.err;
        EXPECT_TRUE(one_line(r.err)) << r.err;
    }
}

// a fabric's name never makes a path that leaves out/.
TEST_F(Reliability, FabricNamesCannotEscapeTheOutputFolder)
{
    write(dir_ / "a.toml", replace(kFabric, "name = \"probe\"", "name = \"x/../../../escaped\""));
    write(dir_ / "b.toml", replace(kFabric, "name = \"probe\"", "name = \"/abs/path\""));
    const fs::path inside = dir_ / "w" / "v";
    fs::create_directories(inside);
    fs::copy(dir_ / "a.toml", inside / "a.toml");
    fs::copy(dir_ / "b.toml", inside / "b.toml");
    const Outcome a = woven("fit a.toml", "cd w/v && ");
    ASSERT_EQ(a.code, 0) << a.err;
    EXPECT_TRUE(fs::is_directory(inside / "out" / "fit-x_.._.._.._escaped"));
    const Outcome b = woven("fit b.toml", "cd w/v && ");
    ASSERT_EQ(b.code, 0) << b.err;
    EXPECT_TRUE(fs::is_directory(inside / "out" / "fit-_abs_path"));
    // Nothing outside w/v/out.
    for (const auto& e : fs::recursive_directory_iterator(dir_)) {
        const std::string p = e.path().string();
        if (p.rfind((inside / "out").string(), 0) == 0) continue;
        EXPECT_TRUE(e.path() == dir_ / "a.toml" || e.path() == dir_ / "b.toml" || e.path() == dir_ / "w" ||
                    e.path() == inside || e.path() == inside / "a.toml" || e.path() == inside / "b.toml")
            << p;
    }
}

// a set appears whole or not at all: a killed rerun leaves the previous complete
// set; its temporaries are removed by the next run; a file that cannot be written fails before
// anything changes; two runs sharing --out do not collide.
TEST_F(Reliability, OutputSetsAreAtomic)
{
    write(dir_ / "tiny.toml", kTinyScene);
    ASSERT_EQ(woven("drape tiny.toml --max-steps 2 --out res --width 64 --height 48").code, 0);
    ASSERT_TRUE(complete_set("res"));
    const std::string old_report = slurp(dir_ / "res" / "report.json");

    // A rerun killed by SIGKILL while it solves.
    const pid_t pid = spawn({"drape", "tiny.toml", "--grid", "41", "--max-steps", "400", "--out", "res"});
    int status = 0;
    bool exited = false;
    wait_for(pid, "\nstep ", status, exited);
    if (!exited) {
        ::kill(pid, SIGKILL);
        ::waitpid(pid, &status, 0);
    }
    EXPECT_EQ(slurp(dir_ / "res" / "report.json"), old_report);
    for (const auto& e : fs::directory_iterator(dir_ / "res")) {
        if (e.path().filename().string().rfind(".woven-tmp.", 0) != 0) {
            EXPECT_TRUE(fs::is_regular_file(e.path()));
        }
    }

    // The next run removes the dead run's temporaries and publishes a complete set.
    ASSERT_EQ(woven("drape tiny.toml --max-steps 1 --out res --no-render").code, 0);
    EXPECT_TRUE(complete_set("res"));
    EXPECT_FALSE(fs::exists(dir_ / "res" / "drape.png"));  // not of this set: removed

    // A directory where report.json goes: bad usage before the run, the set untouched.
    const std::string before = slurp(dir_ / "res" / "report.json");
    fs::rename(dir_ / "res" / "report.json", dir_ / "keep.json");
    fs::create_directory(dir_ / "res" / "report.json");
    const Outcome r = woven("drape tiny.toml --max-steps 1 --out res --no-render");
    EXPECT_EQ(r.code, 2);
    EXPECT_EQ(r.err, "woven: error: command line: --out: res/report.json exists and is not a regular file\n");
    fs::remove(dir_ / "res" / "report.json");
    fs::rename(dir_ / "keep.json", dir_ / "res" / "report.json");
    EXPECT_TRUE(complete_set("res"));

    // Two runs into one --out at the same time: both succeed, one complete set remains.
    const pid_t p1 = spawn({"drape", "tiny.toml", "--max-steps", "2", "--out", "shared", "--no-render"});
    const pid_t p2 = spawn({"drape", "tiny.toml", "--max-steps", "3", "--out", "shared", "--no-render"});
    int s1 = 0, s2 = 0;
    ::waitpid(p1, &s1, 0);
    ::waitpid(p2, &s2, 0);
    EXPECT_TRUE(WIFEXITED(s1) && WEXITSTATUS(s1) == 0);
    EXPECT_TRUE(WIFEXITED(s2) && WEXITSTATUS(s2) == 0);
    EXPECT_TRUE(complete_set("shared"));
}

// SIGTERM is treated like Ctrl-C: the state reached is written, exit 143.
TEST_F(Reliability, SigtermWritesTheStateReached)
{
    const pid_t pid = spawn({"drape", "cube", "--grid", "31", "--max-steps", "400", "--out", "res", "--no-render"});
    int status = 0;
    bool exited = false;
    if (wait_for(pid, "\nstep ", status, exited)) {
        ::kill(pid, SIGTERM);
        ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    }
    if (exited && WIFEXITED(status) && WEXITSTATUS(status) == 0) GTEST_SKIP() << "finished before the signal";
    ASSERT_TRUE(WIFEXITED(status)) << slurp(dir_ / "err.txt");
    EXPECT_EQ(WEXITSTATUS(status), 143) << slurp(dir_ / "err.txt");
    ASSERT_TRUE(complete_set("res"));
    const auto j = report(dir_ / "res" / "report.json");
    EXPECT_TRUE(j["interrupted"].get<bool>());
    EXPECT_FALSE(j["converged"].get<bool>());
}

// Ctrl-C after the solve (while writing) marks the set interrupted, still complete.
TEST_F(Reliability, InterruptWhileWritingMarksACompleteSet)
{
    write(dir_ / "tiny.toml", kTinyScene);
    const pid_t pid = spawn({"drape", "tiny.toml", "--max-steps", "1", "--out", "res", "--width", "1200", "--height", "900"});
    int status = 0;
    bool exited = false;
    if (wait_for(pid, "\nstep 1", status, exited)) {  // the only step: the solve is over, writing begins
        ::kill(pid, SIGINT);
        ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    }
    if (exited) GTEST_SKIP() << "finished before the signal";
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 130) << slurp(dir_ / "err.txt");
    ASSERT_TRUE(complete_set("res"));
    EXPECT_TRUE(report(dir_ / "res" / "report.json")["interrupted"].get<bool>());
}

// never more threads than cores available to the process; the report says how many.
TEST_F(Reliability, ThreadsAreCappedAtTheCoresAvailable)
{
    write(dir_ / "tiny.toml", kTinyScene);
    const Outcome r = woven("drape tiny.toml --max-steps 1 --threads 2 --out res --no-render", "taskset -c 0 ");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("woven: warning: 2 threads asked for, 1 cores available to this process; using 1"),
              std::string::npos)
        << r.err;
    auto j = report(dir_ / "res" / "report.json");
    EXPECT_EQ(j["threads"], 1);
    EXPECT_EQ(j["threads_requested"], 2);
    ASSERT_EQ(woven("drape tiny.toml --max-steps 1 --out res --no-render", "taskset -c 0 ").code, 0);
    j = report(dir_ / "res" / "report.json");
    EXPECT_EQ(j["threads"], 1);  // the default: all cores available, here one
    EXPECT_EQ(j["threads_requested"], 0);
}

// command-line values get short one-line errors in the documented form.
TEST_F(Reliability, CommandLineValuesAreCheckedAgainstTheirRanges)
{
    write(dir_ / "tiny.toml", kTinyScene);
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"drape tiny.toml --threads -1", "command line: --threads: expected an integer in [0, 4096], got '-1'"},
        {"drape tiny.toml --threads abc", "command line: --threads: expected an integer in [0, 4096], got 'abc'"},
        {"drape tiny.toml --seed -1", "command line: --seed: expected an integer in [0, 18446744073709551615], got '-1'"},
        {"drape tiny.toml --seed 18446744073709551616",
         "command line: --seed: expected an integer in [0, 18446744073709551615], got '18446744073709551616'"},
        {"drape tiny.toml --grid 2", "command line: --grid: expected an integer in [3, 100000], got '2'"},
        {"drape tiny.toml --max-steps -5", "command line: --max-steps: expected an integer in [0, 1000000000], got '-5'"},
        {"drape tiny.toml --width 0", "command line: --width: expected an integer in [1, 16384], got '0'"},
        {"drape tiny.toml --out ''", "command line: --out: expected a directory path, got an empty string"},
        {"fit cotton --out ''", "command line: --out: expected a directory path, got an empty string"},
        {"fit cotton --sigma-cm -1", "command line: --sigma-cm: expected a number in [0.01, 100], got '-1'"},
        {"fit cotton --sigma-cm nan", "command line: --sigma-cm: expected a number in [0.01, 100], got 'nan'"},
        {"kes-test cotton --shear-law raw", "command line: --shear-law: expected deembedded or measured, got 'raw'"},
        {"kes-test cotton --bending-form x", "command line: --bending-form: expected work or secant, got 'x'"},
        {"cusick silk --shear-law x", "command line: --shear-law: expected deembedded or measured, got 'x'"},
    };
    for (const auto& [args, expected] : cases) {
        const Outcome r = woven(args);
        EXPECT_EQ(r.code, 2) << args;
        EXPECT_EQ(r.err, "woven: error: " + expected + "\n") << args;
        EXPECT_LT(r.err.size(), 120u) << args;
    }
    write(dir_ / "afile", "x");
    for (const char* args : {"drape tiny.toml --out afile --no-render", "fit cotton --out afile"}) {
        const Outcome r = woven(args);
        EXPECT_EQ(r.code, 2) << args;
        EXPECT_EQ(r.err, "woven: error: command line: --out: afile exists and is not a directory\n") << args;
    }
    // The largest seed is accepted and recorded exactly.
    ASSERT_EQ(woven("drape tiny.toml --seed 18446744073709551615 --max-steps 1 --out res --no-render").code, 0);
    EXPECT_EQ(report(dir_ / "res" / "report.json")["seed"].get<std::uint64_t>(), 18446744073709551615ull);
    EXPECT_FALSE(fs::exists(dir_ / "out"));
}

// the same ranges for a curve's slope as for a summary value; a directory is not a
// fabric file; errors of the fitting stage name the file.
TEST_F(Reliability, FabricsTheFitCannotUseAreBadInput)
{
    const std::string flat = replace(kFabric, "B = 0.05\n2HB = 0.02\n",
                                     "curvature_per_cm = [0.0, 0.5, 1.0, 1.5, 2.0, 2.5]\n"
                                     "moment_gf_cm_per_cm = [0.0, 0.00001, 0.00001, 0.00001, 0.00001, 0.00002]\n");
    write(dir_ / "flat.toml", flat);
    Outcome r = woven("fit flat.toml");
    EXPECT_EQ(r.code, 2);
    EXPECT_EQ(r.err.rfind("woven: error: flat.toml: bending.warp: the curve's slope B (0.5 .. 1.5) is ", 0), 0u) << r.err;
    fs::create_directory(dir_ / "dir.toml");
    r = woven("fit dir.toml");
    EXPECT_EQ(r.code, 2);
    EXPECT_EQ(r.err, "woven: error: dir.toml: file: is a directory; expected a fabric .toml file\n");
    EXPECT_FALSE(fs::exists(dir_ / "out"));
}

// a drape the process cannot hold is refused before it starts, with the estimate
// and the limit.
TEST_F(Reliability, MemoryIsEstimatedBeforeTheRun)
{
#if defined(__SANITIZE_ADDRESS__)
    GTEST_SKIP() << "AddressSanitizer reserves more address space than the limit set here";
#else
    write(dir_ / "big.toml", "[cloth]\nsize_m = [1, 1]\ngrid = [11, 11]\n[solver]\ncontact_distance_m = 1e-5\n"
                             "[[obstacle]]\ntype = \"plane\"\n");
    const Outcome r = woven("drape big.toml --grid 2000 --no-render --out res", "ulimit -v 4000000 && ");
    EXPECT_EQ(r.code, 2) << r.err;
    const std::regex form(R"(woven: error: command line: --grid: 4000000 particles need about [0-9.]+ GB of address space )"
                          R"(\(estimate\), more than the 4\.1 GB of RLIMIT_AS; use a smaller grid\n)");
    EXPECT_TRUE(std::regex_match(r.err, form)) << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "res"));
#endif
}

// an empty scene file is an error (the choice documented in docs/SCENE-FORMAT.md).
TEST_F(Reliability, AnEmptySceneIsAnError)
{
    write(dir_ / "empty.toml", "");
    const Outcome r = woven("drape empty.toml");
    EXPECT_EQ(r.code, 2);
    EXPECT_EQ(r.err, "woven: error: empty.toml: file: the scene is empty; expected at least a [cloth] table and an "
                     "[[obstacle]]\n");
}

// without a terminal, progress starts at once (step 1 is shown) and moves within
// steps (a line per Newton iteration, about every 0.5 s), not once per step.
TEST_F(Reliability, ProgressWithoutATerminalIsOneLinePerEvent)
{
    const Outcome r = woven("drape cube --grid 41 --max-steps 3 --out res --no-render");  // three steps show it
    ASSERT_EQ(r.code, 0) << r.err;
    std::istringstream lines(r.err);
    std::string line;
    std::getline(lines, line);
    EXPECT_EQ(line.rfind("woven: draping cube", 0), 0u) << line;
    std::getline(lines, line);
    EXPECT_EQ(line.rfind("step 1 ", 0), 0u) << line;  // the first report is shown at once
    int progress = 1, newton = line.find("Newton iteration") != std::string::npos;
    while (std::getline(lines, line))
        if (line.rfind("step ", 0) == 0) {
            ++progress;
            newton += line.find("Newton iteration") != std::string::npos;
        }
    EXPECT_GE(progress, 2) << r.err;
    EXPECT_GE(newton, 1) << r.err;  // within a step, from the solver's per-iteration callback
}

// Every class of bad input gives one line in the documented form and exit 2.
TEST_F(Reliability, EveryBadInputClassKeepsTheDocumentedForm)
{
    write(dir_ / "tiny.toml", kTinyScene);
    write(dir_ / "fabric.toml", kFabric);
    struct Case {
        std::string name, file, text, args;
    };
    const std::vector<Case> cases = {
        {"toml syntax", "s.toml", "a = = 1\n", "drape s.toml"},
        {"toml limits", "s.toml", std::string("[").append(200, 'a').append(60, '.').append("b]\n"), "drape s.toml"},
        {"empty scene", "s.toml", "\n", "drape s.toml"},
        {"unknown obstacle", "s.toml", kTinyScene + "[[obstacle]]\ntype = \"cone\"\n", "drape s.toml"},
        {"missing key", "s.toml", kTinyScene + "[[obstacle]]\ntype = \"sphere\"\nradius_m = 1\n", "drape s.toml"},
        {"wrong type", "s.toml", replace(kTinyScene, "height_m = 0.12", "height_m = \"high\""), "drape s.toml"},
        {"not finite", "s.toml", replace(kTinyScene, "height_m = 0.12", "height_m = nan"), "drape s.toml"},
        {"out of range", "s.toml", replace(kTinyScene, "height_m = 0.12", "height_m = 1e9"), "drape s.toml"},
        {"spacing", "s.toml", replace(kTinyScene, "grid = [9, 9]", "grid = [9, 5]"), "drape s.toml"},
        {"grid", "s.toml", replace(kTinyScene, "grid = [9, 9]", "grid = [2, 2]"), "drape s.toml"},
        {"pinned", "s.toml", replace(kTinyScene, "fabric = ", "pinned = [[9, 0]]\nfabric = "), "drape s.toml"},
        {"start inside", "s.toml", replace(kTinyScene, "height_m = 0.12", "height_m = 0.08"), "drape s.toml"},
        {"mesh missing", "s.toml", kTinyScene + "[[obstacle]]\ntype = \"mesh\"\nfile = \"none.obj\"\n", "drape s.toml"},
        {"mesh number", "s.toml", kTinyScene + "[[obstacle]]\ntype = \"mesh\"\nfile = \"m.obj\"\n", "drape s.toml"},
        {"control characters", "s.toml", kTinyScene + "[[obstacle]]\ntype = \"a\\nb\"\n", "drape s.toml"},
        {"no scene", "", "", "drape nosuch"},
        {"fabric syntax", "f.toml", "name = \n", "fit f.toml"},
        {"fabric range", "f.toml", replace(kFabric, "G = 0.5", "G = 500"), "fit f.toml"},
        {"fabric both forms", "f.toml", replace(kFabric, "G = 0.5", "G = 0.5\nangle_deg = [0, 1, 2]"), "fit f.toml"},
        {"fabric missing", "", "", "fit nosuch.toml"},
        {"unknown fabric", "", "", "fit nosuch"},
        {"fabric of a scene", "s.toml", replace(kTinyScene, "fabric = \"cotton\"", "fabric = \"f.toml\""),
         "drape s.toml"},
        {"option value", "", "", "drape tiny.toml --threads x"},
        {"option out", "", "", "drape tiny.toml --out tiny.toml"},
        {"option solver", "", "", "drape tiny.toml --solver slow"},
        {"unknown option", "", "", "drape tiny.toml --no-such-option"},
        {"unknown command", "", "", "nosuchcommand"},
        {"kes-test spacing", "", "", "kes-test cotton --sigma-cm 5"},
        {"kes-test test", "", "", "kes-test cotton --test stretch"},
        {"kes-test direction", "", "", "kes-test cotton --direction bias"},
        {"kes-test form", "", "", "kes-test cotton --bending-form x"},
        {"kes-test shear length", "", "", "kes-test cotton --shear-length-cm 1"},
        {"cusick spacing", "", "", "cusick cotton --spacing-cm 5"},
        {"render size", "", "", "render none.obj --size 0x0"},
        {"experiment name", "", "", "experiment chair"},
    };
    write(dir_ / "m.obj", "v 0 0 0\nv 1 0 zz\nv 0 1 0\nf 1 2 3\n");
    for (const auto& c : cases) {
        if (!c.file.empty()) write(dir_ / c.file, c.text);
        const Outcome r = woven(c.args);
        EXPECT_EQ(r.code, 2) << c.name << ": " << r.err;
        EXPECT_TRUE(documented_form(r.err)) << c.name << ": " << r.err;
        EXPECT_LT(r.err.size(), 400u) << c.name;
        if (!c.file.empty()) fs::remove(dir_ / c.file);
    }
    EXPECT_FALSE(fs::exists(dir_ / "out"));
}

// The perturbation from the command line and the scene: recorded with the seed in the
// report; the same seed gives the same bits, another seed another start.
TEST_F(Reliability, PerturbationIsSeededAndReported)
{
    write(dir_ / "tiny.toml", kTinyScene);
    const std::string run = "drape tiny.toml --max-steps 2 --no-render --perturb 0.002 ";
    ASSERT_EQ(woven(run + "--seed 5 --out a").code, 0);
    ASSERT_EQ(woven(run + "--seed 5 --out b").code, 0);
    ASSERT_EQ(woven(run + "--seed 6 --out c").code, 0);
    const auto j = report(dir_ / "a" / "report.json");
    EXPECT_EQ(j["perturbation_m"].get<double>(), 0.002);
    EXPECT_EQ(j["seed"].get<std::uint64_t>(), 5u);
    EXPECT_EQ(slurp(dir_ / "a" / "drape.obj"), slurp(dir_ / "b" / "drape.obj"));
    EXPECT_NE(slurp(dir_ / "a" / "drape.obj"), slurp(dir_ / "c" / "drape.obj"));
    Outcome r = woven("drape tiny.toml --perturb -1");
    EXPECT_EQ(r.code, 2);
    EXPECT_EQ(r.err, "woven: error: command line: --perturb: expected a number in [0, 0.01], got '-1'\n");
    write(dir_ / "p.toml", kTinyScene + "[solver]\nperturbation_m = 0.003\n");
    ASSERT_EQ(woven("drape p.toml --max-steps 1 --no-render --out d").code, 0);
    EXPECT_EQ(report(dir_ / "d" / "report.json")["perturbation_m"].get<double>(), 0.003);
    write(dir_ / "p.toml", kTinyScene + "[solver]\nperturbation_m = 1.0\n");
    r = woven("drape p.toml --max-steps 1 --no-render --out e");
    EXPECT_EQ(r.code, 2);
    EXPECT_EQ(r.err, "woven: error: p.toml: solver.perturbation_m: expected a non-negative number in [0, 0.01] m, got 1 "
                     "(line 14)\n");
}
