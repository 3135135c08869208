// The instruments' plots and pictures (render/instrument_plots.hpp): series, colours and labels
// as kes-test, fit, cusick and the corner map draw them, and known points at their pixels.
#include <cmath>
#include <cstdint>
#include <vector>

#include <gtest/gtest.h>

#include "woven/render/instrument_plots.hpp"

using namespace woven;
using namespace woven::render;

namespace {

std::array<int, 3> pixel(const Image& img, int x, int y)
{
    const std::uint8_t* p = &img.rgb[(static_cast<std::size_t>(y) * img.width + x) * 3];
    return {p[0], p[1], p[2]};
}

std::array<int, 3> bytes(const Vec3& c)
{
    return {static_cast<int>(std::lround(255 * c[0])), static_cast<int>(std::lround(255 * c[1])), static_cast<int>(std::lround(255 * c[2]))};
}

/// Where the data point (x, y) of `p` lands in a width x height image.
std::pair<int, int> at(const Plot& p, double x, double y, int width, int height)
{
    const PlotFrame f = plot_frame(p, width, height);
    return {static_cast<int>(f.left + (x - f.x_lo) / (f.x_hi - f.x_lo) * (f.right - f.left)),
            static_cast<int>(f.bottom - (y - f.y_lo) / (f.y_hi - f.y_lo) * (f.bottom - f.top))};
}

bool near(const std::array<int, 3>& a, const std::array<int, 3>& b, int tol = 12)
{
    for (int k = 0; k < 3; ++k)
        if (std::abs(a[k] - b[k]) > tol) return false;
    return true;
}

// Shear: both directions share one input loop; the simulated ones differ.
const std::vector<KesCurveView> kShear = {{"warp", {0, 4, 8}, {0, 1.0, 2.5}, {0, 4, 8}, {0, 1.5, 3.0}},
                                          {"weft", {0, 4, 8}, {0, 0.5, 2.0}, {0, 4, 8}, {0, 1.5, 3.0}}};

}  // namespace

TEST(InstrumentPlots, LoopPlotDrawsASharedInputOnceInEachStyle)
{
    const Plot page = kes_loop_plot("t", "x", "y", kShear, true);
    ASSERT_EQ(page.series.size(), 3u);
    EXPECT_EQ(page.series[0].label, "input");
    EXPECT_EQ(page.series[0].style, Series::Style::LINE);
    EXPECT_EQ(page.series[2].label, "simulated weft");
    EXPECT_EQ(*page.series[2].color, kRed);
    // The weft's simulated dot at (4, 0.5) is red at its pixel.
    const Image img = plot(page, 600, 400);
    const auto [px, py] = at(page, 4, 0.5, 600, 400);
    EXPECT_TRUE(near(pixel(img, px, py), bytes(kRed))) << px << " " << py;

    const Plot job = kes_loop_plot("t", "x", "y", kShear, false);
    ASSERT_EQ(job.series.size(), 3u);
    EXPECT_EQ(job.series[0].label, "input loop");
    EXPECT_FALSE(job.series[1].color.has_value());
    // One run alone keeps its direction in the label (kes-test's style).
    EXPECT_EQ(kes_loop_plot("t", "x", "y", {kShear[0]}, false).series[0].label, "input loop warp");
    EXPECT_EQ(kes_loop_plot("t", "x", "y", {kShear[0]}, true).series[0].label, "input");
}

TEST(InstrumentPlots, CurvePlotShowsOneInputCurveOrOnePerDirection)
{
    const Plot shear = kes_curve_plot("t", "x", "y", kShear, false);
    ASSERT_EQ(shear.series.size(), 3u);
    EXPECT_EQ(shear.series[0].label, "input curve");
    EXPECT_EQ(shear.series[2].style, Series::Style::LINE_AND_POINTS);
    EXPECT_DOUBLE_EQ(shear.series[2].y[2], 2.0);
    const Plot bending = kes_curve_plot("t", "x", "y", kShear, true);
    ASSERT_EQ(bending.series.size(), 4u);
    EXPECT_EQ(bending.series[2].label, "input weft");
    EXPECT_DOUBLE_EQ(bending.series[2].y[1], 1.5);
}

