// The report job (report.hpp).
#include "woven/app/report.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "woven/analysis/drape_shadow.hpp"
#include "woven/app/check.hpp"
#include "woven/app/files.hpp"
#include "woven/app/sweep.hpp"
#include "woven/common/error.hpp"
#include "woven/io/fabric_file.hpp"
#include "woven/io/mesh_file.hpp"
#include "woven/io/output_file.hpp"
#include "woven/io/sha256.hpp"
#include "woven/kes/curve.hpp"
#include "woven/kes/fit.hpp"
#include "woven/render/gltf_file.hpp"
#include "woven/render/html_page.hpp"

namespace woven::app {

namespace {

namespace fs = std::filesystem;

/// glb bytes a page may inline (the 3-D view's points beyond it are counted, not shown).
constexpr std::size_t kMeshBudget = 24u << 20;

/// One point of the page: a sweep's row, or the one folder.
struct PointView {
    std::string name;
    fs::path dir;
    std::string status = "done";
    nlohmann::json values = nlohmann::json::object();
    nlohmann::json outputs = nlohmann::json::object();
    nlohmann::json manifest;
    std::optional<double> wall;
    std::string problem;
};

nlohmann::json read_json(const fs::path& p, const std::string& what, std::size_t limit = io::kMaxManifestBytes)
{
    return io::read_output_json(p.string(), limit, what);
}

std::string manifest_name(const fs::path& dir)
{
    for (const char* m : kManifests)
        if (fs::exists(dir / m)) return m;
    return {};
}

/// The folder must verify as woven check verifies it.
void verify(const fs::path& dir, const std::string& why)
{
    const auto problems = check_output_folder(dir.string());
    if (!problems.empty()) throw InputError(dir.string(), "", why + problems.front());
}

std::string cell(const nlohmann::json& v)
{
    if (v.is_null()) return "";
    if (v.is_string()) return v.get<std::string>();
    if (v.is_number_float()) {
        char b[32];
        std::snprintf(b, sizeof b, "%.6g", v.get<double>());
        return b;
    }
    return v.dump();
}

/// The mean of the warp and weft bending lengths c = (B / W)^(1/3), cm (Peirce; B in gf.cm2/cm,
/// W in gf/cm2); nullopt when the fabric cannot be read.
std::optional<double> bending_length_cm(const std::string& fabric)
{
    try {
        const kes::FabricData f = io::find_fabric(fabric);
        const double w = f.areal_density_mg_cm2 * 1e-3;
        const auto b = [](const kes::Measured<kes::BendingSummary>& m) {
            return m.summary ? m.summary->B : kes::data_slope(m.curve, kes::instrument::kBendingSlopeFrom, kes::instrument::kBendingSlopeTo);
        };
        if (!(w > 0)) return std::nullopt;
        return 0.5 * (std::cbrt(b(f.bending_warp) / w) + std::cbrt(b(f.bending_weft) / w));
    } catch (const std::exception&) {
        return std::nullopt;
    }
}

std::array<float, 3> fabric_colour(const std::string& fabric)
{
    try {
        const kes::FabricData f = io::find_fabric(fabric);
        if (f.color) return {static_cast<float>((*f.color)[0]), static_cast<float>((*f.color)[1]), static_cast<float>((*f.color)[2])};
    } catch (const std::exception&) {
    }
    return {0.70f, 0.28f, 0.16f};
}

/// The point's scene for the 3-D view: drape.glb or cusick.glb as written; for a folder from
/// before them, its drape.obj or cusick.obj as the cloth alone.
std::optional<render::ViewModel> view_model(const PointView& p)
{
    for (const char* name : {"drape.glb", "cusick.glb", "drape.obj", "cusick.obj"}) {
        if (!fs::exists(p.dir / name)) continue;
        render::ViewModel v;
        v.name = p.name;
        if (std::string(name).ends_with(".obj")) {
            render::GltfMesh cloth;
            cloth.name = "cloth";
            cloth.mesh = io::load_obj_mesh((p.dir / name).string());
            cloth.double_sided = true;
            v.glb = render::scene_glb({cloth});
        } else {
            v.glb = read_output_file((p.dir / name).string()).value_or("");
        }
        if (v.glb.empty()) continue;
        const std::string fabric = p.values.contains("fabric") && p.values["fabric"].is_string() ? p.values["fabric"].get<std::string>()
                                   : p.manifest.contains("fabric") && p.manifest["fabric"].is_string() ? p.manifest["fabric"].get<std::string>()
                                                                                                       : "";
        v.colour = fabric_colour(fabric);
        return v;
    }
    return std::nullopt;
}

/// The main number of a command's points, and its label.
std::pair<std::string, std::string> main_output(const std::string& command)
{
    if (command == "cusick") return {"drape_coefficient_percent", "drape coefficient, %"};
    if (command == "drape") return {"energy_J", "energy at rest, J"};
    return {"worst_summary_rel_error", "largest relative error of a KES summary value"};
}

double number_of(const nlohmann::json& v)
{
    if (v.is_number()) return v.get<double>();
    return std::nan("");
}

/// Mean and sample standard deviation.
std::pair<double, double> mean_std(const std::vector<double>& v)
{
    double m = 0;
    for (double x : v) m += x / static_cast<double>(v.size());
    double s = 0;
    for (double x : v) s += (x - m) * (x - m);
    return {m, v.size() > 1 ? std::sqrt(s / static_cast<double>(v.size() - 1)) : 0.0};
}

/// y against x over the done points, one series per combination of the axes other than the x
/// axis and `seed`; the points that share x in a series (seeds) become mean +- std.
render::Plot grouped_plot(const std::vector<PointView>& points, const std::vector<std::string>& axes, const std::string& x_axis,
                          const std::function<double(const PointView&)>& x_of, const std::function<double(const PointView&)>& y_of,
                          render::Plot plot)
{
    std::map<std::string, std::map<double, std::vector<double>>> groups;
    for (const auto& p : points) {
        if (p.status != "done") continue;
        const double x = x_of(p), y = y_of(p);
        if (!std::isfinite(x) || !std::isfinite(y)) continue;
        std::string key;
        for (const auto& a : axes)
            if (a != x_axis && a != "seed" && p.values.contains(a)) key += (key.empty() ? "" : ", ") + a + " " + cell(p.values[a]);
        groups[key.empty() ? "all points" : key][x].push_back(y);
    }
    for (const auto& [name, by_x] : groups) {
        render::Series s;
        s.label = name;
        s.style = render::Series::Style::LINE_AND_POINTS;
        for (const auto& [x, ys] : by_x) {
            const auto [m, sd] = mean_std(ys);
            s.x.push_back(x);
            s.y.push_back(m);
            s.err.push_back(sd);
        }
        plot.series.push_back(std::move(s));
    }
    return plot;
}

/// The page's plots, numbered in order ("plot-1", ...).
struct Plots {
    std::string html;
    int count = 0;
    void add(const render::Plot& p, int width = 680, int height = 420) { html += render::html_plot(p, "plot-" + std::to_string(++count), width, height); }
};

/// A CSV file of numbers with a header (a column of text reads as NaN).
struct Csv {
    std::vector<std::string> head;
    std::vector<std::vector<double>> cols;
    std::vector<std::vector<std::string>> text;  ///< the cells as written, per column
    int col(const std::string& name) const
    {
        for (std::size_t k = 0; k < head.size(); ++k)
            if (head[k] == name) return static_cast<int>(k);
        return -1;
    }
    std::vector<double> get(const std::string& name) const { return col(name) < 0 ? std::vector<double>{} : cols[static_cast<std::size_t>(col(name))]; }
};

std::optional<Csv> read_csv(const fs::path& file)
{
    if (!fs::exists(file)) return std::nullopt;
    std::istringstream in(read_output_file(file.string()).value_or(""));
    std::string line;
    if (!std::getline(in, line)) return std::nullopt;
    Csv c;
    std::istringstream h(line);
    for (std::string f; std::getline(h, f, ',');) c.head.push_back(f);
    c.cols.resize(c.head.size());
    c.text.resize(c.head.size());
    while (std::getline(in, line)) {
        std::istringstream r(line);
        std::vector<std::string> v;
        for (std::string f; std::getline(r, f, ',');) v.push_back(f);
        if (v.size() != c.head.size()) continue;
        for (std::size_t k = 0; k < v.size(); ++k) {
            char* end = nullptr;
            const double x = std::strtod(v[k].c_str(), &end);
            c.cols[k].push_back(!v[k].empty() && end && *end == 0 ? x : std::nan(""));
            c.text[k].push_back(v[k]);
        }
    }
    return c;
}

render::Series series(std::vector<double> x, std::vector<double> y, render::Series::Style style, std::optional<Vec3> colour, std::string label)
{
    render::Series s;
    s.x = std::move(x);
    s.y = std::move(y);
    s.style = style;
    s.color = colour;
    s.label = std::move(label);
    return s;
}

// tab10's first colours: input (data) in blue and green, simulated in orange and red.
const Vec3 kBlue(0.122, 0.467, 0.706), kOrange(1.000, 0.498, 0.055), kGreen(0.173, 0.627, 0.173), kRed(0.839, 0.153, 0.157),
    kGrey(0.5, 0.5, 0.5), kLight(0.78, 0.78, 0.78);

/// A kes-test folder: the moment-curvature and force-angle loops (the whole loop where the run
/// wrote one, else the loading curve), input as lines and simulated as dots, each labelled
/// once; the cantilever's deflected shape (x, z) against the elastica. The titles start with
/// `title_prefix` (a sweep's point).
void kes_section(const PointView& p, Plots& plots, const std::string& title_prefix)
{
    const std::string dirs[2] = {"warp", "weft"};
    struct Test {
        std::string name, x, y, title, x_label, y_label;
    };
    const Test tests[2] = {{"bending", "K_per_cm", "M_gf_cm_per_cm", "KES-FB2 bending: moment against curvature", "curvature K, 1/cm",
                            "moment M, gf.cm/cm"},
                           {"shear", "phi_deg", "F_gf_per_cm", "KES-FB1 shear: force against shear angle", "shear angle phi, deg",
                            "force F, gf/cm"}};
    for (const Test& t : tests) {
        render::Plot plot;
        plot.title = title_prefix + t.title;
        plot.x_label = t.x_label;
        plot.y_label = t.y_label;
        std::vector<std::pair<std::vector<double>, std::vector<double>>> inputs;
        std::vector<render::Series> input_series, sim_series;
        for (int d = 0; d < 2; ++d) {
            auto c = read_csv(p.dir / (t.name + "_loop_" + dirs[d] + ".csv"));
            if (!c) c = read_csv(p.dir / (t.name + "_" + dirs[d] + ".csv"));
            if (!c || c->col(t.x) < 0 || c->col("simulated_" + t.y) < 0 || c->col("input_" + t.y) < 0) continue;
            const auto x = c->get(t.x), in = c->get("input_" + t.y), sim = c->get("simulated_" + t.y);
            if (std::find(inputs.begin(), inputs.end(), std::make_pair(x, in)) == inputs.end()) {
                inputs.emplace_back(x, in);
                input_series.push_back(series(x, in, render::Series::Style::LINE, d ? kGreen : kBlue, "input " + dirs[d]));
            }
            sim_series.push_back(series(x, sim, render::Series::Style::POINTS, d ? kRed : kOrange, "simulated " + dirs[d]));
        }
        if (sim_series.empty()) continue;
        if (input_series.size() == 1) input_series[0].label = "input";  // one input curve for both directions
        for (auto& s : input_series) plot.series.push_back(std::move(s));
        for (auto& s : sim_series) plot.series.push_back(std::move(s));
        plots.add(plot);
    }
    render::Plot shape;
    shape.title = title_prefix + "Cantilever: deflected shape against the elastica";
    shape.x_label = "x, m";
    shape.y_label = "z, m";
    shape.equal_aspect = true;
    for (int d = 0; d < 2; ++d) {
        const auto c = read_csv(p.dir / ("cantilever_" + dirs[d] + ".csv"));
        if (!c || c->col("source") < 0 || c->col("x_m") < 0 || c->col("z_m") < 0) continue;
        const auto& source = c->text[static_cast<std::size_t>(c->col("source"))];
        const auto x = c->get("x_m"), z = c->get("z_m");
        std::vector<double> sx, sz, ex, ez;
        for (std::size_t k = 0; k < source.size(); ++k) {
            (source[k] == "simulated" ? sx : ex).push_back(x[k]);
            (source[k] == "simulated" ? sz : ez).push_back(z[k]);
        }
        shape.series.insert(shape.series.begin() + d, series(ex, ez, render::Series::Style::LINE, d ? kGreen : kBlue, "elastica " + dirs[d]));
        shape.series.push_back(series(sx, sz, render::Series::Style::POINTS, d ? kRed : kOrange, "simulated " + dirs[d]));
    }
    if (!shape.series.empty()) plots.add(shape, 680, 420);
}

std::string number_cell(const nlohmann::json& v) { return v.is_number() ? cell(nlohmann::json(v.get<double>())) : cell(v); }

/// A two-column table of the object's numbers (nested objects flattened with '.').
render::HtmlTable key_table(const nlohmann::json& j, const std::string& prefix = "")
{
    render::HtmlTable t;
    t.header = {"quantity", "value"};
    t.numeric = {false, true};
    std::function<void(const nlohmann::json&, const std::string&)> walk = [&](const nlohmann::json& o, const std::string& at) {
        for (auto it = o.begin(); it != o.end(); ++it) {
            const std::string k = at.empty() ? it.key() : at + "." + it.key();
            if (it->is_object())
                walk(*it, k);
            else if (it->is_number() || it->is_boolean() || it->is_string())
                t.rows.push_back({k, number_cell(*it)});
        }
    };
    walk(j, prefix);
    return t;
}

/// A drape folder: its energies and the corner folds.
std::string drape_section(const PointView& p)
{
    std::ostringstream o;
    const auto& m = p.manifest;
    o << "<h2>Energy</h2>";
    render::HtmlTable e;
    e.header = {"term", "energy, J"};
    e.numeric = {false, true};
    if (m.contains("energy") && m["energy"].is_object())
        for (auto it = m["energy"].begin(); it != m["energy"].end(); ++it)
            if (it->is_number()) e.rows.push_back({it.key(), number_cell(*it)});
    if (m.contains("energy_initial_J") && m["energy_initial_J"].is_number()) e.rows.push_back({"energy_initial_J", number_cell(m["energy_initial_J"])});
    o << render::html_table(e, "energy");
    if (m.contains("folds") && m["folds"].is_object()) {
        const auto& f = m["folds"];
        o << "<h2>Folds</h2><p class=\"note\">The billows leaving each corner of the box on horizontal sections (angles from the "
             "corner's diagonal, deg; standout from the box, m).</p>";
        render::HtmlTable t;
        t.header = {"corner", "section height, m", "billows", "structure", "angles, deg", "standout, m"};
        t.numeric = {true, true, true, false, false, false};
        const auto heights = f.value("heights_m", nlohmann::json::array());
        for (const auto& c : f.value("corners", nlohmann::json::array())) {
            const auto billows = c.value("billows", nlohmann::json::array());
            for (std::size_t h = 0; h < billows.size(); ++h) {
                const auto at = [&](const char* key) {
                    const auto v = c.value(key, nlohmann::json::array());
                    return h < v.size() ? v[h] : nlohmann::json();
                };
                std::string angles, standout;
                for (const auto& a : at("angles_deg")) angles += (angles.empty() ? "" : " ") + cell(nlohmann::json(a.get<double>()));
                for (const auto& s : at("standout_m")) standout += (standout.empty() ? "" : " ") + cell(nlohmann::json(s.get<double>()));
                t.rows.push_back({cell(c.value("corner", nlohmann::json())), h < heights.size() ? number_cell(heights[h]) : "", cell(billows[h]),
                                  cell(at("structure")), angles, standout});
            }
        }
        o << render::html_table(t, "folds");
        nlohmann::json rest = nlohmann::json::object();
        for (const char* k : {"hanging_m", "lowest_point_m", "projected_area_m2"})
            if (f.contains(k)) rest[k] = f[k];
        render::HtmlTable r = key_table(rest);
        for (auto& row : r.rows) row[0] = "folds." + row[0];
        for (const char* k : {"hanging_m", "lowest_point_m"})
            if (rest.contains(k) && rest[k].is_array()) {
                std::string v;
                for (const auto& x : rest[k]) v += (v.empty() ? "" : " ") + number_cell(x);
                r.rows.push_back({std::string("folds.") + k, v});
            }
        o << render::html_table(r, "folds-other");
    }
    return o.str();
}

/// A cusick folder: the shadow's outline r(theta) from cusick.obj (seen from above, warp up)
/// with the nodes of cusick.json marked, the disc and the flat specimen; DC and the nodes.
std::string cusick_section(const PointView& p, Plots& plots)
{
    const auto& m = p.manifest;
    std::ostringstream o;
    o << "<h2>Drape coefficient and nodes</h2>";
    render::HtmlTable t;
    t.header = {"quantity", "value"};
    t.numeric = {false, true};
    for (const char* k : {"drape_coefficient_percent", "nodes", "specimen_diameter_m", "disc_diameter_m", "spacing_m", "particles"})
        if (m.contains(k)) t.rows.push_back({k, number_cell(m[k])});
    o << render::html_table(t, "cusick");
    render::HtmlTable n;
    n.header = {"node", "angle from warp, deg", "radius, m", "depth, m"};
    n.numeric = {true, true, true, true};
    // The prediction's nodes; their radii are its run's (the run whose node angles they are).
    const auto angles = m.value("node_angles_deg", nlohmann::json::array()), depths = m.value("node_depths_m", nlohmann::json::array());
    nlohmann::json radii = m.value("node_radii_m", nlohmann::json::array());
    for (const auto& r : m.value("runs", nlohmann::json::array()))
        if (radii.empty() && r.is_object() && r.value("node_angles_deg", nlohmann::json()) == angles) radii = r.value("node_radii_m", nlohmann::json::array());
    render::Series nodes = series({}, {}, render::Series::Style::POINTS, kRed, "nodes");
    for (std::size_t k = 0; k < angles.size() && k < radii.size(); ++k) {
        const double a = number_of(angles[k]) * M_PI / 180, r = number_of(radii[k]);
        nodes.x.push_back(r * std::sin(a));
        nodes.y.push_back(r * std::cos(a));
        n.rows.push_back({std::to_string(k + 1), number_cell(angles[k]), number_cell(radii[k]), k < depths.size() ? number_cell(depths[k]) : ""});
    }
    o << render::html_table(n, "nodes");
    render::Plot plot;
    plot.title = "Shadow seen from above (warp up), DC " + cell(m.value("drape_coefficient_percent", nlohmann::json())) + " %";
    plot.x_label = "x (weft), m";
    plot.y_label = "y (warp), m";
    plot.equal_aspect = true;
    const auto circle = [](double r, const Vec3& c, const std::string& label) {
        render::Series s = series({}, {}, render::Series::Style::LINE, c, label);
        for (int k = 0; k <= 360; k += 2) {
            s.x.push_back(r * std::sin(k * M_PI / 180));
            s.y.push_back(r * std::cos(k * M_PI / 180));
        }
        return s;
    };
    if (m.contains("specimen_diameter_m")) plot.series.push_back(circle(0.5 * number_of(m["specimen_diameter_m"]), kLight, "flat specimen"));
    if (m.contains("disc_diameter_m")) plot.series.push_back(circle(0.5 * number_of(m["disc_diameter_m"]), kGrey, "support disc"));
    if (fs::exists(p.dir / "cusick.obj")) {
        const geometry::TriangleMesh mesh = io::load_obj_mesh((p.dir / "cusick.obj").string());
        const int count = 720;
        const std::vector<double> r = analysis::shadow_radius(mesh, Vec2::Zero(), count);
        render::Series s = series({}, {}, render::Series::Style::LINE, kBlue, "shadow outline");
        for (int k = 0; k <= count; ++k) {
            const double a = 2 * M_PI * (k % count) / count;
            s.x.push_back(r[static_cast<std::size_t>(k % count)] * std::sin(a));
            s.y.push_back(r[static_cast<std::size_t>(k % count)] * std::cos(a));
        }
        plot.series.push_back(std::move(s));
    }
    plot.series.push_back(std::move(nodes));
    plots.add(plot, 600, 600);
    return o.str();
}

/// A fit folder (`woven fit`): the KES curves with their fits (the fabric fitted again, as
/// `fit` does) and the energy functions of its CSV files.
void fit_section(const PointView& p, Plots& plots, std::string& notes)
{
    // fabric_source: "built-in fabric 'NAME'" or the file's path.
    std::string source = p.manifest.value("fabric_source", std::string());
    if (source.empty() || source.rfind("built-in fabric '", 0) == 0) source = p.manifest.value("fabric", std::string());
    try {
        const kes::FabricData fabric = io::find_fabric(source);
        const kes::FittedFabric fit = kes::fit_fabric(fabric);
        struct C {
            const char* title;
            const kes::Curve* data;
            const kes::CurveFit* fit;
            const char *x, *y;
        };
        const C curves[] = {{"Bending, warp: KES curve and fit", &fabric.bending_warp.curve, &fit.bending_warp, "curvature K, 1/cm", "moment M, gf.cm/cm"},
                            {"Bending, weft: KES curve and fit", &fabric.bending_weft.curve, &fit.bending_weft, "curvature K, 1/cm", "moment M, gf.cm/cm"},
                            {"Shear: KES curve and fit", &fabric.shear.curve, &fit.shear, "shear angle, deg", "force F, gf/cm"}};
        for (const C& c : curves) {
            render::Plot plot;
            plot.title = c.title;
            plot.x_label = c.x;
            plot.y_label = c.y;
            plot.series.push_back(series(c.data->x, c.data->y, render::Series::Style::POINTS, Vec3(0.2, 0.2, 0.2), "KES data"));
            render::Series f = series({}, {}, render::Series::Style::LINE, kBlue, "fit (Sec. 5.1)");
            const double hi = std::max(c.fit->data_max_x(), c.data->x.empty() ? 0.0 : c.data->x.back());
            for (int k = 0; k <= 200; ++k) {
                f.x.push_back(hi * k / 200);
                f.y.push_back(c.fit->value(hi * k / 200));
            }
            plot.series.push_back(std::move(f));
            plots.add(plot);
        }
    } catch (const std::exception& e) {
        notes += "<p class=\"note\">The fabric " + render::html_escape(source) + " could not be read again for its fitted curves: " +
                 render::html_escape(e.what()) + "</p>";
    }
    render::Plot bending;
    bending.title = "Bending energy of one thread angle, B(theta)";
    bending.x_label = "thread angle theta, rad (pi: straight)";
    bending.y_label = "B, J";
    for (int d = 0; d < 2; ++d) {
        const std::string dir = d ? "weft" : "warp";
        if (const auto c = read_csv(p.dir / ("bending_" + dir + "_energy.csv")))
            bending.series.push_back(series(c->get("theta_rad"), c->get("B_J"), render::Series::Style::LINE, d ? kOrange : kBlue, dir));
    }
    if (!bending.series.empty()) plots.add(bending);
    if (const auto c = read_csv(p.dir / "trellis_energy.csv")) {
        render::Plot trellis;
        trellis.title = "Trellis energy of one crossing, T(phi) (singular at 1.05 rad)";
        trellis.x_label = "trellis angle phi, rad";
        trellis.y_label = "T, J";
        const auto phi = c->get("phi_rad"), T = c->get("T_J");
        for (std::size_t k = 0; k < phi.size(); ++k)
            if (phi[k] >= 0.95 && std::isfinite(T[k]) && T[k] > 0) {
                trellis.y_max = T[k];  // the singular end clipped, as fit's plot does
                break;
            }
        trellis.series.push_back(series(phi, T, render::Series::Style::LINE, kBlue, "T(phi)"));
        plots.add(trellis);
    }
}

std::string gallery(const std::vector<PointView>& points)
{
    std::ostringstream o;
    o << "<div class=\"gallery\">";
    for (const auto& p : points) {
        if (p.status != "done") continue;
        std::vector<std::string> pngs;
        const auto listed = [&pngs](const nlohmann::json& m) {
            if (!m.is_object() || !m.contains("files")) return;
            const auto& f = m["files"];
            if (f.is_object())
                for (auto it = f.begin(); it != f.end(); ++it) pngs.push_back(it.key());
            else if (f.is_array())
                for (const auto& n : f)
                    if (n.is_string()) pngs.push_back(n.get<std::string>());
        };
        listed(p.manifest);
        if (p.manifest.is_object() && !p.manifest.contains("files"))  // an experiment: one manifest per set
            for (const auto& m : p.manifest) listed(m);
        for (const auto& n : pngs) {
            if (!n.ends_with(".png")) continue;
            o << "<figure><img alt=\"" << render::html_escape(p.name + " " + n) << "\" src=\"data:image/png;base64,"
              << render::base64(read_output_file((p.dir / n).string()).value_or("")) << "\"><figcaption>" << render::html_escape(p.name + ": " + n) << "</figcaption></figure>";
        }
    }
    o << "</div>";
    return o.str();
}

std::string folder_name(const fs::path& dir)
{
    std::string n = fs::absolute(dir).lexically_normal().filename().string();
    if (n.empty()) n = fs::absolute(dir).lexically_normal().parent_path().filename().string();
    return n;
}

/// The experiments' manifests in `dir` (cmd_experiment.cpp; the three may share a folder).
std::vector<std::string> experiment_manifests(const fs::path& dir)
{
    std::vector<std::string> found;
    for (const char* m : {"cube_results.json", "corner_map.json", "figure1.json"})
        if (fs::exists(dir / m)) found.push_back(m);
    return found;
}

/// An experiment's set verifies: each file its manifest lists is there with its size and SHA-256.
void verify_set(const fs::path& dir, const std::string& manifest)
{
    const nlohmann::json j = read_json(dir / manifest, "an experiment's manifest");
    if (!j.is_object() || !j.contains("files") || !j["files"].is_object())
        throw InputError((dir / manifest).string(), "files", "expected the list of the set's files with their sizes and SHA-256");
    for (auto it = j["files"].begin(); it != j["files"].end(); ++it) {
        const auto data = read_output_file((dir / it.key()).string());
        const std::string where = (dir / it.key()).string();
        if (!data) throw InputError(where, "", "listed in " + manifest + " but cannot be read (the folder does not verify)");
        if (!it->is_object() || it->value("sha256", std::string()) != io::sha256_hex(*data))
            throw InputError(where, "sha256", "differs from " + manifest + "'s (the folder does not verify)");
    }
}

/// An experiment folder: cube_results.json's statistics per fabric and its runs' energy and
/// projected area against the fabric's bending length (mean +- std over the seeds); the other
/// experiments' manifests as tables of their numbers.
std::string experiment_section(const PointView& p, Plots& plots)
{
    std::ostringstream o;
    for (auto it = p.manifest.begin(); it != p.manifest.end(); ++it) {
        const nlohmann::json& j = it.value();
        o << "<h2>" << render::html_escape(it.key()) << "</h2>";
        const std::string id = "experiment-" + std::to_string(std::distance(p.manifest.begin(), it));
        nlohmann::json top = nlohmann::json::object();
        for (auto k = j.begin(); k != j.end(); ++k)
            if (!k->is_structured()) top[k.key()] = *k;
        o << render::html_table(key_table(top), id);
        // Its lists of records (runs, cells): one row each, a column per number or word.
        for (auto k = j.begin(); k != j.end(); ++k) {
            if (!k->is_array() || k->empty() || !(*k)[0].is_object()) continue;
            render::HtmlTable t;
            std::vector<std::string> keys;
            for (const auto& r : *k)
                for (auto c = r.begin(); c != r.end(); ++c)
                    if (!c->is_structured() && std::find(keys.begin(), keys.end(), c.key()) == keys.end()) keys.push_back(c.key());
            t.header = keys;
            for (const auto& key : keys) {
                bool numeric = true;
                for (const auto& r : *k) numeric = numeric && (!r.contains(key) || r[key].is_number());
                t.numeric.push_back(numeric);
            }
            for (const auto& r : *k) {
                std::vector<std::string> row;
                for (const auto& key : keys) row.push_back(r.contains(key) ? number_cell(r[key]) : "");
                t.rows.push_back(std::move(row));
            }
            o << "<h3>" << render::html_escape(k.key()) << "</h3>" << render::html_table(t, id + "-" + k.key());
        }
        if (it.key() != "cube_results.json") continue;
        render::HtmlTable t;
        t.header = {"fabric", "corners", "single_diagonal", "single_offset", "multiple", "none", "distinct_drapes"};
        t.numeric = {false, true, true, true, true, true, true};
        const nlohmann::json stats = j.value("statistics", nlohmann::json::object());
        for (auto f = stats.begin(); f != stats.end(); ++f) {
            std::vector<std::string> row{f.key()};
            for (std::size_t c = 1; c < t.header.size(); ++c) row.push_back(cell(f->value(t.header[c], nlohmann::json())));
            t.rows.push_back(std::move(row));
        }
        o << "<p class=\"note\">How often each corner structure appears (counts over seeds and corners).</p>" << render::html_table(t, "statistics");
        // Per fabric: its bending length, and mean +- std of each quantity over its seeds.
        std::map<std::string, std::vector<const nlohmann::json*>> runs;
        const nlohmann::json all_runs = j.value("runs", nlohmann::json::array());
        for (const auto& r : all_runs)
            if (r.is_object() && r.contains("fabric") && r["fabric"].is_string()) runs[r["fabric"].get<std::string>()].push_back(&r);
        struct Q {
            const char* title;
            const char* label;
            std::function<double(const nlohmann::json&)> of;
        };
        const Q qs[] = {{"Energy at rest against the fabric's bending length", "energy at rest, J",
                         [](const nlohmann::json& r) { return number_of(r.value("energy_J", nlohmann::json())); }},
                        {"Projected area against the fabric's bending length", "projected area, m^2", [](const nlohmann::json& r) {
                             return r.contains("folds") && r["folds"].is_object() ? number_of(r["folds"].value("projected_area_m2", nlohmann::json()))
                                                                                   : std::nan("");
                         }}};
        for (const Q& q : qs) {
            render::Plot plot;
            plot.title = q.title;
            plot.x_label = "bending length (B / W)^(1/3), mean of warp and weft, cm";
            plot.y_label = q.label;
            for (const auto& [fabric, rs] : runs) {
                std::vector<double> ys;
                for (const auto* r : rs)
                    if (std::isfinite(q.of(*r))) ys.push_back(q.of(*r));
                const double x = bending_length_cm(fabric).value_or(std::nan(""));
                if (ys.empty() || !std::isfinite(x)) continue;
                const auto [m, sd] = mean_std(ys);
                render::Series s = series({x}, {m}, render::Series::Style::POINTS, std::nullopt, fabric + " (" + std::to_string(ys.size()) + (ys.size() == 1 ? " seed)" : " seeds)"));
                s.err = {sd};
                plot.series.push_back(std::move(s));
            }
            if (!plot.series.empty()) plots.add(plot);
        }
    }
    return o.str();
}

/// What a report is made of: the folder's points, the table's axes and output columns, the
/// command that made them, the page's title and summary.
struct ReportFolder {
    std::vector<PointView> points;
    std::vector<std::string> axes, columns;
    std::string command, title, summary;
    bool is_sweep = false;
};

/// A sweep folder: a point per row of sweep.json, each point listed as done verified.
ReportFolder read_sweep(const fs::path& dir)
{
    ReportFolder f;
    f.is_sweep = true;
    const nlohmann::json s = read_json(dir / "sweep.json", "a sweep's merged table", io::kMaxSweepTableBytes);
    if (!s.is_object() || !s.contains("rows") || !s["rows"].is_array() || !s.contains("command") || !s["command"].is_string())
        throw InputError((dir / "sweep.json").string(), "rows", "expected the merged table of `woven sweep` (command, axes, rows)");
    f.command = s["command"].get<std::string>();
    for (const auto& a : s.value("axes", nlohmann::json::array())) f.axes.push_back(a.value("key", std::string()));
    for (const auto& c : s.value("output_columns", nlohmann::json::array())) f.columns.push_back(c.get<std::string>());
    f.title = "woven sweep " + s.value("name", std::string());
    const std::string d = s.value("description", std::string());
    f.summary = (d.empty() ? "" : d + ". ") + "woven " + f.command + " at " + std::to_string(s["rows"].size()) + " points: " +
              cell(s.value("done", nlohmann::json(0))) + " done, " + cell(s.value("failed", nlohmann::json(0))) + " failed, " +
              cell(s.value("missing", nlohmann::json(0))) + " missing. Plan " + s.value("plan", std::string()) + ".";
    for (const auto& r : s["rows"]) {
        PointView p;
        p.name = r.value("point", std::string());
        if (p.name.empty() || p.name.find('/') != std::string::npos || p.name[0] == '.')
            throw InputError((dir / "sweep.json").string(), "rows", "expected point folder names, got '" + p.name + "'");
        p.dir = dir / p.name;
        p.status = r.value("status", std::string("missing"));
        p.values = r.value("values", nlohmann::json::object());
        p.outputs = r.value("outputs", nlohmann::json::object());
        if (r.contains("wall_time_s") && r["wall_time_s"].is_number()) p.wall = r["wall_time_s"].get<double>();
        p.problem = r.value("problem", std::string());
        if (p.status == "done") {
            verify(p.dir, "listed as done in sweep.json but does not verify (run `woven sweep PLAN --merge` again): ");
            p.manifest = read_json(p.dir / manifest_name(p.dir), "a manifest");
        }
        f.points.push_back(std::move(p));
    }
    return f;
}

/// An experiment's output folder: one point, each of its sets verified.
ReportFolder read_experiment(const fs::path& dir, const std::vector<std::string>& ex)
{
    ReportFolder f;
    f.command = "experiment";
    PointView p;
    p.dir = dir;
    p.name = folder_name(dir);
    for (const auto& m : ex) {
        verify_set(dir, m);
        p.manifest[m] = read_json(dir / m, "an experiment's manifest");
    }
    f.title = "woven experiment " + p.name;
    f.summary = "The output folder " + dir.string() + " of woven experiment (" + [&] {
        std::string l;
        for (const auto& m : ex) l += (l.empty() ? "" : ", ") + m;
        return l;
    }() + ").";
    f.points.push_back(std::move(p));
    return f;
}

/// An output folder of drape, cusick, kes-test or fit: one point, its set verified.
ReportFolder read_output(const fs::path& dir, const std::string& name)
{
    ReportFolder f;
    const std::string m = manifest_name(dir);
    if (m.empty())
        throw InputError(name, "",
                         "expected a sweep folder (sweep.json), an output folder of drape, cusick, kes-test or fit (report.json, "
                         "cusick.json or kes-report.json) or of an experiment (cube_results.json, corner_map.json, figure1.json)");
    verify(dir, "the output folder does not verify: ");
    PointView p;
    p.manifest = read_json(dir / m, "a manifest");
    f.command = m == "cusick.json" ? "cusick" : m == "kes-report.json" ? "kes-test" : p.manifest.value("command", std::string("drape"));
    if (f.command != "drape" && f.command != "cusick" && f.command != "kes-test" && f.command != "fit")
        throw InputError((dir / m).string(), "command", "expected the output of drape, cusick, kes-test or fit, got " + f.command);
    p.name = folder_name(dir);
    p.dir = dir;
    if (p.manifest.contains("wall_time_s") && p.manifest["wall_time_s"].is_number()) p.wall = p.manifest["wall_time_s"].get<double>();
    if (p.manifest.contains("fabric")) p.values["fabric"] = p.manifest["fabric"];
    if (p.manifest.contains("scene")) p.values["scene"] = p.manifest["scene"];
    p.outputs = f.command == "fit" ? nlohmann::json::object() : point_outputs(f.command, p.manifest);
    for (auto it = p.outputs.begin(); it != p.outputs.end(); ++it) f.columns.push_back(it.key());
    for (auto it = p.values.begin(); it != p.values.end(); ++it) f.axes.push_back(it.key());
    f.title = "woven " + f.command + " " + p.name;
    f.summary = "The output folder " + dir.string() + " of woven " + f.command + " (version " + p.manifest.value("version", std::string("?")) + ").";
    f.points.push_back(std::move(p));
    return f;
}

/// The folder read and verified (InputError naming what is wrong; nothing is written then).
ReportFolder read_report_folder(const fs::path& dir, const std::string& name)
{
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) throw InputError(name, "", "no such folder");
    if (fs::exists(dir / "sweep.json")) return read_sweep(dir);
    if (const std::vector<std::string> ex = experiment_manifests(dir); manifest_name(dir).empty() && !ex.empty()) return read_experiment(dir, ex);
    return read_output(dir, name);
}

/// The points' table: a row each, the axes' values, status, wall time and the main outputs.
render::HtmlTable points_table(const ReportFolder& f)
{
    render::HtmlTable t;
    t.header = {"point"};
    t.numeric = {false};
    for (const auto& a : f.axes) {
        t.header.push_back(a);
        bool numeric = true;
        for (const auto& p : f.points) numeric = numeric && (!p.values.contains(a) || p.values[a].is_number());
        t.numeric.push_back(numeric);
    }
    t.header.push_back("status");
    t.numeric.push_back(false);
    t.header.push_back("wall_time_s");
    t.numeric.push_back(true);
    for (const auto& c : f.columns) {
        t.header.push_back(c);
        bool numeric = true;
        for (const auto& p : f.points) numeric = numeric && (!p.outputs.contains(c) || p.outputs[c].is_number() || p.outputs[c].is_null());
        t.numeric.push_back(numeric);
    }
    for (const auto& p : f.points) {
        std::vector<std::string> row{p.name};
        for (const auto& a : f.axes) row.push_back(p.values.contains(a) ? cell(p.values[a]) : "");
        row.push_back(p.status + (p.problem.empty() ? "" : ": " + p.problem));
        row.push_back(p.wall ? cell(*p.wall) : "");
        for (const auto& c : f.columns) row.push_back(p.outputs.contains(c) ? cell(p.outputs[c]) : "");
        t.rows.push_back(std::move(row));
        t.row_class.push_back(p.status == "done" ? "" : p.status);
    }
    return t;
}

/// A sweep's plots: its main output against the fabric's bending length or its first numeric
/// axis, and the wall time against the particles when they vary.
void sweep_plots(const ReportFolder& f, Plots& plots)
{
    const auto [key, label] = main_output(f.command);
    const auto y_main = [key = key](const PointView& p) { return p.outputs.contains(key) ? number_of(p.outputs[key]) : std::nan(""); };
    std::string x_axis;
    std::function<double(const PointView&)> x_of;
    std::string x_label;
    if (std::find(f.axes.begin(), f.axes.end(), "fabric") != f.axes.end()) {
        auto cache = std::make_shared<std::map<std::string, double>>();
        x_axis = "fabric";
        x_label = "bending length (B / W)^(1/3), mean of warp and weft, cm";
        x_of = [cache](const PointView& p) {
            const std::string fabric = p.values.value("fabric", std::string());
            if (!cache->count(fabric)) (*cache)[fabric] = bending_length_cm(fabric).value_or(std::nan(""));
            return (*cache)[fabric];
        };
    } else {
        for (const auto& a : f.axes)
            if (a != "seed" && !f.points.empty() && f.points[0].values.contains(a) && f.points[0].values[a].is_number()) {
                x_axis = a;
                x_label = a;
                x_of = [a](const PointView& p) { return p.values.contains(a) ? number_of(p.values[a]) : std::nan(""); };
                break;
            }
    }
    if (x_of) {
        render::Plot spec;
        spec.title = label + " against " + (x_axis == "fabric" ? "the fabric's bending length" : x_axis);
        spec.x_label = x_label;
        spec.y_label = label;
        plots.add(grouped_plot(f.points, f.axes, x_axis, x_of, y_main, spec));
    }
    std::set<double> particles;
    for (const auto& p : f.points)
        if (p.outputs.contains("particles") && p.outputs["particles"].is_number()) particles.insert(p.outputs["particles"].get<double>());
    if (particles.size() > 1) {
        render::Plot spec;
        spec.title = "wall time against particles";
        spec.x_label = "particles";
        spec.y_label = "wall time of the point, s";
        plots.add(grouped_plot(f.points, f.axes, "grid", [](const PointView& p) { return number_of(p.outputs["particles"]); },
                                               [](const PointView& p) { return p.wall ? *p.wall : std::nan(""); }, spec));
    }
}

/// The 3-D views of the points' meshes, within the page's budget; `body` gets a note of those
/// left out.
std::vector<render::ViewModel> scene_models(const std::vector<PointView>& points, std::ostringstream& body)
{
    std::vector<render::ViewModel> models;
    std::size_t bytes = 0, left_out = 0;
    for (const auto& p : points) {
        if (p.status != "done") continue;
        auto m = view_model(p);
        if (!m) continue;
        if (bytes + render::inlined_size(*m) > kMeshBudget) {
            ++left_out;
            continue;
        }
        bytes += render::inlined_size(*m);
        models.push_back(std::move(*m));
    }
    if (left_out > 0)
        body << "<p class=\"note\">" << left_out << " drapes are left out of the 3-D view (the page keeps its scenes under "
             << (kMeshBudget >> 20) << " MiB).</p>";
    return models;
}

/// three.js and its loaders (Debian's libjs-three), inlined when there is a scene to show.
render::ViewScripts view_scripts(const std::vector<render::ViewModel>& models, const fs::path& lib, std::vector<std::string>& warnings)
{
    render::ViewScripts scripts;
    if (models.empty()) return scripts;
    const fs::path files[3] = {lib / "three.min.js", lib / "examples/js/controls/OrbitControls.js", lib / "examples/js/loaders/GLTFLoader.js"};
    if (fs::exists(files[0]) && fs::exists(files[1]) && fs::exists(files[2])) {
        scripts.three = read_output_file(files[0].string()).value_or("");
        scripts.orbit_controls = read_output_file(files[1].string()).value_or("");
        scripts.gltf_loader = read_output_file(files[2].string()).value_or("");
    } else {
        warnings.push_back(lib.string() + ": three.min.js, OrbitControls.js or GLTFLoader.js not found (Debian package "
                        "libjs-three); the page has no 3-D view");
    }
    return scripts;
}

/// `page` as `out`, through a temporary in the same folder and a rename.
void write_page(const fs::path& out, const std::string& page)
{
    std::error_code ec;
    const fs::path tmp = out.parent_path() / (".woven-tmp." + std::to_string(::getpid()) + ".report.html");
    {
        std::ofstream f(tmp, std::ios::binary);
        f << page;
        f.flush();
        if (!f) {
            fs::remove(tmp, ec);
            throw RuntimeError(out.string() + ": cannot write");
        }
    }
    fs::rename(tmp, out, ec);
    if (ec) {
        fs::remove(tmp, ec);
        throw RuntimeError(out.string() + ": cannot move into place: " + ec.message());
    }
}

}  // namespace

