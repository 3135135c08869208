// plot: size, where the data line lands, gaps for non-finite values, empty plots, clipping.
#include <algorithm>
#include <cmath>
#include <array>
#include <cstdio>
#include <cstring>
#include <limits>
#include <set>
#include <sstream>
#include <string>
#include <vector>

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
    Plot p{std::string("Diagonal"), std::string("x"), std::string("y"), {diagonal()}, std::nullopt, false};
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
    single.series.push_back(Series{{2.0}, {3.0}, Series::Style::POINTS, kRed, "one", {}});
    single.series.push_back(Series{{std::nan("")}, {1.0}, Series::Style::LINE_AND_POINTS, Vec3(0, 0.5, 0), "", {}});
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
    const Image without = plot(Plot{{}, {}, {}, {p.series[1]}, {}, false});
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

namespace {

/// The <path> elements of a cairo SVG with their colour (0..255, from the style's stroke or fill) and their vertices (M/L only;
/// each "M" starts a subpath).
struct SvgPath {
    std::array<int, 3> rgb{-1, -1, -1};
    bool stroked = false;
    std::vector<std::vector<std::array<double, 2>>> subpaths;
};

std::vector<SvgPath> svg_paths(const std::string& svg)
{
    std::vector<SvgPath> out;
    for (std::size_t at = 0; (at = svg.find("<path", at)) != std::string::npos; ++at) {
        const std::string tag = svg.substr(at, svg.find('>', at) - at);
        SvgPath p;
        for (const char* attr : {"stroke:rgb(", "fill:rgb("}) {
            const std::size_t c = tag.find(attr);
            if (c == std::string::npos) continue;
            double r = 0, g = 0, b = 0;
            if (std::sscanf(tag.c_str() + c + std::strlen(attr), "%lf%%,%lf%%,%lf%%", &r, &g, &b) == 3) {
                p.rgb = {static_cast<int>(std::lround(r * 2.55)), static_cast<int>(std::lround(g * 2.55)), static_cast<int>(std::lround(b * 2.55))};
                p.stroked = attr[0] == 's';
            }
        }
        const std::size_t d = tag.find(" d=\"");
        if (d == std::string::npos) continue;
        std::istringstream in(tag.substr(d + 4, tag.find('"', d + 4) - d - 4));
        std::string tok;
        char cmd = 0;
        while (in >> tok) {
            if (std::isalpha(static_cast<unsigned char>(tok[0]))) {
                cmd = tok[0];
                if (cmd == 'M') p.subpaths.emplace_back();
                continue;
            }
            std::string y;
            in >> y;
            if ((cmd == 'M' || cmd == 'L') && !p.subpaths.empty()) p.subpaths.back().push_back({std::stod(tok), std::stod(y)});
            if (cmd == 'C') {  // two more points; the last is the curve's end
                std::string a, b, c, e;
                in >> a >> b >> c >> e;
            }
        }
        out.push_back(std::move(p));
    }
    return out;
}

std::array<int, 3> rgb255(const Vec3& c)
{
    return {static_cast<int>(std::lround(255 * c[0])), static_cast<int>(std::lround(255 * c[1])), static_cast<int>(std::lround(255 * c[2]))};
}

Plot two_series()
{
    Plot p;
    p.title = "Known points";
    p.x_label = "x, m";
    p.y_label = "y, N";
    Series a;
    for (int i = 0; i <= 20; ++i) {
        a.x.push_back(0.1 * i);
        a.y.push_back(std::sin(0.3 * i));
    }
    a.label = "sine";
    Series b;
    b.x = {0.3, 1.0, 1.7};
    b.y = {-0.5, 0.25, 0.8};
    b.style = Series::Style::POINTS;
    b.label = "three points";
    p.series = {a, b};
    return p;
}

}  // namespace

