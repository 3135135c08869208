#pragma once
// The pieces of a self-contained HTML report (`woven report`, cli/cmd_report.cpp): SVG plots,
// sortable tables, inlined pictures and meshes, and the page around them, whose script sets
// <body data-ready="1"> once its tables, plots and 3-D view are built. Nothing is fetched: the
// three.js text is passed in and inlined.
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace woven::render {

/// `text` with & < > " ' escaped for HTML text and attribute values.
std::string html_escape(std::string_view text);

/// RFC 4648 base64 of `bytes`.
std::string base64(std::string_view bytes);

/// One series of a plot: points (x, y) with optional symmetric error bars (empty: none).
struct PlotSeries {
    std::string name;
    std::vector<double> x, y, err;
    bool lines = true;  ///< join the points (sorted by x) with a line
};

struct PlotSpec {
    std::string title, x_label, y_label;
    std::vector<PlotSeries> series;
};

/// An SVG plot (inline <svg>, `width` x `height` px): axes with round ticks, one colour per
/// series, error bars, a legend; the points carry <title> tooltips. Non-finite points are left
/// out. An empty plot says "no data".
std::string svg_plot(const PlotSpec& spec, int width = 680, int height = 400);

/// A table whose columns sort when their header is clicked (numerically where `numeric`).
struct HtmlTable {
    std::vector<std::string> header;
    std::vector<bool> numeric;                  ///< per column
    std::vector<std::vector<std::string>> rows; ///< cell texts (escaped when written)
    std::vector<std::string> row_class;         ///< per row ("" or a CSS class: "failed", "missing")
};
std::string html_table(const HtmlTable& table, const std::string& id);

/// A mesh for the 3-D view: positions in metres (z up), triangles.
struct ViewMesh {
    std::string name;
    std::vector<float> xyz;
    std::vector<std::uint32_t> triangles;
    std::array<float, 3> colour{0.7f, 0.28f, 0.16f};
};

/// Bytes the mesh takes in the page (base64 of float32 positions and uint32 indices).
std::size_t inlined_size(const ViewMesh& m);

/// The page: `title`, `body` (HTML made of the pieces above), the meshes (a 3-D view with a
/// chooser; none: no view) and three.js with its OrbitControls (global-script builds; empty
/// `three_js`: the view says the library was not found, the rest of the page still builds).
std::string html_page(const std::string& title, const std::string& body, const std::vector<ViewMesh>& meshes,
                      std::string_view three_js, std::string_view orbit_controls_js);

}  // namespace woven::render
