// Friction inside the weave in `woven drape` and `woven cusick` (issue 33): --hysteresis and the
// scene's [model] hysteresis, bad values (one line, exit 2, nothing written), the hysteresis and
// protocol recorded in report.json and cusick.json, the lowered Cusick protocol.
#include <algorithm>
#include <filesystem>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_support.hpp"

namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using woven::test::Outcome;
using woven::test::slurp;

class HysteresisCli : public woven::test::WovenProcessTest { };

TEST_F(HysteresisCli, BadValuesGiveOneLineAndExit2)
{
    woven::test::write(dir_ / "tiny.toml", woven::test::kTinyScene);
    woven::test::write(dir_ / "bad.toml", woven::test::kTinyScene + "[model]\nhysteresis = \"sticky\"\n");
    woven::test::write(dir_ / "paper.toml", woven::test::kTinyScene + "[solver]\nkind = \"paper\"\n[model]\nhysteresis = \"friction\"\n");
    struct Bad {
        std::string args, err;
    };
    for (const Bad& b : {Bad{"drape tiny.toml --hysteresis elastic",
                             "woven: error: command line: --hysteresis: expected loading-branch or friction, got 'elastic'\n"},
                         Bad{"drape tiny.toml --hysteresis friction --solver paper", "woven: error: command line: --hysteresis: expected loading-branch with the paper solver"},
                         Bad{"drape bad.toml", "model.hysteresis"},
                         Bad{"drape paper.toml", "paper.toml: model.hysteresis: expected loading-branch with the paper solver"},
                         Bad{"cusick silk --hysteresis none", "woven: error: command line: --hysteresis: expected loading-branch or friction, got 'none'\n"},
                         Bad{"cusick silk --protocol drop", "woven: error: command line: --protocol: expected release or lowered, got 'drop'\n"}}) {
        SCOPED_TRACE(b.args);
        const Outcome r = woven(b.args + " --out o");
        EXPECT_EQ(r.code, 2);
        EXPECT_THAT(r.err, HasSubstr(b.err));
        EXPECT_TRUE(woven::test::one_line(r.err)) << r.err;
        EXPECT_FALSE(fs::exists(dir_ / "o"));
    }
}

TEST_F(HysteresisCli, DrapeRecordsHysteresisAndProtocolAndFrictionMovesTheDrape)
{
    // wool gives all three curves by summary values with widths: every family has friction.
    woven::test::write(dir_ / "tiny.toml", woven::test::kTinyScene);
    Outcome r = woven("drape tiny.toml --fabric wool --threads 1 --no-render --out a");
    ASSERT_EQ(r.code, 0) << r.err;
    r = woven("drape tiny.toml --fabric wool --threads 1 --no-render --hysteresis friction --out b");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_THAT(r.err, HasSubstr("friction inside the weave"));
    // The same through the scene file.
    woven::test::write(dir_ / "friction.toml", woven::test::kTinyScene + "[model]\nhysteresis = \"friction\"\n");
    r = woven("drape friction.toml --fabric wool --threads 1 --no-render --out c");
    ASSERT_EQ(r.code, 0) << r.err;
    const auto a = nlohmann::json::parse(slurp(dir_ / "a" / "report.json"));
    const auto b = nlohmann::json::parse(slurp(dir_ / "b" / "report.json"));
    const auto c = nlohmann::json::parse(slurp(dir_ / "c" / "report.json"));
    EXPECT_EQ(a["model"]["hysteresis"], "loading-branch");
    EXPECT_EQ(b["model"]["hysteresis"], "friction");
    EXPECT_EQ(c["model"]["hysteresis"], "friction");
    for (const auto* j : {&a, &b, &c}) {
        EXPECT_EQ((*j)["protocol"], "drop");
        EXPECT_TRUE((*j)["converged"].get<bool>());
    }
    // Friction gives another rest state; the scene key and the option the same one, bit for bit.
    EXPECT_NE(slurp(dir_ / "a" / "drape.obj"), slurp(dir_ / "b" / "drape.obj"));
    EXPECT_EQ(slurp(dir_ / "b" / "drape.obj"), slurp(dir_ / "c" / "drape.obj"));
    // --hysteresis loading-branch overrides the scene's friction.
    r = woven("drape friction.toml --fabric wool --threads 1 --no-render --hysteresis loading-branch --out d");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(slurp(dir_ / "a" / "drape.obj"), slurp(dir_ / "d" / "drape.obj"));
}

TEST_F(HysteresisCli, CusickRecordsHysteresisAndProtocol)
{
    // A 12 cm specimen on a 6 cm disc at 1 cm (about 110 particles), silk (widths on every curve).
    const std::string small = "cusick silk --specimen-cm 12 --disc-cm 6 --spacing-cm 1 --no-render --threads 1";
    Outcome r = woven(small + " --out a");
    ASSERT_EQ(r.code, 0) << r.err;
    r = woven(small + " --hysteresis friction --protocol lowered --out b");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_THAT(r.err, HasSubstr("hysteresis friction, protocol lowered"));
    const auto a = nlohmann::json::parse(slurp(dir_ / "a" / "cusick.json"));
    const auto b = nlohmann::json::parse(slurp(dir_ / "b" / "cusick.json"));
    EXPECT_EQ(a["hysteresis"], "loading-branch");
    EXPECT_EQ(a["protocol"], "release");
    EXPECT_FALSE(a.contains("lower_step_m"));
    EXPECT_EQ(a["runs"][0]["stages"], 1);
    EXPECT_EQ(b["hysteresis"], "friction");
    EXPECT_EQ(b["protocol"], "lowered");
    // The 3 cm overhang in 2 cm plate steps (two spacings): one plate stage and the settling.
    EXPECT_DOUBLE_EQ(b["lower_step_m"].get<double>(), 0.02);
    EXPECT_EQ(b["runs"][0]["stages"], 2);
    EXPECT_TRUE(b["converged"].get<bool>());
    const double dc = b["drape_coefficient_percent"].get<double>();
    EXPECT_GT(dc, 0.0);
    EXPECT_LT(dc, 100.0);
    EXPECT_EQ(a["shakes"], 0);
    EXPECT_EQ(b["shakes"], 0);
    EXPECT_FALSE(b.contains("shake_amplitude_g"));
    // One quasi-static shake after the release: to rest at 1.5 g, at 0.5 g, then at g.
    r = woven(small + " --hysteresis friction --shakes 1 --out c");
    ASSERT_EQ(r.code, 0) << r.err;
    const auto c = nlohmann::json::parse(slurp(dir_ / "c" / "cusick.json"));
    EXPECT_EQ(c["protocol"], "release");
    EXPECT_EQ(c["shakes"], 1);
    EXPECT_DOUBLE_EQ(c["shake_amplitude_g"].get<double>(), 0.5);
    EXPECT_EQ(c["runs"][0]["stages"], 4);
    EXPECT_TRUE(c["converged"].get<bool>());
    r = woven(small + " --shakes -1 --out d");
    EXPECT_EQ(r.code, 2);
    EXPECT_THAT(r.err, HasSubstr("command line: --shakes:"));
}

}  // namespace
