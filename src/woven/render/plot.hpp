#pragma once
// Line plots (KES curves, energy functions) as PNG-ready images, in a clean matplotlib-like style.
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
    /// How the series is drawn: a 2 px anti-aliased polyline, dots, or both.
    enum class Style { LINE, POINTS, LINE_AND_POINTS } style = Style::LINE;
    /// sRGB colour in 0..1. Series after the first that keep this default (matplotlib's
    /// "tab:blue") get the next colour of matplotlib's tab10 cycle instead.
    Vec3 color{0.12, 0.47, 0.71};
    std::string label;      ///< legend entry; series with an empty label are not listed
};

/// A plot: white background, framed axes with 1-2-5 ticks and numeric labels, light grey grid,
/// axis labels, title and a legend box (placed in the emptiest corner) when any series is labelled.
struct Plot {
    std::string title;             ///< drawn above the axes (ASCII)
    std::string x_label;           ///< below the x axis
    std::string y_label;           ///< left of the y axis, rotated
    std::vector<Series> series;    ///< drawn in order
    /// Upper limit of the y axis when the data go above it (e.g. a singular energy curve):
    /// points above it do not widen either axis, and the lines are clipped at the axes.
    std::optional<double> y_max;
};

/// Draws `plot` into a width x height image (each at least 200 x 150 is sensible; smaller
/// sizes are clamped to 64). An empty plot still gives axes with ticks over [0, 1].
Image plot(const Plot& plot, int width = 800, int height = 560);

}  // namespace woven::render
