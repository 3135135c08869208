#pragma once
// The pieces of a self-contained HTML report (`woven report`, cli/cmd_report.cpp): plots (SVG
// with their data), sortable tables, inlined pictures and glTF scenes, and the page around them,
// whose script sets <body data-ready="1"> once its tables, plots and 3-D view are built. Nothing
// is fetched: the three.js text is passed in and inlined.
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "woven/render/plot.hpp"

namespace woven::render {

/// `text` with & < > " ' escaped for HTML text and attribute values.
std::string html_escape(std::string_view text);

/// RFC 4648 base64 of `bytes`.
std::string base64(std::string_view bytes);

/// A plot for the page (render/plot.hpp's drawing as inline SVG) in a <figure class="plot"
/// id="ID">, followed by <script type="application/json" class="plot-data"> holding what it
/// shows: {"id", "title", "x_label", "y_label", "frame": {x_lo, x_hi, y_lo, y_hi, left, top,
/// right, bottom, legend: [x, y, w, h], legend_whole, width, height}, "series": [{label, color: [r, g, b]
/// 0..255, style: line|points|line_and_points, x, y, err}]} (non-finite numbers as null), so that
/// a reader can map the SVG's vertices back to data. The SVG keeps its `width` x `height` px in a
/// wide page and shrinks to a narrower one (its viewBox, the page's style).
std::string html_plot(const Plot& plot, const std::string& id, int width = 680, int height = 420);

/// A table whose columns sort when their header is clicked (numerically where `numeric`), in a
/// <div class="table-box"> that scrolls when the table is wider than the page (or taller than
/// most of the window; its header stays in view).
struct HtmlTable {
    std::vector<std::string> header;
    std::vector<bool> numeric;                  ///< per column
    std::vector<std::vector<std::string>> rows; ///< cell texts (escaped when written)
    std::vector<std::string> row_class;         ///< per row ("" or a CSS class: "failed", "missing")
};
std::string html_table(const HtmlTable& table, const std::string& id);

/// A scene for the 3-D view: a binary glTF (drape.glb, cusick.glb: y-up, metres; its node
/// "cloth" and the obstacles' "obstacle K KIND"), inlined as base64.
struct ViewModel {
    std::string name;
    std::string glb;                                  ///< the file's bytes
    std::array<float, 3> colour{0.7f, 0.28f, 0.16f};  ///< the cloth's sRGB colour when no field is shown
};

/// Bytes the model takes in the page.
std::size_t inlined_size(const ViewModel& m);

/// The JavaScript libraries of the view (global-script builds; empty: none).
struct ViewScripts {
    std::string three, orbit_controls, gltf_loader;
};

/// The page: `title`, `body` (HTML made of the pieces above) and, when `models` is not empty, a
/// 3-D view with a chooser of the model and of the field that colours the cloth (each per-vertex
/// attribute of the cloth, "_NAME" in the glb with its unit from the asset's extras, and the
/// height), with a colour legend (name, unit, min, max). The obstacles are drawn in one colour.
/// Without three.js or its GLTFLoader the view says so and the rest of the page still builds.
/// URL hash parameters (for a link or a test): field=NAME|none, camera=x,y,z and target=x,y,z
/// (m, z up), obstacles=RRGGBB, hide=a comma list of cloth, obstacles
/// or a part of an obstacle's name (plane, box, ...), model=K; with any of them the page shows
/// the view alone. The body's data-view is webgl, failed or none; data-bounds gives
/// each obstacle's name and box [x0, y0, z0, x1, y1, z1] (woven axes) once loaded; data-ready is 1 when all is built.
std::string html_page(const std::string& title, const std::string& body, const std::vector<ViewModel>& models, const ViewScripts& scripts);

}  // namespace woven::render
