#include <algorithm>
// Fabric files: the built-in library (sources, the paper's Sec. 6 relations), both input forms,
// and every bad-input case of docs/FABRIC-FORMAT.md.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "woven/common/error.hpp"
#include "woven/io/fabric_file.hpp"
#include "woven/kes/curve.hpp"
#include "woven/kes/fabric.hpp"

using ::testing::AllOf;
using ::testing::HasSubstr;
using woven::InputError;
using woven::io::builtin_fabric_names;
using woven::io::find_fabric;
using woven::io::parse_fabric;
namespace kes = woven::kes;
namespace inst = woven::kes::instrument;

namespace {

double bending_slope(const kes::Curve& c) { return kes::data_slope(c, inst::kBendingSlopeFrom, inst::kBendingSlopeTo); }
double shear_slope(const kes::Curve& c) { return kes::data_slope(c, inst::kShearSlopeFrom, inst::kShearSlopeTo); }

/// A valid fabric; the bad-input tests replace one part.
struct Parts {
    std::string head = "name = \"test\"\nsource = \"unit test\"\nareal_density_mg_cm2 = 12.0\n";
    std::string warp = "[bending.warp]\nB = 0.05\n2HB = 0.04\n";
    std::string weft = "[bending.weft]\nB = 0.1\n2HB = 0.05\n";
    std::string shear = "[shear]\nG = 1.5\n2HG = 2.0\n2HG5 = 3.0\n";
    std::string extra;
    std::string text() const { return head + warp + weft + shear + extra; }
};

const std::string kSource = "bad.toml";

/// Expects parse_fabric(text) to throw an InputError naming the source and `field`.
void expect_error(const std::string& text, const std::string& field, const std::string& also = "")
{
    try {
        parse_fabric(text, kSource);
        ADD_FAILURE() << "expected InputError naming '" << field << "' for:\n" << text;
    } catch (const InputError& e) {
        EXPECT_THAT(e.what(), AllOf(HasSubstr(kSource), HasSubstr(field), HasSubstr(also))) << text;
        EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << "message must be one line";
    }
}

}  // namespace

TEST(FabricFile, BuiltinNamesAreSortedAndIncludeTheLibrary)
{
    const auto names = builtin_fabric_names();
    for (const char* n : {"cotton", "wool", "polyester_cotton", "silk", "denim"})
        EXPECT_NE(std::find(names.begin(), names.end(), n), names.end()) << n;
    EXPECT_TRUE(std::is_sorted(names.begin(), names.end()));
}

TEST(FabricFile, EveryBuiltinParsesValidatesAndFits)
{
    for (const auto& name : builtin_fabric_names()) {
        SCOPED_TRACE(name);
        std::vector<std::string> warnings;
        kes::FabricData f;
        ASSERT_NO_THROW(f = find_fabric(name, &warnings));
        EXPECT_TRUE(warnings.empty()) << warnings.front();
        EXPECT_EQ(f.name, name);
        EXPECT_FALSE(f.source.empty());
        EXPECT_FALSE(f.representative.empty()) << "every built-in fabric says which numbers are representative";
        EXPECT_NO_THROW(kes::validate(f, name));
        // The Sec. 5.1 fit accepts every curve.
        EXPECT_NO_THROW(kes::fit_first_stage(f.bending_warp.curve, kes::bending_fit_options(), name));
        EXPECT_NO_THROW(kes::fit_first_stage(f.bending_weft.curve, kes::bending_fit_options(), name));
        EXPECT_NO_THROW(kes::fit_first_stage(f.shear.curve, kes::shear_fit_options(), name));
    }
}

TEST(FabricFile, SynthesisedCurvesReproduceBAndG)
{
    for (const auto& name : builtin_fabric_names()) {
        SCOPED_TRACE(name);
        const auto f = find_fabric(name);
        for (const auto* m : {&f.bending_warp, &f.bending_weft}) {
            if (!m->summary) continue;
            EXPECT_NEAR(bending_slope(m->curve), m->summary->B, 0.02 * m->summary->B);
        }
        if (f.shear.summary) {
            // kes::synthesize_shear_curve keeps G as the loading branch's slope over the G window
            // (docs/FABRIC-FORMAT.md: the hysteresis widening from 2HG to 2HG5 is given up).
            EXPECT_NEAR(shear_slope(f.shear.curve), f.shear.summary->G, 0.02 * f.shear.summary->G);
        }
    }
}

