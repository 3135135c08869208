// The sections of `woven report`'s page (report_sections.hpp).
#include "woven/render/report_sections.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <sstream>

#include "woven/render/instrument_plots.hpp"

namespace woven::render {

namespace {

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
Plot grouped_plot(const std::vector<ReportPoint>& points, const std::vector<std::string>& axes, const std::string& x_axis,
                 const std::function<double(const ReportPoint&)>& x_of, const std::function<double(const ReportPoint&)>& y_of, Plot plot)
{
    std::map<std::string, std::map<double, std::vector<double>>> groups;
    for (const auto& p : points) {
        if (p.status != "done") continue;
        const double x = x_of(p), y = y_of(p);
        if (!std::isfinite(x) || !std::isfinite(y)) continue;
        std::string key;
        for (const auto& a : axes)
            if (a != x_axis && a != "seed" && p.values.contains(a)) key += (key.empty() ? "" : ", ") + a + " " + report_cell(p.values[a]);
        groups[key.empty() ? "all points" : key][x].push_back(y);
    }
    for (const auto& [name, by_x] : groups) {
        Series s;
        s.label = name;
        s.style = Series::Style::LINE_AND_POINTS;
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

Series series(std::vector<double> x, std::vector<double> y, Series::Style style, std::optional<Vec3> colour, std::string label)
{
    Series s;
    s.x = std::move(x);
    s.y = std::move(y);
    s.style = style;
    s.color = colour;
    s.label = std::move(label);
    return s;
}

const Vec3 kGrey(0.5, 0.5, 0.5), kLight(0.78, 0.78, 0.78);

std::string number_cell(const nlohmann::json& v) { return v.is_number() ? report_cell(nlohmann::json(v.get<double>())) : report_cell(v); }

}  // namespace

int CsvTable::col(const std::string& name) const
{
    for (std::size_t k = 0; k < head.size(); ++k)
        if (head[k] == name) return static_cast<int>(k);
    return -1;
}

std::vector<double> CsvTable::get(const std::string& name) const { return col(name) < 0 ? std::vector<double>{} : cols[static_cast<std::size_t>(col(name))]; }

void ReportPlots::add(const Plot& p, int width, int height) { html += html_plot(p, "plot-" + std::to_string(++count), width, height); }

std::string report_cell(const nlohmann::json& v)
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

HtmlTable key_table(const nlohmann::json& j)
{
    HtmlTable t;
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
    walk(j, "");
    return t;
}

void kes_section(const ReportPoint& p, const CsvReader& read_csv, ReportPlots& plots, const std::string& title_prefix)
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
        std::vector<KesCurveView> runs;
        for (int d = 0; d < 2; ++d) {
            auto c = read_csv(p, t.name + "_loop_" + dirs[d] + ".csv");
            if (!c) c = read_csv(p, t.name + "_" + dirs[d] + ".csv");
            if (!c || c->col(t.x) < 0 || c->col("simulated_" + t.y) < 0 || c->col("input_" + t.y) < 0) continue;
            runs.push_back({dirs[d], c->get(t.x), c->get("simulated_" + t.y), c->get(t.x), c->get("input_" + t.y)});
        }
        if (!runs.empty()) plots.add(kes_loop_plot(title_prefix + t.title, t.x_label, t.y_label, runs, true));
    }
    Plot shape;
    shape.title = title_prefix + "Cantilever: deflected shape against the elastica";
    shape.x_label = "x, m";
    shape.y_label = "z, m";
    shape.equal_aspect = true;
    for (int d = 0; d < 2; ++d) {
        const auto c = read_csv(p, "cantilever_" + dirs[d] + ".csv");
        if (!c || c->col("source") < 0 || c->col("x_m") < 0 || c->col("z_m") < 0) continue;
        const auto& source = c->text[static_cast<std::size_t>(c->col("source"))];
        const auto x = c->get("x_m"), z = c->get("z_m");
        std::vector<double> sx, sz, ex, ez;
        for (std::size_t k = 0; k < source.size(); ++k) {
            (source[k] == "simulated" ? sx : ex).push_back(x[k]);
            (source[k] == "simulated" ? sz : ez).push_back(z[k]);
        }
        shape.series.insert(shape.series.begin() + d, series(ex, ez, Series::Style::LINE, d ? kGreen : kBlue, "elastica " + dirs[d]));
        shape.series.push_back(series(sx, sz, Series::Style::POINTS, d ? kRed : kOrange, "simulated " + dirs[d]));
    }
    if (!shape.series.empty()) plots.add(shape, 680, 420);
}

std::string drape_section(const ReportPoint& p)
{
    std::ostringstream o;
    const auto& m = p.manifest;
    o << "<h2>Energy</h2>";
    HtmlTable e;
    e.header = {"term", "energy, J"};
    e.numeric = {false, true};
    if (m.contains("energy") && m["energy"].is_object())
        for (auto it = m["energy"].begin(); it != m["energy"].end(); ++it)
            if (it->is_number()) e.rows.push_back({it.key(), number_cell(*it)});
    if (m.contains("energy_initial_J") && m["energy_initial_J"].is_number()) e.rows.push_back({"energy_initial_J", number_cell(m["energy_initial_J"])});
    o << html_table(e, "energy");
    if (m.contains("folds") && m["folds"].is_object()) {
        const auto& f = m["folds"];
        o << "<h2>Folds</h2><p class=\"note\">The billows leaving each corner of the box on horizontal sections (angles from the "
             "corner's diagonal, deg; standout from the box, m).</p>";
        HtmlTable t;
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
                for (const auto& a : at("angles_deg")) angles += (angles.empty() ? "" : " ") + report_cell(nlohmann::json(a.get<double>()));
                for (const auto& s : at("standout_m")) standout += (standout.empty() ? "" : " ") + report_cell(nlohmann::json(s.get<double>()));
                t.rows.push_back({report_cell(c.value("corner", nlohmann::json())), h < heights.size() ? number_cell(heights[h]) : "", report_cell(billows[h]),
                                  report_cell(at("structure")), angles, standout});
            }
        }
        o << html_table(t, "folds");
        nlohmann::json rest = nlohmann::json::object();
        for (const char* k : {"hanging_m", "lowest_point_m", "projected_area_m2"})
            if (f.contains(k)) rest[k] = f[k];
        HtmlTable r = key_table(rest);
        for (auto& row : r.rows) row[0] = "folds." + row[0];
        for (const char* k : {"hanging_m", "lowest_point_m"})
            if (rest.contains(k) && rest[k].is_array()) {
                std::string v;
                for (const auto& x : rest[k]) v += (v.empty() ? "" : " ") + number_cell(x);
                r.rows.push_back({std::string("folds.") + k, v});
            }
        o << html_table(r, "folds-other");
    }
    return o.str();
}

