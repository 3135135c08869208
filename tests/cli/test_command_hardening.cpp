// Every command as safe as `drape` with bad input, signals and full disks, run on the real
// binary (WOVEN_BINARY) in a temporary directory. Small specimens and grids, few steps.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "woven/io/sha256.hpp"

#include "process_support.hpp"

namespace fs = std::filesystem;

namespace {

using woven::test::kTinyScene;
using woven::test::documented_form;
using woven::test::one_line;
using woven::test::Outcome;
using woven::test::replace;
using woven::test::slurp;
using woven::test::write;

class CommandHardening : public woven::test::SpawningProcessTest {};

/// A 2 x 2 corner map (the cells `experiment map --map-grid 2x2` asks for), each cell's folds given.
std::string corner_map(const std::string& folds, const std::string& converged = "true")
{
    std::string cells;
    for (const char* r : {"0.25", "4.0"})
        for (const char* c : {"1.0", "5.0"})
            cells += std::string(cells.empty() ? "" : ",") + "{\"ratio_warp_weft\": " + r + ", \"bending_length_cm\": " + c +
                ", \"converged\": " + converged + ", \"folds\": " + folds + "}";
    return "{\"command\": \"woven experiment map\", \"version\": \"t\", \"cells\": [" + cells + "]}";
}

}  // namespace

// the --reuse file is input like any other: an empty corner list (a segfault), a
// short standout_m list (read out of bounds, exit 0), a missing list or a string for a boolean
// (raw library text, exit 1) are one-line errors naming the field, exit 2, nothing written.
TEST_F(CommandHardening, ReuseJsonIsCheckedInput)
{
    const std::vector<std::pair<std::string, std::string>> cases = {
        {corner_map("{\"corners\": []}"), "m.json: cells[0].folds.corners: expected 4 corners, got 0"},
        {corner_map("{\"corners\": [{\"angles_deg\": [[1, 2]], \"standout_m\": [[0.1]]}, 1, 2, 3]}"),
         "m.json: cells[0].folds.corners[0].standout_m[0]: expected 2 numbers (one per billow, as angles_deg), got 1"},
        {corner_map("{}"), "m.json: cells[0].folds.corners: missing"},
        {corner_map("null", "\"yes\""), "m.json: cells[0].converged: expected true or false, got 'yes'"},
    };
    for (const auto& [text, expected] : cases) {
        write(dir_ / "m.json", text);
        const Outcome r = woven("experiment map --map-grid 2x2 --reuse m.json --out o");
        EXPECT_EQ(r.code, 2) << expected;
        EXPECT_EQ(r.err, "woven: error: " + expected + "\n");
        EXPECT_FALSE(fs::exists(dir_ / "o"));
    }
    // A valid map with folds is analysed again: one billow on the diagonal per corner.
    const std::string one = "{\"angles_deg\": [[5], []], \"standout_m\": [[0.1], []]}";
    write(dir_ / "m.json", corner_map("{\"corners\": [" + one + "," + one + "," + one + "," + one + "]}"));
    const Outcome r = woven("experiment map --map-grid 2x2 --reuse m.json --out o");
    ASSERT_EQ(r.code, 0) << r.err;
    const auto j = nlohmann::json::parse(slurp(dir_ / "o" / "corner_map.json"));
    ASSERT_EQ(j["cells"].size(), 4u);
    EXPECT_EQ(j["cells"][0]["structure"], "single, on the diagonal");
    // A cell the grid needs but the map lacks: exit 2 before anything is written.
    write(dir_ / "m.json", corner_map("null"));
    const Outcome r3 = woven("experiment map --map-grid 3x2 --reuse m.json --out o3");
    EXPECT_EQ(r3.code, 2);
    EXPECT_TRUE(documented_form(r3.err)) << r3.err;
    EXPECT_FALSE(fs::exists(dir_ / "o3"));
}