TEST(Plot, KnownPointLandsAtItsPixelInThePng)
{
    const Plot p = two_series();
    const PlotFrame f = plot_frame(p, 700, 480);
    ASSERT_EQ(f.colors.size(), 2u);
    EXPECT_EQ(rgb255(f.colors[1]), (std::array<int, 3>{255, 127, 14}));  // tab10's second colour
    const Image img = plot(p, 700, 480);
    for (std::size_t k = 0; k < 3; ++k) {
        const double px = f.left + (p.series[1].x[k] - f.x_lo) / (f.x_hi - f.x_lo) * (f.right - f.left);
        const double py = f.bottom - (p.series[1].y[k] - f.y_lo) / (f.y_hi - f.y_lo) * (f.bottom - f.top);
        // The dot (radius 3.5 px) is at its point: its colour at the centre, white 8 px to the side.
        EXPECT_TRUE(is_colour(img, static_cast<int>(px), static_cast<int>(py), f.colors[1], 12)) << "point " << k;
        EXPECT_FALSE(is_colour(img, static_cast<int>(px) + 8, static_cast<int>(py), f.colors[1], 40)) << "point " << k;
    }
    // Real anti-aliased text: the title's pixels take many grey levels (a bitmap font has two).
    std::set<int> greys;
    for (int y = 0; y < static_cast<int>(f.top) - 4; ++y)
        for (int x = 0; x < img.width; ++x) greys.insert(img.rgb[(static_cast<std::size_t>(y) * img.width + x) * 3]);
    EXPECT_GT(greys.size(), 20u);
}

TEST(Plot, SvgHoldsEachSeriesAsAPathWithItsVertices)
{
    const Plot p = two_series();
    const PlotFrame f = plot_frame(p, 700, 480);
    const std::string svg = plot_svg(p, 700, 480, "t");
    EXPECT_EQ(svg.rfind("<svg", 0), 0u);
    const auto paths = svg_paths(svg);
    int lines = 0, dots = 0;
    for (const auto& path : paths) {
        if (path.stroked && path.rgb == rgb255(f.colors[0]) && path.subpaths.size() == 1 && path.subpaths[0].size() > 2) {
            ++lines;
            // 21 vertices, each at its data point through the frame (within 0.01 px).
            ASSERT_EQ(path.subpaths[0].size(), 21u);
            for (std::size_t k = 0; k < 21; ++k) {
                const double x = f.x_lo + (path.subpaths[0][k][0] - f.left) / (f.right - f.left) * (f.x_hi - f.x_lo);
                const double y = f.y_lo + (f.bottom - path.subpaths[0][k][1]) / (f.bottom - f.top) * (f.y_hi - f.y_lo);
                EXPECT_NEAR(x, p.series[0].x[k], 1e-4 * (f.x_hi - f.x_lo));
                EXPECT_NEAR(y, p.series[0].y[k], 1e-4 * (f.y_hi - f.y_lo));
            }
        }
        if (!path.stroked && path.rgb == rgb255(f.colors[1]) && path.subpaths.size() == 3) ++dots;
    }
    EXPECT_EQ(lines, 1);
    EXPECT_EQ(dots, 1);  // the three dots of the second series, one subpath each
}

TEST(Plot, LegendLiesInsideTheImageAwayFromTheData)
{
    Plot p = two_series();
    p.series[0].label = "a long legend entry that must still fit inside the plot";
    for (int w : {320, 700, 1200}) {
        const PlotFrame f = plot_frame(p, w, 400);
        ASSERT_GT(f.legend_w, 0);
        // Inside the axes, or right of them; always inside the image.
        const bool inside = f.legend_x >= f.left && f.legend_x + f.legend_w <= f.right;
        EXPECT_TRUE(inside || f.legend_x >= f.right) << w;
        EXPECT_LE(f.legend_x + f.legend_w, w) << w;
        EXPECT_GE(f.legend_y, f.top);
        EXPECT_LE(f.legend_y + f.legend_h, f.bottom);
    }
    // Data in every corner: the legend goes right of the axes, whole, where the image is wide
    // enough, and covers none of them.
    Plot full;
    Series grid;
    for (int i = 0; i <= 20; ++i)
        for (int j = 0; j <= 20; ++j) {
            grid.x.push_back(i);
            grid.y.push_back(j);
        }
    grid.style = Series::Style::POINTS;
    grid.label = "a grid of points";
    full.series.push_back(grid);
    const PlotFrame g = plot_frame(full, 900, 400);
    EXPECT_GT(g.legend_x, g.right);
    EXPECT_LE(g.legend_x + g.legend_w, 900);
    EXPECT_GT(g.right - g.left, 400);
    EXPECT_TRUE(g.legend_whole);
    EXPECT_FALSE(plot_frame(p, 320, 400).legend_whole);  // the long entry cannot fit 320 px
    // A rising line leaves the top-left and bottom-right corners free: the legend takes one (pixel y down).
    Plot rising;
    rising.series.push_back(diagonal());
    const PlotFrame f = plot_frame(rising, 700, 480);
    const double cx = f.legend_x + 0.5 * f.legend_w - 0.5 * (f.left + f.right), cy = f.legend_y + 0.5 * f.legend_h - 0.5 * (f.top + f.bottom);
    EXPECT_GT(cx * cy, 0) << "legend centre offset " << cx << ", " << cy;
    EXPECT_EQ(plot_frame(Plot{{}, {}, {}, {diagonal()}, {}, false}, 700, 480).legend_w > 0, true);
    Series unlabelled = diagonal();
    unlabelled.label.clear();
    EXPECT_EQ(plot_frame(Plot{{}, {}, {}, {unlabelled}, {}, false}, 700, 480).legend_w, 0);
}

