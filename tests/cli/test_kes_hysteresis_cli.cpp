// woven kes-test --hysteresis (issue 33): friction by default, full loops, the hysteresis fields
// of kes-report.json, the loop CSVs and plots; loading-branch as before; a bad value exits 2.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_support.hpp"

namespace {

namespace fs = std::filesystem;
using woven::test::Outcome;
using woven::test::slurp;

class KesHysteresisCli : public woven::test::WovenProcessTest { };

TEST_F(KesHysteresisCli, FrictionLoopsFillTheReport)
{
    const Outcome r = woven("kes-test wool --test shear --direction warp --sigma-cm 1 --out k");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("hysteresis friction"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("2HG5"), std::string::npos) << r.out;
    const auto j = nlohmann::json::parse(slurp(dir_ / "k" / "kes-report.json"));
    EXPECT_EQ(j["hysteresis"], "friction");
    const auto& t = j["tests"][0];
    EXPECT_EQ(t["test"], "shear");
    EXPECT_DOUBLE_EQ(t["input_hysteresis"]["2HG"].get<double>(), 0.9);  // fabrics/wool.toml
    EXPECT_DOUBLE_EQ(t["input_hysteresis"]["2HG5"].get<double>(), 1.6);
    EXPECT_NEAR(t["simulated_hysteresis"]["2HG"].get<double>() / 0.9, 1.0, 0.05);
    EXPECT_NEAR(t["simulated_hysteresis"]["2HG5"].get<double>() / 1.6, 1.0, 0.05);
    EXPECT_LT(std::abs(t["hysteresis_rel_error"].get<double>()), 0.05);
    EXPECT_LT(t["loop_max_rel_error"].get<double>(), 0.05);
    EXPECT_NEAR(t["summary_rel_error"].get<double>(), 0.0, 0.01);
    EXPECT_TRUE(fs::exists(dir_ / "k" / "shear_loop_warp.csv"));
    EXPECT_TRUE(fs::exists(dir_ / "k" / "shear_loop.png"));
    // 0 -> +8 -> -8 -> 0 degrees in 0.5 degree steps: 65 rows and the header.
    const std::string csv = slurp(dir_ / "k" / "shear_loop_warp.csv");
    EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 66);
    EXPECT_EQ(csv.substr(0, csv.find('\n')), "step,phi_deg,simulated_F_gf_per_cm,input_F_gf_per_cm");
}

TEST_F(KesHysteresisCli, BendingGivenAsPointsKeepsTheLoadingBranch)
{
    // cotton's bending curves are point lists (no 2HB): no loop, null hysteresis.
    const Outcome r = woven("kes-test cotton --test bending --direction warp --sigma-cm 1 --out k");
    ASSERT_EQ(r.code, 0) << r.err;
    const auto j = nlohmann::json::parse(slurp(dir_ / "k" / "kes-report.json"));
    const auto& t = j["tests"][0];
    EXPECT_TRUE(t["input_hysteresis"].is_null());
    EXPECT_TRUE(t["simulated_hysteresis"].is_null());
    EXPECT_TRUE(t["loop_max_rel_error"].is_null());
    EXPECT_FALSE(fs::exists(dir_ / "k" / "bending_loop_warp.csv"));
}

TEST_F(KesHysteresisCli, LoadingBranchRunsNoLoopAndBadValueExits2)
{
    Outcome r = woven("kes-test silk --test bending --direction weft --sigma-cm 0.5 --hysteresis loading-branch --out k");
    ASSERT_EQ(r.code, 0) << r.err;
    auto j = nlohmann::json::parse(slurp(dir_ / "k" / "kes-report.json"));
    EXPECT_EQ(j["hysteresis"], "loading-branch");
    EXPECT_TRUE(j["tests"][0]["simulated_hysteresis"].is_null());
    EXPECT_FALSE(fs::exists(dir_ / "k" / "bending_loop_weft.csv"));
    r = woven("kes-test silk --test bending --direction weft --sigma-cm 0.5 --out f");
    ASSERT_EQ(r.code, 0) << r.err;
    j = nlohmann::json::parse(slurp(dir_ / "f" / "kes-report.json"));
    EXPECT_NEAR(j["tests"][0]["simulated_hysteresis"]["2HB"].get<double>() / 0.007, 1.0, 0.05);
    EXPECT_TRUE(fs::exists(dir_ / "f" / "bending_loop_weft.csv"));
    EXPECT_TRUE(fs::exists(dir_ / "f" / "bending_loop.png"));
    r = woven("kes-test silk --hysteresis elastic");
    EXPECT_EQ(r.code, 2);
    EXPECT_EQ(r.err, "woven: error: command line: --hysteresis: expected loading-branch or friction, got 'elastic'\n");
}

}  // namespace
