// Sweep plans (batch/sweep_plan.hpp, docs/SWEEP-FORMAT.md): axes in file order, points as the
// Cartesian product named from their values, command lines, bounds and the error form
// "<file>: <field>: <what is expected>", and the scene/fabric key overrides.
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "woven/batch/sweep_plan.hpp"
#include "woven/common/error.hpp"
#include "woven/io/fabric_file.hpp"

using namespace woven;
using ::testing::ElementsAre;
using ::testing::HasSubstr;

namespace {

batch::SweepPlan plan(const std::string& text, std::vector<std::string>* warnings = nullptr)
{
    return batch::parse_sweep_plan(text, "plan.toml", ".", warnings);
}

std::string error_of(const std::string& text)
{
    try {
        plan(text);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(SweepPlan, PointsAreTheProductInFileOrderNamedFromTheirValues)
{
    // The axes' order is the file's (seed before fabric), not toml++'s sorted one.
    const auto p = plan(R"(command = "cusick"
[axes]
seed = [1, 2, 3]
fabric = ["wool", "cotton"]
[options]
spacing_cm = 2
render = false
)");
    EXPECT_EQ(p.name, "plan");
    ASSERT_EQ(p.axes.size(), 2u);
    EXPECT_EQ(p.axes[0].key, "seed");
    EXPECT_EQ(p.size(), 6u);
    const auto pts = p.points();
    ASSERT_EQ(pts.size(), 6u);
    EXPECT_EQ(pts[0].name, "seed-1_fabric-wool");
    EXPECT_EQ(pts[1].name, "seed-1_fabric-cotton");  // the last axis varies fastest
    EXPECT_EQ(pts[5].name, "seed-3_fabric-cotton");
    EXPECT_EQ(pts[5].index, 5u);
    // The command line: command, positional fabric, then the options in a fixed order.
    EXPECT_THAT(pts[1].args, ElementsAre("cusick", "cotton", "--seed", "1", "--spacing-cm", "2", "--no-render"));
}

TEST(SweepPlan, RangesAndNumbers)
{
    const auto p = plan(R"(command = "drape"
name = "grids"
[axes]
grid = {from = 9, to = 15, step = 3}
perturb_m = [0.001, 0.0025]
)");
    EXPECT_EQ(p.name, "grids");
    ASSERT_EQ(p.axes[0].values.size(), 3u);
    EXPECT_EQ(p.axes[0].values[2].text, "15");
    EXPECT_EQ(p.axes[1].values[1].text, "0.0025");
    const auto pts = p.points();
    EXPECT_EQ(pts[0].name, "grid-9_perturb_m-0.001");
    // drape's scene defaults to the cube, as on the command line.
    EXPECT_THAT(pts[0].args, ElementsAre("drape", "cube", "--grid", "9", "--perturb", "0.001"));
}

TEST(SweepPlan, AnAxisOverridesTheSameSharedOption)
{
    const auto p = plan(R"(command = "cusick"
[axes]
spacing_cm = [1.5]
[options]
fabric = "denim"
spacing_cm = 3
)");
    EXPECT_THAT(p.points()[0].args, ElementsAre("cusick", "denim", "--spacing-cm", "1.5"));
}

TEST(SweepPlan, OverridesAreTomlLiteralsAppliedToACopy)
{
    const auto p = plan(R"(command = "drape"
[axes]
"scene.cloth.grid" = [[9, 9], [11, 13]]
"fabric.shear.G" = [1.5]
)");
    const auto pts = p.points();
    ASSERT_EQ(pts.size(), 2u);
    EXPECT_EQ(pts[1].name, "scene.cloth.grid-11x13_fabric.shear.G-1.5");
    ASSERT_EQ(pts[1].scene_overrides.size(), 1u);
    EXPECT_EQ(pts[1].scene_overrides[0].key, "cloth.grid");
    EXPECT_EQ(pts[1].scene_overrides[0].text, "[11, 13]");
    EXPECT_EQ(pts[1].fabric_overrides[0].key, "shear.G");
    EXPECT_EQ(pts[1].fabric_overrides[0].text, "1.5");
    // Set into a fabric whose shear is given as summary values (the wool file): the reader
    // then reads the new G.
    const std::string wool = batch::scene_or_fabric_text("wool", "fabric");
    const std::string changed = batch::apply_toml_overrides(wool, "wool", pts[1].fabric_overrides);
    const kes::FabricData f = io::parse_fabric(changed, "wool with G 1.5");
    const kes::FabricData f0 = io::parse_fabric(wool, "wool");
    EXPECT_EQ(f.name, f0.name);
    EXPECT_NE(changed.find("G = 1.5"), std::string::npos) << changed;
    // A key part that is a value, not a table, cannot be descended into.
    batch::SweepValue bad{"name.x", "1", "1", true};
    EXPECT_THROW(batch::apply_toml_overrides(wool, "wool", {bad}), InputError);
}

TEST(SweepPlan, ErrorsNameTheFileTheFieldAndTheExpectation)
{
    EXPECT_EQ(error_of(""), "plan.toml: file: the plan is empty; expected at least `command` and an [axes] table");
    EXPECT_THAT(error_of("command = \"dance\"\n"), HasSubstr("plan.toml: command: expected one of \"drape\", \"cusick\", \"kes-test\", got \"dance\" (line 1)"));
    EXPECT_EQ(error_of("command = \"cusick\"\n[axes]\nseed = [1]\n"),
              "plan.toml: axes.fabric: missing; cusick needs a fabric: give it as an axis or in [options]");
    EXPECT_THAT(error_of("command = \"cusick\"\n[axes]\nfabric = [\"cotton\"]\nspacing_cm = [0.5, 12]\n"),
                HasSubstr("plan.toml: axes.spacing_cm[2]: expected a positive number in (0, 10], got 12 (line 4)"));
    EXPECT_THAT(error_of("command = \"cusick\"\n[axes]\nfabric = [\"cotton\"]\nseed = [-1]\n"),
                HasSubstr("plan.toml: axes.seed[1]: expected an integer in [0, "));
    EXPECT_THAT(error_of("command = \"cusick\"\n[axes]\nfabric = [\"velvet\"]\n"),
                HasSubstr("plan.toml: axes.fabric[1]: expected a built-in fabric (canvas, cotton,"));
    EXPECT_THAT(error_of("command = \"cusick\"\n[axes]\nfabric = [\"cotton\"]\ngrid = [9]\n"),
                HasSubstr("plan.toml: axes.grid: unknown key for command cusick; expected one of fabric, seed, seeds"));
    EXPECT_THAT(error_of("command = \"cusick\"\n[axes]\nfabric = [\"cotton\", \"cotton\"]\n"),
                HasSubstr("plan.toml: axes.fabric: the value 'cotton' is listed twice"));
    EXPECT_THAT(error_of("command = \"cusick\"\n[axes]\nfabric = []\n"), HasSubstr("plan.toml: axes.fabric: expected a non-empty array"));
    EXPECT_THAT(error_of("command = \"kes-test\"\n[axes]\nfabric = [\"cotton\"]\n[options]\nrender = false\n"),
                HasSubstr("plan.toml: options.render: kes-test draws no render"));
    EXPECT_THAT(error_of("command = \"drape\"\n[axes]\ngrid = {from = 9, to = 3}\n"),
                HasSubstr("plan.toml: axes.grid.to: expected a number >= from (9), got 3"));
    EXPECT_THAT(error_of("command = \"drape\"\nname = \"../x\"\n"), HasSubstr("plan.toml: name: expected a name of letters"));
    // Too many points: the product of the axes' lengths is checked before any point is made.
    EXPECT_THAT(error_of("command = \"drape\"\n[axes]\ngrid = {from = 3, to = 1003}\nseed = {from = 0, to = 999}\n"),
                HasSubstr("plan.toml: axes: expected at most 1000000 points, got 1001000"));
    // A syntax error keeps the TOML reader's form.
    EXPECT_THAT(error_of("command = \n"), HasSubstr("plan.toml:1:"));
}

TEST(SweepPlan, UnknownTopLevelKeysAreWarnings)
{
    std::vector<std::string> w;
    plan("command = \"kes-test\"\ncolour = 1\n[axes]\nfabric = [\"cotton\"]\n", &w);
    ASSERT_EQ(w.size(), 1u);
    EXPECT_THAT(w[0], HasSubstr("plan.toml:2: colour: unknown key, ignored"));
}

TEST(SweepPlan, FabricFilesResolveAgainstThePlanFolderAndNameTheFolder)
{
    const auto p = batch::parse_sweep_plan("command = \"kes-test\"\n[axes]\nfabric = [\"fabrics/wool.toml\"]\n", WOVEN_SOURCE_DIR "/x.toml",
                                        WOVEN_SOURCE_DIR);
    const auto pts = p.points();
    EXPECT_EQ(pts[0].name, "fabric-wool");
    EXPECT_EQ(pts[0].args[1], WOVEN_SOURCE_DIR "/fabrics/wool.toml");
    EXPECT_THAT(error_of("command = \"kes-test\"\n[axes]\nfabric = [\"nowhere/wool.toml\"]\n"), HasSubstr("(no such file: nowhere/wool.toml)"));
}

TEST(SweepPlanRules, NegativeZeroIsZero)
{
    // [0.0, -0.0] would run one point twice.
    EXPECT_THAT(error_of("command = \"drape\"\n[axes]\nperturb_m = [0.0, -0.0]\n"), HasSubstr("axes.perturb_m: the value '0' is listed twice"));
    EXPECT_THAT(error_of("command = \"drape\"\n[axes]\n\"scene.solver.contact_distance_m\" = [0.0, -0.0]\n"),
                HasSubstr("is listed twice"));
}

TEST(SweepPlanRules, DistinctArraysOfInlineTablesAreNotDuplicates)
{
    const auto p = plan("command = \"drape\"\n[axes]\n\"scene.obstacle\" = [[{type = \"plane\"}], [{type = \"sphere\", radius_m = 0.1}]]\n");
    ASSERT_EQ(p.size(), 2u);
    EXPECT_EQ(p.point(0).scene_overrides[0].text, "[{\"type\" = \"plane\"}]");
    EXPECT_EQ(p.point(1).scene_overrides[0].text, "[{\"radius_m\" = 0.1, \"type\" = \"sphere\"}]");
    EXPECT_THAT(error_of("command = \"drape\"\n[axes]\n\"scene.obstacle\" = [[{type = \"plane\"}], [{type = \"plane\"}]]\n"),
                HasSubstr("is listed twice"));
}

TEST(SweepPlanRules, TheSizeIsCountedBeforeAnyValueIsRead)
{
    // 10^12 points: refused on the count, before the axes' values are made (the bad third axis
    // is never reached; reading the first two took 13 s and 300 MB).
    const std::string e = error_of("command = \"drape\"\n[axes]\nseed = {from = 0, to = 999999}\nmax_steps = {from = 0, to = 999999}\n"
                                   "grid = [1]\n");
    EXPECT_EQ(e, "plan.toml: axes: expected at most 1000000 points, got 1000000000000");
}

TEST(SweepPlanRules, PointsAreMadeOnDemandAsTheListMakesThem)
{
    const auto p = plan("command = \"cusick\"\n[axes]\nfabric = [\"cotton\", \"wool\"]\nseed = [1, 2, 3]\n");
    const auto all = p.points();
    ASSERT_EQ(all.size(), 6u);
    for (std::size_t i = 0; i < all.size(); ++i) {
        EXPECT_EQ(p.point(i).name, all[i].name);
        EXPECT_EQ(p.point(i).args, all[i].args);
    }
    EXPECT_EQ(p.point(4).name, "fabric-wool_seed-2");
}

TEST(SweepPlanRules, AFileThatIsNotAFabricIsRefusedUpFront)
{
    const auto e = error_of("command = \"kes-test\"\n[axes]\nfabric = [\"" WOVEN_SOURCE_DIR "/scenes/cube.toml\"]\n");
    EXPECT_THAT(e, HasSubstr("plan.toml: axes.fabric[1]: expected a built-in fabric"));
    EXPECT_THAT(e, HasSubstr("got '" WOVEN_SOURCE_DIR "/scenes/cube.toml': "));
    // A scene file is read as `woven drape` reads it: one that does not parse is refused too.
    EXPECT_THAT(error_of("command = \"drape\"\n[axes]\nscene = [\"" WOVEN_SOURCE_DIR "/assets/chair.obj\"]\n"),
                HasSubstr("plan.toml: axes.scene[1]: expected a built-in scene"));
}