TEST(FabricFile, CottonBendingIsGivenAsPointsConsistentWithItsBAndHB)
{
    const auto f = find_fabric("cotton");
    EXPECT_FALSE(f.bending_warp.summary);
    EXPECT_FALSE(f.bending_weft.summary);
    EXPECT_EQ(f.bending_warp.curve.x.size(), 26u);
    // The file documents B = 0.095 (warp), 0.23 (weft) and 2HB = 0.06, 0.10.
    EXPECT_NEAR(bending_slope(f.bending_warp.curve), 0.095, 0.02 * 0.095);
    EXPECT_NEAR(bending_slope(f.bending_weft.curve), 0.23, 0.02 * 0.23);
    auto offset_at_1 = [](const kes::Curve& c, double B) {
        return c.y[10] - B * c.x[10];  // x[10] = 1.0 1/cm
    };
    EXPECT_NEAR(offset_at_1(f.bending_warp.curve, 0.095), 0.03, 0.003);
    EXPECT_NEAR(offset_at_1(f.bending_weft.curve, 0.23), 0.05, 0.003);
    ASSERT_TRUE(f.shear.summary);  // both input forms in built-in data
}

TEST(FabricFile, PaperRelationsHoldBetweenCottonWoolPolyesterCotton)
{
    const auto cotton = find_fabric("cotton");
    const auto wool = find_fabric("wool");
    const auto pc = find_fabric("polyester_cotton");
    const double cw = bending_slope(cotton.bending_warp.curve), cf = bending_slope(cotton.bending_weft.curve);
    const double ww = bending_slope(wool.bending_warp.curve), wf = bending_slope(wool.bending_weft.curve);
    const double pw = bending_slope(pc.bending_warp.curve), pf = bending_slope(pc.bending_weft.curve);
    // Cotton: doubled weft threads, weft much stiffer than warp.
    EXPECT_GE(cf / cw, 2.0);
    EXPECT_LE(cf / cw, 3.0);
    // Polyester/cotton: warp much stiffer than weft.
    EXPECT_GE(pw / pf, 2.0);
    EXPECT_LE(pw / pf, 3.0);
    // Wool: the weakest bending, in every direction.
    for (double other : {cw, cf, pw, pf}) {
        EXPECT_LT(ww, other);
        EXPECT_LT(wf, other);
    }
    // Wool: the shallowest shear curve (lowest G, lowest slope and force over the KES range).
    EXPECT_LT(wool.shear.summary->G, cotton.shear.summary->G);
    EXPECT_LT(wool.shear.summary->G, pc.shear.summary->G);
    EXPECT_LT(shear_slope(wool.shear.curve), shear_slope(cotton.shear.curve));
    EXPECT_LT(shear_slope(wool.shear.curve), shear_slope(pc.shear.curve));
    EXPECT_LT(wool.shear.curve.y.back(), cotton.shear.curve.y.back());
    EXPECT_LT(wool.shear.curve.y.back(), pc.shear.curve.y.back());
}

TEST(FabricFile, BuiltinValuesLieInTheirTypicalRanges)
{
    struct Range { const char* name; double w_lo, w_hi, g_lo, g_hi; };
    for (const Range r : {Range{"cotton", 10, 14, 1, 3}, Range{"wool", 20, 25, 0.5, 1.0}, Range{"polyester_cotton", 10, 14, 1, 2},
                          Range{"silk", 3, 8, 0.2, 0.5}, Range{"denim", 35, 45, 2, 5}}) {
        SCOPED_TRACE(r.name);
        const auto f = find_fabric(r.name);
        EXPECT_GE(f.areal_density_mg_cm2, r.w_lo);
        EXPECT_LE(f.areal_density_mg_cm2, r.w_hi);
        ASSERT_TRUE(f.shear.summary);
        EXPECT_GE(f.shear.summary->G, r.g_lo);
        EXPECT_LE(f.shear.summary->G, r.g_hi);
    }
}