std::string garment_section(const ReportPoint& p, ReportPlots& plots)
{
    const auto& m = p.manifest;
    const auto obj = [&m](const char* k) { return m.contains(k) && m[k].is_object() ? m[k] : nlohmann::json::object(); };
    const auto list = [](const nlohmann::json& j, const char* k) {
        return j.contains(k) && j[k].is_array() ? j[k] : nlohmann::json::array();
    };
    const auto numbers = [&list](const nlohmann::json& j, const char* k) {
        std::vector<double> v;
        for (const auto& x : list(j, k)) v.push_back(number_of(x));
        return v;
    };
    std::ostringstream o;
    o << "<h2>Garment</h2>";
    HtmlTable g;
    g.header = {"quantity", "value"};
    g.numeric = {false, true};
    for (const char* k : {"garment", "fabric", "spacing_m", "particles", "converged", "interrupted", "steps", "iterations", "wall_time_s", "threads",
                          "seam_max_gap_m", "seam_max_gap_over_spacing"})
        if (m.contains(k)) g.rows.push_back({k, number_cell(m[k])});
    const nlohmann::json waist = obj("waist");
    for (auto it = waist.begin(); it != waist.end(); ++it) g.rows.push_back({"waist." + it.key(), number_cell(*it)});
    o << html_table(g, "garment");

    o << "<h2>Pieces</h2><p class=\"note\">Each piece's grain angle: the angle between the warp and its grain line (0: the "
         "straight grain, 45: the bias).</p>";
    HtmlTable pieces;
    pieces.header = {"piece", "grain, deg", "particles", "area, m^2"};
    pieces.numeric = {false, true, true, true};
    for (const auto& pc : list(m, "pieces"))
        if (pc.is_object())
            pieces.rows.push_back({report_cell(pc.value("name", nlohmann::json())), number_cell(pc.value("grain_deg", nlohmann::json())),
                                   number_cell(pc.value("particles", nlohmann::json())), number_cell(pc.value("area_m2", nlohmann::json()))});
    o << html_table(pieces, "pieces");

    const nlohmann::json hem = obj("hem");
    o << "<h2>Hem</h2><p class=\"note\">The hem's particles from the body's axis: its nodes (peaks of the radius per 5-degree bin "
         "of azimuth from +x), flare (mean hem radius over the waist's) and length drop (the highest bin's height minus the "
         "lowest's).</p>";
    HtmlTable h;
    h.header = {"quantity", "value"};
    h.numeric = {false, true};
    for (const char* k : {"nodes", "flare", "mean_radius_m", "mean_height_m", "below_waist_m", "length_drop_m", "min_prominence_m", "particles"})
        if (hem.contains(k)) h.rows.push_back({k, number_cell(hem[k])});
    std::string angles;
    for (const auto& a : list(hem, "node_angle_deg")) angles += (angles.empty() ? "" : " ") + number_cell(a);
    h.rows.push_back({"node_angle_deg", angles});
    o << html_table(h, "hem");

    o << "<h2>Seams</h2><p class=\"note\">Each seam's gaps between its stitched particles at rest and the forces k d that "
         "hold them (k: the last stage's stiffness).</p>";
    HtmlTable seams;
    seams.header = {"seam", "stitches", "max_gap_m", "mean_gap_m", "max_gap_over_spacing", "max_force_N", "mean_force_N"};
    seams.numeric = {false, true, true, true, true, true, true};
    for (const auto& sm : list(m, "seams")) {
        if (!sm.is_object()) continue;
        std::vector<std::string> row{report_cell(sm.value("name", nlohmann::json()))};
        for (std::size_t c = 1; c < seams.header.size(); ++c) row.push_back(number_cell(sm.value(seams.header[c], nlohmann::json())));
        seams.rows.push_back(std::move(row));
    }
    o << html_table(seams, "seams");

    HtmlTable stages;
    stages.header = {"stage", "seam_stiffness_N_m", "converged", "steps", "iterations", "wall_time_s", "energy_J", "max_residual_rel"};
    stages.numeric = {true, true, false, true, true, true, true, true};
    int n = 0;
    for (const auto& st : list(m, "stages")) {
        if (!st.is_object()) continue;
        std::vector<std::string> row{std::to_string(++n)};
        for (std::size_t c = 1; c < stages.header.size(); ++c) row.push_back(number_cell(st.value(stages.header[c], nlohmann::json())));
        stages.rows.push_back(std::move(row));
    }
    o << "<h2>Stages of the seams' ramp</h2>" << html_table(stages, "stages");
    if (m.contains("energy") && m["energy"].is_object()) {
        HtmlTable e = key_table(m["energy"]);
        e.header = {"term", "energy, J"};
        o << "<h2>Energy</h2>" << html_table(e, "energy");
    }

    // The hem per bin of azimuth; each node at its angle, on the line between the bins beside it
    // (periodic: past the last bin comes the first, 360 degrees on).
    const std::vector<double> angle = numbers(hem, "angle_deg"), radius = numbers(hem, "radius_m"), height = numbers(hem, "height_m");
    const std::vector<double> node_angle = numbers(hem, "node_angle_deg");
    const auto at_nodes = [&](const std::vector<double>& y) {
        Series s = series({}, {}, Series::Style::POINTS, kRed, "nodes");
        const std::size_t n = std::min(angle.size(), y.size());
        if (n == 0) return s;
        for (double a : node_angle) {
            std::size_t k = 0;  // the last bin at or before a (n - 1 before the first: wrapped)
            while (k < n && angle[k] <= a) ++k;
            const std::size_t lo = k == 0 ? n - 1 : k - 1, hi = k % n;
            const double a_lo = k == 0 ? angle[lo] - 360 : angle[lo], a_hi = k == n ? angle[hi] + 360 : angle[hi];
            const double t = a_hi > a_lo ? (a - a_lo) / (a_hi - a_lo) : 0.0;
            s.x.push_back(a);
            s.y.push_back((1 - t) * y[lo] + t * y[hi]);
        }
        return s;
    };
    if (!angle.empty() && !radius.empty()) {
        Plot plot;
        plot.title = "Hem radius from the body's axis per 5-degree bin, " + report_cell(hem.value("nodes", nlohmann::json())) + " nodes";
        plot.x_label = "azimuth from +x towards +y, deg";
        plot.y_label = "hem radius, m";
        plot.series.push_back(series(angle, radius, Series::Style::LINE_AND_POINTS, kBlue, "hem radius"));
        if (waist.contains("radius_m") && waist["radius_m"].is_number())
            plot.series.push_back(series({0.0, 360.0}, {number_of(waist["radius_m"]), number_of(waist["radius_m"])}, Series::Style::LINE, kGrey,
                                         "waist radius"));
        if (!node_angle.empty()) plot.series.push_back(at_nodes(radius));
        plots.add(plot);
    }
    if (!angle.empty() && !height.empty()) {
        Plot plot;
        plot.title = "Hem height above the floor per 5-degree bin, length drop " + report_cell(hem.value("length_drop_m", nlohmann::json())) + " m";
        plot.x_label = "azimuth from +x towards +y, deg";
        plot.y_label = "hem height, m";
        plot.series.push_back(series(angle, height, Series::Style::LINE_AND_POINTS, kBlue, "hem height"));
        if (!node_angle.empty()) plot.series.push_back(at_nodes(height));
        plots.add(plot);
    }
    return o.str();
}

