// woven experiment runs its drapes as a sweep plan (issue 35): the plan it writes is the one in
// examples/, the experiment's numbers are those of a direct `woven sweep` of that plan, a second
// run drapes nothing again (resume), --plan-only runs nothing, and the drapes split between
// shards with the figures written once every drape is done. Small grids (7 x 7 particles): each
// test a few seconds on one core.
#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_support.hpp"

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;
using woven::test::one_line;
using woven::test::slurp;

namespace {

using ExperimentSweep = woven::test::WovenProcessTest;

nlohmann::json read_json(const fs::path& p) { return nlohmann::json::parse(slurp(p)); }

/// The point folders of a sweep folder (those with a point.json), sorted.
std::vector<std::string> point_folders(const fs::path& sweep)
{
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(sweep))
        if (fs::exists(e.path() / "point.json")) out.push_back(e.path().filename().string());
    std::sort(out.begin(), out.end());
    return out;
}

/// Occurrences of `what` in `text`.
int count(const std::string& text, const std::string& what)
{
    int n = 0;
    for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
    return n;
}

}  // namespace

// The cube experiment (3 fabrics x 2 seeds at 7 x 7) against a direct sweep of the plan it wrote:
// the same drapes bit for bit (drape.obj), and every number of cube_results.json (energy, steps,
// converged, the fold analysis) is the point's report.json's. (Its figure takes most of the
// time: 9 views of 480 x 360.)
TEST_F(ExperimentSweep, CubeIsADirectSweepOfItsPlan)
{
    const auto e = woven("experiment cube --grid 7 --seeds 2 --out E --sweep S");
    ASSERT_EQ(e.code, 0) << e.err;
    EXPECT_THAT(e.err, HasSubstr("6 points; 0 done already, 6 to run"));
    EXPECT_EQ(count(e.err, "woven: experiment: cube, "), 6) << e.err;
    EXPECT_THAT(e.err, HasSubstr("woven: experiment: cube, wool, seed 2 ...\n"));
    const std::vector<std::string> names = {"fabric-cotton_seed-1", "fabric-cotton_seed-2", "fabric-polyester_cotton_seed-1",
                                            "fabric-polyester_cotton_seed-2", "fabric-wool_seed-1", "fabric-wool_seed-2"};
    ASSERT_EQ(point_folders(dir_ / "S"), names);
    EXPECT_EQ(read_json(dir_ / "S" / "sweep.json")["done"], 6);
    // `woven check` takes the experiment's folder and its sweep folder, as `woven report` does.
    const auto c = woven("check E S");
    ASSERT_EQ(c.code, 0) << c.err;
    EXPECT_THAT(c.out, HasSubstr("E: ok (output of "));
    EXPECT_THAT(c.out, HasSubstr("cube_results.json)\n"));
    EXPECT_THAT(c.out, HasSubstr("S: ok (sweep "));
    EXPECT_THAT(c.out, HasSubstr("6 points: 6 done and verified, 0 not done)\n"));

    const auto d = woven("sweep S/plan.toml --out D");
    ASSERT_EQ(d.code, 0) << d.err;
    ASSERT_EQ(point_folders(dir_ / "D"), names);
    const nlohmann::json results = read_json(dir_ / "E" / "cube_results.json");
    ASSERT_EQ(results["runs"].size(), 6u);
    const std::string folds_md = slurp(dir_ / "E" / "cube_folds.md");
    // Plan order: fabric (cotton, wool, polyester_cotton), then seed.
    const std::vector<std::string> plan_order = {"fabric-cotton_seed-1", "fabric-cotton_seed-2", "fabric-wool_seed-1",
                                                 "fabric-wool_seed-2", "fabric-polyester_cotton_seed-1", "fabric-polyester_cotton_seed-2"};
    for (std::size_t k = 0; k < plan_order.size(); ++k) {
        const std::string& p = plan_order[k];
        EXPECT_EQ(slurp(dir_ / "S" / p / "drape.obj"), slurp(dir_ / "D" / p / "drape.obj")) << p;
        const nlohmann::json report = read_json(dir_ / "D" / p / "report.json");
        const nlohmann::json& run = results["runs"][k];
        EXPECT_EQ(run["fabric"], p.substr(7, p.rfind("_seed") - 7)) << p;
        EXPECT_EQ(run["seed"], report["seed"]) << p;
        EXPECT_EQ(run["converged"], report["converged"]) << p;
        EXPECT_EQ(run["steps"], report["steps"]) << p;
        EXPECT_EQ(run["energy_J"].get<double>(), report["energy"]["total_J"].get<double>()) << p;  // exact: the same drape
        EXPECT_EQ(run["folds"], report["folds"]) << p;
        EXPECT_EQ(run["wall_s"], read_json(dir_ / "S" / p / "report.json")["wall_time_s"]) << p;
        EXPECT_TRUE(run["folds"].is_object()) << p;  // the cube is a box: folds analysed
        const std::string row = "| " + run["fabric"].get<std::string>() + " | " + run["seed"].dump() + " | " +
                                (run["converged"].get<bool>() ? "yes" : "no") + " |";
        EXPECT_THAT(folds_md, HasSubstr(row)) << p;
    }
    EXPECT_THAT(folds_md, HasSubstr("1 m x 1 m cloth, 7 x 7 particles"));
    EXPECT_THAT(folds_md, HasSubstr("Made by `woven experiment cube --out E --seeds 2 --grid 7`"));  // --sweep, --jobs: not recorded
}

