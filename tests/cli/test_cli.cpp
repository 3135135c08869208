// The `woven` command line, run as a real process (WOVEN_BINARY) in a temporary directory.
// Kept fast (tiny grids, few steps) since the suite also runs under the sanitizers.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_support.hpp"

namespace fs = std::filesystem;

namespace {

using woven::test::kTinyScene;
using woven::test::one_line;
using woven::test::Outcome;
using woven::test::quote;
using woven::test::replace;
using woven::test::slurp;
using woven::test::write;

class Cli : public woven::test::WovenProcessTest {
protected:
    /// Files in the temporary directory (recursively), besides the test's own inputs.
    int count_entries(const fs::path& sub) const
    {
        int n = 0;
        for (auto it = fs::recursive_directory_iterator(dir_ / sub); it != fs::recursive_directory_iterator(); ++it) ++n;
        return n;
    }

    /// `args` is refused as bad usage: exit 2, one line on stderr, `not_written` not created.
    void expect_rejected(const std::string& args, const fs::path& not_written)
    {
        const Outcome b = woven(args);
        EXPECT_EQ(b.code, 2) << args << ": " << b.err;
        EXPECT_TRUE(one_line(b.err)) << args << ": " << b.err;
        EXPECT_FALSE(fs::exists(dir_ / not_written)) << args;
    }
};

TEST_F(Cli, VersionPrintsTheVersion)
{
    const Outcome r = woven("--version");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.out, std::string("woven ") + WOVEN_VERSION + "\n");
}

TEST_F(Cli, HelpOfEverySubcommand)
{
    for (const char* args : {"--help", "fabrics --help", "scenes --help", "fit --help", "drape --help"}) {
        const Outcome r = woven(args);
        EXPECT_EQ(r.code, 0) << args << ": " << r.err;
        EXPECT_NE(r.out.find("Usage"), std::string::npos) << args;
    }
    EXPECT_NE(woven("drape --help").out.find("--max-steps"), std::string::npos);
    EXPECT_NE(woven("fit --help").out.find("--sigma-cm"), std::string::npos);
}

TEST_F(Cli, BadUsageExitsWithTwo)
{
    Outcome r = woven("nosuchcommand");
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("nosuchcommand"), std::string::npos) << r.err;
    EXPECT_TRUE(one_line(r.err)) << r.err;
    r = woven("");
    EXPECT_EQ(r.code, 2);
    r = woven("fabrics --no-such-option");
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("--no-such-option"), std::string::npos) << r.err;
    r = woven("fit");  // FABRIC is required
    EXPECT_EQ(r.code, 2);
    r = woven("drape --solver slow");
    EXPECT_EQ(r.code, 2);
    r = woven("drape --grid many");
    EXPECT_EQ(r.code, 2);
    r = woven("drape --seed -1");
    EXPECT_EQ(r.code, 2);
    r = woven("fit cotton --sigma-cm abc");
    EXPECT_EQ(r.code, 2);
    EXPECT_FALSE(fs::exists(dir_ / "out"));
}

TEST_F(Cli, FabricsListsTheBuiltIns)
{
    const Outcome r = woven("fabrics");
    ASSERT_EQ(r.code, 0) << r.err;
    for (const char* name : {"cotton", "wool", "polyester_cotton", "silk", "denim"})
        EXPECT_NE(r.out.find(name), std::string::npos) << name;
    EXPECT_NE(r.out.find("mg/cm2"), std::string::npos);

    const Outcome j = woven("fabrics --json");
    ASSERT_EQ(j.code, 0) << j.err;
    const auto list = nlohmann::json::parse(j.out);
    ASSERT_TRUE(list.is_array());
    ASSERT_GE(list.size(), 5u);
    for (const auto& f : list) {
        EXPECT_GT(f.at("W_mg_cm2").get<double>(), 0);
        EXPECT_GT(f.at("B_warp_gf_cm2_cm").get<double>(), 0);
        EXPECT_GT(f.at("B_weft_gf_cm2_cm").get<double>(), 0);
        EXPECT_GT(f.at("G_gf_cm_deg").get<double>(), 0);
    }
}

TEST_F(Cli, ScenesListsTheBuiltIns)
{
    const Outcome r = woven("scenes");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("cube"), std::string::npos);
}

