// The virtual KES-FB2 and FB1 run full loops with the friction inside the weave
// (model::Hysteresis::FRICTION, model/slip.hpp): every built-in fabric's 2HB, 2HG, 2HG5 within
// 5 % of its file, B and G within 1 %, the loops within 5 % of the input loops. Coarse grids
// (bending 1 mm on a 1 cm wide specimen, shear 1 cm) keep the suite short.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "woven/io/fabric_file.hpp"
#include "woven/kes/fabric.hpp"
#include "woven/testers/kes_bending.hpp"
#include "woven/testers/kes_shear.hpp"

namespace woven::testers {
namespace {

model::ModelOptions friction()
{
    model::ModelOptions o;
    o.hysteresis = model::Hysteresis::FRICTION;
    return o;
}

class KesHysteresis : public testing::TestWithParam<std::string> { };

TEST_P(KesHysteresis, BendingLoopsHaveTheInputWidthAndB)
{
    const kes::FabricData f = io::find_fabric(GetParam());
    BendingTestOptions o;
    o.sigma = 0.001;  // the curve's discretisation error (K sigma)^2 / 8: 0.8 % at 2.5 1/cm
    o.width = 0.01;
    o.model = friction();
    for (Direction d : {Direction::WARP, Direction::WEFT}) {
        const KesCurveResult r = kes_bending_test(f, d, o);
        const auto& m = d == Direction::WARP ? f.bending_warp : f.bending_weft;
        SCOPED_TRACE(GetParam() + " " + to_string(d));
        EXPECT_NEAR(r.summary_rel_error, 0.0, 0.01);
        if (!m.summary || !(m.summary->two_HB > 0)) {  // points (cotton): the loading branch, no loop
            EXPECT_FALSE(r.loop);
            continue;
        }
        ASSERT_TRUE(r.loop);
        ASSERT_EQ(r.loop_x.size(), 101u);
        EXPECT_DOUBLE_EQ(r.input_hysteresis, m.summary->two_HB);
        EXPECT_NEAR(r.hysteresis_rel_error, 0.0, 0.05);
        EXPECT_LT(r.loop_max_rel_error, 0.05);
        // Back at 0 the friction holds +2HB/2: it slid back at -2.5 1/cm and loaded up by 2.5
        // 1/cm, past every element's yield.
        EXPECT_NEAR(r.loop_y.back(), 0.5 * m.summary->two_HB, 0.05 * m.summary->two_HB);
    }
}

TEST_P(KesHysteresis, ShearLoopHasTheInputWidthsAndG)
{
    const kes::FabricData f = io::find_fabric(GetParam());
    ShearTestOptions o;
    o.sigma = 0.01;
    o.model = friction();
    o.model.shear_scale = shear_deembedding(f, o.model, o.sigma);
    const KesCurveResult r = kes_shear_test(f, Direction::WARP, o);
    SCOPED_TRACE(GetParam());
    ASSERT_TRUE(f.shear.summary);
    ASSERT_TRUE(r.loop);
    ASSERT_EQ(r.loop_x.size(), 65u);
    EXPECT_NEAR(r.summary_rel_error, 0.0, 0.01);
    EXPECT_DOUBLE_EQ(r.input_hysteresis, f.shear.summary->two_HG);
    EXPECT_DOUBLE_EQ(r.input_hysteresis5, f.shear.summary->two_HG5);
    EXPECT_NEAR(r.simulated_hysteresis / r.input_hysteresis - 1, 0.0, 0.05);
    EXPECT_NEAR(r.simulated_hysteresis5 / r.input_hysteresis5 - 1, 0.0, 0.05);
    EXPECT_NEAR(r.hysteresis_rel_error, 0.0, 0.05);
    EXPECT_LT(r.loop_max_rel_error, 0.05);
}

INSTANTIATE_TEST_SUITE_P(BuiltIn, KesHysteresis, testing::ValuesIn(io::builtin_fabric_names()),
                         [](const auto& info) { return info.param; });

// LOADING_BRANCH (the default) runs today's loading sweep: no loop.
TEST(KesHysteresisMode, LoadingBranchRunsNoLoop)
{
    const kes::FabricData f = io::find_fabric("wool");
    BendingTestOptions o;
    o.sigma = 0.0025;
    o.width = 0.01;
    const KesCurveResult r = kes_bending_test(f, Direction::WARP, o);
    EXPECT_FALSE(r.loop);
    EXPECT_TRUE(r.loop_x.empty());
    EXPECT_EQ(r.x.size(), 26u);
}

// The input loop of summary values: the virgin leg is the synthesised loading curve.
TEST(KesHysteresisMode, InputLoopsVirginLegIsTheSynthesisedCurve)
{
    const kes::BendingSummary s{0.1, 0.06};
    const kes::Curve c = kes::synthesize_bending_curve(s);
    const model::SlipLaw law = model::make_slip_law(1.0, 0.03, 1.0, 0.03, kes::kBendingRise);
    for (std::size_t k = 0; k < c.x.size(); ++k) EXPECT_NEAR(input_loop_value(0.1, law, kes::kBendingRise, 0, 2.5, c.x[k]), c.y[k], 1e-15);
    // Down from 2.5: the width at 1 is 2HB.
    EXPECT_NEAR(input_loop_value(0.1, law, kes::kBendingRise, 0, 2.5, 1.0) - input_loop_value(0.1, law, kes::kBendingRise, 1, 2.5, 1.0), 0.06, 1e-15);
}

}  // namespace
}  // namespace woven::testers
