// Fabrics and scenes from in-memory values (io/values.hpp: what a Python caller passes): read as
// the same TOML text is, with the same messages but no line, and the values' own refusals.
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "woven/common/error.hpp"
#include "woven/io/fabric_file.hpp"
#include "woven/io/scene_file.hpp"
#include "woven/io/values.hpp"

using woven::InputError;
namespace io = woven::io;
using nlohmann::json;

namespace {

const char* kFabricToml = "name = \"test\"\nsource = \"unit test\"\nareal_density_mg_cm2 = 12.0\n"
                          "[bending.warp]\nB = 0.05\n2HB = 0.04\n"
                          "[bending.weft]\ncurvature_per_cm = [0.0, 0.5, 1.0, 1.5, 2.0, 2.5]\n"
                          "moment_gf_cm_per_cm = [0.0, 0.07, 0.12, 0.17, 0.22, 0.27]\n"
                          "[shear]\nG = 1.5\n2HG = 2.0\n2HG5 = 3.0\n";

json fabric_values()
{
    return json{{"name", "test"},
                {"source", "unit test"},
                {"areal_density_mg_cm2", 12.0},
                {"bending",
                 {{"warp", {{"B", 0.05}, {"2HB", 0.04}}},
                  {"weft", {{"curvature_per_cm", {0.0, 0.5, 1.0, 1.5, 2.0, 2.5}}, {"moment_gf_cm_per_cm", {0.0, 0.07, 0.12, 0.17, 0.22, 0.27}}}}}},
                {"shear", {{"G", 1.5}, {"2HG", 2.0}, {"2HG5", 3.0}}}};
}

std::string message(const std::function<void()>& f)
{
    try {
        f();
    } catch (const InputError& e) {
        return e.what();
    }
    return "(no error)";
}

}  // namespace

TEST(Values, FabricIsReadAsItsTomlText)
{
    const woven::kes::FabricData file = io::parse_fabric(kFabricToml, "test.toml");
    const woven::kes::FabricData values = io::fabric_from_values(fabric_values(), "Python fabric");
    EXPECT_EQ(values.name, "test");
    EXPECT_EQ(values.areal_density_mg_cm2, 12.0);
    EXPECT_EQ(values.bending_warp.curve.x, file.bending_warp.curve.x);
    EXPECT_EQ(values.bending_warp.curve.y, file.bending_warp.curve.y);
    EXPECT_EQ(values.bending_weft.curve.y, file.bending_weft.curve.y);
    EXPECT_EQ(values.shear.curve.y, file.shear.curve.y);
    ASSERT_TRUE(values.shear.summary);
    EXPECT_EQ(values.shear.summary->two_HG5, 3.0);
}

TEST(Values, MessagesAreTheFilesWithoutALine)
{
    json v = fabric_values();
    v["areal_density_mg_cm2"] = -1;
    const std::string from_values = message([&] { io::fabric_from_values(v, "Python fabric"); });
    std::string text = kFabricToml;
    text.replace(text.find("12.0"), 4, "-1");
    const std::string from_file = message([&] { io::parse_fabric(text, "test.toml"); });
    EXPECT_EQ(from_values, "Python fabric: areal_density_mg_cm2: expected a positive number in (0, 1000000000] mg/cm^2, got -1");
    EXPECT_EQ(from_file, "test.toml: areal_density_mg_cm2: expected a positive number in (0, 1000000000] mg/cm^2, got -1 (line 3)");

    std::vector<std::string> warnings;
    v = fabric_values();
    v["bending"]["warp"]["colour"] = "red";
    io::fabric_from_values(v, "Python fabric", &warnings);
    EXPECT_THAT(warnings, ::testing::ElementsAre("Python fabric: bending.warp.colour: unknown key, ignored"));
}

TEST(Values, WhatAFileCannotHoldIsRefused)
{
    json v = fabric_values();
    v["thickness_mm"] = nullptr;
    EXPECT_EQ(message([&] { io::fabric_from_values(v, "Python fabric"); }),
              "Python fabric: thickness_mm: expected a value, got None (leave the key out for its default)");
    v = fabric_values();
    v["bending"]["weft"]["moment_gf_cm_per_cm"][2] = nullptr;
    EXPECT_EQ(message([&] { io::fabric_from_values(v, "Python fabric"); }),
              "Python fabric: bending.weft.moment_gf_cm_per_cm[3]: expected a value, got None (leave the key out for its default)");
    v = fabric_values();
    v["thickness_mm"] = 18446744073709551615ull;
    EXPECT_EQ(message([&] { io::fabric_from_values(v, "Python fabric"); }),
              "Python fabric: thickness_mm: expected an integer within 64 bits (at most 9223372036854775807), got 18446744073709551615");
    EXPECT_EQ(message([&] { io::fabric_from_values(json::array({1, 2}), "Python fabric"); }),
              "Python fabric: expected a dict of the file's keys");
    json deep = 1;
    for (int k = 0; k < 40; ++k) deep = json::array({deep});
    v = fabric_values();
    v["x"] = deep;
    EXPECT_THAT(message([&] { io::fabric_from_values(v, "Python fabric"); }), ::testing::EndsWith(": nested more than 32 levels deep"));
    v = fabric_values();
    v["areal_density_mg_cm2"] = std::numeric_limits<double>::quiet_NaN();
    EXPECT_THAT(message([&] { io::fabric_from_values(v, "Python fabric"); }), ::testing::StartsWith("Python fabric: areal_density_mg_cm2: "));
}

TEST(Values, SceneIsReadAsItsTomlText)
{
    const char* toml = "name = \"s\"\nfabric = \"cotton\"\n[cloth]\nsize_m = [1.0, 1.0]\ngrid = [11, 11]\nheight_m = 0.6\n"
                       "[[obstacle]]\ntype = \"plane\"\npoint_m = [0.0, 0.0, 0.0]\nnormal = [0.0, 0.0, 1.0]\n"
                       "[[obstacle]]\ntype = \"sphere\"\ncentre_m = [0.0, 0.0, 0.3]\nradius_m = 0.25\n";
    const json values = {{"name", "s"},
                         {"fabric", "cotton"},
                         {"cloth", {{"size_m", {1.0, 1.0}}, {"grid", {11, 11}}, {"height_m", 0.6}}},
                         {"obstacle",
                          {{{"type", "plane"}, {"point_m", {0.0, 0.0, 0.0}}, {"normal", {0.0, 0.0, 1.0}}},
                           {{"type", "sphere"}, {"centre_m", {0.0, 0.0, 0.3}}, {"radius_m", 0.25}}}}};
    const io::SceneSpec file = io::parse_scene(toml, "s.toml", ".");
    const io::SceneSpec s = io::scene_from_values(values, "Python scene", ".");
    EXPECT_EQ(s.name, "s");
    EXPECT_EQ(s.source_path, "Python scene");
    EXPECT_EQ(s.obstacle_kinds, file.obstacle_kinds);
    EXPECT_EQ(s.cloth.nu, 11);
    EXPECT_EQ(s.cloth.initial_positions(), file.cloth.initial_positions());
    json bad = values;
    bad["cloth"]["grid"] = {2, 2};
    EXPECT_THAT(message([&] { io::scene_from_values(bad, "Python scene", "."); }), ::testing::StartsWith("Python scene: cloth.grid: "));
}