TEST_F(Cli, FitWritesPlotsAndTables)
{
    const Outcome r = woven("fit cotton --out fit");
    ASSERT_EQ(r.code, 0) << r.err;
    for (const char* f : {"bending_warp_fit.png", "bending_weft_fit.png", "shear_fit.png", "bending_warp_energy.png",
                          "bending_warp_energy.csv", "bending_weft_energy.png", "bending_weft_energy.csv",
                          "trellis_energy.png", "trellis_energy.csv"}) {
        ASSERT_TRUE(fs::exists(dir_ / "fit" / f)) << f;
        EXPECT_GT(fs::file_size(dir_ / "fit" / f), 0u) << f;
    }
    // Only the outputs and their manifest: no temporary files left.
    EXPECT_EQ(count_entries("fit"), 10);
    const std::string png = slurp(dir_ / "fit" / "shear_fit.png");
    EXPECT_EQ(png.substr(1, 3), "PNG");

    auto header = [&](const char* f) {
        std::ifstream in(dir_ / "fit" / f);
        std::string line;
        std::getline(in, line);
        return line;
    };
    EXPECT_EQ(header("bending_warp_energy.csv"), "theta_rad,B_J,K_per_cm");
    EXPECT_EQ(header("bending_weft_energy.csv"), "theta_rad,B_J,K_per_cm");
    EXPECT_EQ(header("trellis_energy.csv"), "phi_rad,phi_deg,T_J");

    // The trellis table covers 0 .. 1.04 rad with finite energies.
    std::ifstream in(dir_ / "fit" / "trellis_energy.csv");
    std::string line;
    std::getline(in, line);
    double last_phi = -1, last_T = -1;
    int rows = 0;
    while (std::getline(in, line)) {
        double phi = 0, deg = 0, T = 0;
        ASSERT_EQ(std::sscanf(line.c_str(), "%lf,%lf,%lf", &phi, &deg, &T), 3) << line;
        EXPECT_GT(phi, last_phi);
        EXPECT_GE(T, last_T);
        last_phi = phi;
        last_T = T;
        ++rows;
    }
    EXPECT_GT(rows, 100);
    EXPECT_NEAR(last_phi, 1.04, 1e-9);

    // The text names the segments and compares the outer slope with the KES values.
    EXPECT_NE(r.out.find("Bending, warp"), std::string::npos);
    EXPECT_NE(r.out.find("KES B"), std::string::npos);
    EXPECT_NE(r.out.find("KES G"), std::string::npos);
    EXPECT_NE(r.out.find("max fit error"), std::string::npos);
}

TEST_F(Cli, FitDefaultsToOutFitName)
{
    const Outcome r = woven("fit silk");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(fs::exists(dir_ / "out" / "fit-silk" / "shear_fit.png"));
}

TEST_F(Cli, FitUnknownFabricWritesNothing)
{
    const Outcome r = woven("fit nosuchfabric");
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("nosuchfabric"), std::string::npos) << r.err;
    EXPECT_TRUE(one_line(r.err)) << r.err;
    EXPECT_EQ(r.err.rfind("woven: error: ", 0), 0u) << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "out"));
    EXPECT_EQ(count_entries(""), 0);
}

TEST_F(Cli, FitMalformedFabricFile)
{
    write(dir_ / "bad.toml", "name = \"bad\"\nareal_density_mg_cm2 = [1\n");  // TOML syntax error
    Outcome r = woven("fit bad.toml --out fit");
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("bad.toml"), std::string::npos) << r.err;
    EXPECT_TRUE(one_line(r.err)) << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "fit"));

    // A valid fabric file with a negative rigidity.
    std::string cotton = slurp(fs::path(WOVEN_SOURCE_DIR) / "fabrics" / "cotton.toml");
    write(dir_ / "neg.toml", replace(cotton, "G = 1.6", "G = -1.6"));
    r = woven("fit neg.toml --out fit");
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("neg.toml"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("shear.G"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "fit"));

    r = woven("fit cotton --sigma-cm -1 --out fit");
    EXPECT_EQ(r.code, 2);
    EXPECT_FALSE(fs::exists(dir_ / "fit"));
}

