// The report job (report.hpp).
#include "woven/app/report.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "woven/analysis/drape_shadow.hpp"
#include "woven/app/check.hpp"
#include "woven/app/fit.hpp"
#include "woven/app/files.hpp"
#include "woven/common/error.hpp"
#include "woven/io/fabric_file.hpp"
#include "woven/io/mesh_file.hpp"
#include "woven/io/output_file.hpp"
#include "woven/io/point_outputs.hpp"
#include "woven/kes/curve.hpp"
#include "woven/kes/fit.hpp"
#include "woven/render/gltf_file.hpp"
#include "woven/render/html_page.hpp"
#include "woven/render/report_sections.hpp"

namespace woven::app {

namespace {

namespace fs = std::filesystem;

/// glb bytes a page may inline (the 3-D view's points beyond it are counted, not shown).
constexpr std::size_t kMeshBudget = 24u << 20;

using PointView = render::ReportPoint;

std::string cell(const nlohmann::json& v) { return render::report_cell(v); }

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

/// The point's scene for the 3-D view: drape.glb, cusick.glb or garment.glb as written; for a folder from
/// before them, its drape.obj or cusick.obj as the cloth alone.
std::optional<render::ViewModel> view_model(const PointView& p)
{
    for (const char* name : {"drape.glb", "cusick.glb", "garment.glb", "drape.obj", "cusick.obj"}) {
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

std::optional<render::CsvTable> read_csv(const fs::path& file)
{
    if (!fs::exists(file)) return std::nullopt;
    std::istringstream in(read_output_file(file.string()).value_or(""));
    std::string line;
    if (!std::getline(in, line)) return std::nullopt;
    render::CsvTable c;
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

/// A cusick folder's shadow outline r(theta) from cusick.obj, 720 angles from the warp (none:
/// empty).
std::vector<double> shadow_outline(const PointView& p)
{
    if (!fs::exists(p.dir / "cusick.obj")) return {};
    return analysis::shadow_radius(io::load_obj_mesh((p.dir / "cusick.obj").string()), Vec2::Zero(), 720);
}

/// A fit folder's KES curves with their fits (the fabric fitted again, as `fit` does); `notes`
/// says why when the fabric cannot be read again.
std::vector<render::CurveFitView> fit_curves(const PointView& p, std::string& notes)
{
    // fabric_source: "built-in fabric 'NAME'" or the file's path.
    std::string source = p.manifest.value("fabric_source", std::string());
    if (source.empty() || source.rfind("built-in fabric '", 0) == 0) source = p.manifest.value("fabric", std::string());
    std::vector<render::CurveFitView> views;
    try {
        const kes::FabricData fabric = io::find_fabric(source);
        const kes::FittedFabric fit = kes::fit_fabric(fabric);
        views = {curve_fit_view(fabric.bending_warp.curve, fit.bending_warp, 200, false),
                 curve_fit_view(fabric.bending_weft.curve, fit.bending_weft, 200, false), curve_fit_view(fabric.shear.curve, fit.shear, 200, false)};
        const char* titles[3] = {"Bending, warp: KES curve and fit", "Bending, weft: KES curve and fit", "Shear: KES curve and fit"};
        for (std::size_t k = 0; k < 3; ++k) {
            views[k].title = titles[k];
            views[k].x_label = k < 2 ? "curvature K, 1/cm" : "shear angle, deg";
            views[k].y_label = k < 2 ? "moment M, gf.cm/cm" : "force F, gf/cm";
            views[k].fit_colour = render::kBlue;
        }
    } catch (const std::exception& e) {
        notes += "<p class=\"note\">The fabric " + render::html_escape(source) + " could not be read again for its fitted curves: " +
                 render::html_escape(e.what()) + "</p>";
    }
    return views;
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
        const auto problems = check_output_set(dir.string(), m);
        if (!problems.empty()) throw InputError(dir.string(), "", "the output folder does not verify: " + problems.front());
        p.manifest[m] = read_json(dir / m, "an experiment's manifest");
    }
    // Its wall time: the sum of its drapes' (each run's or cell's wall_s, as the drape recorded it).
    double wall = 0;
    bool any = false;
    for (const auto& m : ex)
        for (const char* list : {"runs", "cells"})
            for (const auto& r : p.manifest[m].value(list, nlohmann::json::array()))
                if (r.is_object() && r.contains("wall_s") && r["wall_s"].is_number()) {
                    wall += r["wall_s"].get<double>();
                    any = true;
                }
    if (any) p.wall = wall;
    f.title = "woven experiment " + p.name;
    f.summary = "The output folder " + dir.string() + " of woven experiment (" + [&] {
        std::string l;
        for (const auto& m : ex) l += (l.empty() ? "" : ", ") + m;
        return l;
    }() + ").";
    f.points.push_back(std::move(p));
    return f;
}

/// An output folder of drape, cusick, kes-test, fit or garment: one point, its set verified.
ReportFolder read_output(const fs::path& dir, const std::string& name)
{
    ReportFolder f;
    const std::string m = manifest_name(dir);
    if (m.empty())
        throw InputError(name, "",
                         "expected a sweep folder (sweep.json), an output folder of drape, cusick, kes-test, fit or garment (report.json, "
                         "cusick.json or kes-report.json) or of an experiment (cube_results.json, corner_map.json, figure1.json)");
    verify(dir, "the output folder does not verify: ");
    PointView p;
    p.manifest = read_json(dir / m, "a manifest");
    f.command = m == "cusick.json" ? "cusick" : m == "kes-report.json" ? "kes-test" : p.manifest.value("command", std::string("drape"));
    if (f.command != "drape" && f.command != "cusick" && f.command != "kes-test" && f.command != "fit" && f.command != "garment")
        throw InputError((dir / m).string(), "command", "expected the output of drape, cusick, kes-test, fit or garment, got " + f.command);
    p.name = folder_name(dir);
    p.dir = dir;
    if (p.manifest.contains("wall_time_s") && p.manifest["wall_time_s"].is_number()) p.wall = p.manifest["wall_time_s"].get<double>();
    if (p.manifest.contains("fabric")) p.values["fabric"] = p.manifest["fabric"];
    if (p.manifest.contains("scene")) p.values["scene"] = p.manifest["scene"];
    if (p.manifest.contains("garment")) p.values["garment"] = p.manifest["garment"];
    p.outputs = f.command == "fit" ? nlohmann::json::object() : io::point_outputs(f.command, p.manifest);
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
        errno = 0;
        std::ofstream f(tmp, std::ios::binary);
        const int open_errno = errno;  // why it could not be opened (a read-only folder: EACCES, EROFS)
        f << page;
        f.flush();
        if (!f) {
            const int why = open_errno != 0 ? open_errno : errno;
            fs::remove(tmp, ec);
            throw RuntimeError(out.string() + ": cannot write: " + (why != 0 ? std::strerror(why) : "the write failed"));
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
    const render::CsvReader csv = [](const PointView& p, const std::string& name) { return read_csv(p.dir / name); };
    std::map<std::string, double> lengths;
    const render::BendingLength bending_length = [&lengths](const std::string& fabric) {
        if (!lengths.count(fabric)) lengths[fabric] = bending_length_cm(fabric).value_or(std::nan(""));
        return lengths[fabric];
    };
    const render::FabricColour display_colour = [](const std::string& fabric) -> std::optional<Vec3> {
        try {
            const kes::FabricData f = io::find_fabric(fabric);
            if (f.color) return Vec3((*f.color)[0], (*f.color)[1], (*f.color)[2]);
        } catch (const std::exception&) {
        }
        return std::nullopt;
    };
    std::ostringstream body;
    body << "<h1>" << render::html_escape(f.title) << "</h1><p>" << render::html_escape(f.summary) << "</p>";
    body << "<h2>Table</h2><p class=\"note\">Click a column's header to sort.</p>" << render::html_table(render::points_table(f.points, f.axes, f.columns), "points");

    // Plots.
    render::ReportPlots plots;
    std::string sections, notes;
    if (f.is_sweep) render::sweep_plots(f.points, f.axes, f.command, bending_length, plots);
    for (const auto& p : f.points) {
        if (p.status != "done") continue;
        if (f.command == "kes-test") render::kes_section(p, csv, plots, f.is_sweep ? p.name + ": " : "");
        if (f.command == "fit") render::fit_section(p, csv, fit_curves(p, notes), plots);
        if (f.command == "experiment") sections += render::experiment_section(p, bending_length, display_colour, plots);
        if (f.command == "cusick" && !f.is_sweep) sections += render::cusick_section(p, shadow_outline(p), plots);
        if (f.command == "drape" && !f.is_sweep) sections += render::drape_section(p);
        if (f.command == "garment" && !f.is_sweep) sections += render::garment_section(p, plots);
    }
    body << sections;
    if (plots.count > 0) body << "<h2>Plots</h2>" << notes << "<div class=\"plots\">" << plots.html << "</div>";
    body << "<h2>Pictures</h2>" << render::gallery(f.points, [](const PointView& p, const std::string& n) {
        return read_output_file((p.dir / n).string()).value_or("");
    });

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