std::string cusick_section(const ReportPoint& p, const std::vector<double>& outline, ReportPlots& plots)
{
    const auto& m = p.manifest;
    std::ostringstream o;
    o << "<h2>Drape coefficient and nodes</h2>";
    HtmlTable t;
    t.header = {"quantity", "value"};
    t.numeric = {false, true};
    for (const char* k : {"drape_coefficient_percent", "nodes", "specimen_diameter_m", "disc_diameter_m", "spacing_m", "particles"})
        if (m.contains(k)) t.rows.push_back({k, number_cell(m[k])});
    o << html_table(t, "cusick");
    HtmlTable n;
    n.header = {"node", "angle from warp, deg", "radius, m", "depth, m"};
    n.numeric = {true, true, true, true};
    // The prediction's nodes; their radii are its run's (the run whose node angles they are).
    const auto angles = m.value("node_angles_deg", nlohmann::json::array()), depths = m.value("node_depths_m", nlohmann::json::array());
    nlohmann::json radii = m.value("node_radii_m", nlohmann::json::array());
    for (const auto& r : m.value("runs", nlohmann::json::array()))
        if (radii.empty() && r.is_object() && r.value("node_angles_deg", nlohmann::json()) == angles) radii = r.value("node_radii_m", nlohmann::json::array());
    Series nodes = series({}, {}, Series::Style::POINTS, kRed, "nodes");
    for (std::size_t k = 0; k < angles.size() && k < radii.size(); ++k) {
        const double a = number_of(angles[k]) * M_PI / 180, r = number_of(radii[k]);
        nodes.x.push_back(r * std::sin(a));
        nodes.y.push_back(r * std::cos(a));
        n.rows.push_back({std::to_string(k + 1), number_cell(angles[k]), number_cell(radii[k]), k < depths.size() ? number_cell(depths[k]) : ""});
    }
    o << html_table(n, "nodes");
    Plot plot;
    plot.title = "Shadow seen from above (warp up), DC " + report_cell(m.value("drape_coefficient_percent", nlohmann::json())) + " %";
    plot.x_label = "x (weft), m";
    plot.y_label = "y (warp), m";
    plot.equal_aspect = true;
    const auto circle = [](double r, const Vec3& c, const std::string& label) {
        Series s = series({}, {}, Series::Style::LINE, c, label);
        for (int k = 0; k <= 360; k += 2) {
            s.x.push_back(r * std::sin(k * M_PI / 180));
            s.y.push_back(r * std::cos(k * M_PI / 180));
        }
        return s;
    };
    if (m.contains("specimen_diameter_m")) plot.series.push_back(circle(0.5 * number_of(m["specimen_diameter_m"]), kLight, "flat specimen"));
    if (m.contains("disc_diameter_m")) plot.series.push_back(circle(0.5 * number_of(m["disc_diameter_m"]), kGrey, "support disc"));
    if (!outline.empty()) {
        const int count = static_cast<int>(outline.size());
        Series s = series({}, {}, Series::Style::LINE, kBlue, "shadow outline");
        for (int k = 0; k <= count; ++k) {
            const double a = 2 * M_PI * (k % count) / count;
            s.x.push_back(outline[static_cast<std::size_t>(k % count)] * std::sin(a));
            s.y.push_back(outline[static_cast<std::size_t>(k % count)] * std::cos(a));
        }
        plot.series.push_back(std::move(s));
    }
    plot.series.push_back(std::move(nodes));
    plots.add(plot, 600, 600);
    return o.str();
}