TEST_F(Cli, DrapeTinySceneWritesEverything)
{
    write(dir_ / "tiny.toml", kTinyScene);
    const Outcome r = woven("drape tiny.toml --out res --max-steps 40 --width 160 --height 120 --threads 1");
    ASSERT_EQ(r.code, 0) << r.err;
    for (const char* f : {"drape.obj", "drape.ply", "drape.glb", "drape.png", "report.json"}) {
        ASSERT_TRUE(fs::exists(dir_ / "res" / f)) << f;
        EXPECT_GT(fs::file_size(dir_ / "res" / f), 0u) << f;
    }
    EXPECT_EQ(count_entries("res"), 5);  // no temporary files left
    EXPECT_EQ(slurp(dir_ / "res" / "drape.ply").substr(0, 4), "ply\n");

    const auto j = nlohmann::json::parse(slurp(dir_ / "res" / "report.json"));
    for (const char* key : {"version", "scene", "fabric", "grid", "sigma_m", "solver", "seed", "converged",
                            "interrupted", "steps", "iterations", "simulated_time_s", "wall_time_s", "energy",
                            "energy_initial_J", "equilibrium", "contact", "strain", "bbox", "particle_mass_kg", "C0_J",
                            "shear_scale", "model", "kes"})
        EXPECT_TRUE(j.contains(key)) << key;
    for (const char* key : {"repulsion_J", "stretch_J", "bending_warp_J", "bending_weft_J", "trellis_J", "gravity_J",
                            "total_J"})
        EXPECT_TRUE(j["energy"].contains(key)) << key;
    EXPECT_TRUE(j["equilibrium"].contains("max_move_m"));
    EXPECT_TRUE(j["equilibrium"].contains("max_residual_rel"));
    EXPECT_TRUE(j["contact"].contains("max_penetration_m"));
    EXPECT_TRUE(j["contact"].contains("particles"));
    EXPECT_TRUE(j["strain"].contains("max"));
    EXPECT_TRUE(j["strain"].contains("min"));
    EXPECT_TRUE(j["strain"].contains("mean"));
    EXPECT_TRUE(j["bbox"].contains("min_m"));
    EXPECT_TRUE(j["bbox"].contains("max_m"));

    EXPECT_EQ(j["version"], WOVEN_VERSION);
    EXPECT_EQ(j["scene"], "tiny");
    EXPECT_EQ(j["fabric"], "cotton");
    EXPECT_EQ(j["grid"], nlohmann::json::array({9, 9}));
    EXPECT_NEAR(j["sigma_m"].get<double>(), 0.3 / 8, 1e-12);
    EXPECT_EQ(j["solver"], "fast");
    EXPECT_FALSE(j["interrupted"].get<bool>());
    EXPECT_LE(j["steps"].get<int>(), 40);
    // The cloth falls: the energy goes down, and it stays above the floor.
    EXPECT_LT(j["energy"]["total_J"].get<double>(), j["energy_initial_J"].get<double>());
    EXPECT_GE(j["bbox"]["min_m"][2].get<double>(), -1e-3);
    EXPECT_GE(j["contact"]["max_penetration_m"].get<double>(), 0.0);
    EXPECT_NEAR(j["particle_mass_kg"].get<double>(), 12.0 * 1e-2 * (0.3 / 8) * (0.3 / 8), 1e-12);
    // The de-embedded shear law: cotton's curve raised by its FB1 end effect (docs/VALIDATION.md: x 1.0068).
    EXPECT_NEAR(j["shear_scale"].get<double>(), 1.0068, 1e-3);

    EXPECT_NE(r.out.find("converged"), std::string::npos);
    EXPECT_NE(r.out.find("strain"), std::string::npos);
}

