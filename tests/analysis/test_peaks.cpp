// Prominent maxima of open and periodic sequences (analysis/peaks.hpp).
#include <gtest/gtest.h>

#include "woven/analysis/peaks.hpp"
#include "woven/common/error.hpp"

namespace an = woven::analysis;

TEST(Peaks, AnOpenSequencesEndsAreNoMaxima)
{
    // 5 at the start and 4 at the end are ends, not maxima; 3 at index 3 rises 2 above the
    // lower of its saddles (1 at index 2, 1.5 at index 5).
    const std::vector<double> v{5, 2, 1, 3, 2, 1.5, 4};
    const auto open = an::prominent_peaks(v, 0.1, an::SequenceEnds::OPEN);
    ASSERT_EQ(open.size(), 1u);
    EXPECT_EQ(open[0].sample, 3);
    EXPECT_DOUBLE_EQ(open[0].value, 3.0);
    EXPECT_DOUBLE_EQ(open[0].prominence, 3.0 - 1.5);
    // Read periodically, the 4 -> 5 wrap makes 5 a maximum (its saddle is the global 1); the
    // parabola through 4, 5, 2 puts its top a quarter sample before index 0, at 6.75.
    const auto loop = an::prominent_peaks(v, 0.1, an::SequenceEnds::PERIODIC);
    ASSERT_EQ(loop.size(), 2u);
    EXPECT_EQ(loop[0].sample, 3);
    EXPECT_EQ(loop[1].sample, 0);
    EXPECT_DOUBLE_EQ(loop[1].index, 6.75);
    EXPECT_DOUBLE_EQ(loop[1].prominence, 5.0 - 1.0);
}

TEST(Peaks, APlateauCountsOnceAtItsMiddle)
{
    const auto p = an::prominent_peaks({0, 1, 2, 2, 2, 1, 0}, 0.5, an::SequenceEnds::OPEN);
    ASSERT_EQ(p.size(), 1u);
    EXPECT_EQ(p[0].sample, 3);
    EXPECT_DOUBLE_EQ(p[0].index, 3.0);
    // A plateau that runs into an open end is not a maximum.
    EXPECT_TRUE(an::prominent_peaks({0, 1, 2, 2}, 0.5, an::SequenceEnds::OPEN).empty());
    EXPECT_THROW(an::prominent_peaks({0, 1}, 0.5, an::SequenceEnds::OPEN), woven::InputError);
}
