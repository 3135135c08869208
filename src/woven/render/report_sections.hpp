#pragma once
// The sections of `woven report`'s page from a point's parsed manifest and tables: the points'
// table, the sections of drape, cusick, kes-test, fit and experiment folders, a sweep's plots and
// the gallery. Reading and verifying the folder is the caller's (app/report.cpp).
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "woven/render/html_page.hpp"
#include "woven/render/instrument_plots.hpp"

namespace woven::render {

/// A CSV file of numbers with a header (a cell of text reads as NaN).
struct CsvTable {
    std::vector<std::string> head;
    std::vector<std::vector<double>> cols;
    std::vector<std::vector<std::string>> text;  ///< the cells as written, per column
    int col(const std::string& name) const;      ///< -1: none
    std::vector<double> get(const std::string& name) const;  ///< empty: no such column
};

/// One point of the page: a sweep's row, or the one folder.
struct ReportPoint {
    std::string name;
    std::string status = "done";
    nlohmann::json values = nlohmann::json::object();   ///< the axes' values
    nlohmann::json outputs = nlohmann::json::object();  ///< the main numbers
    nlohmann::json manifest;
    std::optional<double> wall;  ///< wall time, s
    std::string problem;
    std::filesystem::path dir;  ///< its folder (its files are read by the caller)
};

/// A point's CSV file NAME, read (nullopt: none).
using CsvReader = std::function<std::optional<CsvTable>(const ReportPoint& p, const std::string& name)>;

/// The page's plots, numbered in order ("plot-1", ...).
struct ReportPlots {
    std::string html;
    int count = 0;
    void add(const Plot& p, int width = 680, int height = 420);
};

/// A fabric's bending length (B / W)^(1/3), cm, mean of warp and weft; NaN when unknown.
using BendingLength = std::function<double(const std::string& fabric)>;

/// A fabric's display colour (sRGB 0..1, the fabric file's `color`: the colour its cloth has in
/// the pictures); none when it has none or cannot be read.
using FabricColour = std::function<std::optional<Vec3>(const std::string& fabric)>;

/// A JSON value as a cell: a string as it is, a float as %.6g, null empty, the rest as JSON.
std::string report_cell(const nlohmann::json& v);

/// A two-column table (quantity, value) of the object's scalars, nested objects flattened with '.'.
HtmlTable key_table(const nlohmann::json& j);

/// The points' table: a row each with its name, the `axes`' values, status, wall time and the
/// `columns` of its outputs; rows not done get their status as class.
HtmlTable points_table(const std::vector<ReportPoint>& points, const std::vector<std::string>& axes, const std::vector<std::string>& columns);

/// A sweep's plots: the main output of `command` against the fabric's bending length (a "fabric"
/// axis) or the first numeric axis, and the wall time against the particles when they vary; one
/// series per combination of the other axes, seeds as mean +- std.
void sweep_plots(const std::vector<ReportPoint>& points, const std::vector<std::string>& axes, const std::string& command,
                 const BendingLength& bending_length, ReportPlots& plots);

/// A kes-test folder: the moment-curvature and force-angle loops (else the loading curves) of its
/// CSV files, input as lines and simulated as dots; the cantilever's shape against the elastica.
/// The titles start with `title_prefix`.
void kes_section(const ReportPoint& p, const CsvReader& csv, ReportPlots& plots, const std::string& title_prefix);

/// A drape folder: its energies and the corner folds.
std::string drape_section(const ReportPoint& p);

/// A cusick folder: DC and the nodes; the shadow seen from above (warp up): `shadow_radius`
/// r(theta_k) at theta_k = 360 k / n deg from the warp (empty: none), the nodes, the disc and
/// the flat specimen.
std::string cusick_section(const ReportPoint& p, const std::vector<double>& shadow_radius, ReportPlots& plots);

/// A garment folder (report.json of `woven garment`): the garment, fabric, spacing and ramp; the
/// pieces with their grain angles; the hem (nodes, flare, length drop); each seam's gaps and
/// forces; plots of the hem's radius and height per 5-degree bin of azimuth (nodes marked).
std::string garment_section(const ReportPoint& p, ReportPlots& plots);

/// A fit folder: `curves` and the energy functions of its CSV files.
void fit_section(const ReportPoint& p, const CsvReader& csv, const std::vector<CurveFitView>& curves, ReportPlots& plots);

/// An experiment folder (its manifests in p.manifest by file name): each as tables; for
/// cube_results.json the corner statistics and energy and projected area against the bending
/// length (mean +- std over the seeds), each fabric in its display colour (as in cube_figure.png;
/// none: the plot's own cycle).
std::string experiment_section(const ReportPoint& p, const BendingLength& bending_length, const FabricColour& fabric_colour,
                               ReportPlots& plots);

/// The PNG files the done points' manifests list, inlined (`png`: a point's file's bytes).
std::string gallery(const std::vector<ReportPoint>& points, const std::function<std::string(const ReportPoint&, const std::string&)>& png);

}  // namespace woven::render
