// The experiment job (experiment.hpp; woven experiment cube|map|figure1): the paper's
// experiments (Sec. 6, Fig. 1, Fig. 8), drawn and measured. Each experiment's drapes are a sweep plan (examples/experiment-cube.toml, ...)
// written into its sweep folder (--sweep, default out/experiment-<name>) and run there by the
// sweep's own point loop (run_sweep_points: resume, verify, --jobs, ranks); the experiment then
// reads each point's report.json and drape.obj back and writes pictures, tables (Markdown) and
// the raw numbers (JSON) into --out.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>


#include <nlohmann/json.hpp>

#include "woven/analysis/leaving_folds.hpp"
#include "woven/analysis/folds.hpp"
#include "woven/app/drape_report.hpp"
#include "woven/batch/experiment.hpp"
#include "woven/app/files.hpp"
#include "woven/app/material.hpp"
#include "woven/app/progress.hpp"
#include "woven/app/run_checks.hpp"
#include "woven/app/scene_view.hpp"
#include "woven/batch/sweep.hpp"
#include "woven/batch/sweep_parts.hpp"
#include "woven/common/error.hpp"
#include "woven/common/format.hpp"
#include "woven/io/corner_map_file.hpp"
#include "woven/io/fabric_file.hpp"
#include "woven/io/input_file.hpp"
#include "woven/io/mesh_file.hpp"
#include "woven/io/output.hpp"
#include "woven/io/output_checks.hpp"
#include "woven/io/output_file.hpp"
#include "woven/io/output_set.hpp"
#include "woven/io/scene_file.hpp"
#include "woven/batch/sweep_plan.hpp"
#include "woven/render/drape_view.hpp"
#include "woven/render/figure.hpp"
#include "woven/render/instrument_plots.hpp"

