// woven report DIR: one self-contained DIR/report.html for a sweep folder (its sweep.json and
// point folders) or for one output folder of drape, cusick or kes-test: the tables (sortable),
// plots (the main number against the fabric's bending length or the first numeric axis, seeds
// as error bars; wall time against particles; KES curves, simulated against input), every
// picture inlined, and a 3-D view of each drape (three.js from Debian's libjs-three, inlined).
// Every folder is verified first (woven check's test): a broken folder is a one-line error and
// no page.
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

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "woven/cli/commands.hpp"
#include "woven/app/sweep.hpp"
#include "woven/common/error.hpp"
#include "woven/io/fabric_file.hpp"
#include "woven/io/mesh_file.hpp"
#include "woven/io/output_file.hpp"
#include "woven/kes/curve.hpp"
#include "woven/render/html_page.hpp"

namespace woven::cli {

namespace {

namespace fs = std::filesystem;

/// Mesh bytes a page may inline (the 3-D view's points beyond it are listed, not shown).
constexpr std::size_t kMeshBudget = 24u << 20;

struct ReportOptions {
    std::string dir;
};

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

/// The point's mesh (cusick.obj or drape.obj) with its coincident vertices merged.
std::optional<render::ViewMesh> view_mesh(const PointView& p)
{
    for (const char* name : {"drape.obj", "cusick.obj"}) {
        if (!fs::exists(p.dir / name)) continue;
        const geometry::TriangleMesh m = io::load_obj_mesh((p.dir / name).string());
        render::ViewMesh v;
        v.name = p.name;
        std::map<std::array<long long, 3>, std::uint32_t> index;
        std::vector<std::uint32_t> remap(m.vertices.size());
        for (std::size_t k = 0; k < m.vertices.size(); ++k) {
            const auto& x = m.vertices[k];
            const std::array<long long, 3> key{std::llround(x.x() * 1e6), std::llround(x.y() * 1e6), std::llround(x.z() * 1e6)};
            const auto [it, fresh] = index.emplace(key, static_cast<std::uint32_t>(v.xyz.size() / 3));
            if (fresh)
                for (int d = 0; d < 3; ++d) v.xyz.push_back(static_cast<float>(x[d]));
            remap[k] = it->second;
        }
        for (const auto& f : m.faces)
            for (int d = 0; d < 3; ++d) v.triangles.push_back(remap[static_cast<std::size_t>(f[d])]);
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
render::PlotSpec grouped_plot(const std::vector<PointView>& points, const std::vector<std::string>& axes, const std::string& x_axis,
                              const std::function<double(const PointView&)>& x_of, const std::function<double(const PointView&)>& y_of,
                              render::PlotSpec spec)
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
        render::PlotSeries s;
        s.name = name;
        for (const auto& [x, ys] : by_x) {
            const auto [m, sd] = mean_std(ys);
            s.x.push_back(x);
            s.y.push_back(m);
            s.err.push_back(sd);
        }
        spec.series.push_back(std::move(s));
    }
    return spec;
}

/// The KES curves of a kes-test folder: each CSV (first column x, the others simulated and input).
std::string kes_curves(const PointView& p)
{
    std::string out;
    std::vector<fs::path> csvs;
    for (const auto& e : fs::directory_iterator(p.dir))
        if (e.path().extension() == ".csv") csvs.push_back(e.path());
    std::sort(csvs.begin(), csvs.end());
    for (const auto& c : csvs) {
        std::istringstream in(read_output_file(c.string()).value_or(""));
        std::string line;
        if (!std::getline(in, line)) continue;
        std::vector<std::string> head;
        std::istringstream h(line);
        for (std::string f; std::getline(h, f, ',');) head.push_back(f);
        if (head.size() < 2) continue;
        render::PlotSpec spec;
        spec.title = p.name + ": " + c.stem().string();
        spec.x_label = head[0];
        spec.y_label = head.size() == 3 && head[1].find("simulated_") == 0 ? head[1].substr(10) : "value";
        spec.series.resize(head.size() - 1);
        for (std::size_t k = 1; k < head.size(); ++k) {
            spec.series[k - 1].name = head[k].substr(0, head[k].find('_'));
            spec.series[k - 1].lines = true;
        }
        while (std::getline(in, line)) {
            std::istringstream r(line);
            std::vector<double> v;
            for (std::string f; std::getline(r, f, ',');) v.push_back(f.empty() ? std::nan("") : std::strtod(f.c_str(), nullptr));
            if (v.size() != head.size()) continue;
            for (std::size_t k = 1; k < v.size(); ++k) {
                spec.series[k - 1].x.push_back(v[0]);
                spec.series[k - 1].y.push_back(v[k]);
            }
        }
        out += render::svg_plot(spec, 480, 320);
    }
    return out;
}

std::string gallery(const std::vector<PointView>& points)
{
    std::ostringstream o;
    o << "<div class=\"gallery\">";
    for (const auto& p : points) {
        if (p.status != "done") continue;
        std::vector<std::string> pngs;
        if (p.manifest.contains("files")) {
            const auto& f = p.manifest["files"];
            if (f.is_object())
                for (auto it = f.begin(); it != f.end(); ++it) pngs.push_back(it.key());
            else
                for (const auto& n : f) pngs.push_back(n.get<std::string>());
        }
        for (const auto& n : pngs) {
            if (!n.ends_with(".png")) continue;
            o << "<figure><img alt=\"" << render::html_escape(p.name + " " + n) << "\" src=\"data:image/png;base64,"
              << render::base64(read_output_file((p.dir / n).string()).value_or("")) << "\"><figcaption>" << render::html_escape(p.name + ": " + n) << "</figcaption></figure>";
        }
    }
    o << "</div>";
    return o.str();
}

int run_report(const ReportOptions& o)
{
    const fs::path dir(o.dir);
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) throw InputError(o.dir, "", "no such folder");
    std::vector<PointView> points;
    std::vector<std::string> axes, columns;
    std::string command, title, summary;
    const bool is_sweep = fs::exists(dir / "sweep.json");
    if (is_sweep) {
        const nlohmann::json s = read_json(dir / "sweep.json", "a sweep's merged table", io::kMaxSweepTableBytes);
        if (!s.is_object() || !s.contains("rows") || !s["rows"].is_array() || !s.contains("command") || !s["command"].is_string())
            throw InputError((dir / "sweep.json").string(), "rows", "expected the merged table of `woven sweep` (command, axes, rows)");
        command = s["command"].get<std::string>();
        for (const auto& a : s.value("axes", nlohmann::json::array())) axes.push_back(a.value("key", std::string()));
        for (const auto& c : s.value("output_columns", nlohmann::json::array())) columns.push_back(c.get<std::string>());
        title = "woven sweep " + s.value("name", std::string());
        const std::string d = s.value("description", std::string());
        summary = (d.empty() ? "" : d + ". ") + "woven " + command + " at " + std::to_string(s["rows"].size()) + " points: " +
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
            points.push_back(std::move(p));
        }
    } else {
        const std::string m = manifest_name(dir);
        if (m.empty())
            throw InputError(o.dir, "",
                             "expected a sweep folder (sweep.json) or an output folder of drape, cusick or kes-test (report.json, "
                             "cusick.json or kes-report.json)");
        verify(dir, "the output folder does not verify: ");
        PointView p;
        p.manifest = read_json(dir / m, "a manifest");
        command = m == "cusick.json" ? "cusick" : m == "kes-report.json" ? "kes-test" : p.manifest.value("command", std::string("drape"));
        if (command != "drape" && command != "cusick" && command != "kes-test")
            throw InputError((dir / m).string(), "command", "expected the output of drape, cusick or kes-test, got " + command);
        p.name = fs::absolute(dir).lexically_normal().filename().string();
        if (p.name.empty()) p.name = fs::absolute(dir).lexically_normal().parent_path().filename().string();
        p.dir = dir;
        if (p.manifest.contains("wall_time_s") && p.manifest["wall_time_s"].is_number()) p.wall = p.manifest["wall_time_s"].get<double>();
        if (p.manifest.contains("fabric")) p.values["fabric"] = p.manifest["fabric"];
        if (p.manifest.contains("scene")) p.values["scene"] = p.manifest["scene"];
        p.outputs = point_outputs(command, p.manifest);
        for (auto it = p.outputs.begin(); it != p.outputs.end(); ++it) columns.push_back(it.key());
        for (auto it = p.values.begin(); it != p.values.end(); ++it) axes.push_back(it.key());
        title = "woven " + command + " " + p.name;
        summary = "The output folder " + dir.string() + " of woven " + command + " (version " + p.manifest.value("version", std::string("?")) + ").";
        points.push_back(std::move(p));
    }

