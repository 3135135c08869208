// kes::validate_curve and the synthesis of first-stage curves from KES summary values.
#include <cmath>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "woven/common/error.hpp"
#include "woven/kes/curve.hpp"
#include "woven/kes/fabric.hpp"

namespace woven::kes {
namespace {

namespace inst = instrument;

Curve good_curve() { return {{0.0, 0.5, 1.0, 1.5}, {0.0, 0.1, 0.15, 0.2}}; }

/// Expects validate_curve to throw an InputError that names the source and the field and says `what`.
void expect_rejected(const Curve& c, const std::string& what)
{
    try {
        validate_curve(c, "fabrics/x.toml", "bending.weft", 5.0);
        ADD_FAILURE() << "accepted a curve with " << what;
    } catch (const InputError& e) {
        EXPECT_EQ(e.field(), "bending.weft");
        EXPECT_EQ(e.source(), "fabrics/x.toml");
        const std::string m = e.what();
        EXPECT_NE(m.find("bending.weft"), std::string::npos) << m;
        EXPECT_NE(m.find("fabrics/x.toml"), std::string::npos) << m;
        EXPECT_NE(m.find(what), std::string::npos) << "message '" << m << "' should say " << what;
    }
}

TEST(ValidateCurve, AcceptsAFirstStageCurve)
{
    EXPECT_NO_THROW(validate_curve(good_curve(), "src", "bending.weft", 5.0));
    EXPECT_NO_THROW(validate_curve(Curve{{0.0, 1.0, 2.0}, {0.0, 0.0, 0.0}}, "src", "shear", 30.0));  // flat is non-decreasing
}

TEST(ValidateCurve, RejectsNaN)
{
    Curve c = good_curve();
    c.y[2] = std::numeric_limits<double>::quiet_NaN();
    expect_rejected(c, "finite");
    c = good_curve();
    c.x[1] = std::numeric_limits<double>::infinity();
    expect_rejected(c, "finite");
}

TEST(ValidateCurve, RejectsNonIncreasingAbscissae)
{
    Curve c = good_curve();
    c.x[2] = c.x[1];
    expect_rejected(c, "strictly increasing");
    c = good_curve();
    c.x[2] = 0.4;
    expect_rejected(c, "strictly increasing");
}

TEST(ValidateCurve, RejectsDecreasingOrdinates)
{
    Curve c = good_curve();
    c.y[2] = 0.05;
    expect_rejected(c, "non-decreasing");
}

TEST(ValidateCurve, RejectsTooFewPoints)
{
    expect_rejected(Curve{{0.0, 1.0}, {0.0, 0.1}}, "at least 3 points");
    expect_rejected(Curve{{}, {}}, "at least 3 points");
}

TEST(ValidateCurve, RejectsMismatchedNegativeAndOutOfRange)
{
    expect_rejected(Curve{{0.0, 0.5, 1.0}, {0.0, 0.1}}, "same length");
    expect_rejected(Curve{{-0.1, 0.5, 1.0}, {0.0, 0.1, 0.2}}, "negative");
    expect_rejected(Curve{{0.0, 0.5, 6.0}, {0.0, 0.1, 0.2}}, "range");
}

TEST(Synthesis, BendingCurveFollowsTheDocumentedRule)
{
    // M(K) = B K + (2HB/2) r(K/0.3), r(u) = 1 - (1 - u)^2 below 1, then 1; K = 0..2.5 1/cm, 51 points.
    const BendingSummary s{0.08, 0.05};
    const Curve c = synthesize_bending_curve(s);
    ASSERT_EQ(c.x.size(), 51u);
    EXPECT_EQ(c.x.front(), 0.0);
    EXPECT_EQ(c.y.front(), 0.0);
    EXPECT_NEAR(c.x.back(), inst::kBendingMaxCurvature, 1e-15);
    EXPECT_NEAR(c.y[20], 0.08 * 1.0 + 0.025, 1e-15);  // K = 1.0
    EXPECT_NEAR(c.y[2], 0.08 * 0.1 + 0.025 * (1 - (1 - 0.1 / 0.3) * (1 - 0.1 / 0.3)), 1e-15);  // K = 0.1, in the rise
    EXPECT_NO_THROW(validate_curve(c, "synth", "bending.warp", 5.0));
    // The hysteresis offset at K = 1: the loading branch lies 2HB/2 above the mean line B K.
    EXPECT_NEAR(c.y[20] - 0.08 * 1.0, 0.5 * s.two_HB, 1e-15);
    // Straight over the KES window: its KES slope is B itself.
    EXPECT_NEAR(data_slope(c, inst::kBendingSlopeFrom, inst::kBendingSlopeTo), s.B, 1e-12 * s.B);
}

TEST(Synthesis, ShearCurveFollowsTheDocumentedRule)
{
    // F(phi) = G phi + h r(phi/0.3), h = (2HG + 2HG5)/4 = 1.025 gf/cm, r as for bending.
    const ShearSummary s{1.2, 1.6, 2.5};
    const Curve c = synthesize_shear_curve(s);
    ASSERT_EQ(c.x.size(), 33u);
    EXPECT_EQ(c.y.front(), 0.0);
    EXPECT_NEAR(c.x.back(), inst::kShearMaxAngle, 1e-15);
    EXPECT_NEAR(c.y[2], 1.2 * 0.5 + 1.025, 1e-14);   // phi = 0.5 deg
    EXPECT_NEAR(c.y[20], 1.2 * 5.0 + 1.025, 1e-14);  // phi = 5 deg
    EXPECT_NEAR(c.y[1], 1.2 * 0.25 + 1.025 * (1 - (1 - 0.25 / 0.3) * (1 - 0.25 / 0.3)), 1e-14);  // in the rise
    // Straight over the KES window: its KES slope is G itself (not G + (2HG5 - 2HG)/9).
    EXPECT_NEAR(data_slope(c, inst::kShearSlopeFrom, inst::kShearSlopeTo), s.G, 1e-12 * s.G);
    EXPECT_NO_THROW(validate_curve(c, "synth", "shear", 30.0));
}

TEST(Synthesis, FitOptionsUseTheKesWindows)
{
    EXPECT_EQ(bending_fit_options().line_from, inst::kBendingSlopeFrom);
    EXPECT_EQ(shear_fit_options().line_from, inst::kShearSlopeFrom);
    EXPECT_EQ(bending_fit_options().slope_from, inst::kBendingSlopeFrom);
    EXPECT_EQ(bending_fit_options().slope_to, inst::kBendingSlopeTo);
    EXPECT_EQ(shear_fit_options().slope_from, inst::kShearSlopeFrom);
    EXPECT_EQ(shear_fit_options().slope_to, inst::kShearSlopeTo);
}

}  // namespace
}  // namespace woven::kes
