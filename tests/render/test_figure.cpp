// render / figure: composing pictures (blank, paste with clipping, rectangles, discs, labels).
#include <set>

#include <gtest/gtest.h>

#include "woven/render/figure.hpp"

using namespace woven;

namespace {
int channel(const render::Image& img, int x, int y, int k) { return img.rgb[(static_cast<std::size_t>(y) * img.width + x) * 3 + k]; }
}  // namespace

TEST(Figure, BlankPasteClipsAndRectanglesBlend)
{
    render::Image a = render::blank(10, 8, Vec3(1, 1, 1));
    ASSERT_EQ(a.rgb.size(), 10u * 8u * 3u);
    const render::Image b = render::blank(4, 4, Vec3(1, 0, 0));
    render::paste(a, b, 8, 6);  // only 2 x 2 of it lands
    EXPECT_EQ(channel(a, 9, 7, 1), 0);
    EXPECT_EQ(channel(a, 7, 7, 1), 255);
    EXPECT_EQ(channel(a, 9, 5, 1), 255);
    render::fill_rect(a, -5, -5, 2, 2, Vec3(0, 0, 0), 0.5);
    EXPECT_EQ(channel(a, 1, 1, 0), 128);  // half way from white to black
    EXPECT_EQ(channel(a, 2, 2, 0), 255);
}

TEST(Figure, DiscCoversItsAreaAndLabelsInk)
{
    render::Image img = render::blank(60, 60);
    render::fill_disc(img, 30, 30, 10, Vec3(0, 0, 0));
    double ink = 0;
    for (int y = 0; y < 60; ++y)
        for (int x = 0; x < 60; ++x) ink += (255 - channel(img, x, y, 0)) / 255.0;
    EXPECT_NEAR(ink, 3.14159265 * 100, 3.0);  // anti-aliased edge: the area to 1 %
    render::Image t = render::blank(200, 30);
    render::draw_label(t, "corner", 5, 5, 2);
    int dark = 0, right = 0;
    for (int y = 0; y < 30; ++y)
        for (int x = 0; x < 200; ++x)
            if (channel(t, x, y, 0) < 128) {
                ++dark;
                right = std::max(right, x);
            }
    EXPECT_GT(dark, 50);
    EXPECT_NEAR(right + 1 - 5, render::label_width("corner", 2), 4);
    // Real, anti-aliased text (a bitmap font has two levels): many greys along the glyphs' edges.
    std::set<int> greys;
    for (int y = 0; y < 30; ++y)
        for (int x = 0; x < 200; ++x) greys.insert(channel(t, x, y, 0));
    EXPECT_GT(greys.size(), 20u);
    // Two lines: twice the height and more, as wide as the wider.
    EXPECT_GT(render::label_height("a\nb", 2), 2 * render::label_height("a", 2));
    EXPECT_EQ(render::label_width("corner\nx", 2), render::label_width("corner", 2));
}
