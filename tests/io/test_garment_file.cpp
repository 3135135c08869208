// The garment file (io/garment_file.hpp, docs/GARMENT-FORMAT.md): the examples read, cm turned
// into m once, and each kind of bad input one line naming the file and the field.
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "woven/common/error.hpp"
#include "woven/io/garment_file.hpp"

using namespace woven;

namespace {

std::string example(const std::string& name)
{
    std::ifstream in(std::string(WOVEN_SOURCE_DIR) + "/examples/garments/" + name);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

std::string replaced(std::string text, const std::string& from, const std::string& to)
{
    const std::size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
    return text;
}

std::string error_of(const std::string& text)
{
    try {
        (void)io::parse_garment(text, "g.toml", ".");
    } catch (const InputError& e) {
        return e.what();
    }
    return "(no error)";
}

TEST(GarmentFile, TheExamplesReadInMetres)
{
    std::vector<std::string> warnings;
    const io::GarmentSpec g = io::parse_garment(example("gored-skirt-bias.toml"), "gored.toml", ".", &warnings);
    EXPECT_TRUE(warnings.empty()) << warnings.front();
    EXPECT_EQ(g.fabric, "silk");
    EXPECT_DOUBLE_EQ(g.spacing_m, 0.02);
    ASSERT_EQ(g.pattern.pieces.size(), 4u);
    ASSERT_EQ(g.pattern.seams.size(), 4u);
    const model::PatternPiece& front = g.pattern.pieces[0];
    EXPECT_NEAR(front.grain, std::numbers::pi / 4, 1e-15);
    ASSERT_EQ(front.segments.size(), 4u);
    // The waist arc: 12 cm / sin(20 deg) from the apex, a quarter of the 75.4 cm waist long.
    EXPECT_NEAR(front.segments[2].radius(), 0.12 / std::sin(20 * std::numbers::pi / 180), 1e-6);
    EXPECT_NEAR(front.segments[2].length(), 2 * std::numbers::pi * 0.12 / 4, 1e-6);
    EXPECT_EQ(front.segments[2].role, model::OutlineSegment::Role::WAIST);
    EXPECT_EQ(front.segments[0].role, model::OutlineSegment::Role::HEM);
    EXPECT_EQ(front.placement.wrap, model::Placement::Wrap::CONE);
    EXPECT_NEAR(front.placement.half_angle, 20 * std::numbers::pi / 180, 1e-15);
    EXPECT_NEAR(g.body.form.waist, 0.68, 1e-15);
    EXPECT_NEAR(g.body.form.waist_height, 1.04, 1e-15);
    EXPECT_TRUE(g.pattern.seams[0].reversed);
    EXPECT_EQ(g.pattern.seams[0].piece_a, 0);
    EXPECT_EQ(g.pattern.seams[0].piece_b, 1);
    for (const char* name : {"circular-skirt.toml", "gored-skirt-straight.toml", "tube-skirt.toml"})
        EXPECT_NO_THROW((void)io::parse_garment(example(name), name, ".")) << name;
}

TEST(GarmentFile, BadInputIsOneLineNamingTheField)
{
    const std::string tube = example("tube-skirt.toml");
    EXPECT_EQ(error_of(replaced(tube, "to_cm = [-26.7035, -55]", "to_cm = [-20, -55]")),
              "g.toml: piece[1].segment[4].to_cm: expected the last segment to end at the piece's start_cm (a closed outline)");
    EXPECT_EQ(error_of(replaced(tube, "b = \"back.left\"", "b = \"back.side\"")),
              "g.toml: seam[1].b: expected '<piece>.<segment>' naming a segment of piece 'back', got 'back.side'");
    EXPECT_EQ(error_of(replaced(tube, "b = \"back.left\"", "b = \"front.right\"")), "g.toml: seam[1].b: expected another segment than a's");
    EXPECT_EQ(error_of(replaced(tube, "wrap = \"cylinder\"", "wrap = \"sphere\"")).substr(0, 35), "g.toml: piece[1].place.wrap: expect");
    EXPECT_EQ(error_of(replaced(tube, "spacing_cm = 2", "spacing_cm = 0.01")).substr(0, 24), "g.toml: spacing_cm: expe");
    EXPECT_NE(error_of(replaced(tube, "grain_deg = 0", "grain_deg = 0\nfabric = \"denim\""))
                  .find("piece[1].fabric: expected the garment's fabric"),
              std::string::npos);
    const std::string circle = example("circular-skirt.toml");
    EXPECT_NE(error_of(replaced(circle, "centre_cm = [0, 0]", "centre_cm = [1, 0]"))
                  .find("piece[1].segment[1].centre_cm: expected the arc's centre as far"),
              std::string::npos);
}

}  // namespace