TEST(Plot, NonFinitePointsSplitTheSvgPath)
{
    Plot p;
    Series s = diagonal(11);
    for (std::size_t k = 0; k < s.y.size(); ++k) s.y[k] = s.x[k] * s.x[k];  // no three points collinear (cairo would merge them)
    s.y[5] = std::numeric_limits<double>::quiet_NaN();
    p.series.push_back(s);
    int found = 0;
    for (const auto& path : svg_paths(plot_svg(p, 500, 400)))
        if (path.stroked && path.rgb == rgb255(kRed) && path.subpaths.size() == 2) {
            ++found;
            EXPECT_EQ(path.subpaths[0].size(), 5u);  // points 0..4
            EXPECT_EQ(path.subpaths[1].size(), 5u);  // points 6..10
        }
    EXPECT_EQ(found, 1);
}

TEST(Plot, SvgTextIsRealText)
{
    Plot p = two_series();
    p.title = "Moment & curvature <warp>";
    p.x_label = "curvature K, 1/cm";
    p.y_label = "moment M, gf.cm/cm";
    const std::string svg = plot_svg(p, 700, 480, "t");
    // No glyph outlines: cairo's text would be <symbol> glyphs drawn with <use>.
    EXPECT_EQ(svg.find("<symbol"), std::string::npos);
    EXPECT_EQ(svg.find("glyph"), std::string::npos);
    std::vector<std::string> texts;
    for (std::size_t at = 0; (at = svg.find("<text", at)) != std::string::npos;) {
        const std::size_t open = svg.find('>', at) + 1, close = svg.find("</text>", open);
        texts.push_back(svg.substr(open, close - open));
        at = close;
    }
    const auto has = [&texts](const std::string& t) { return std::find(texts.begin(), texts.end(), t) != texts.end(); };
    EXPECT_TRUE(has("Moment &amp; curvature &lt;warp&gt;"));  // escaped for XML
    EXPECT_TRUE(has("curvature K, 1/cm"));
    EXPECT_TRUE(has("moment M, gf.cm/cm"));
    for (const auto& s : p.series)
        if (!s.label.empty()) EXPECT_TRUE(has(s.label)) << s.label;
    // The y label turned about its anchor, the title bold and centred on the image.
    EXPECT_NE(svg.find("rotate(-90)\" font-size=\"13px\" text-anchor=\"middle\">moment M"), std::string::npos);
    EXPECT_NE(svg.find("<text x=\"350.00\" y=\"22.00\" font-size=\"15px\" text-anchor=\"middle\" font-weight=\"bold\">Moment"), std::string::npos);
    // A tick label of each axis: at least three per axis, all numbers.
    int numbers = 0;
    for (const auto& t : texts) {
        char* end = nullptr;
        std::strtod(t.c_str(), &end);
        numbers += !t.empty() && end && *end == 0;
    }
    EXPECT_GE(numbers, 6);
}