TEST(InstrumentPlots, CurveFitPlotMarksTheJunctions)
{
    CurveFitView v{"fit", "K", "M", {0, 1, 2}, {0, 1, 4}, {0, 1, 2}, {0, 1, 4}, {1.5}, {2.25}, kBlue};
    const Plot p = curve_fit_plot(v);
    ASSERT_EQ(p.series.size(), 3u);
    EXPECT_EQ(p.series[2].label, "segment junctions");
    const Image img = plot(p, 600, 400);
    const auto [px, py] = at(p, 1.5, 2.25, 600, 400);
    EXPECT_TRUE(near(pixel(img, px, py), {214, 38, 41})) << px << " " << py;  // (0.84, 0.15, 0.16)
    v.junction_x.clear();
    v.junction_y.clear();
    EXPECT_EQ(curve_fit_plot(v).series.size(), 2u);
}

TEST(InstrumentPlots, ShadowPictureHasTheShadowTheCirclesAndTheNodes)
{
    const int n = 100;
    const double R = 0.1;  // half width 0.108 m: 2.16 mm pixels
    std::vector<unsigned char> covered(n * n, 0);
    covered[10 + n * 10] = 1;  // column 10 of the 11th row from the bottom
    const Image img = shadow_picture(covered, n, R, 0.05, {0.0}, {0.05}, 42.0);
    ASSERT_EQ(img.width, n);
    ASSERT_EQ(img.height, n);
    EXPECT_EQ(pixel(img, 10, n - 1 - 10), (std::array<int, 3>{0, 0, 0}));
    EXPECT_EQ(pixel(img, 11, n - 1 - 10), (std::array<int, 3>{255, 255, 255}));
    // The specimen's circle at 90 deg (x = R): (0.208 / 0.00216, 99 - 0.108 / 0.00216) = (96, 49).
    EXPECT_EQ(pixel(img, 96, 49), (std::array<int, 3>{150, 150, 150}));
    // The node at 0 deg (warp, up) ticks red from r = 0.05 m out: at y = 0.07 m, row 99 - 82.
    EXPECT_EQ(pixel(img, 50, 17), (std::array<int, 3>{220, 0, 0}));
    EXPECT_EQ(shadow_half_width(R), 1.08 * R);
}

TEST(InstrumentPlots, CornerMapColoursEachCellByItsStructure)
{
    // 2 ratios x 2 lengths; cell 0 (lowest ratio, shortest length) single on the diagonal (green),
    // cell 3 none (grey).
    const std::vector<MapCellView> cells = {{0, 1.0, 0, true}, {1, 1.0, 30, true}, {2, 2.0, 0, true}, {3, 0.0, 0, false}};
    const Image img = corner_map_picture(cells, {0.5, 2}, {1, 3}, {}, {"a", "b", "c", "d"}, "footer");
    EXPECT_EQ(img.width, 120 + 2 * 190 + 30);
    EXPECT_EQ(img.height, 60 + 2 * 110 + 150);
    // Cell 0 is bottom left (x from 120, y from 60 + 110); its lower right holds no text.
    EXPECT_EQ(pixel(img, 120 + 150, 170 + 90), (std::array<int, 3>{140, 204, 140}));   // (0.55, 0.80, 0.55)
    EXPECT_EQ(pixel(img, 310 + 150, 60 + 90), (std::array<int, 3>{217, 217, 217}));    // cell 3: top right, grey 0.85
    // A marked fabric at the middle of the map: its dot in its colour.
    const Image marked = corner_map_picture(cells, {0.5, 2}, {1, 3}, {{"m", 2, 1, Vec3(1, 0, 0)}}, {"a", "b", "c", "d"}, "footer");
    EXPECT_EQ(pixel(marked, 120 + 95 + 95, 60 + 55 + 55), (std::array<int, 3>{255, 0, 0}));
}