namespace woven::batch {

using namespace woven::app;

namespace {

/// The corners' structures (analysis/leaving_folds.hpp).
using Structure = analysis::LeavingFolds;
using analysis::kCornerConeDeg;
using analysis::kDiagonalToleranceDeg;
using analysis::structure_name;

std::string which_name(const ExperimentRequest& o) { return name_of(kExperimentNames, o.which); }

/// Thrown when SIGINT or SIGTERM stopped the drapes or the experiment before it published: it
/// ends without publishing, so its folder keeps the previous complete set.
struct ExperimentInterrupted {
    int signal = 0;  ///< 0: drape's interrupt flag (interrupted_exit_code)
};

/// The experiment's JSON (its set's manifest) holds finite numbers only; a drape's `folds` may
/// be null where the scene has no box to analyse. RuntimeError (exit 1, nothing published) else.
void require_finite_experiment(nlohmann::json j, const std::string& what)
{
    std::function<void(nlohmann::json&)> strip = [&strip](nlohmann::json& v) {
        if (v.is_object()) {
            if (v.contains("folds") && v["folds"].is_null()) v.erase("folds");
            for (auto& e : v) strip(e);
        } else if (v.is_array()) {
            for (auto& e : v) strip(e);
        }
    };
    strip(j);
    io::require_finite(j, what);
}

/// One drape and what it measured, read back from its point folder in the sweep.
struct Outcome {
    std::string fabric;
    std::uint64_t seed = 0;
    Positions x;  ///< from drape.obj (9 significant digits); empty unless asked for
    model::Grid grid;
    bool converged = false;
    int steps = 0;
    double wall_s = 0;
    double energy_J = 0;
    nlohmann::json folds;  ///< the drape's report.json `folds` (null: no box to analyse)
    /// The billows of each section (0.10 m, 0.20 m below the top) at each corner, from `folds`.
    std::vector<std::array<std::vector<analysis::Billow>, 4>> sections;
    bool has_folds() const { return !folds.is_null(); }
};


/// The drape of `point` in `sweep_dir` (a complete point folder: run_sweep_points verified it):
/// its report.json, and with `positions` its particles from drape.obj. RuntimeError when the
/// folder does not hold a drape's report of the form written by `woven drape`.
Outcome read_outcome(const std::string& sweep_dir, const batch::SweepPoint& point, const std::string& fabric_label, bool positions)
{
    const std::string dir = join_path(sweep_dir, point.name);
    const std::string path = join_path(dir, "report.json");
    Outcome d;
    d.fabric = fabric_label;
    try {
        const nlohmann::json r = io::read_output_json(path, io::kMaxManifestBytes, "a drape's report.json");
        d.seed = r.at("seed").get<std::uint64_t>();
        d.converged = r.at("converged").get<bool>();
        d.steps = r.at("steps").get<int>();
        d.wall_s = r.at("wall_time_s").get<double>();
        d.energy_J = r.at("energy").at("total_J").get<double>();
        d.grid.nu = r.at("grid").at(0).get<int>();
        d.grid.nv = r.at("grid").at(1).get<int>();
        d.folds = r.at("folds");
        if (d.has_folds()) {
            const std::size_t n = r["folds"].at("sections").size();
            d.sections.resize(n);
            for (const auto& corner : d.folds.at("corners")) {
                const int c = corner.at("corner").get<int>();
                if (c < 0 || c > 3) throw RuntimeError(path + ": folds.corners: a corner outside 0 .. 3");
                for (std::size_t s = 0; s < n; ++s) {
                    const auto& angles = corner.at("angles_deg").at(s);
                    const auto& standout = corner.at("standout_m").at(s);
                    for (std::size_t b = 0; b < angles.size(); ++b) {
                        analysis::Billow billow;
                        billow.corner = c;
                        billow.angle_deg = angles.at(b).get<double>();
                        billow.standout_m = standout.at(b).get<double>();
                        d.sections[s][c].push_back(billow);
                    }
                }
            }
        }
    } catch (const nlohmann::json::exception& e) {
        throw RuntimeError(path + ": not a drape's report.json (" + e.what() + ")");
    }
    if (positions) {
        const std::string obj = join_path(dir, "drape.obj");
        const geometry::TriangleMesh mesh = io::load_obj_mesh(obj);
        if (static_cast<long long>(mesh.vertices.size()) != static_cast<long long>(d.grid.nu) * d.grid.nv)
            throw RuntimeError(obj + ": " + std::to_string(mesh.vertices.size()) + " vertices, expected the report's grid " +
                               std::to_string(d.grid.nu) + " x " + std::to_string(d.grid.nv));
        d.x.assign(mesh.vertices.begin(), mesh.vertices.end());
    }
    return d;
}

/// Writes `text` to `path` (through a temporary and a rename) unless the file holds it already.
void write_if_changed(const std::string& path, const std::string& text)
{
    {
        std::ifstream in(path, std::ios::binary);
        if (in) {
            std::ostringstream s;
            s << in.rdbuf();
            if (s.str() == text) return;
        }
    }
    write_atomic(path, text);
}

/// The plan's head: its name, description and command (every experiment drapes).
std::string plan_head(const std::string& which, const std::string& description)
{
    return "# The drapes of `woven experiment " + which +
           "` (docs/EXPERIMENTS.md) as a sweep plan (docs/SWEEP-FORMAT.md): the experiment\n"
           "# writes it into its sweep folder, runs it there and builds its figures and tables from the points.\n"
           "name = \"experiment-" + which + "\"\ndescription = \"" + description + "\"\ncommand = \"drape\"\n";
}

/// The plan's [options]: `scene` and `seed` when not an axis, the experiment's --grid and --threads.
std::string plan_options(const ExperimentRequest& o, bool scene_cube, bool seed_one)
{
    std::string t = "\n[options]\n";
    if (scene_cube) t += "scene = \"cube\"\n";
    if (seed_one) t += "seed = 1\n";
    if (o.grid) t += "grid = " + std::to_string(*o.grid) + "\n";
    t += "threads = " + std::to_string(o.threads) + "\n";
    t += "render = false  # the experiment draws its own pictures from drape.obj\n";
    return t;
}

/// A plan run for an experiment: the plan, or none when this process builds nothing (--plan-only,
/// or a rank whose points are done while another rank's still run).
struct PlanRun {
    std::optional<batch::SweepPlan> plan;
    std::string dir;
    std::string message;  ///< without a plan: what the command prints
};

/// The sweep folder, --jobs and the shard, checked before anything is written.
struct SweepPlace {
    std::string dir;
    SweepRunOptions run;
};

SweepPlace sweep_place(const ExperimentRequest& o)
{
    SweepPlace p;
    p.dir = path_given(o.sweep, "--sweep").value_or(join_path("out", "experiment-" + which_name(o)));
    p.run.executable = o.executable;
    p.run.jobs = static_cast<int>(integer_in_range(o.jobs, "--jobs", kJobsRange[0], kJobsRange[1]));
    p.run.shard = o.shard;
    p.run.on_line = o.on_sweep_line;
    return p;
}

/// Writes `plan_text` as <sweep>/plan.toml and `files` (paths relative to the sweep folder)
/// where they differ, reads the plan back as `woven sweep` reads it, and (unless --plan-only)
/// runs it with run_sweep_points: the points of this shard whose folders do not verify run,
/// each announced on stderr as "woven: experiment: <what> ..." (`what`: one per point, in plan
/// order). SIGINT/SIGTERM: ExperimentInterrupted; a failed point: RuntimeError.
PlanRun run_experiment_plan(const ExperimentRequest& o, SweepPlace place, const std::string& plan_text,
                            const std::vector<std::pair<std::string, std::string>>& files, const std::vector<std::string>& what)
{
    PlanRun r;
    r.dir = place.dir;
    make_output_dir(r.dir);
    for (const auto& [name, text] : files) {
        std::filesystem::create_directories(std::filesystem::path(join_path(r.dir, name)).parent_path());
        write_if_changed(join_path(r.dir, name), text);
    }
    const std::string plan_path = join_path(r.dir, "plan.toml");
    write_if_changed(plan_path, plan_text);
    std::vector<std::string> warnings;
    batch::SweepPlan plan = batch::load_sweep_plan(plan_path, &warnings);
    if (o.on_warnings) o.on_warnings(warnings);
    if (plan.size() != what.size()) throw RuntimeError(plan_path + ": " + std::to_string(plan.size()) + " points, expected " + std::to_string(what.size()));
    if (o.plan_only) {
        r.message = "wrote " + plan_path + " (" + std::to_string(plan.size()) + " drapes); run it with `woven sweep " + plan_path + " --out " +
                    r.dir + "`, then `woven experiment " + which_name(o) + " --sweep " + r.dir + "` builds the figures and tables from it";
        return r;
    }
    place.run.on_start = [&what, &o](const batch::SweepPoint& p) {
        if (o.on_drape) o.on_drape(what[p.index]);
    };
    const SweepRunResult res = run_sweep_points(plan, r.dir, place.run);
    if (res.signal != 0) throw ExperimentInterrupted{res.signal};
    if (res.merged.done < plan.size()) {
        if (res.failed == 0 && place.run.shard.count > 1) {
            r.message = "experiment " + which_name(o) + ": this shard's drapes are done, " + std::to_string(res.merged.done) + " of " +
                        std::to_string(plan.size()) + " in all; the rank that finds every drape done writes the figures and tables (or run " +
                        "`woven experiment " + which_name(o) + " --sweep " + r.dir + "` once they are)";
            return r;
        }
        throw RuntimeError("experiment " + which_name(o) + ": " + std::to_string(res.merged.failed) + " of " + std::to_string(plan.size()) +
                           " drapes failed and " + std::to_string(res.merged.missing) + " are missing (see " + join_path(r.dir, "failed") +
                           "/); nothing written; run it again to retry them");
    }
    r.plan = std::move(plan);
    return r;
}

/// Stops before publishing when SIGINT or SIGTERM came after the drapes.
void check_not_interrupted()
{
    if (const int sig = sweep_signal_received()) throw ExperimentInterrupted{sig};
}

render::DrapeScene drape_scene(const Outcome& d, const io::SceneSpec& scene, const kes::FabricData& fabric)
{
    return scene_view(render::grid_surface(d.x, d.grid.nu, d.grid.nv), scene.obstacles, fabric, &scene.camera);
}

/// "1 (+49)" / "2 (-21, +19)" / "0" for one corner at one depth.
std::string corner_cell(const std::vector<analysis::Billow>& b)
{
    std::string s = std::to_string(b.size());
    if (b.empty()) return s;
    s += " (";
    for (std::size_t k = 0; k < b.size(); ++k) s += (k ? ", " : "") + strf("%+.0f", b[k].angle_deg);
    return s + ")";
}

std::string provenance(const std::string& command) { return std::string("Made by `") + command + "` (woven " + WOVEN_VERSION + ")."; }

nlohmann::json outcome_json(const Outcome& d)
{
    nlohmann::json j{{"fabric", d.fabric}, {"seed", d.seed},     {"converged", d.converged},
                     {"steps", d.steps},   {"wall_s", d.wall_s}, {"energy_J", d.energy_J}};
    j["folds"] = d.folds;
    return j;
}

// ---------------------------------------------------------------------------------------------
// woven experiment cube

ExperimentResult run_cube(const ExperimentRequest& o)
{
    const std::string out_dir = o.out.string();
    std::vector<std::string> warnings;
    (void)io::find_scene("cube", &warnings);  // warnings once
    std::vector<kes::FabricData> fabrics;
    for (const auto& f : o.fabrics) fabrics.push_back(io::find_fabric(f, &warnings));
    if (o.on_warnings) o.on_warnings(warnings);
    const SweepPlace place = sweep_place(o);
    if (!o.plan_only) {
        make_output_dir(out_dir);
        check_output_targets(out_dir, {"cube_figure.png", "cube_folds.md", "cube_results.json"});
    }

    // The drapes: a plan of fabric x seed over the cube (examples/experiment-cube.toml).
    std::string plan = plan_head("cube", "The cube experiment (Sec. 6, Fig. 8): cotton, wool and polyester/cotton over the 0.5 m cube, seeds 1.." +
                                             std::to_string(o.seeds)) +
        "\n[axes]\nfabric = [";
    std::vector<std::string> what;
    for (std::size_t f = 0; f < o.fabrics.size(); ++f) {
        plan += (f ? ", \"" : "\"") + o.fabrics[f] + "\"";
        for (int s = 1; s <= o.seeds; ++s) what.push_back("cube, " + o.fabrics[f] + ", seed " + std::to_string(s));
    }
    plan += "]\nseed = {from = 1, to = " + std::to_string(o.seeds) + "}\n" + plan_options(o, true, false);
    const PlanRun pr = run_experiment_plan(o, place, plan, {}, what);
    if (!pr.plan) return {pr.message, nlohmann::json()};
    const SweepFolderLock lock(pr.dir);  // ranks that find every drape done build one after another
    const std::vector<batch::SweepPoint> points = pr.plan->points();
    io::OutputSet set(out_dir, {"cube_figure.png", "cube_folds.md"});

    std::vector<std::vector<Outcome>> runs(fabrics.size());
    std::vector<io::SceneSpec> scenes;
    std::size_t k = 0;
    for (std::size_t f = 0; f < fabrics.size(); ++f) {
        scenes.push_back(io::find_scene("cube"));
        for (int s = 1; s <= o.seeds; ++s) runs[f].push_back(read_outcome(pr.dir, points[k++], o.fabrics[f], s == 1));
    }

    // The figure: one column per fabric (seed 1), rows corner, side, top.
    const int pw = 480, ph = 360, label_h = 40, margin_l = 90;
    const std::vector<std::pair<render::View, std::string>> rows = {
        {render::View::CORNER, "corner"}, {render::View::SIDE, "side"}, {render::View::TOP, "top"}};
    render::Image fig = render::blank(margin_l + pw * static_cast<int>(fabrics.size()), label_h + ph * 3 + 30);
    Activity figure_word("drawing the figure's pictures");
    for (std::size_t f = 0; f < fabrics.size(); ++f) {
        const render::DrapeScene ds = drape_scene(runs[f][0], scenes[f], fabrics[f]);
        const int x0 = margin_l + pw * static_cast<int>(f);
        render::draw_label(fig, o.fabrics[f], x0 + (pw - render::label_width(o.fabrics[f], 3)) / 2, 10, 3);
        for (std::size_t r = 0; r < rows.size(); ++r) {
            figure_word.update(static_cast<double>(f * rows.size() + r) / static_cast<double>(fabrics.size() * rows.size()),
                               o.fabrics[f] + ", " + rows[r].second);
            render::paste(fig, render_view(ds, rows[r].first, pw, ph, o.fabrics[f] + " " + rows[r].second), x0,
                          label_h + ph * static_cast<int>(r));
            if (f == 0) render::draw_label(fig, rows[r].second, 10, label_h + ph * static_cast<int>(r) + ph / 2 - 7, 3);
        }
    }
    const std::string note = "seed 1 of each; " + std::string("woven ") + WOVEN_VERSION;
    render::draw_label(fig, note, margin_l, label_h + ph * 3 + 8, 2, Vec3(0.3, 0.3, 0.3));
    set.add("cube_figure.png", render::encode_png(fig, join_path(out_dir, "cube_figure.png")));

    // The fold table and the per-seed statistics.
    const auto& depths = analysis::FoldOptions{}.depths_m;
    std::ostringstream md;
    md << "# The cube experiment: corner folds\n\n" << provenance(o.command) << "\n\n";
    md << "The paper's Sec. 6: 1 m x 1 m cloth, " << runs[0][0].grid.nu << " x " << runs[0][0].grid.nv
       << " particles, over a 0.5 m cube; seeds 1.." << o.seeds << ". Each cell: billows leaving the corner on the section "
       << strf("%.2f", depths[0]) << " m below the top face, then on the one " << strf("%.2f", depths[1])
       << " m below, with each billow's direction from the corner's diagonal (degrees, counter-clockwise seen from above). "
       << "Corners: 0 (+x +y), 1 (-x +y), 2 (-x -y), 3 (+x -y); warp threads run along y, weft along x.\n\n";
    md << "| fabric | seed | converged | corner 0 | corner 1 | corner 2 | corner 3 |\n|---|---|---|---|---|---|---|\n";
    nlohmann::json all = nlohmann::json::array();
    for (std::size_t f = 0; f < fabrics.size(); ++f)
        for (const Outcome& d : runs[f]) {
            all.push_back(outcome_json(d));
            md << "| " << d.fabric << " | " << d.seed << " | " << (d.converged ? "yes" : "no") << " |";
            for (int c = 0; c < 4; ++c) {
                md << " ";
                for (std::size_t h = 0; h < d.sections.size(); ++h) md << (h ? " / " : "") << corner_cell(d.sections[h][c]);
                md << " |";
            }
            md << "\n";
        }
    md << "\n## How often each corner structure appears\n\nOver all seeds and the four corners, on the section " << strf("%.2f", depths[0])
       << " m below the top. Only billows within " << strf("%.0f", kCornerConeDeg)
       << " degrees of the corner's diagonal count as leaving the corner (further round a billow stands in front of a side: "
       << "a wave of the side's panel), and of those only the ones standing out at least " << strf("%.2g", analysis::kFoldStandoutFraction)
       << " of the corner's largest (a smaller one is a ripple on a fold's flank); a single one counts as on the diagonal within "
       << strf("%.0f", kDiagonalToleranceDeg)
       << " degrees of it:\n\n";
    md << "| fabric | corners | single, on the diagonal | single, off the diagonal | two or more folds | none | mean angle of single "
          "billows (deg) | mean abs angle (deg) | distinct drapes |\n|---|---|---|---|---|---|---|---|---|\n";
    nlohmann::json stats = nlohmann::json::object();
    for (std::size_t f = 0; f < fabrics.size(); ++f) {
        analysis::CornerCounts counts;
        std::vector<double> energies;
        for (const Outcome& d : runs[f]) {
            energies.push_back(d.energy_J);
            if (!d.has_folds() || d.sections.empty()) continue;
            for (int c = 0; c < 4; ++c) counts.add(d.sections[0][c]);
        }
        const int distinct = analysis::distinct_energies(energies);
        std::map<Structure, int>& count = counts.count;
        const int corners = counts.corners, singles = counts.singles;
        const double sum = counts.sum_angle_deg, sum_abs = counts.sum_abs_angle_deg;
        auto pct = [&](Structure s) { return corners ? strf("%.0f %%", 100.0 * count[s] / corners) : std::string("-"); };
        md << "| " << o.fabrics[f] << " | " << corners << " | " << pct(Structure::SINGLE_DIAGONAL) << " | " << pct(Structure::SINGLE_OFFSET)
           << " | " << pct(Structure::MULTIPLE) << " | " << pct(Structure::NONE) << " | " << (singles ? strf("%+.1f", sum / singles) : "-")
           << " | " << (singles ? strf("%.1f", sum_abs / singles) : "-") << " | " << distinct << " of " << energies.size() << " |\n";
        stats[o.fabrics[f]] = {{"corners", corners},
                               {"single_diagonal", count[Structure::SINGLE_DIAGONAL]},
                               {"single_offset", count[Structure::SINGLE_OFFSET]},
                               {"multiple", count[Structure::MULTIPLE]},
                               {"none", count[Structure::NONE]},
                               {"distinct_drapes", distinct}};
    }
    md << "\n\"distinct drapes\": seeds whose final energies differ (by more than 1e-9 relative); with a "
          "symmetric start and no perturbation every seed gives the same drape.\n\n![cube figure](cube_figure.png)\n";
    set.add("cube_folds.md", md.str());
    nlohmann::json j{{"command", o.command},
                     {"version", WOVEN_VERSION},
                     {"runs", all},
                     {"statistics", stats},
                     {"diagonal_tolerance_deg", kDiagonalToleranceDeg},
                     {"corner_cone_deg", kCornerConeDeg}};
    require_finite_experiment(j, "experiment cube");
    check_not_interrupted();
    j["files"] = set.files_json();
    set.publish("cube_results.json", j.dump(1) + "\n");
    return {"wrote " + join_path(out_dir, "cube_figure.png") + ", cube_folds.md, cube_results.json", std::move(j)};
}

// ---------------------------------------------------------------------------------------------
// woven experiment map

/// A synthetic fabric: the cotton's W and shear, bending from the Peirce bending length
/// c = (B / W)^(1/3) of the geometric-mean rigidity B = sqrt(B_warp B_weft) and the ratio
/// B_warp / B_weft; 2HB half of B (gf.cm/cm per gf.cm^2/cm, cotton's order).
std::string synthetic_fabric(double ratio, double length_cm, double W_mg_cm2, double G)
{
    const double W_gf_cm2 = W_mg_cm2 * 1e-3;
    const double B = length_cm * length_cm * length_cm * W_gf_cm2;
    const double bw = B * std::sqrt(ratio), bf = B / std::sqrt(ratio);
    std::ostringstream t;
    t.precision(6);
    t << "name = \"map\"\nsource = \"synthetic: woven experiment map\"\n";
    t << "areal_density_mg_cm2 = " << W_mg_cm2 << "\n";
    t << "[bending.warp]\nB = " << bw << "\n2HB = " << 0.5 * bw << "\n";
    t << "[bending.weft]\nB = " << bf << "\n2HB = " << 0.5 * bf << "\n";
    t << "[shear]\nG = " << G << "\n2HG = " << 1.5 * G << "\n2HG5 = " << 2.25 * G << "\n";
    return t.str();
}

/// (bending length cm, warp/weft ratio) of a fabric, from its KES values.
std::pair<double, double> map_position(const kes::FabricData& f)
{
    const KesValues v = kes_values(f);
    const double B = std::sqrt(v.B_warp * v.B_weft);
    return {std::cbrt(B / (v.W * 1e-3)), v.B_warp / v.B_weft};
}

/// One cell of the corner map (a synthetic fabric over the cube).
struct MapCell {
    double ratio, length;
    bool converged = false;
    double mean_billows = 0, mean_abs_angle = 0;
    Structure majority = Structure::NONE;
    std::vector<std::vector<analysis::Billow>> corners;
};

/// One cell of the corner map: its drape's corners (the billows of each on the first section)
/// read as the structure most of them show, the mean count of billows leaving a corner and the
/// mean |angle| of single ones.
MapCell analyse_cell(double r, double c, bool converged, bool has_folds, const std::vector<std::vector<analysis::Billow>>& corner_billows)
{
    MapCell cell;
    cell.ratio = r;
    cell.length = c;
    cell.converged = converged;
    if (has_folds) cell.corners.assign(corner_billows.begin(), corner_billows.begin() + 4);
    const analysis::CornerSummary summary = analysis::summarise_corners(has_folds, corner_billows);
    cell.mean_billows = summary.mean_billows;
    cell.mean_abs_angle = summary.mean_abs_angle;
    cell.majority = summary.majority;
    return cell;
}

/// corner_map.png: a cell per fabric, coloured by the majority structure; the paper's fabrics
/// (`paper`, named `names`) marked where their bending length and ratio put them.
render::Image map_picture(const std::vector<MapCell>& cells, const std::vector<double>& ratios, const std::vector<double>& lengths,
                          const std::vector<kes::FabricData>& paper, const std::vector<std::string>& names)
{
    const Structure legend[] = {Structure::SINGLE_DIAGONAL, Structure::SINGLE_OFFSET, Structure::MULTIPLE, Structure::NONE};
    std::vector<render::MapCellView> views;
    for (const MapCell& c : cells)
        views.push_back({static_cast<int>(std::find(legend, legend + 4, c.majority) - legend), c.mean_billows, c.mean_abs_angle, c.converged});
    std::vector<render::MapMark> marks;
    for (std::size_t f = 0; f < paper.size(); ++f) {
        const auto [len, ratio] = map_position(paper[f]);
        marks.push_back({names[f], len, ratio, render::fabric_color(paper[f].color).array().pow(1 / 2.2).matrix()});
    }
    std::vector<std::string> structures;
    for (Structure s : legend) structures.push_back(structure_name(s));
    return render::corner_map_picture(views, ratios, lengths, marks, structures, std::string("woven ") + WOVEN_VERSION + "; W, G of cotton");
}

/// corner_map.md: the cells' table and the paper's fabrics on the map.
std::string map_markdown(const ExperimentRequest& o, const std::vector<MapCell>& cells, const std::vector<kes::FabricData>& paper,
                         const KesValues& cv, const std::optional<io::CornerMap>& reused)
{
    std::ostringstream md;
    md << "# Corner-structure map\n\n" << provenance(o.command) << "\n\n";
    if (o.reuse)
        md << "The drapes are those of `" << (reused->command.empty() ? "?" : reused->command) << "` (woven "
           << (reused->version.empty() ? "?" : reused->version) << "), read back from its corner_map.json and analysed again.\n\n";
    md << "Synthetic fabrics with the cotton's W (" << cv.W << " mg/cm2) and shear (G " << cv.G
       << " gf/(cm.deg)), bending from the bending length c and the warp/weft ratio; one drape each (seed 1) over the cube, "
       << "section 0.10 m below the top. Cell: the structure most corners show, the mean count per corner of billows leaving it (within "
       << strf("%.0f", kCornerConeDeg)
       << " degrees of the diagonal and standing out at least " << strf("%.2g", analysis::kFoldStandoutFraction)
       << " of the corner's largest), the mean |angle| of single ones from the diagonal; the last column lists every billow in each "
          "corner's quadrant.\n\n";
    md << "| warp/weft | c (cm) | B warp | B weft | structure | billows/corner | mean abs angle (deg) | corners (count (angles)) "
          "|\n|---|---|---|---|---|---|---|---|\n";
    for (const MapCell& c : cells) {
        const double B = std::pow(c.length, 3) * cv.W * 1e-3;
        md << "| " << strf("%.3g", c.ratio) << " | " << strf("%.2g", c.length) << " | " << strf("%.3g", B * std::sqrt(c.ratio)) << " | "
           << strf("%.3g", B / std::sqrt(c.ratio)) << " | " << structure_name(c.majority) << (c.converged ? "" : " (not converged)") << " | "
           << strf("%.2f", c.mean_billows) << " | " << strf("%.0f", c.mean_abs_angle) << " |";
        for (const auto& b : c.corners) md << " " << corner_cell(b);
        md << " |\n";
    }
    md << "\nThe paper's fabrics on the map:\n\n| fabric | c (cm) | warp/weft |\n|---|---|---|\n";
    for (std::size_t f = 0; f < paper.size(); ++f) {
        const auto [len, ratio] = map_position(paper[f]);
        md << "| " << o.fabrics[f] << " | " << strf("%.2f", len) << " | " << strf("%.2f", ratio) << " |\n";
    }
    md << "\n![corner map](corner_map.png)\n";
    return md.str();
}

ExperimentResult run_map(const ExperimentRequest& o)
{
    const std::string out_dir = o.out.string();
    if (o.reuse && o.plan_only) throw InputError(kCommandLine, "--plan-only", "expected no --reuse (reused drapes need no plan)");
    const int nr = o.map_rows, nc = o.map_columns;
    const auto in_range = [](int n) { return n >= kMapGridRange[0] && n <= kMapGridRange[1]; };
    if (!in_range(nr) || !in_range(nc)) throw InputError(kCommandLine, "--map-grid", map_grid_expected());
    std::vector<std::string> warnings;
    const kes::FabricData cotton = io::find_fabric("cotton", &warnings);
    std::vector<kes::FabricData> paper;
    for (const auto& f : o.fabrics) paper.push_back(io::find_fabric(f, &warnings));
    if (o.on_warnings) o.on_warnings(warnings);
    const KesValues cv = kes_values(cotton);

    // Ratios 1/4 .. 4 evenly in log2; bending lengths 1 .. 5 cm evenly.
    std::vector<double> ratios, lengths;
    for (int i = 0; i < nr; ++i) ratios.push_back(std::pow(2.0, -2.0 + 4.0 * i / (nr - 1)));
    for (int i = 0; i < nc; ++i) lengths.push_back(1.0 + 4.0 * i / (nc - 1));
    std::vector<MapCell> cells;
    nlohmann::json jcells = nlohmann::json::array();
    // --reuse: the drapes of an earlier run (its corner_map.json), analysed again (no draping);
    // read and checked whole before anything is written (io::load_corner_map).
    std::optional<io::CornerMap> reused;
    if (o.reuse) reused = io::load_corner_map(o.reuse->string());
    auto reused_cell = [&](double r, double c) -> const io::CornerMapCell& {
        for (const auto& cell : reused->cells)
            if (std::abs(cell.ratio_warp_weft - r) < 1e-9 * r && std::abs(cell.bending_length_cm - c) < 1e-9 * c) return cell;
        throw InputError(o.reuse->string(), "cells",
                         "no drape for ratio " + strf("%.3g", r) + ", length " + strf("%.3g", c) + " cm (use the same --map-grid)");
    };
    if (reused)
        for (double r : ratios)
            for (double c : lengths) reused_cell(r, c);
    std::optional<SweepPlace> place;
    if (!o.reuse) place = sweep_place(o);
    if (!o.plan_only) {
        make_output_dir(out_dir);  // after every input is read: a bad one writes nothing
        check_output_targets(out_dir, {"corner_map.png", "corner_map.md", "corner_map.json"});
    }
    // The drapes: a plan with one fabric file per cell (<sweep>/fabrics/ratio-R_length-C.toml).
    std::optional<PlanRun> pr;
    std::optional<SweepFolderLock> lock;
    std::vector<batch::SweepPoint> points;
    if (!o.reuse) {
        std::string plan = plan_head("map", "The corner map: synthetic fabrics (cotton's W and shear) of warp/weft bending ratio " +
                                                strf("%.3g", ratios.front()) + " .. " + strf("%.3g", ratios.back()) + " by bending length " +
                                                strf("%.3g", lengths.front()) + " .. " + strf("%.3g", lengths.back()) + " cm over the cube") +
            "\n[axes]\nfabric = [\n";
        std::vector<std::pair<std::string, std::string>> files;
        std::vector<std::string> what;
        for (double r : ratios)
            for (double c : lengths) {
                const std::string name = "fabrics/ratio-" + strf("%.3g", r) + "_length-" + strf("%.3g", c) + ".toml";
                files.emplace_back(name, synthetic_fabric(r, c, cv.W, cv.G));
                plan += "  \"" + name + "\",\n";
                what.push_back("cube, ratio " + strf("%.3g", r) + ", length " + strf("%.3g", c) + " cm, seed 1");
            }
        plan += "]\n" + plan_options(o, true, true);
        pr = run_experiment_plan(o, *place, plan, files, what);
        if (!pr->plan) return {pr->message, nlohmann::json()};
        lock.emplace(pr->dir);
        points = pr->plan->points();
    }
    io::OutputSet set(out_dir, {"corner_map.png", "corner_map.md"});
    std::size_t next = 0;
    for (double r : ratios)
        for (double c : lengths) {
            Outcome d;
            nlohmann::json jc;
            std::vector<std::vector<analysis::Billow>> corner_billows(4);
            if (o.reuse) {
                const io::CornerMapCell& rc = reused_cell(r, c);
                jc = rc.json;
                d.converged = rc.converged;
                for (int k = 0; k < 4; ++k) corner_billows[k] = rc.corners[k];
            } else {
                d = read_outcome(pr->dir, points[next++], "ratio " + strf("%.3g", r) + ", length " + strf("%.3g", c) + " cm", false);
                jc = outcome_json(d);
                if (d.has_folds() && !d.sections.empty())
                    for (int k = 0; k < 4; ++k) corner_billows[k] = d.sections[0][k];
            }
            const MapCell cell = analyse_cell(r, c, d.converged, o.reuse ? reused_cell(r, c).has_folds : d.has_folds(), corner_billows);
            jc["ratio_warp_weft"] = r;
            jc["bending_length_cm"] = c;
            jc["structure"] = structure_name(cell.majority);
            jcells.push_back(jc);
            cells.push_back(cell);
        }

    const render::Image img = map_picture(cells, ratios, lengths, paper, o.fabrics);
    set.add("corner_map.png", render::encode_png(img, join_path(out_dir, "corner_map.png")));

    set.add("corner_map.md", map_markdown(o, cells, paper, cv, reused));
    nlohmann::json j{{"command", o.command}, {"version", WOVEN_VERSION}, {"cells", jcells}};
    if (o.reuse)
        j["drapes_from"] = {{"file", o.reuse->string()}, {"command", reused->command}, {"version", reused->version}};
    require_finite_experiment(j, "experiment map");
    check_not_interrupted();
    if (o.reuse && interrupt_requested()) throw ExperimentInterrupted{};
    j["files"] = set.files_json();
    set.publish("corner_map.json", j.dump(1) + "\n");
    return {"wrote " + join_path(out_dir, "corner_map.png") + ", corner_map.md, corner_map.json", std::move(j)};
}

// ---------------------------------------------------------------------------------------------
// woven experiment figure1

ExperimentResult run_figure1(const ExperimentRequest& o)
{
    const std::string out_dir = o.out.string();
    std::vector<std::string> warnings;
    const std::vector<std::string> names = {"chair", "table"};
    std::vector<io::SceneSpec> scenes;
    std::vector<kes::FabricData> fabrics;
    for (const auto& name : names) {
        scenes.push_back(io::find_scene(name, &warnings));
        fabrics.push_back(io::find_fabric(scenes.back().fabric, &warnings));
    }
    if (o.on_warnings) o.on_warnings(warnings);
    const SweepPlace place = sweep_place(o);
    if (!o.plan_only) {
        make_output_dir(out_dir);
        check_output_targets(out_dir, {"figure1_chair.png", "figure1_table.png", "figure1.md", "figure1.json"});
    }
    // The drapes: each scene with its own fabric, seed 1 (examples/experiment-figure1.toml).
    std::string plan = plan_head("figure1", "Fig. 1: the chair and the end table, each with its scene's fabric") + "\n[axes]\nscene = [";
    std::vector<std::string> what;
    for (std::size_t k = 0; k < names.size(); ++k) {
        plan += (k ? ", \"" : "\"") + names[k] + "\"";
        what.push_back(names[k] + ", " + scenes[k].fabric + ", seed 1");
    }
    plan += "]\n" + plan_options(o, false, true);
    const PlanRun pr = run_experiment_plan(o, place, plan, {}, what);
    if (!pr.plan) return {pr.message, nlohmann::json()};
    const SweepFolderLock lock(pr.dir);
    const std::vector<batch::SweepPoint> points = pr.plan->points();
    io::OutputSet set(out_dir, {"figure1_chair.png", "figure1_table.png", "figure1.md"});
    std::ostringstream md;
    md << "# Fig. 1: a chair and an end table\n\n"
       << provenance(o.command) << "\n\n| scene | converged | steps | wall (s) |\n|---|---|---|---|\n";
    nlohmann::json runs = nlohmann::json::array();
    for (std::size_t k = 0; k < names.size(); ++k) {
        const std::string& name = names[k];
        const io::SceneSpec& scene = scenes[k];
        const Outcome d = read_outcome(pr.dir, points[k], scene.fabric, true);
        const render::DrapeScene ds = drape_scene(d, scene, fabrics[k]);
        const std::string png = "figure1_" + name + ".png";
        set.add(png, render::encode_png(render_view(ds, render::View::SCENE, 1024, 768, png), join_path(out_dir, png)));
        md << "| " << name << " (" << scene.fabric << ", " << d.grid.nu << " x " << d.grid.nv << ") | " << (d.converged ? "yes" : "no")
           << " | " << d.steps << " | " << strf("%.0f", d.wall_s) << " |\n";
        runs.push_back(outcome_json(d));
        runs.back()["scene"] = name;
    }
    md << "\n![chair](figure1_chair.png)\n\n![table](figure1_table.png)\n";
    set.add("figure1.md", md.str());
    nlohmann::json j{{"command", o.command}, {"version", WOVEN_VERSION}, {"runs", runs}};
    require_finite_experiment(j, "experiment figure1");
    check_not_interrupted();
    j["files"] = set.files_json();
    set.publish("figure1.json", j.dump(1) + "\n");
    return {"wrote " + join_path(out_dir, "figure1_chair.png") + ", figure1_table.png, figure1.md", std::move(j)};
}

}  // namespace

std::string map_grid_expected()
{
    return "expected RxL: R ratios by L bending lengths, each an integer in [" + std::to_string(kMapGridRange[0]) + ", "
        + std::to_string(kMapGridRange[1]) + "]";
}

ExperimentResult experiment(const ExperimentRequest& request)
{
    const MonitorScope monitor(request.monitor);
    integer_in_range(request.seeds, "--seeds", kExperimentSeedsRange[0], kExperimentSeedsRange[1]);
    if (request.grid) integer_in_range(*request.grid, "--grid", kExperimentGridRange[0], kExperimentGridRange[1]);
    integer_in_range(request.threads, "--threads", 0, io::kMaxThreads);
    ExperimentResult result;
    try {
        result = request.which == Experiment::CUBE  ? run_cube(request)
                 : request.which == Experiment::MAP ? run_map(request)
                                                    : run_figure1(request);
    } catch (const ExperimentInterrupted& e) {
        result.interrupted = true;
        result.signal = e.signal;
    }
    return result;
}

}  // namespace woven::batch
