// A corner's fold structure (analysis/leaving_folds.hpp): which billows leave a corner, the
// structure they form, the counts over corners and drapes the experiments report.
#include <vector>

#include <gtest/gtest.h>

#include "woven/analysis/leaving_folds.hpp"

namespace woven::analysis {
namespace {

std::vector<Billow> billows(const std::vector<double>& angles_deg)
{
    std::vector<Billow> out;
    for (double a : angles_deg) {
        Billow b;
        b.angle_deg = a;
        b.standout_m = 0.05;
        out.push_back(b);
    }
    return out;
}

TEST(LeavingFolds, BillowsBeyondTheConeAreSideWavesNotFolds)
{
    // A side wave at 110 degrees (the cube's sit at 99-132) and one at -90.5 leave nothing.
    EXPECT_TRUE(leaving(billows({110, -90.5})).empty());
    const auto kept = leaving(billows({-90, 30, 99}));
    ASSERT_EQ(kept.size(), 2u);
    EXPECT_EQ(kept[0].angle_deg, -90);
    EXPECT_EQ(kept[1].angle_deg, 30);
}

TEST(LeavingFolds, ClassifiesKnownCorners)
{
    EXPECT_EQ(classify_leaving({}), LeavingFolds::NONE);
    EXPECT_EQ(classify_leaving(billows({120})), LeavingFolds::NONE);                 // a side wave only
    EXPECT_EQ(classify_leaving(billows({15})), LeavingFolds::SINGLE_DIAGONAL);       // at the tolerance
    EXPECT_EQ(classify_leaving(billows({-14.9, 100})), LeavingFolds::SINGLE_DIAGONAL);
    EXPECT_EQ(classify_leaving(billows({15.1})), LeavingFolds::SINGLE_OFFSET);
    EXPECT_EQ(classify_leaving(billows({-49})), LeavingFolds::SINGLE_OFFSET);
    EXPECT_EQ(classify_leaving(billows({-21, 19})), LeavingFolds::MULTIPLE);
    std::vector<Billow> ripple = billows({-21, 19});  // a fold standing out 0.05 m and a ripple of 0.02 m
    ripple[1].standout_m = 0.02;
    EXPECT_EQ(classify_leaving(ripple), LeavingFolds::SINGLE_OFFSET);
    EXPECT_STREQ(structure_name(LeavingFolds::SINGLE_OFFSET), "single, off the diagonal");
    EXPECT_STREQ(structure_name(LeavingFolds::MULTIPLE), "two or more folds");
}

TEST(LeavingFolds, CountsOverCorners)
{
    CornerCounts c;
    c.add(billows({10}));        // single on the diagonal
    c.add(billows({-40, 120}));  // single off it (the side wave left out)
    c.add(billows({-21, 19}));   // two
    c.add({});                   // none
    EXPECT_EQ(c.corners, 4);
    EXPECT_EQ(c.singles, 2);
    EXPECT_EQ(c.count[LeavingFolds::SINGLE_DIAGONAL], 1);
    EXPECT_EQ(c.count[LeavingFolds::SINGLE_OFFSET], 1);
    EXPECT_EQ(c.count[LeavingFolds::MULTIPLE], 1);
    EXPECT_EQ(c.count[LeavingFolds::NONE], 1);
    EXPECT_DOUBLE_EQ(c.sum_angle_deg, -30);
    EXPECT_DOUBLE_EQ(c.sum_abs_angle_deg, 50);
}

TEST(LeavingFolds, DistinctDrapesByEnergy)
{
    EXPECT_EQ(distinct_energies({}), 0);
    EXPECT_EQ(distinct_energies({0.5, 0.5 * (1 + 5e-10), 0.5}), 1);  // within 1e-9: one drape
    EXPECT_EQ(distinct_energies({0.52, 0.5, 0.5 * (1 + 2e-9)}), 3);
}

TEST(LeavingFolds, DrapeSummaryTakesTheMajorityOfItsCorners)
{
    const std::vector<std::vector<Billow>> corners{billows({-30}), billows({40}), billows({5}), billows({-21, 19, 130})};
    const CornerSummary s = summarise_corners(true, corners);
    EXPECT_EQ(s.majority, LeavingFolds::SINGLE_OFFSET);
    EXPECT_DOUBLE_EQ(s.mean_billows, (1 + 1 + 1 + 2) / 4.0);
    EXPECT_DOUBLE_EQ(s.mean_abs_angle, (30 + 40 + 5) / 3.0);
    // A tie goes to the first structure in the enumeration's order; no folds: none.
    const CornerSummary tie = summarise_corners(true, {billows({}), billows({}), billows({1, 2}), billows({3, 4})});
    EXPECT_EQ(tie.majority, LeavingFolds::NONE);
    EXPECT_EQ(tie.mean_abs_angle, 0);
    const CornerSummary none = summarise_corners(false, {});
    EXPECT_EQ(none.majority, LeavingFolds::NONE);
    EXPECT_EQ(none.mean_billows, 0);
}

}  // namespace
}  // namespace woven::analysis
