#pragma once
// Line plots (KES curves, energy functions, sweeps) drawn once with cairo, to a PNG image or to
// an SVG document: axes with 1-2-5 ticks, a grid, DejaVu Sans text, a legend where it covers
// the least data, matplotlib's tab10 colours, error bars, gaps at non-finite points.
#include <optional>
#include <string>
#include <vector>

#include "woven/common/types.hpp"
#include "woven/render/image.hpp"

namespace woven::render {

/// One data series. Non-finite (x, y) pairs are skipped and break the line (a gap).
struct Series {
    std::vector<double> x;  ///< abscissae; pairs beyond min(x.size(), y.size()) are ignored
    std::vector<double> y;  ///< ordinates
    /// How the series is drawn: a 2 px polyline, dots, or both.
    enum class Style { LINE, POINTS, LINE_AND_POINTS } style = Style::LINE;
    /// sRGB colour in 0..1; none: matplotlib's tab10 cycle, by the series' index.
    std::optional<Vec3> color;
    std::string label;        ///< legend entry; series with an empty label are not listed
    std::vector<double> err;  ///< symmetric error bars in y per point (empty, non-finite or 0: none)
};

/// A plot: white background, framed axes with 1-2-5 ticks and numeric labels, light grey grid,
/// axis labels, title and a legend box when any series is labelled: inside the axes in a corner
/// where it fits and covers no data, else right of the axes (narrowing them to no less than half).
struct Plot {
    std::string title;             ///< drawn above the axes (UTF-8)
    std::string x_label;           ///< below the x axis
    std::string y_label;           ///< left of the y axis, rotated
    std::vector<Series> series;    ///< drawn in order
    /// Upper limit of the y axis when the data go above it (e.g. a singular energy curve):
    /// points above it do not widen either axis, and the lines are clipped at the axes.
    std::optional<double> y_max;
    /// One metre of x is as long as one of y on the page (shapes, outlines): the axis with the
    /// shorter range is widened about its centre.
    bool equal_aspect = false;
};

/// Where a plot's data land: pixel = left + (x - x_lo) / (x_hi - x_lo) * (right - left) and
/// pixel y = bottom - (y - y_lo) / (y_hi - y_lo) * (bottom - top) (image pixels, y down).
struct PlotFrame {
    double x_lo = 0, x_hi = 1, y_lo = 0, y_hi = 1;       ///< data range of the axes
    double left = 0, top = 0, right = 1, bottom = 1;     ///< the axes' box, pixels
    double legend_x = 0, legend_y = 0, legend_w = 0, legend_h = 0;  ///< the legend's box (w 0: none)
    bool legend_whole = true;  ///< false when the image is too small for all the legend's text
    std::vector<Vec3> colors;                            ///< each series' colour as drawn
};

/// Draws `plot` into a width x height image (each side clamped to 64..8192). An empty plot still
/// gives axes with ticks over [0, 1].
Image plot(const Plot& plot, int width = 800, int height = 560);

/// The same drawing as an SVG document (no XML declaration, for inlining in HTML), its ids
/// prefixed with `id_prefix` so that several plots can share a page. Each series' line is one
/// <path> (a subpath per unbroken run; cairo merges the middle points of collinear runs) and its
/// dots another (a subpath per dot), stroked or filled in its colour. Its text (title, axis
/// labels, tick labels, legend) is SVG <text> elements, not glyph outlines: searchable and read
/// by screen readers, at the positions and sizes the PNG's glyphs have.
std::string plot_svg(const Plot& plot, int width = 680, int height = 420, const std::string& id_prefix = "p");

/// The layout plot() and plot_svg() use at that size.
PlotFrame plot_frame(const Plot& plot, int width, int height);

}  // namespace woven::render