ReportResult report(const ReportRequest& request)
{
    const MonitorScope monitor(request.monitor);
    const fs::path dir(request.dir);
    const ReportFolder f = read_report_folder(dir, request.dir.string());
    std::ostringstream body;
    body << "<h1>" << render::html_escape(f.title) << "</h1><p>" << render::html_escape(f.summary) << "</p>";
    body << "<h2>Table</h2><p class=\"note\">Click a column's header to sort.</p>" << render::html_table(points_table(f), "points");

    // Plots.
    Plots plots;
    std::string sections, notes;
    if (f.is_sweep) sweep_plots(f, plots);
    for (const auto& p : f.points) {
        if (p.status != "done") continue;
        if (f.command == "kes-test") kes_section(p, plots, f.is_sweep ? p.name + ": " : "");
        if (f.command == "fit") fit_section(p, plots, notes);
        if (f.command == "experiment") sections += experiment_section(p, plots);
        if (f.command == "cusick" && !f.is_sweep) sections += cusick_section(p, plots);
        if (f.command == "drape" && !f.is_sweep) sections += drape_section(p);
    }
    body << sections;
    if (plots.count > 0) body << "<h2>Plots</h2>" << notes << "<div class=\"plots\">" << plots.html << "</div>";
    body << "<h2>Pictures</h2>" << gallery(f.points);

    // The scenes, within the budget.
    std::vector<render::ViewModel> models = scene_models(f.points, body);
    std::vector<std::string> warnings;
    const render::ViewScripts scripts = view_scripts(models, request.three_js_dir.value_or(WOVEN_THREE_JS_DIR), warnings);
    if (request.on_warnings) request.on_warnings(warnings);
    const std::string page = render::html_page(f.title, body.str(), models, scripts);
    ReportResult result;
    result.page = (dir / "report.html").string();
    write_page(result.page, page);
    result.points = static_cast<int>(f.points.size());
    result.scenes = static_cast<int>(models.size());
    result.bytes = page.size();
    return result;
}

}  // namespace woven::app