// no command reads a device or a FIFO for ever: each is refused at once, exit 2.
TEST_F(CommandHardening, InputsAreRegularFilesReadBounded)
{
    ASSERT_EQ(::mkfifo((dir_ / "fifo.toml").c_str(), 0600), 0);
    write(dir_ / "zs.toml", replace(kTinyScene, "fabric = \"cotton\"", "fabric = \"/dev/zero\""));
    write(dir_ / "ms.toml", kTinyScene + "[[obstacle]]\ntype = \"mesh\"\nfile = \"fifo.toml\"\n");
    const std::string not_regular = "is not a regular file (a device, FIFO or socket); expected ";
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"fit /dev/zero", "/dev/zero: file: " + not_regular + "a fabric .toml file"},
        {"fit ./fifo.toml", "./fifo.toml: file: " + not_regular + "a fabric .toml file"},
        {"drape cube --fabric /dev/zero", "/dev/zero: file: " + not_regular + "a fabric .toml file"},
        {"drape zs.toml", "/dev/zero: file: " + not_regular + "a fabric .toml file"},
        {"drape ./fifo.toml", "./fifo.toml: file: " + not_regular + "a scene .toml file"},
        {"drape /dev/zero", "/dev/zero: file: " + not_regular + "a scene .toml file"},
        {"kes-test /dev/urandom", "/dev/urandom: file: " + not_regular + "a fabric .toml file"},
        {"cusick /dev/zero", "/dev/zero: file: " + not_regular + "a fabric .toml file"},
        {"render /dev/zero", "/dev/zero: file: " + not_regular + "an OBJ file"},
        {"experiment map --reuse /dev/zero --out o", "/dev/zero: file: " + not_regular + "a corner_map.json"},
    };
    for (const auto& [args, expected] : cases) {
        const Outcome r = woven(args, "timeout 20 ");
        EXPECT_EQ(r.code, 2) << args;
        EXPECT_EQ(r.err, "woven: error: " + expected + "\n") << args;
    }
    const Outcome m = woven("drape ms.toml", "timeout 20 ");
    EXPECT_EQ(m.code, 2);
    EXPECT_NE(m.err.find(not_regular + "an OBJ file"), std::string::npos) << m.err;
    // A fabric file over the 8 MiB limit: refused from its size, not read.
    write(dir_ / "big.toml", std::string((8u << 20) + 1, '#'));
    const Outcome b = woven("fit big.toml");
    EXPECT_EQ(b.code, 2);
    EXPECT_EQ(b.err, "woven: error: big.toml: file: expected a fabric .toml file of at most 8 MiB, got 8388609 bytes\n");
    EXPECT_FALSE(fs::exists(dir_ / "out"));
}

// fit's --sigma-cm is bounded (1e-160 wrote 1,000 -nan rows with exit 0); at both
// ends of the range every table holds numbers only.
TEST_F(CommandHardening, FitSpacingIsBoundedAndTablesAreFinite)
{
    Outcome r = woven("fit wool --sigma-cm 1e-160 --out f");
    EXPECT_EQ(r.code, 2);
    EXPECT_EQ(r.err, "woven: error: command line: --sigma-cm: expected a number in [0.01, 100], got '1e-160'\n");
    EXPECT_FALSE(fs::exists(dir_ / "f"));
    for (const char* s : {"0.01", "100"}) {
        r = woven(std::string("fit wool --sigma-cm ") + s + " --out f" + s);
        ASSERT_EQ(r.code, 0) << s << r.err;
        EXPECT_TRUE(complete_set(std::string("f") + s, "report.json"));
        for (const char* csv : {"bending_warp_energy.csv", "bending_weft_energy.csv", "trellis_energy.csv"}) {
            const std::string t = slurp(dir_ / (std::string("f") + s) / csv);
            EXPECT_EQ(t.find("nan"), std::string::npos) << s << " " << csv;
            EXPECT_EQ(t.find("inf"), std::string::npos) << s << " " << csv;
        }
    }
}