void fit_section(const ReportPoint& p, const CsvReader& read_csv, const std::vector<CurveFitView>& curves, ReportPlots& plots)
{
    for (const CurveFitView& c : curves) plots.add(curve_fit_plot(c));
    Plot bending;
    bending.title = "Bending energy of one thread angle, B(theta)";
    bending.x_label = "thread angle theta, rad (pi: straight)";
    bending.y_label = "B, J";
    for (int d = 0; d < 2; ++d) {
        const std::string dir = d ? "weft" : "warp";
        if (const auto c = read_csv(p, "bending_" + dir + "_energy.csv"))
            bending.series.push_back(series(c->get("theta_rad"), c->get("B_J"), Series::Style::LINE, d ? kOrange : kBlue, dir));
    }
    if (!bending.series.empty()) plots.add(bending);
    if (const auto c = read_csv(p, "trellis_energy.csv")) {
        Plot trellis;
        trellis.title = "Trellis energy of one crossing, T(phi) (singular at 1.05 rad)";
        trellis.x_label = "trellis angle phi, rad";
        trellis.y_label = "T, J";
        const auto phi = c->get("phi_rad"), T = c->get("T_J");
        for (std::size_t k = 0; k < phi.size(); ++k)
            if (phi[k] >= 0.95 && std::isfinite(T[k]) && T[k] > 0) {
                trellis.y_max = T[k];  // the singular end clipped, as fit's plot does
                break;
            }
        trellis.series.push_back(series(phi, T, Series::Style::LINE, kBlue, "T(phi)"));
        plots.add(trellis);
    }
}

