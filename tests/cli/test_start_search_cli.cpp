// Starting a drape from a given state (`--start`), the search of the Cusick tester's rest states
// (`cusick --search`) and the bias bending switch (`--bias`), on the command line.
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_support.hpp"

namespace fs = std::filesystem;
using ::testing::HasSubstr;

namespace {

using Ran = woven::test::Outcome;
using StartCli = woven::test::WovenProcessTest;

nlohmann::json read_json(const fs::path& p)
{
    std::ifstream in(p);
    return nlohmann::json::parse(in);
}

}  // namespace

TEST_F(StartCli, ADrapeStartedFromItsOwnRestStaysThere)
{
    woven::test::write(dir_ / "tiny.toml", woven::test::kTinyScene);
    const Ran first = woven("drape tiny.toml --no-render --threads 1 --perturb 0 --out a");
    ASSERT_EQ(first.code, 0) << first.err;
    const auto a = read_json(dir_ / "a" / "report.json");
    EXPECT_EQ(a.at("start_sha256").get<std::string>(), "");
    const Ran again = woven("drape tiny.toml --no-render --threads 1 --perturb 0 --start a/drape.obj --out b");
    ASSERT_EQ(again.code, 0) << again.err;
    const auto b = read_json(dir_ / "b" / "report.json");
    // The start is the first drape's file, named by its SHA-256, and its energy the first's end.
    EXPECT_EQ(b.at("start_sha256").get<std::string>(), a.at("files").at("drape.obj").at("sha256").get<std::string>());
    const double e_a = a.at("energy").at("total_J").get<double>();
    EXPECT_NEAR(b.at("energy_initial_J").get<double>(), e_a, 1e-6 * std::abs(e_a));  // 9 digits in the file
    EXPECT_NEAR(b.at("energy").at("total_J").get<double>(), e_a, 1e-6 * std::abs(e_a));
    EXPECT_LE(b.at("steps").get<int>(), a.at("steps").get<int>());
}

TEST_F(StartCli, AStartOfAnotherGridIsAOneLineInputError)
{
    woven::test::write(dir_ / "tiny.toml", woven::test::kTinyScene);
    ASSERT_EQ(woven("drape tiny.toml --no-render --threads 1 --out a").code, 0);
    const Ran r = woven("drape tiny.toml --grid 11 --no-render --threads 1 --start a/drape.obj --out b");
    EXPECT_EQ(r.code, 2);
    EXPECT_TRUE(woven::test::one_line(r.err)) << r.err;
    EXPECT_THAT(r.err, HasSubstr("a/drape.obj: v: 81 vertices"));
    EXPECT_THAT(r.err, HasSubstr("expected a drape of the same scene and grid (11 x 11"));
    EXPECT_FALSE(fs::exists(dir_ / "b" / "report.json"));
    woven::test::write(dir_ / "x.ply", "ply\n");
    const Ran ply = woven("drape tiny.toml --no-render --start x.ply --out c");
    EXPECT_EQ(ply.code, 2);
    EXPECT_THAT(ply.err, HasSubstr("x.ply: file: expected a drape .obj file"));
}

TEST_F(StartCli, TheSearchKeepsEveryRestStateAndPredictsTheLowest)
{
    // A 12 cm specimen on a 6 cm disc at 1 cm: the release, two guided starts and the
    // continuations from the fabric 4 and 16 times stiffer in bending.
    const Ran r = woven("cusick silk --specimen-cm 12 --disc-cm 6 --spacing-cm 1 --search --modes 2,3 --jobs 2 --no-render --threads 1 --out o");
    ASSERT_EQ(r.code, 0) << r.err;
    const auto j = read_json(dir_ / "o" / "cusick.json");
    EXPECT_EQ(j.at("search").at("modes"), nlohmann::json::array({2, 3}));
    const auto& run = j.at("runs").at(0);
    const auto& states = run.at("states");
    ASSERT_EQ(states.size(), 5u);
    EXPECT_EQ(states[0].at("start").get<std::string>(), "release");
    EXPECT_EQ(states[1].at("guides").get<int>(), 2);
    EXPECT_EQ(states[2].at("guides").get<int>(), 3);
    EXPECT_EQ(states[3].at("stiffer").get<double>(), 4.0);
    EXPECT_EQ(states[4].at("start").get<std::string>(), "from 16 x B");
    double lowest = std::numeric_limits<double>::infinity();
    int which = -1;
    for (int k = 0; k < 5; ++k)
        if (states[k].at("energy_J").get<double>() < lowest) lowest = states[k].at("energy_J").get<double>(), which = k;
    EXPECT_EQ(run.at("prediction").at("state").get<int>(), which);
    EXPECT_EQ(run.at("drape_coefficient_percent").get<double>(), states[which].at("drape_coefficient_percent").get<double>());
    EXPECT_EQ(j.at("drape_coefficient_percent").get<double>(), states[which].at("drape_coefficient_percent").get<double>());
    // --modes and --jobs belong to --search; --start does not go with it.
    for (const char* bad : {"cusick silk --modes 2-4", "cusick silk --jobs 2", "cusick silk --search --modes 1-4",
                            "cusick silk --search --modes 4,3", "cusick silk --search --start o/cusick.obj"}) {
        const Ran b = woven(bad);
        EXPECT_EQ(b.code, 2) << bad;
        EXPECT_TRUE(woven::test::one_line(b.err)) << bad << ": " << b.err;
    }
}

TEST_F(StartCli, BiasBendingStiffensTheDrapeAndIsReported)
{
    woven::test::write(dir_ / "tiny.toml", woven::test::kTinyScene);
    ASSERT_EQ(woven("drape tiny.toml --no-render --threads 1 --out t").code, 0);
    ASSERT_EQ(woven("drape tiny.toml --no-render --threads 1 --bias fabric --out f").code, 0);
    const auto t = read_json(dir_ / "t" / "report.json"), f = read_json(dir_ / "f" / "report.json");
    EXPECT_EQ(t.at("model").at("bias_bending").get<std::string>(), "threads");
    EXPECT_EQ(t.at("energy").at("twist_J").get<double>(), 0.0);
    EXPECT_EQ(f.at("model").at("bias_bending").get<std::string>(), "fabric");
    EXPECT_GT(f.at("model").at("twist_rigidity_N_m").get<double>(), 0.0);
    EXPECT_GT(f.at("energy").at("twist_J").get<double>(), 0.0);  // the cloth over a sphere bends across its threads
    const Ran bad = woven("drape tiny.toml --bias diagonal");
    EXPECT_EQ(bad.code, 2);
    EXPECT_THAT(bad.err, HasSubstr("--bias"));
}