// kes-test writes one output set (unique temporaries, kes-report.json last naming
// every file with its SHA-256); a rerun with another --test removes the first run's files.
TEST_F(CommandHardening, KesTestOutputIsOneSet)
{
    Outcome r = woven("kes-test cotton --test cantilever --direction warp --sigma-cm 1 --out k");
    ASSERT_EQ(r.code, 0) << r.err;
    ASSERT_TRUE(complete_set("k", "kes-report.json"));
    EXPECT_TRUE(fs::exists(dir_ / "k" / "cantilever_warp.csv"));
    r = woven("kes-test cotton --test bending --direction weft --sigma-cm 1 --out k");
    ASSERT_EQ(r.code, 0) << r.err;
    ASSERT_TRUE(complete_set("k", "kes-report.json"));
    EXPECT_FALSE(fs::exists(dir_ / "k" / "cantilever_warp.csv"));  // of the earlier set: removed
    EXPECT_FALSE(fs::exists(dir_ / "k" / "cantilever.png"));
    EXPECT_TRUE(fs::exists(dir_ / "k" / "bending_weft.csv"));
    const auto j = nlohmann::json::parse(slurp(dir_ / "k" / "kes-report.json"));
    EXPECT_EQ(j["files"].size(), 2u);
    EXPECT_EQ(j["tests"][0]["test"], "bending");
    r = woven("check k");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.out, "k: ok (output of kes-test, 2 files listed in kes-report.json)\n");
    // A directory where a file of the set goes: bad usage before the tests run, the set kept.
    fs::create_directory(dir_ / "k" / "shear.png");
    r = woven("kes-test cotton --test shear --sigma-cm 1 --out k");
    EXPECT_EQ(r.code, 2);
    EXPECT_EQ(r.err, "woven: error: command line: --out: k/shear.png exists and is not a regular file\n");
    EXPECT_EQ(r.out, "");
    fs::remove(dir_ / "k" / "shear.png");
    EXPECT_TRUE(complete_set("k", "kes-report.json"));
    // The temporaries of a run killed while writing are removed by the next run.
    write(dir_ / "k" / ".woven-tmp.999999999.0.bending.png", "partial");
    ASSERT_EQ(woven("kes-test cotton --test bending --direction weft --sigma-cm 1 --out k").code, 0);
    EXPECT_TRUE(complete_set("k", "kes-report.json"));
}

// kes-test estimates the memory of its largest specimen before it starts (the
// issue's run died with std::bad_alloc after 47 s under a 4 GB address-space limit).
TEST_F(CommandHardening, KesTestMemoryIsEstimatedBeforeTheRun)
{
#if defined(__SANITIZE_ADDRESS__)
    GTEST_SKIP() << "AddressSanitizer reserves more address space than the limit set here";
#else
    const Outcome r = woven("kes-test cotton --sigma-cm 0.02 --test shear --out k", "ulimit -v 4000000 && ");
    EXPECT_EQ(r.code, 2) << r.err;
    const std::regex form(R"(woven: error: command line: --sigma-cm: 251251 particles need about [0-9.]+ GB of address space )"
                          R"(\(estimate\), more than the 4\.1 GB of RLIMIT_AS; use a larger --sigma-cm\n)");
    EXPECT_TRUE(std::regex_match(r.err, form)) << r.err;
    EXPECT_EQ(r.out, "");
    EXPECT_FALSE(fs::exists(dir_ / "k"));
#endif
}

// every kes-test option is checked before any test runs (a zero clamp length was
// refused only after 2.8 s of tests): nothing printed, nothing written.
TEST_F(CommandHardening, KesTestOptionsAreCheckedBeforeWork)
{
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"kes-test cotton --shear-length-cm 0", "command line: --shear-length-cm: expected a number in [5, 200], got '0'"},
        {"kes-test cotton --test bending --shear-length-cm x", "command line: --shear-length-cm: expected a number in [5, 200], got 'x'"},
        {"kes-test cotton --sigma-cm 0.01", "command line: --sigma-cm: expected a number in [0.02, 2], got '0.01'"},
        {"kes-test cotton --out ''", "command line: --out: expected a directory path, got an empty string"},
        {"kes-test cotton --test shear --convergence", "command line: --convergence: expected --test cantilever or all (a study of the cantilever test)"},
    };
    for (const auto& [args, expected] : cases) {
        const Outcome r = woven(args);
        EXPECT_EQ(r.code, 2) << args;
        EXPECT_EQ(r.err, "woven: error: " + expected + "\n") << args;
        EXPECT_EQ(r.out, "") << args;  // no test ran: no table
    }
    EXPECT_FALSE(fs::exists(dir_ / "out"));
}