std::string gallery(const std::vector<ReportPoint>& points, const std::function<std::string(const ReportPoint&, const std::string&)>& png)
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
            o << "<figure><img alt=\"" << html_escape(p.name + " " + n) << "\" src=\"data:image/png;base64,"
              << base64(png(p, n)) << "\"><figcaption>" << html_escape(p.name + ": " + n) << "</figcaption></figure>";
        }
    }
    o << "</div>";
    return o.str();
}

std::string experiment_section(const ReportPoint& p, const BendingLength& bending_length, const FabricColour& fabric_colour,
                               ReportPlots& plots)
{
    std::ostringstream o;
    for (auto it = p.manifest.begin(); it != p.manifest.end(); ++it) {
        const nlohmann::json& j = it.value();
        o << "<h2>" << html_escape(it.key()) << "</h2>";
        const std::string id = "experiment-" + std::to_string(std::distance(p.manifest.begin(), it));
        nlohmann::json top = nlohmann::json::object();
        for (auto k = j.begin(); k != j.end(); ++k)
            if (!k->is_structured()) top[k.key()] = *k;
        o << html_table(key_table(top), id);
        // Its lists of records (runs, cells): one row each, a column per number or word.
        for (auto k = j.begin(); k != j.end(); ++k) {
            if (!k->is_array() || k->empty() || !(*k)[0].is_object()) continue;
            HtmlTable t;
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
            o << "<h3>" << html_escape(k.key()) << "</h3>" << html_table(t, id + "-" + k.key());
        }
        if (it.key() != "cube_results.json") continue;
        HtmlTable t;
        t.header = {"fabric", "corners", "single_diagonal", "single_offset", "multiple", "none", "distinct_drapes"};
        t.numeric = {false, true, true, true, true, true, true};
        const nlohmann::json stats = j.value("statistics", nlohmann::json::object());
        for (auto f = stats.begin(); f != stats.end(); ++f) {
            std::vector<std::string> row{f.key()};
            for (std::size_t c = 1; c < t.header.size(); ++c) row.push_back(report_cell(f->value(t.header[c], nlohmann::json())));
            t.rows.push_back(std::move(row));
        }
        o << "<p class=\"note\">How often each corner structure appears (counts over seeds and corners).</p>" << html_table(t, "statistics");
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
            Plot plot;
            plot.title = q.title;
            plot.x_label = "bending length (B / W)^(1/3), mean of warp and weft, cm";
            plot.y_label = q.label;
            for (const auto& [fabric, rs] : runs) {
                std::vector<double> ys;
                for (const auto* r : rs)
                    if (std::isfinite(q.of(*r))) ys.push_back(q.of(*r));
                const double x = bending_length(fabric);
                if (ys.empty() || !std::isfinite(x)) continue;
                const auto [m, sd] = mean_std(ys);
                Series s = series({x}, {m}, Series::Style::POINTS, fabric_colour ? fabric_colour(fabric) : std::nullopt,
                                  fabric + " (" + std::to_string(ys.size()) + (ys.size() == 1 ? " seed)" : " seeds)"));
                s.err = {sd};
                plot.series.push_back(std::move(s));
            }
            if (!plot.series.empty()) plots.add(plot);
        }
    }
    return o.str();
}

