// Issue 36: every command as safe as `drape`, one test per defect, run on the real binary
// (WOVEN_BINARY) in a temporary directory. Small specimens and grids, few steps.
#include <chrono>
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

#include "cli_support.hpp"

namespace fs = std::filesystem;

namespace {

using woven::test::kTinyScene;
using woven::test::one_line;
using woven::test::Outcome;
using woven::test::replace;
using woven::test::slurp;
using woven::test::write;

/// The documented form of an error (as tests/cli/test_reliability.cpp checks it).
bool documented_form(const std::string& err)
{
    static const std::regex form(R"(woven: error: [^:\n]+(:[0-9]+){0,2}: [^\n:]+: [^\n]+\n)");
    return std::regex_match(err, form);
}

class Issue36 : public woven::test::WovenProcessTest {
protected:
    /// Starts woven with `args` (stdout to /dev/null, stderr to err.txt); returns its pid.
    pid_t spawn(const std::vector<std::string>& args)
    {
        const fs::path err = dir_ / "err.txt";
        const pid_t pid = ::fork();
        if (pid == 0) {
            if (::chdir(dir_.c_str()) != 0) ::_exit(99);
            if (!std::freopen(err.c_str(), "w", stderr) || !std::freopen("/dev/null", "w", stdout)) ::_exit(99);
            std::vector<char*> argv{const_cast<char*>(WOVEN_BINARY)};
            for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
            argv.push_back(nullptr);
            ::execv(WOVEN_BINARY, argv.data());
            ::_exit(98);
        }
        return pid;
    }

    /// Waits until err.txt contains `text` (true) or the process exits (false).
    bool wait_for(pid_t pid, const std::string& text, int& status, bool& exited)
    {
        exited = false;
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(300);
        while (std::chrono::steady_clock::now() < deadline) {
            if (::waitpid(pid, &status, WNOHANG) == pid) {
                exited = true;
                return false;
            }
            if (slurp(dir_ / "err.txt").find(text) != std::string::npos) return true;
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
        return false;
    }

    /// The set in `sub` is complete: `manifest` exists and every file it names (and only those,
    /// besides itself) is there with its checksum; no temporaries.
    ::testing::AssertionResult complete_set(const std::string& sub, const std::string& manifest)
    {
        const fs::path d = dir_ / sub;
        if (!fs::exists(d / manifest)) return ::testing::AssertionFailure() << "no " << manifest;
        const auto j = nlohmann::json::parse(slurp(d / manifest));
        std::size_t named = 0;
        for (const auto& [name, f] : j.at("files").items()) {
            ++named;
            if (!fs::exists(d / name)) return ::testing::AssertionFailure() << name << " missing";
            if (woven::io::sha256_hex(slurp(d / name)) != f.at("sha256").get<std::string>())
                return ::testing::AssertionFailure() << name << " is not the file the manifest names";
        }
        std::size_t present = 0;
        for (const auto& e : fs::directory_iterator(d)) {
            const std::string n = e.path().filename().string();
            if (n.rfind(".woven-tmp.", 0) == 0) return ::testing::AssertionFailure() << "temporary " << n << " left";
            ++present;
        }
        if (present != named + 1) return ::testing::AssertionFailure() << present << " files, " << manifest << " names " << named;
        return ::testing::AssertionSuccess();
    }
};

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

// Defect 1: the --reuse file is input like any other: an empty corner list (a segfault), a
// short standout_m list (read out of bounds, exit 0), a missing list or a string for a boolean
// (raw library text, exit 1) are one-line errors naming the field, exit 2, nothing written.
TEST_F(Issue36, Defect01ReuseJsonIsCheckedInput)
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

// Defect 2: no command reads a device or a FIFO for ever: each is refused at once, exit 2.
TEST_F(Issue36, Defect02InputsAreRegularFilesReadBounded)
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

// Defect 3: fit's --sigma-cm is bounded (1e-160 wrote 1,000 -nan rows with exit 0); at both
// ends of the range every table holds numbers only.
TEST_F(Issue36, Defect03FitSpacingIsBoundedAndTablesAreFinite)
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