TEST_F(Cli, DrapeNoRenderAndOverrides)
{
    write(dir_ / "tiny.toml", kTinyScene);
    const Outcome r = woven("drape tiny.toml --out res --max-steps 3 --no-render --grid 7 --fabric wool --solver fast "
                        "--seed 5");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "res" / "drape.png"));
    EXPECT_TRUE(fs::exists(dir_ / "res" / "drape.obj"));
    const auto j = nlohmann::json::parse(slurp(dir_ / "res" / "report.json"));
    EXPECT_EQ(j["grid"], nlohmann::json::array({7, 7}));
    EXPECT_EQ(j["fabric"], "wool");
    EXPECT_EQ(j["seed"], 5);
    EXPECT_LE(j["steps"].get<int>(), 3);
    EXPECT_EQ(j["creep_softening"].get<double>(), 100.0);  // the continuation's default (sim/drape.hpp)
    // The creep continuation off, from the scene: recorded as given.
    write(dir_ / "nocreep.toml", kTinyScene + "\n[solver]\ncreep_softening = 1\n");
    ASSERT_EQ(woven("drape nocreep.toml --out res3 --max-steps 1 --no-render").code, 0);
    EXPECT_EQ(nlohmann::json::parse(slurp(dir_ / "res3" / "report.json"))["creep_softening"].get<double>(), 1.0);
    // The shear law as measured: no factor.
    write(dir_ / "measured.toml", kTinyScene + "\n[model]\nshear_law = \"measured\"\n");
    ASSERT_EQ(woven("drape measured.toml --out res2 --max-steps 1 --no-render").code, 0);
    EXPECT_EQ(nlohmann::json::parse(slurp(dir_ / "res2" / "report.json"))["shear_scale"].get<double>(), 1.0);
}

/// Each bad input: exit 2, one line naming the file and the field, nothing written.
TEST_F(Cli, DrapeBadInputsWriteNothing)
{
    const std::string tiny = kTinyScene;
    struct Case {
        const char* what;
        std::string scene;
        std::string args;
        std::vector<std::string> expect;  // substrings of the message
    };
    const std::vector<Case> cases = {
        {"unknown obstacle type", replace(tiny, "type = \"sphere\"", "type = \"sphre\""), "", {"obstacle[2].type", "sphre"}},
        {"missing mesh file", replace(tiny, "type = \"sphere\"", "type = \"mesh\"\nfile = \"nothere.obj\""), "",
         {"obstacle[2].file", "nothere.obj"}},
        {"cloth inside an obstacle", replace(tiny, "height_m = 0.12", "height_m = 0.05"), "", {"cloth", "obstacle[2]"}},
        {"grid 2", replace(tiny, "grid = [9, 9]", "grid = [2, 2]"), "", {"cloth.grid"}},
        {"NaN", replace(tiny, "height_m = 0.12", "height_m = nan"), "", {"cloth.height_m"}},
        {"grid 2 on the command line", tiny, "--grid 2", {"--grid"}},
        {"unknown fabric", tiny, "--fabric nosuchfabric", {"nosuchfabric"}},
        {"bad picture size", tiny, "--width 0", {"--width"}},
    };
    for (const auto& c : cases) {
        write(dir_ / "scene.toml", c.scene);
        const Outcome r = woven("drape scene.toml --out res --max-steps 2 " + c.args);
        EXPECT_EQ(r.code, 2) << c.what << ": " << r.err;
        EXPECT_TRUE(one_line(r.err)) << c.what << ": " << r.err;
        EXPECT_EQ(r.err.rfind("woven: error: ", 0), 0u) << c.what << ": " << r.err;
        if (c.args.empty()) {
            EXPECT_NE(r.err.find("scene.toml"), std::string::npos) << c.what << ": " << r.err;
        }
        for (const auto& e : c.expect) EXPECT_NE(r.err.find(e), std::string::npos) << c.what << ": " << r.err;
        EXPECT_FALSE(fs::exists(dir_ / "res")) << c.what;
        fs::remove_all(dir_ / "res");
    }
    const Outcome r = woven("drape nosuchscene --out res");
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("nosuchscene"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "res"));
}

TEST_F(Cli, DrapeOutputPathThatIsAFileIsBadUsage)
{
    write(dir_ / "tiny.toml", kTinyScene);
    write(dir_ / "res", "not a directory");
    const Outcome r = woven("drape tiny.toml --out res --max-steps 2 --no-render");
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_EQ(r.err, "woven: error: command line: --out: res exists and is not a directory\n");
    EXPECT_TRUE(one_line(r.err)) << r.err;
    EXPECT_EQ(slurp(dir_ / "res"), "not a directory");
}