    std::ostringstream body;
    body << "<h1>" << render::html_escape(title) << "</h1><p>" << render::html_escape(summary) << "</p>";
    // The table.
    render::HtmlTable t;
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
        for (const auto& a : axes) row.push_back(p.values.contains(a) ? cell(p.values[a]) : "");
        row.push_back(p.status + (p.problem.empty() ? "" : ": " + p.problem));
        row.push_back(p.wall ? cell(*p.wall) : "");
        for (const auto& c : columns) row.push_back(p.outputs.contains(c) ? cell(p.outputs[c]) : "");
        t.rows.push_back(std::move(row));
        t.row_class.push_back(p.status == "done" ? "" : p.status);
    }
    body << "<h2>Table</h2><p class=\"note\">Click a column's header to sort.</p>" << render::html_table(t, "points");

    // Plots.
    std::string plots;
    if (is_sweep) {
        const auto [key, label] = main_output(command);
        const auto y_main = [key = key](const PointView& p) { return p.outputs.contains(key) ? number_of(p.outputs[key]) : std::nan(""); };
        std::string x_axis;
        std::function<double(const PointView&)> x_of;
        std::string x_label;
        if (std::find(axes.begin(), axes.end(), "fabric") != axes.end()) {
            auto cache = std::make_shared<std::map<std::string, double>>();
            x_axis = "fabric";
            x_label = "bending length (B / W)^(1/3), mean of warp and weft, cm";
            x_of = [cache](const PointView& p) {
                const std::string f = p.values.value("fabric", std::string());
                if (!cache->count(f)) (*cache)[f] = bending_length_cm(f).value_or(std::nan(""));
                return (*cache)[f];
            };
        } else {
            for (const auto& a : axes)
                if (a != "seed" && !points.empty() && points[0].values.contains(a) && points[0].values[a].is_number()) {
                    x_axis = a;
                    x_label = a;
                    x_of = [a](const PointView& p) { return p.values.contains(a) ? number_of(p.values[a]) : std::nan(""); };
                    break;
                }
        }
        if (x_of) {
            render::PlotSpec spec;
            spec.title = label + " against " + (x_axis == "fabric" ? "the fabric's bending length" : x_axis);
            spec.x_label = x_label;
            spec.y_label = label;
            plots += render::svg_plot(grouped_plot(points, axes, x_axis, x_of, y_main, spec));
        }
        std::set<double> particles;
        for (const auto& p : points)
            if (p.outputs.contains("particles") && p.outputs["particles"].is_number()) particles.insert(p.outputs["particles"].get<double>());
        if (particles.size() > 1) {
            render::PlotSpec spec;
            spec.title = "wall time against particles";
            spec.x_label = "particles";
            spec.y_label = "wall time of the point, s";
            plots += render::svg_plot(grouped_plot(points, axes, "grid", [](const PointView& p) { return number_of(p.outputs["particles"]); },
                                                   [](const PointView& p) { return p.wall ? *p.wall : std::nan(""); }, spec));
        }
    }
    if (command == "kes-test")
        for (const auto& p : points)
            if (p.status == "done") plots += kes_curves(p);
    if (!plots.empty()) body << "<h2>Plots</h2><div class=\"plots\">" << plots << "</div>";
    body << "<h2>Pictures</h2>" << gallery(points);

    // Meshes, within the budget.
    std::vector<render::ViewMesh> meshes;
    std::size_t bytes = 0, left_out = 0;
    for (const auto& p : points) {
        if (p.status != "done") continue;
        auto m = view_mesh(p);
        if (!m) continue;
        if (bytes + render::inlined_size(*m) > kMeshBudget) {
            ++left_out;
            continue;
        }
        bytes += render::inlined_size(*m);
        meshes.push_back(std::move(*m));
    }
    if (left_out > 0)
        body << "<p class=\"note\">" << left_out << " drapes are left out of the 3-D view (the page keeps its meshes under "
             << (kMeshBudget >> 20) << " MiB).</p>";
    std::string three, orbit;
    if (!meshes.empty()) {
        const fs::path lib(WOVEN_THREE_JS_DIR);
        if (fs::exists(lib / "three.min.js") && fs::exists(lib / "examples/js/controls/OrbitControls.js")) {
            three = read_output_file((lib / "three.min.js").string()).value_or("");
            orbit = read_output_file((lib / "examples/js/controls/OrbitControls.js").string()).value_or("");
        } else {
            print_warnings({std::string(WOVEN_THREE_JS_DIR) + ": three.min.js not found (Debian package libjs-three); the page has no 3-D view"});
        }
    }
    const std::string page = render::html_page(title, body.str(), meshes, three, orbit);
    const fs::path out = dir / "report.html";
    const fs::path tmp = dir / (".woven-tmp." + std::to_string(::getpid()) + ".report.html");
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
    std::cout << "wrote " << out.string() << " (" << points.size() << (points.size() == 1 ? " point, " : " points, ") << meshes.size()
              << (meshes.size() == 1 ? " mesh, " : " meshes, ") << (page.size() + 512) / 1024 << " KiB)\n";
    return kExitOk;
}

}  // namespace

void add_report_command(CLI::App& app, int& exit_code)
{
    auto o = std::make_shared<ReportOptions>();
    CLI::App* sub = app.add_subcommand("report", "Write one self-contained report.html for a sweep or an output folder");
    sub->footer("DIR is a sweep folder (woven sweep) or an output folder of drape, cusick or kes-test. The page holds the table "
                "(click a header to sort), plots (SVG), the pictures and a 3-D view of each drape (three.js from libjs-three), all "
                "inlined: it opens from a file without a network. Every folder is verified first (as woven check does); a broken one "
                "is an error and no page is written.");
    sub->add_option("DIR", o->dir, "The folder")->required();
    sub->callback([o, &exit_code] { exit_code = run_report(*o); });
}

}  // namespace woven::cli