TEST(FabricFile, SummaryFormSynthesisesAndPointsFormKeepsCurve)
{
    Parts p;
    p.weft = "[bending.weft]\ncurvature_per_cm = [0, 0.5, 1.0, 1.5, 2.0, 2.5]\nmoment_gf_cm_per_cm = [0, 0.08, 0.13, 0.18, 0.23, 0.28]\n";
    p.shear = "[shear]\nangle_deg = [0, 1, 2, 4, 6, 8]\nforce_gf_per_cm = [0, 2.5, 4, 7, 10, 13]\n";
    p.extra = "[tensile]\nLT = 0.6\nWT = 8\nRT = 50\nEMT = 5\n";
    std::vector<std::string> warnings;
    const auto f = parse_fabric(p.text(), "mem", &warnings);
    EXPECT_TRUE(warnings.empty());
    ASSERT_TRUE(f.bending_warp.summary);
    EXPECT_DOUBLE_EQ(f.bending_warp.summary->B, 0.05);
    EXPECT_DOUBLE_EQ(f.bending_warp.summary->two_HB, 0.04);
    EXPECT_EQ(f.bending_warp.curve.x, kes::synthesize_bending_curve(*f.bending_warp.summary).x);
    EXPECT_EQ(f.bending_warp.curve.y, kes::synthesize_bending_curve(*f.bending_warp.summary).y);
    EXPECT_FALSE(f.bending_weft.summary);
    EXPECT_EQ(f.bending_weft.curve.y, (std::vector<double>{0, 0.08, 0.13, 0.18, 0.23, 0.28}));
    EXPECT_FALSE(f.shear.summary);
    EXPECT_EQ(f.shear.curve.x.back(), 8.0);  // integers accepted as numbers
    ASSERT_TRUE(f.tensile);
    EXPECT_DOUBLE_EQ(f.tensile->RT, 50);
    EXPECT_FALSE(f.thickness_mm);
}

TEST(FabricFile, UnknownKeysWarnNotFail)
{
    Parts p;
    p.head += "foo = 3\n";
    p.warp += "colour = \"blue\"\n";
    std::vector<std::string> warnings;
    EXPECT_NO_THROW(parse_fabric(p.text(), kSource, &warnings));
    ASSERT_EQ(warnings.size(), 2u);
    const std::string text = p.text();
    auto line = [&](const std::string& needle) {
        return std::to_string(1 + std::count(text.begin(), text.begin() + text.find(needle), '\n'));
    };
    // One warning format for every file woven reads: "<file>:<line>: <field>: unknown key, ignored".
    EXPECT_THAT(warnings, ::testing::Contains("bad.toml:" + line("foo =") + ": foo: unknown key, ignored"));
    EXPECT_THAT(warnings,
                ::testing::Contains("bad.toml:" + line("colour =") + ": bending.warp.colour: unknown key, ignored"));
}

TEST(FabricFile, ValidateWarningsArePassedOn)
{
    Parts p;
    p.head = "name = \"t\"\nsource = \"s\"\nareal_density_mg_cm2 = 80\n";  // plausible but atypical
    std::vector<std::string> warnings;
    parse_fabric(p.text(), kSource, &warnings);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_THAT(warnings[0], AllOf(HasSubstr(kSource), HasSubstr("areal_density_mg_cm2")));
}

TEST(FabricFileErrors, SyntaxErrorGivesLineAndColumn)
{
    try {
        parse_fabric("name = \"x\"\nsource = \"s\"\nareal_density_mg_cm2 = = 3\n", kSource);
        FAIL();
    } catch (const InputError& e) {
        EXPECT_THAT(e.what(), HasSubstr("bad.toml:3:"));
    }
}

TEST(FabricFileErrors, MissingRequiredFields)
{
    Parts p;
    p.head = "source = \"s\"\nareal_density_mg_cm2 = 12\n";
    expect_error(p.text(), "name");
    p.head = "name = \"\"\nsource = \"s\"\nareal_density_mg_cm2 = 12\n";
    expect_error(p.text(), "name", "non-empty");
    p.head = "name = \"t\"\nareal_density_mg_cm2 = 12\n";
    expect_error(p.text(), "source");
    p.head = "name = \"t\"\nsource = \"s\"\n";
    expect_error(p.text(), "areal_density_mg_cm2");
    Parts q;
    q.weft = "";
    expect_error(q.text(), "bending.weft");
    Parts r;
    r.shear = "";
    expect_error(r.text(), "shear");
    Parts s;
    s.warp = "[bending.warp]\nB = 0.05\n";
    expect_error(s.text(), "bending.warp.2HB");
    Parts t;
    t.shear = "[shear]\nG = 1.5\n2HG = 2.0\n";
    expect_error(t.text(), "shear.2HG5");
}