// experiment writes one set (its JSON last, naming every file with its SHA-256) and
// SIGINT or SIGTERM ends it as they end `drape` (exit 130, 143), leaving the previous complete
// set: a new picture never stands beside an old table.
TEST_F(CommandHardening, ExperimentOutputIsOneSetAndSignalsEndIt)
{
    const std::string one = "{\"angles_deg\": [[5]], \"standout_m\": [[0.1]]}";
    write(dir_ / "m.json", corner_map("{\"corners\": [" + one + "," + one + "," + one + "," + one + "]}"));
    ASSERT_EQ(woven("experiment map --map-grid 2x2 --reuse m.json --out M").code, 0);
    ASSERT_TRUE(complete_set("M", "corner_map.json"));
    const std::string before = slurp(dir_ / "M" / "corner_map.json");
    for (const int sig : {SIGINT, SIGTERM}) {
        fs::remove(dir_ / "err.txt");  // the previous run's lines must not be taken for this one's
        const pid_t pid = spawn({"experiment", "map", "--map-grid", "2x2", "--grid", "41", "--out", "M"});
        int status = 0;
        bool exited = false;
        if (wait_for(pid, "woven: experiment: cube", status, exited)) {  // the first drape has begun
            ::kill(pid, sig);
            ASSERT_EQ(::waitpid(pid, &status, 0), pid);
        }
        ASSERT_FALSE(exited) << "finished before the signal";
        ASSERT_TRUE(WIFEXITED(status)) << "signal " << WTERMSIG(status) << ": " << slurp(dir_ / "err.txt");
        EXPECT_EQ(WEXITSTATUS(status), 128 + sig) << slurp(dir_ / "err.txt");
        EXPECT_NE(slurp(dir_ / "err.txt").find("woven: interrupted; nothing written"), std::string::npos);
        EXPECT_EQ(slurp(dir_ / "M" / "corner_map.json"), before);
        EXPECT_TRUE(complete_set("M", "corner_map.json"));  // and no temporaries
    }
}

// an outline of more than 10,000 points is refused before its O(n^2) self-
// intersection test (a 200,000-point one spent 285 s there).
TEST_F(CommandHardening, OutlinePointsAreBounded)
{
    std::string points;
    const int n = 10001;
    for (int k = 0; k < n; ++k) {
        const double a = 2 * M_PI * k / n;
        points += (k ? ", [" : "[") + std::to_string(0.1 * std::cos(a)) + ", " + std::to_string(0.1 * std::sin(a)) + "]";
    }
    write(dir_ / "s.toml", replace(kTinyScene, "fabric = \"cotton\"", "fabric = \"cotton\"\n[cloth.outline]\ntype = \"polygon\"\npoints_m = [" + points + "]"));
    const Outcome r = woven("drape s.toml --out o");
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("s.toml: cloth.outline.points_m: expected at most 10000 points, got 10001"), std::string::npos) << r.err;
    EXPECT_TRUE(one_line(r.err));
    EXPECT_FALSE(fs::exists(dir_ / "o"));
}

// a shear curve far from linear (3.5 gf/cm by 0.01 degrees, then nearly flat) got a
// de-embedding factor of 0.00022 silently (this one 0.89); a factor outside 0.98 .. 1.10 is a failed virtual
// instrument: one warning line, and the curve is used as measured (shear_scale 1).
TEST_F(CommandHardening, ImplausibleShearCorrectionIsNotApplied)
{
    write(dir_ / "steep.toml", R"(name = "steep"
source = "test: issue 36"
areal_density_mg_cm2 = 15
[bending.warp]
B = 0.05
2HB = 0.02
[bending.weft]
B = 0.04
2HB = 0.02
[shear]
angle_deg = [0, 0.01, 0.5, 1, 2, 5, 8]
force_gf_per_cm = [0, 3.5, 3.5, 3.5, 3.5, 3.5045, 3.508]
)");
    const Outcome r = woven("kes-test steep.toml --test bending --direction warp --sigma-cm 1 --out k");
    ASSERT_EQ(r.code, 0) << r.err;
    const std::regex warning(R"(woven: warning: fabric 'steep': the shear de-embedding factor [0-9.e+-]+ is outside the plausible )"
                             R"(0\.98 \.\. 1\.1 \(1\.001 \.\. 1\.013 for the built-in fabrics\); the curve is used as measured\n)");
    std::smatch m;
    EXPECT_TRUE(std::regex_search(r.err, m, warning)) << r.err;
    const auto j = nlohmann::json::parse(slurp(dir_ / "k" / "kes-report.json"));
    EXPECT_EQ(j["shear_scale"].get<double>(), 1.0);
    // A built-in fabric keeps its factor (1.001 .. 1.013) without a warning.
    const Outcome c = woven("kes-test cotton --test bending --direction warp --sigma-cm 1 --out c");
    ASSERT_EQ(c.code, 0) << c.err;
    EXPECT_EQ(c.err.find("de-embedding factor"), std::string::npos) << c.err;
    const double s = nlohmann::json::parse(slurp(dir_ / "c" / "kes-report.json"))["shear_scale"].get<double>();
    EXPECT_GT(s, 1.001);
    EXPECT_LT(s, 1.013);
}

