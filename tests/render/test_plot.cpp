// plot: size, where the data line lands, gaps for non-finite values, empty plots, clipping.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "woven/render/plot.hpp"

using namespace woven;
using namespace woven::render;

namespace {

struct Box {
    int x0 = 1 << 30, y0 = 1 << 30, x1 = -1, y1 = -1, count = 0;
};

/// True where the pixel is close (per channel within tol) to the pure series colour.
bool is_colour(const Image& img, int x, int y, const Vec3& c, int tol = 40)
{
    const std::uint8_t* p = &img.rgb[(static_cast<std::size_t>(y) * img.width + x) * 3];
    for (int k = 0; k < 3; ++k)
        if (std::abs(p[k] - static_cast<int>(std::lround(255 * c[k]))) > tol) return false;
    return true;
}

Box find_colour(const Image& img, const Vec3& c, int tol = 40)
{
    Box b;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            if (is_colour(img, x, y, c, tol)) {
                b.x0 = std::min(b.x0, x);
                b.x1 = std::max(b.x1, x);
                b.y0 = std::min(b.y0, y);
                b.y1 = std::max(b.y1, y);
                ++b.count;
            }
    return b;
}

const Vec3 kRed(0.84, 0.15, 0.16);

Series diagonal(int n = 11)
{
    Series s;
    for (int i = 0; i < n; ++i) {
        s.x.push_back(i);
        s.y.push_back(i);
    }
    s.color = kRed;
    s.label = "y = x";
    return s;
}

}  // namespace

TEST(Plot, LineYEqualsXLiesOnTheDiagonalOfThePlotArea)
{
    Plot p{std::string("Diagonal"), std::string("x"), std::string("y"), {diagonal()}, std::nullopt};
    p.series.back().label.clear();  // no legend sample to confuse the bounding box
    const Image img = plot(p, 800, 560);
    ASSERT_EQ(img.width, 800);
    ASSERT_EQ(img.height, 560);
    ASSERT_EQ(img.rgb.size(), 800u * 560u * 3u);

    const Box b = find_colour(img, kRed);
    ASSERT_GT(b.count, 300);
    EXPECT_GT(b.x1 - b.x0, 400);  // spans most of the axes
    EXPECT_GT(b.y1 - b.y0, 250);
    // Every red pixel lies within 3 px of the line from the
    // bottom-left to the top-right of the data's bounding box: y decreases as x increases.
    int off = 0;
    for (int y = b.y0; y <= b.y1; ++y)
        for (int x = b.x0; x <= b.x1; ++x) {
            if (!is_colour(img, x, y, kRed)) continue;
            const double t = static_cast<double>(x - b.x0) / (b.x1 - b.x0);
            const double expected_y = b.y1 - t * (b.y1 - b.y0);
            const double dist = std::abs(y - expected_y) * (b.x1 - b.x0) / std::hypot(b.x1 - b.x0, b.y1 - b.y0);
            if (dist > 3) ++off;
        }
    EXPECT_EQ(off, 0);
    // The middle of the diagonal is drawn.
    const int mx = (b.x0 + b.x1) / 2, my = (b.y0 + b.y1) / 2;
    bool near_middle = false;
    for (int dy = -3; dy <= 3; ++dy)
        for (int dx = -3; dx <= 3; ++dx) near_middle |= is_colour(img, mx + dx, my + dy, kRed);
    EXPECT_TRUE(near_middle);
    // Background white, with dark axis/text pixels.
    EXPECT_TRUE(is_colour(img, 2, 2, Vec3(1, 1, 1), 0));
    EXPECT_GT(find_colour(img, Vec3(0, 0, 0)).count + find_colour(img, Vec3(0.15, 0.15, 0.15)).count, 500);
}

TEST(Plot, NonFiniteValuesLeaveAGap)
{
    Plot p;
    Series s = diagonal(101);
    s.label.clear();
    for (int i = 45; i <= 55; ++i) s.y[i] = std::numeric_limits<double>::quiet_NaN();
    s.x[20] = std::numeric_limits<double>::infinity();
    p.series.push_back(s);
    const Image img = plot(p, 600, 400);
    ASSERT_EQ(img.width, 600);
    ASSERT_EQ(img.height, 400);
    const Box b = find_colour(img, kRed);
    ASSERT_GT(b.count, 100);
    const int mx = (b.x0 + b.x1) / 2;
    for (int y = 0; y < img.height; ++y) EXPECT_FALSE(is_colour(img, mx, y, kRed)) << "y " << y;
}

TEST(Plot, EmptyAndDegeneratePlotsStillHaveAxes)
{
    const Image empty = plot(Plot{});
    ASSERT_EQ(empty.width, 800);
    ASSERT_EQ(empty.height, 560);
    EXPECT_GT(find_colour(empty, Vec3(0.15, 0.15, 0.15), 10).count, 1000);  // the frame

    Plot single;
    single.series.push_back(Series{{2.0}, {3.0}, Series::Style::POINTS, kRed, "one"});
    single.series.push_back(Series{{std::nan("")}, {1.0}, Series::Style::LINE_AND_POINTS, Vec3(0, 0.5, 0), ""});
    const Image img = plot(single, 300, 200);
    EXPECT_EQ(img.width, 300);
    EXPECT_GT(find_colour(img, kRed).count, 20);
}

TEST(Plot, LegendShowsLabelledSeriesOnly)
{
    Plot p;
    p.series.push_back(diagonal());
    Series unlabelled = diagonal();
    unlabelled.label.clear();
    unlabelled.color = Vec3(0.0, 0.6, 0.0);
    for (double& y : unlabelled.y) y = 10 - y;
    p.series.push_back(unlabelled);
    const Image without = plot(Plot{{}, {}, {}, {p.series[1]}, {}});
    const Image with = plot(p);
    // The legend adds a light grey (0.8) box outline that the unlabelled plot does not have.
    EXPECT_GT(find_colour(with, Vec3(0.8, 0.8, 0.8), 3).count, find_colour(without, Vec3(0.8, 0.8, 0.8), 3).count + 100);
}

TEST(Plot, YMaxClipsASingularCurve)
{
    Plot p;
    p.y_max = 10.0;
    Series s;
    for (int i = 0; i <= 200; ++i) {
        const double x = i / 200.0;
        s.x.push_back(x);
        s.y.push_back(1 / (1 - x));  // 1 / 0 = inf at the end
    }
    s.color = kRed;
    p.series.push_back(s);
    const Image img = plot(p, 640, 480);
    const Box b = find_colour(img, kRed);
    ASSERT_GT(b.count, 200);
    // The curve reaches the top of the axes but not above it (title area and margin stay clean).
    EXPECT_GT(b.y0, 10);
    EXPECT_LT(b.y0, 40);
}