TEST(FabricFileErrors, BothOrNeitherForm)
{
    Parts p;
    p.warp = "[bending.warp]\nB = 0.05\n2HB = 0.04\ncurvature_per_cm = [0, 1, 2]\nmoment_gf_cm_per_cm = [0, 0.05, 0.1]\n";
    expect_error(p.text(), "bending.warp", "not both");
    p.warp = "[bending.warp]\n";
    expect_error(p.text(), "bending.warp", "expected");
    Parts q;
    q.shear = "[shear]\nG = 1\n2HG = 1\n2HG5 = 1\nangle_deg = [0, 1, 2]\nforce_gf_per_cm = [0, 1, 2]\n";
    expect_error(q.text(), "shear", "not both");
    Parts r;
    r.warp = "[bending.warp]\ncurvature_per_cm = [0, 1, 2]\n";
    expect_error(r.text(), "bending.warp.moment_gf_cm_per_cm");
}

TEST(FabricFileErrors, WrongTypes)
{
    Parts p;
    p.warp = "[bending.warp]\ncurvature_per_cm = [\"0\", \"1\", \"2\"]\nmoment_gf_cm_per_cm = [0, 0.05, 0.1]\n";
    expect_error(p.text(), "bending.warp.curvature_per_cm[0]", "expected a number");
    p.warp = "[bending.warp]\ncurvature_per_cm = 1.0\nmoment_gf_cm_per_cm = [0, 0.05, 0.1]\n";
    expect_error(p.text(), "bending.warp.curvature_per_cm", "array");
    p.warp = "[bending.warp]\nB = \"0.05\"\n2HB = 0.04\n";
    expect_error(p.text(), "bending.warp.B", "expected a number");
    Parts q;
    q.head = "name = 3\nsource = \"s\"\nareal_density_mg_cm2 = 12\n";
    expect_error(q.text(), "name", "string");
    Parts r;
    r.head += "bending = 3\n";
    r.warp = r.weft = "";
    expect_error(r.text(), "bending", "table");
}

TEST(FabricFileErrors, MismatchedAndShortLists)
{
    Parts p;
    p.warp = "[bending.warp]\ncurvature_per_cm = [0, 1, 2, 2.5]\nmoment_gf_cm_per_cm = [0, 0.05, 0.1]\n";
    expect_error(p.text(), "bending.warp", "same length");
    p.warp = "[bending.warp]\ncurvature_per_cm = [0, 1]\nmoment_gf_cm_per_cm = [0, 0.05]\n";
    expect_error(p.text(), "bending.warp", "at least 3");
    Parts q;
    q.shear = "[shear]\nangle_deg = [0, 1, 2]\nforce_gf_per_cm = [0, 1]\n";
    expect_error(q.text(), "shear", "same length");
}

TEST(FabricFileErrors, NonFiniteValues)
{
    Parts p;
    p.warp = "[bending.warp]\nB = nan\n2HB = 0.04\n";
    expect_error(p.text(), "bending.warp.B", "finite");
    p.warp = "[bending.warp]\ncurvature_per_cm = [0, 1, inf]\nmoment_gf_cm_per_cm = [0, 0.05, 0.1]\n";
    expect_error(p.text(), "bending.warp.curvature_per_cm[2]", "finite");
    Parts q;
    q.head = "name = \"t\"\nsource = \"s\"\nareal_density_mg_cm2 = -inf\n";
    expect_error(q.text(), "areal_density_mg_cm2", "finite");
}

TEST(FabricFileErrors, NonPositiveRequiredValues)
{
    Parts p;
    p.head = "name = \"t\"\nsource = \"s\"\nareal_density_mg_cm2 = 0\n";
    expect_error(p.text(), "areal_density_mg_cm2", "positive");
    Parts q;
    q.warp = "[bending.warp]\nB = -0.05\n2HB = 0.04\n";
    expect_error(q.text(), "bending.warp.B", "positive");
    Parts r;
    r.shear = "[shear]\nG = 0\n2HG = 2.0\n2HG5 = 3.0\n";
    expect_error(r.text(), "shear.G", "positive");
    Parts s;
    s.weft = "[bending.weft]\nB = 0.1\n2HB = -0.01\n";
    expect_error(s.text(), "bending.weft.2HB", "non-negative");
    Parts t;
    t.head += "thickness_mm = 0\n";
    expect_error(t.text(), "thickness_mm", "positive");
}