// --plan-only writes the plan (the map: and its fabric files) and runs nothing; the plans of
// cube and figure1 with the default options are examples/experiment-cube.toml and
// experiment-figure1.toml. Bad options are one-line errors, exit 2, with nothing written.
TEST_F(ExperimentSweep, PlanOnlyWritesThePlansOfExamples)
{
    for (const char* which : {"cube", "figure1"}) {
        const auto r = woven(std::string("experiment ") + which + " --plan-only");
        ASSERT_EQ(r.code, 0) << which << ": " << r.err;
        const fs::path plan = dir_ / "out" / ("experiment-" + std::string(which)) / "plan.toml";
        EXPECT_THAT(r.out, HasSubstr("wrote out/experiment-" + std::string(which) + "/plan.toml"));
        EXPECT_EQ(slurp(plan), slurp(fs::path(WOVEN_SOURCE_DIR) / "examples" / ("experiment-" + std::string(which) + ".toml"))) << which;
        EXPECT_TRUE(point_folders(plan.parent_path()).empty()) << which;
        EXPECT_FALSE(fs::exists(plan.parent_path() / "sweep.json")) << which;
    }
    EXPECT_FALSE(fs::exists(dir_ / "docs"));  // the default --out: not made by --plan-only

    const auto m = woven("experiment map --map-grid 2x3 --grid 7 --plan-only --sweep M");
    ASSERT_EQ(m.code, 0) << m.err;
    EXPECT_THAT(m.out, HasSubstr("(6 drapes)"));
    const auto l = woven("sweep M/plan.toml --list");
    ASSERT_EQ(l.code, 0) << l.err;
    EXPECT_EQ(count(l.out, "\n"), 6);
    const std::string first = "0 fabric-ratio-0.25_length-1: drape cube --fabric " + (dir_ / "M" / "fabrics" / "ratio-0.25_length-1.toml").string() +
                              " --seed 1 --grid 7 --threads 1 --no-render\n";
    EXPECT_EQ(l.out.substr(0, first.size()), first);
    EXPECT_THAT(l.out, HasSubstr("5 fabric-ratio-4_length-5: "));
    EXPECT_THAT(slurp(dir_ / "M" / "fabrics" / "ratio-4_length-3.toml"), HasSubstr("[bending.warp]"));
    EXPECT_TRUE(point_folders(dir_ / "M").empty());

    const struct {
        const char* args;
        const char* message;
    } bad[] = {
        {"experiment cube --jobs 0 --sweep B", "woven: error: command line: --jobs: expected an integer in [1, 4096], got '0'\n"},
        {"experiment cube --shard 2/2 --sweep B",
         "woven: error: command line: --shard: expected I/N with 0 <= I < N (shard I of N, counted from 0), got '2/2'\n"},
        {"experiment cube --sweep ''", "woven: error: command line: --sweep: expected a directory path, got an empty string\n"},
        {"experiment map --plan-only --reuse m.json --sweep B",
         "woven: error: command line: --plan-only: expected no --reuse (reused drapes need no plan)\n"},
    };
    woven::test::write(dir_ / "m.json", "{\"cells\": []}");
    for (const auto& c : bad) {
        const auto r = woven(c.args);
        EXPECT_EQ(r.code, 2) << c.args << ": " << r.err;
        EXPECT_TRUE(one_line(r.err)) << c.args << ": " << r.err;
        EXPECT_EQ(r.err, c.message) << c.args;
        EXPECT_FALSE(fs::exists(dir_ / "B")) << c.args;
    }
}