// render creates a missing folder for --out as the other commands do; a directory as
// --out is bad usage (exit 2), not a runtime failure.
TEST_F(CommandHardening, RenderWritesIntoItsOutFolderAndRefusesADirectory)
{
    write(dir_ / "m.obj", "v 0 0 0\nv 0.1 0 0\nv 0 0.1 0.01\nf 1 2 3\n");
    Outcome r = woven("render m.obj --size 32x24 --out new/deeper/r.png");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(fs::is_regular_file(dir_ / "new" / "deeper" / "r.png"));
    for (const auto& e : fs::directory_iterator(dir_ / "new" / "deeper")) EXPECT_EQ(e.path().filename(), "r.png");  // no temporary
    fs::create_directory(dir_ / "adir");
    r = woven("render m.obj --size 32x24 --out adir");
    EXPECT_EQ(r.code, 2);
    EXPECT_EQ(r.err, "woven: error: command line: --out: adir is a directory; expected a PNG file name\n");
    write(dir_ / "afile", "x");
    r = woven("render m.obj --size 32x24 --out afile/r.png");
    EXPECT_EQ(r.code, 2);
    EXPECT_EQ(r.err, "woven: error: command line: --out: afile exists and is not a directory\n");
}

// '+0.2' is a number in an OBJ file; cusick's run seeds do not wrap round past
// 2^64 - 1; an I/O error names the output file, never its temporary.
TEST_F(CommandHardening, SignedNumbersSeedRangesAndAFullDiskAreOneLineErrors)
{
    write(dir_ / "m.obj", "v +0.2 0 0\nv 0.1 0 +1e-2\nv 0 0.1 0.01\nf 1 2 3\n");
    Outcome r = woven("render m.obj --size 32x24 --out r.png");
    EXPECT_EQ(r.code, 0) << r.err;
    write(dir_ / "m.obj", "v +-0.2 0 0\nv 0.1 0 0\nv 0 0.1 0.01\nf 1 2 3\n");
    r = woven("render m.obj --size 32x24 --out r.png");
    EXPECT_EQ(r.code, 2);
    EXPECT_EQ(r.err, "woven: error: m.obj:1: v: expected a number in [-1000000, 1000000], got '+-0.2'\n");

    r = woven("cusick cotton --seed 18446744073709551615 --seeds 2 --out c");
    EXPECT_EQ(r.code, 2);
    EXPECT_EQ(r.err, "woven: error: command line: --seed: expected at most 18446744073709551614 with --seeds 2 (the runs' seeds are "
                     "seed .. seed + 1), got '18446744073709551615'\n");
    EXPECT_FALSE(fs::exists(dir_ / "c"));

    // A file size limit makes the first picture's write fail (EFBIG, SIGXFSZ ignored).
    r = woven("fit cotton --out f", "trap '' XFSZ; ulimit -f 8 && ");
    EXPECT_EQ(r.code, 1) << r.err;
    EXPECT_NE(r.err.find("woven: error: f/"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find(".woven-tmp"), std::string::npos) << r.err;
    EXPECT_TRUE(one_line(r.err)) << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "f" / "report.json"));
}