/// Ctrl-C: the solver stops after the current step; the outputs are written with
/// converged = false, interrupted = true, and the exit code is 130.
TEST_F(Cli, DrapeInterruptWritesTheStateReached)
{
    const fs::path err = dir_ / "stderr.txt";
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        if (::chdir(dir_.c_str()) != 0) ::_exit(99);
        FILE* f = std::freopen(err.c_str(), "w", stderr);
        if (!f) ::_exit(99);
        FILE* o = std::freopen("/dev/null", "w", stdout);
        if (!o) ::_exit(99);
        ::execl(WOVEN_BINARY, WOVEN_BINARY, "drape", "cube", "--grid", "31", "--max-steps", "400", "--out", "res",
                "--no-render", static_cast<char*>(nullptr));
        ::_exit(98);
    }
    // Wait for the first progress line (printed after about 0.5 s), then press Ctrl-C.
    int status = 0;
    bool exited = false;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    while (std::chrono::steady_clock::now() < deadline) {
        if (::waitpid(pid, &status, WNOHANG) == pid) {
            exited = true;
            break;
        }
        if (slurp(err).find("\nstep ") != std::string::npos) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    if (!exited) {
        ::kill(pid, SIGINT);
        ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    }
    if (exited && WIFEXITED(status) && WEXITSTATUS(status) == 0)
        GTEST_SKIP() << "the drape finished before the first progress line";
    ASSERT_TRUE(WIFEXITED(status)) << slurp(err);
    EXPECT_EQ(WEXITSTATUS(status), 130) << slurp(err);
    for (const char* f : {"drape.obj", "drape.ply", "report.json"}) EXPECT_TRUE(fs::exists(dir_ / "res" / f)) << f;
    const auto j = nlohmann::json::parse(slurp(dir_ / "res" / "report.json"));
    EXPECT_TRUE(j["interrupted"].get<bool>());
    EXPECT_FALSE(j["converged"].get<bool>());
}

}  // namespace

namespace {

/// Width and height from a PNG's IHDR chunk (bytes 16-23, big-endian); {0, 0} if not a PNG.
std::pair<unsigned, unsigned> png_size(const std::string& png)
{
    if (png.size() < 24 || png.compare(1, 3, "PNG") != 0) return {0, 0};
    auto be32 = [&](std::size_t at) {
        unsigned v = 0;
        for (std::size_t k = 0; k < 4; ++k) v = (v << 8) | static_cast<unsigned char>(png[at + k]);
        return v;
    };
    return {be32(16), be32(20)};
}

}  // namespace

/// woven render draws a drape's mesh at the size asked, the same bits twice, and turns bad
/// options into one-line errors (exit 2) that write nothing.
TEST_F(Cli, RenderDrawsADrapedMeshAndRejectsBadOptions)
{
    write(dir_ / "tiny.toml", kTinyScene);
    ASSERT_EQ(woven("drape tiny.toml --out d --max-steps 2 --no-render").code, 0);
    const Outcome r = woven("render d/drape.obj --scene tiny.toml --view top --size 80x60 --out top.png");
    ASSERT_EQ(r.code, 0) << r.err;
    const std::string png = slurp(dir_ / "top.png");
    EXPECT_EQ(png_size(png), std::make_pair(80u, 60u));
    ASSERT_EQ(woven("render d/drape.obj --scene tiny.toml --view top --size 80x60 --out again.png").code, 0);
    EXPECT_EQ(slurp(dir_ / "again.png"), png);  // deterministic
    // Without a scene: a floor under the mesh, the corner view.
    ASSERT_EQ(woven("render d/drape.obj --size 40x30 --out plain.png").code, 0);
    EXPECT_EQ(png_size(slurp(dir_ / "plain.png")), std::make_pair(40u, 30u));

    for (const char* bad : {"render d/drape.obj --size 0x10 --out x.png", "render d/drape.obj --size big --out x.png",
                            "render d/drape.obj --view sideways --out x.png", "render nothere.obj --out x.png",
                            "render d/drape.obj --scene nothere.toml --out x.png"})
        expect_rejected(bad, "x.png");
}

/// woven experiment: help on every experiment, and bad names and options rejected before any
/// drape (exit 2, one line, nothing written).
TEST_F(Cli, ExperimentHelpAndBadOptions)
{
    const Outcome h = woven("experiment --help");
    EXPECT_EQ(h.code, 0);
    for (const char* name : {"cube", "map", "figure1"}) EXPECT_NE(h.out.find(name), std::string::npos) << name;
    for (const char* bad : {"experiment", "experiment chair --out e", "experiment cube --seeds 0 --out e",
                            "experiment cube --grid 2 --out e", "experiment map --map-grid 5y4 --out e",
                            "experiment map --reuse nothere.json --out e"})
        expect_rejected(bad, "e");
}