// The map's drapes in two shards (--shard, as ranks of a launcher run them): the first shard
// drapes its half and writes no figure; the second finds every drape done and writes the map,
// whose cells are the points' reports. Run again, it drapes nothing and writes the same files;
// a larger grid drapes only its new cells.
TEST_F(ExperimentSweep, MapInTwoShardsThenResumed)
{
    const auto a = woven("experiment map --map-grid 2x2 --grid 7 --out O --sweep S --shard 0/2");
    ASSERT_EQ(a.code, 0) << a.err;
    EXPECT_THAT(a.err, HasSubstr("shard 0/2 (--shard): 2 here"));
    EXPECT_THAT(a.out, HasSubstr("this shard's drapes are done, 2 of 4 in all"));
    EXPECT_EQ(point_folders(dir_ / "S").size(), 2u);
    EXPECT_FALSE(fs::exists(dir_ / "O" / "corner_map.json"));
    const auto b = woven("experiment map --map-grid 2x2 --grid 7 --out O --sweep S --shard 1/2");
    ASSERT_EQ(b.code, 0) << b.err;
    EXPECT_EQ(count(b.err, "woven: experiment: cube, ratio "), 2) << b.err;
    const nlohmann::json map = read_json(dir_ / "O" / "corner_map.json");
    ASSERT_EQ(map["cells"].size(), 4u);
    const std::vector<std::string> points = {"fabric-ratio-0.25_length-1", "fabric-ratio-0.25_length-5", "fabric-ratio-4_length-1",
                                             "fabric-ratio-4_length-5"};
    EXPECT_EQ(point_folders(dir_ / "S"), points);
    for (std::size_t k = 0; k < points.size(); ++k) {
        const nlohmann::json report = read_json(dir_ / "S" / points[k] / "report.json");
        const nlohmann::json& cell = map["cells"][k];
        EXPECT_EQ(cell["energy_J"].get<double>(), report["energy"]["total_J"].get<double>()) << points[k];
        EXPECT_EQ(cell["folds"], report["folds"]) << points[k];
        EXPECT_EQ(cell["converged"], report["converged"]) << points[k];
        EXPECT_EQ(cell["ratio_warp_weft"].get<double>(), k < 2 ? 0.25 : 4.0) << points[k];
        EXPECT_EQ(cell["bending_length_cm"].get<double>(), k % 2 == 0 ? 1.0 : 5.0) << points[k];
    }
    EXPECT_EQ(read_json(dir_ / "S" / "sweep.json")["done"], 4);

    // Resume: nothing drapes again; the same files, byte for byte.
    const std::string run_id = read_json(dir_ / "S" / points[0] / "point.json")["run_id"];
    const std::string png = slurp(dir_ / "O" / "corner_map.png"), md = slurp(dir_ / "O" / "corner_map.md");
    const auto again = woven("experiment map --map-grid 2x2 --grid 7 --out O --sweep S --jobs 2");
    ASSERT_EQ(again.code, 0) << again.err;
    EXPECT_THAT(again.err, HasSubstr("4 points; 4 done already, 0 to run"));
    EXPECT_THAT(again.err, Not(HasSubstr("woven: experiment:")));
    EXPECT_EQ(read_json(dir_ / "S" / points[0] / "point.json")["run_id"], run_id);
    EXPECT_EQ(slurp(dir_ / "O" / "corner_map.png"), png);
    EXPECT_EQ(slurp(dir_ / "O" / "corner_map.md"), md);
    EXPECT_EQ(read_json(dir_ / "O" / "corner_map.json"), map);  // with every file's SHA-256

    // A third bending length (3 cm): the four drapes are kept, two run.
    const auto more = woven("experiment map --map-grid 2x3 --grid 7 --out O3 --sweep S");
    ASSERT_EQ(more.code, 0) << more.err;
    EXPECT_THAT(more.err, HasSubstr("6 points; 4 done already, 2 to run"));
    EXPECT_EQ(count(more.err, "woven: experiment: cube, ratio "), 2) << more.err;
    EXPECT_EQ(read_json(dir_ / "O3" / "corner_map.json")["cells"].size(), 6u);
}