HtmlTable points_table(const std::vector<ReportPoint>& points, const std::vector<std::string>& axes, const std::vector<std::string>& columns)
{
    HtmlTable t;
    t.header = {"point"};
    t.numeric = {false};
    for (const auto& a : axes) {
        t.header.push_back(a);
        bool numeric = true;
        for (const auto& p : points) numeric = numeric && (!p.values.contains(a) || p.values[a].is_number());
        t.numeric.push_back(numeric);
    }
    t.header.push_back("status");
    t.numeric.push_back(false);
    t.header.push_back("wall_time_s");
    t.numeric.push_back(true);
    for (const auto& c : columns) {
        t.header.push_back(c);
        bool numeric = true;
        for (const auto& p : points) numeric = numeric && (!p.outputs.contains(c) || p.outputs[c].is_number() || p.outputs[c].is_null());
        t.numeric.push_back(numeric);
    }
    for (const auto& p : points) {
        std::vector<std::string> row{p.name};
        for (const auto& a : axes) row.push_back(p.values.contains(a) ? report_cell(p.values[a]) : "");
        row.push_back(p.status + (p.problem.empty() ? "" : ": " + p.problem));
        row.push_back(p.wall ? report_cell(*p.wall) : "");
        for (const auto& c : columns) row.push_back(p.outputs.contains(c) ? report_cell(p.outputs[c]) : "");
        t.rows.push_back(std::move(row));
        t.row_class.push_back(p.status == "done" ? "" : p.status);
    }
    return t;
}

void sweep_plots(const std::vector<ReportPoint>& points, const std::vector<std::string>& axes, const std::string& command,
                 const BendingLength& bending_length, ReportPlots& plots)
{
    const auto [key, label] = main_output(command);
    const auto y_main = [key = key](const ReportPoint& p) { return p.outputs.contains(key) ? number_of(p.outputs[key]) : std::nan(""); };
    std::string x_axis;
    std::function<double(const ReportPoint&)> x_of;
    std::string x_label;
    if (std::find(axes.begin(), axes.end(), "fabric") != axes.end()) {
        x_axis = "fabric";
        x_label = "bending length (B / W)^(1/3), mean of warp and weft, cm";
        x_of = [&bending_length](const ReportPoint& p) { return bending_length(p.values.value("fabric", std::string())); };
    } else {
        for (const auto& a : axes)
            if (a != "seed" && !points.empty() && points[0].values.contains(a) && points[0].values[a].is_number()) {
                x_axis = a;
                x_label = a;
                x_of = [a](const ReportPoint& p) { return p.values.contains(a) ? number_of(p.values[a]) : std::nan(""); };
                break;
            }
    }
    if (x_of) {
        Plot spec;
        spec.title = label + " against " + (x_axis == "fabric" ? "the fabric's bending length" : x_axis);
        spec.x_label = x_label;
        spec.y_label = label;
        plots.add(grouped_plot(points, axes, x_axis, x_of, y_main, spec));
    }
    std::set<double> particles;
    for (const auto& p : points)
        if (p.outputs.contains("particles") && p.outputs["particles"].is_number()) particles.insert(p.outputs["particles"].get<double>());
    if (particles.size() > 1) {
        Plot spec;
        spec.title = "wall time against particles";
        spec.x_label = "particles";
        spec.y_label = "wall time of the point, s";
        plots.add(grouped_plot(points, axes, "grid", [](const ReportPoint& p) { return number_of(p.outputs["particles"]); },
                               [](const ReportPoint& p) { return p.wall ? *p.wall : std::nan(""); }, spec));
    }
}

}  // namespace woven::render