TEST(FabricFileErrors, CurveShape)
{
    Parts p;
    p.warp = "[bending.warp]\ncurvature_per_cm = [0, 1, 1, 2]\nmoment_gf_cm_per_cm = [0, 0.05, 0.06, 0.1]\n";
    expect_error(p.text(), "bending.warp", "increasing");
    p.warp = "[bending.warp]\ncurvature_per_cm = [0, 1, 2, 2.5]\nmoment_gf_cm_per_cm = [0, 0.08, 0.06, 0.1]\n";
    expect_error(p.text(), "bending.warp", "non-decreasing");
    Parts q;
    q.shear = "[shear]\nangle_deg = [0, 2, 1]\nforce_gf_per_cm = [0, 1, 2]\n";
    expect_error(q.text(), "shear", "increasing");
}

TEST(FabricFileErrors, OutOfPlausibleRange)
{
    Parts p;
    p.warp = "[bending.warp]\nB = 100\n2HB = 0.04\n";
    expect_error(p.text(), "bending.warp.B");
    Parts q;
    q.head = "name = \"t\"\nsource = \"s\"\nareal_density_mg_cm2 = 5000\n";
    expect_error(q.text(), "areal_density_mg_cm2");
    Parts r;
    r.shear = "[shear]\nG = 1.5\n2HG = 2.0\n2HG5 = 300\n";
    expect_error(r.text(), "shear.2HG5");
    Parts s;
    s.extra = "[tensile]\nLT = 0.6\nWT = 8\nRT = 150\nEMT = 5\n";
    expect_error(s.text(), "tensile.RT");
    Parts t;
    t.warp = "[bending.warp]\ncurvature_per_cm = [0, 1, 2, 9]\nmoment_gf_cm_per_cm = [0, 0.05, 0.1, 0.2]\n";
    expect_error(t.text(), "bending.warp", "range");
}

TEST(FabricFileErrors, FindFabricUnknownNameListsBuiltins)
{
    try {
        find_fabric("nope");
        FAIL();
    } catch (const InputError& e) {
        EXPECT_THAT(e.what(), HasSubstr("nope"));
        for (const auto& n : builtin_fabric_names()) EXPECT_THAT(e.what(), HasSubstr(n));
    }
}

TEST(FabricFileErrors, MissingFile)
{
    try {
        find_fabric("/nonexistent/dir/x.toml");
        FAIL();
    } catch (const InputError& e) {
        EXPECT_STREQ(e.what(), "/nonexistent/dir/x.toml: file: no such fabric file");
    }
}

TEST(FabricFile, LoadsAFileAndNamesItInErrors)
{
    const std::string path = testing::TempDir() + "woven_fabric_test.toml";
    Parts p;
    { std::ofstream(path) << p.text(); }
    EXPECT_EQ(find_fabric(path).name, "test");
    p.shear = "[shear]\nG = 0\n2HG = 2.0\n2HG5 = 3.0\n";
    { std::ofstream(path) << p.text(); }
    try {
        woven::io::load_fabric_file(path);
        FAIL();
    } catch (const InputError& e) {
        EXPECT_THAT(e.what(), AllOf(HasSubstr(path), HasSubstr("shear.G")));
    }
    std::remove(path.c_str());
}

TEST(FabricFile, BuiltinErrorsNameTheBuiltin)
{
    // The source of a built-in is "built-in fabric '<name>'"; a repository fabric file parses the same.
    const auto a = find_fabric("wool");
    const auto b = woven::io::load_fabric_file(std::string(WOVEN_SOURCE_DIR) + "/fabrics/wool.toml");
    EXPECT_EQ(a.bending_warp.curve.y, b.bending_warp.curve.y);
    EXPECT_EQ(a.source, b.source);
}

TEST(FabricFile, DocumentedExampleParses)
{
    std::ifstream in(std::string(WOVEN_SOURCE_DIR) + "/docs/FABRIC-FORMAT.md");
    ASSERT_TRUE(in);
    std::string line, example;
    bool inside = false, done = false;
    while (!done && std::getline(in, line)) {
        if (!inside && line == "```toml") inside = true;
        else if (inside && line == "```") done = true;
        else if (inside) example += line + "\n";
    }
    ASSERT_TRUE(done);
    std::vector<std::string> warnings;
    const auto f = parse_fabric(example, "FABRIC-FORMAT.md example", &warnings);
    EXPECT_TRUE(warnings.empty());
    EXPECT_EQ(f.name, "my_wool");
    EXPECT_TRUE(f.bending_warp.summary);
    EXPECT_FALSE(f.shear.summary);
    EXPECT_NO_THROW(kes::fit_first_stage(f.shear.curve, kes::shear_fit_options(), "example"));
}
