// Scene files: [cloth.outline] (docs/SCENE-FORMAT.md): parsed into the cloth's outline, cut
// against the grid, and every documented error naming its field.
#include <cmath>
#include <numbers>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "woven/common/error.hpp"
#include "woven/io/scene_file.hpp"

using ::testing::HasSubstr;

namespace {

/// A 32 cm cloth at 1 cm spacing over a disc; `outline` is the [cloth.outline] table's body.
std::string scene(const std::string& outline)
{
    return "[cloth]\nsize_m = [0.32, 0.32]\ngrid = [33, 33]\nheight_m = 0.205\n[cloth.outline]\n" + outline
        + "\n[[obstacle]]\ntype = \"disc\"\ncentre_m = [0.0, 0.0, 0.20]\nradius_m = 0.09\n";
}

woven::io::SceneSpec parse(const std::string& text) { return woven::io::parse_scene(text, "s.toml", "."); }

void expect_error(const std::string& outline, const std::string& field, const std::string& what)
{
    try {
        parse(scene(outline));
        ADD_FAILURE() << "no error for " << outline;
    } catch (const woven::InputError& e) {
        EXPECT_THAT(e.what(), HasSubstr("s.toml: " + field));
        EXPECT_THAT(e.what(), HasSubstr(what));
    }
}

}  // namespace

TEST(SceneOutline, DiscAnnulusAndPolygonAreCut)
{
    const auto d = parse(scene("type = \"disc\"\nradius_m = 0.15"));
    ASSERT_TRUE(d.cloth.is_cut());
    const auto cd = d.cloth.cut("s.toml");
    EXPECT_NEAR(cd.total_area, std::numbers::pi * 0.15 * 0.15, 1e-14);
    EXPECT_EQ(cd.active[d.cloth.grid().index(0, 0)], 0);    // a corner is cut away
    EXPECT_EQ(cd.active[d.cloth.grid().index(16, 16)], 1);  // the centre is kept

    const auto a = parse(scene("type = \"annulus\"\ncentre_m = [0.005, 0.0]\nradius_m = 0.15\ninner_radius_m = 0.05"));
    EXPECT_NEAR(a.cloth.cut("s.toml").total_area, std::numbers::pi * (0.15 * 0.15 - 0.05 * 0.05), 1e-14);

    const auto p = parse(scene("type = \"polygon\"\npoints_m = [[-0.1, -0.1], [0.1, -0.1], [0.0, 0.12]]"));
    EXPECT_NEAR(p.cloth.cut("s.toml").total_area, 0.5 * 0.2 * 0.22, 1e-14);

    const auto r = parse(scene("type = \"rectangle\""));
    EXPECT_FALSE(r.cloth.is_cut());
}

TEST(SceneOutline, ErrorsNameTheField)
{
    expect_error("type = \"star\"", "cloth.outline.type", "");
    expect_error("type = \"disc\"", "cloth.outline.radius_m", "");
    expect_error("type = \"disc\"\nradius_m = 0.2", "cloth.outline", "reaches beyond the grid's particles");
    expect_error("type = \"disc\"\nradius_m = 0.004\ncentre_m = [0.005, 0.005]", "cloth.outline", "encloses no particle");
    expect_error("type = \"disc\"\nradius_m = 0.006", "cloth.outline", "too small for the grid");
    expect_error("type = \"annulus\"\nradius_m = 0.1\ninner_radius_m = 0.12", "cloth.outline.inner_radius_m", "below radius_m");
    expect_error("type = \"polygon\"\npoints_m = [[0, 0], [0.1, 0.1], [0.1, 0], [0, 0.05]]", "cloth.outline.points_m", "intersects itself");
    expect_error("type = \"polygon\"\npoints_m = [[0, 0], [0.1]]", "cloth.outline.points_m", "[x, y]");
}

TEST(SceneOutline, DroppedParticlesMayStartInsideAnObstacle)
{
    // The disc obstacle reaches z = 0.20 only within 9 cm; a cloth cut to 8 cm starting at
    // 0.19 m would touch it, so the scene is an error; cut to a ring outside 9.5 cm it is not.
    const std::string low = "[cloth]\nsize_m = [0.32, 0.32]\ngrid = [33, 33]\nheight_m = 0.19\n[cloth.outline]\n";
    const std::string disc = "\n[[obstacle]]\ntype = \"disc\"\ncentre_m = [0.0, 0.0, 0.20]\nradius_m = 0.09\nthickness_m = 0.02\n";
    EXPECT_THROW(parse(low + "type = \"disc\"\nradius_m = 0.08" + disc), woven::InputError);
    EXPECT_NO_THROW(parse(low + "type = \"annulus\"\nradius_m = 0.15\ninner_radius_m = 0.105" + disc));
}
