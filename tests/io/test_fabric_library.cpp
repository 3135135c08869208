// The built-in fabric library from silk to denim (the drape tester's fabrics, docs/CUSICK.md):
// each new fabric lies in its published range, and the library is ordered by bending length
// with the silk habotai the limpest and the denim the stiffest.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "woven/io/fabric_file.hpp"
#include "woven/kes/curve.hpp"
#include "woven/kes/fabric.hpp"

using woven::io::builtin_fabric_names;
using woven::io::find_fabric;
namespace kes = woven::kes;
namespace inst = woven::kes::instrument;

namespace {

double bending_slope(const kes::Curve& c) { return kes::data_slope(c, inst::kBendingSlopeFrom, inst::kBendingSlopeTo); }

/// Bending length c = (B / W)^(1/3) in cm (B in gf.cm2/cm, W in gf/cm2), of the mean of the
/// warp and weft rigidities: the length that sets how far a cloth hangs under its own weight.
double bending_length_cm(const kes::FabricData& f)
{
    const double B = 0.5 * (bending_slope(f.bending_warp.curve) + bending_slope(f.bending_weft.curve));
    const double W_gf_cm2 = f.areal_density_mg_cm2 * 1e-3;
    return std::cbrt(B / W_gf_cm2);
}

}  // namespace

TEST(FabricLibrary, HasAtLeastTenFabricsFromSilkToDenim)
{
    const auto names = builtin_fabric_names();
    EXPECT_GE(names.size(), 10u);
    for (const char* n :
         {"silk", "crepe", "cotton_lawn", "cotton", "polyester", "polyester_cotton", "viscose", "linen", "wool", "canvas", "denim"})
        EXPECT_NE(std::find(names.begin(), names.end(), n), names.end()) << n;
}

TEST(FabricLibrary, NewFabricsLieInTheirStatedRanges)
{
    // The ranges each file's `representative` text states (KES-DATA.md bands, or the stated
    // departure from them): W mg/cm2, B gf.cm2/cm (both directions), G gf/(cm.deg).
    struct Range {
        const char* name;
        double w_lo, w_hi, b_lo, b_hi, g_lo, g_hi;
    };
    for (const Range r : {Range{"silk", 3, 8, 0.01, 0.04, 0.2, 0.5}, Range{"crepe", 3, 8, 0.01, 0.04, 0.2, 0.5},
                          Range{"cotton_lawn", 6, 9, 0.02, 0.05, 0.5, 1.0}, Range{"polyester", 8, 12, 0.03, 0.08, 0.5, 1.5},
                          Range{"viscose", 9, 13, 0.03, 0.07, 0.4, 1.0}, Range{"linen", 14, 20, 0.15, 0.4, 1.0, 3.0},
                          Range{"canvas", 20, 30, 0.2, 0.5, 2.0, 5.0}}) {
        SCOPED_TRACE(r.name);
        const auto f = find_fabric(r.name);
        EXPECT_GE(f.areal_density_mg_cm2, r.w_lo);
        EXPECT_LE(f.areal_density_mg_cm2, r.w_hi);
        for (const auto* m : {&f.bending_warp, &f.bending_weft}) {
            ASSERT_TRUE(m->summary);
            EXPECT_GE(m->summary->B, r.b_lo);
            EXPECT_LE(m->summary->B, r.b_hi);
        }
        ASSERT_TRUE(f.shear.summary);
        EXPECT_GE(f.shear.summary->G, r.g_lo);
        EXPECT_LE(f.shear.summary->G, r.g_hi);
    }
}

TEST(FabricLibrary, SilkHasTheShortestBendingLengthAndDenimTheLongest)
{
    const double silk = bending_length_cm(find_fabric("silk"));
    const double denim = bending_length_cm(find_fabric("denim"));
    // Documented in silk.toml: a 10-momme habotai, c = (0.011 / 0.0045)^(1/3) = 1.35 cm.
    EXPECT_NEAR(silk, 1.347, 0.005);
    // denim.toml: c = (0.75 / 0.040)^(1/3) = 2.66 cm.
    EXPECT_NEAR(denim, 2.657, 0.005);
    for (const auto& name : builtin_fabric_names()) {
        SCOPED_TRACE(name);
        const double c = bending_length_cm(find_fabric(name));
        if (name != "silk") {
            EXPECT_GT(c, silk * 1.05);
        }
        if (name != "denim") {
            EXPECT_LT(c, denim);
        }
    }
}
