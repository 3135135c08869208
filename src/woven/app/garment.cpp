#include "woven/app/garment.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>

#include "woven/analysis/peaks.hpp"
#include "woven/app/files.hpp"
#include "woven/app/material.hpp"
#include "woven/app/scene_view.hpp"
#include "woven/common/error.hpp"
#include "woven/common/format.hpp"
#include "woven/common/units.hpp"
#include "woven/geometry/dress_form.hpp"
#include "woven/geometry/mesh_obstacle.hpp"
#include "woven/io/fabric_file.hpp"
#include "woven/io/mesh_file.hpp"
#include "woven/io/output_set.hpp"
#include "woven/render/gltf_file.hpp"
#include "woven/render/image.hpp"

namespace woven::app {

namespace {

constexpr double kCm = units::kMToCm;
constexpr int kHemBins = 72;      ///< 5 degrees each
constexpr double kOverlap = 0.5;  ///< spacings: two repelling particles closer than this at the start overlap

std::string cm3(const Vec3& p) { return strf("(%.1f, %.1f, %.1f) cm", p.x() * kCm, p.y() * kCm, p.z() * kCm); }

double radius_of(const Vec3& p) { return std::hypot(p.x(), p.y()); }

/// The start checked against the body: no particle inside it or within the contact distance,
/// no stitch through it.
void check_start(const GarmentSetup& s)
{
    const model::GarmentCloth& c = s.cloth;
    const std::string& src = s.spec.source;
    const double clearance = s.solver.contact_distance;
    for (int p = 0; p < c.grid.size(); ++p) {
        if (!c.active[p]) continue;
        const double d = s.body.distance(c.start[p]);
        if (d < clearance) {
            const int k = c.piece_of[p];
            const Vec2 at = c.piece_point[p] * kCm;
            throw InputError(
                src, strf("piece[%d].place", k + 1),
                strf("piece '%s' starts inside the body: its point (%.1f, %.1f) cm goes to %s, %.2f cm %s the body's surface; "
                     "expected every point at least %.2g cm outside (a larger radius_cm or half_angle_deg, or another height_cm)",
                     s.spec.pattern.pieces[k].name.c_str(), at.x(), at.y(), cm3(c.start[p]).c_str(), std::abs(d) * kCm,
                     d < 0 ? "inside" : "outside, closer than the contact distance to", clearance * kCm));
        }
    }
    // Two particles of the cloth that repel each other (of two pieces, or of one piece folded
    // onto itself) may not start on top of each other: the repulsion (Eq. 2) is singular there.
    const double sigma = c.grid.sigma;
    if (const std::vector<model::Stencil<2>> close = s.model->close_pairs(c.start, kOverlap * sigma); !close.empty()) {
        const int a = close.front()[0], b = close.front()[1];
        const auto& pieces = s.spec.pattern.pieces;
        const Vec2 pa = c.piece_point[a] * kCm, pb = c.piece_point[b] * kCm;
        const std::string who = c.piece_of[a] == c.piece_of[b]
            ? strf("piece '%s' overlaps itself", pieces[c.piece_of[a]].name.c_str())
            : strf("pieces '%s' and '%s' overlap", pieces[c.piece_of[a]].name.c_str(), pieces[c.piece_of[b]].name.c_str());
        throw InputError(src, strf("piece[%d].place", c.piece_of[b] + 1),
                         strf("%s: their points (%.1f, %.1f) cm and (%.1f, %.1f) cm both go to about %s, "
                              "%.2g cm apart; expected pieces placed apart (at least %.2g of a spacing) unless a seam sews them there",
                              who.c_str(), pa.x(), pa.y(), pb.x(), pb.y(), cm3(c.start[a]).c_str(), (c.start[a] - c.start[b]).norm() * kCm,
                              kOverlap));
    }
    for (const model::Stitch& st : c.seams.stitches) {
        const Vec3 a = c.start[st.p], b = (1 - st.w) * c.start[st.q1] + st.w * c.start[st.q2];
        if (s.body.first_contact(a, b))
            throw InputError(src, strf("seam[%d]", st.seam + 1),
                             strf("the seam '%s' crosses the body: its stitch from %s to %s passes through it; expected the two edges "
                                  "placed on the same side of the body (check the pieces' azimuth_deg and the seam's direction)",
                                  s.spec.pattern.seams[st.seam].name.c_str(), cm3(a).c_str(), cm3(b).c_str()));
    }
}

}  // namespace

std::unique_ptr<GarmentSetup> prepare_garment(const GarmentRequest& r, std::vector<std::string>& warnings)
{
    auto setup = std::make_unique<GarmentSetup>();
    GarmentSetup& s = *setup;
    s.spec = io::load_garment(r.file, &warnings);
    if (r.fabric) s.spec.fabric = *r.fabric;
    if (r.spacing_cm) {
        if (!(*r.spacing_cm >= io::kGarmentSpacingCm[0] && *r.spacing_cm <= io::kGarmentSpacingCm[1]))
            throw InputError(kCommandLine, "--spacing",
                             strf("expected a spacing in [%g, %g] cm", io::kGarmentSpacingCm[0], io::kGarmentSpacingCm[1]));
        s.spec.spacing_m = *r.spacing_cm * units::kCmToM;
    }
    if (r.threads) s.spec.threads = *r.threads;
    if (r.max_steps) s.spec.max_steps = *r.max_steps;

    // The pieces cut from one grid, sewn and placed.
    s.cloth = model::cut_pattern(s.spec.pattern, s.spec.spacing_m, s.spec.source);
    s.threads = choose_threads(s.spec.threads, warnings);
    s.memory = check_memory(s.cloth.grid.size(), s.threads.used, r.spacing_cm ? kCommandLine : s.spec.source,
                            r.spacing_cm ? "--spacing" : "spacing_cm");

    // The body.
    if (s.spec.body.obj) {
        geometry::TriangleMesh mesh = io::load_obj_mesh(*s.spec.body.obj);
        for (auto& v : mesh.vertices) v *= s.spec.body.obj_scale;
        s.body.add(std::make_unique<geometry::MeshObstacle>(std::move(mesh)));
    } else {
        s.body.add(std::make_unique<geometry::MeshObstacle>(geometry::dress_form_mesh(s.spec.body.form)));
    }

    // The fabric and its model, sewn.
    s.fabric = io::find_fabric(s.spec.fabric, &warnings);
    s.fabric_label = s.fabric.name.empty() ? s.spec.fabric : s.fabric.name;
    model::ModelOptions options;
    with_fabric_source(fabric_source(s.spec.fabric), [&] {
        resolve_shear_law(s.fabric, options, warnings);
        s.model.emplace(model::make_cloth_model(s.fabric, s.cloth.grid, options, s.cloth.active, s.cloth.area));
    });
    s.seam_stiffness = s.spec.seam_stiffness;
    if (s.seam_stiffness.empty()) {
        const double Et = s.model->spacing().tensile > 0 ? s.model->spacing().tensile
                                                         : model::tensile_stiffness_from_emt(model::kDefaultEMT, options.gram_force);
        // Seams that start closed (the pieces wrapped edge to edge: every gap within half a spacing,
        // the extrapolation's error on a curved start) are held at E_t from the
        // start; open ones are pulled closed by a ramp over three drapes.
        const std::vector<double> gaps = model::stitch_gaps(s.cloth.seams, s.cloth.start);
        const double widest = gaps.empty() ? 0.0 : *std::max_element(gaps.begin(), gaps.end());
        if (widest < 0.5 * s.cloth.grid.sigma)
            s.seam_stiffness = {Et};
        else
            s.seam_stiffness = {0.01 * Et, 0.1 * Et, Et};
    }
    s.model->set_seams(s.cloth.seams, s.seam_stiffness.front());

    s.solver.threads = s.threads.used;
    s.solver.max_steps = s.spec.max_steps;
    if (r.seed) s.solver.seed = *r.seed;

    // The waist: where it starts.
    for (int p : s.cloth.waist) {
        s.waist_radius_m += radius_of(s.cloth.start[p]);
        s.waist_height_m += s.cloth.start[p].z();
    }
    if (!s.cloth.waist.empty()) {
        s.waist_radius_m /= static_cast<double>(s.cloth.waist.size());
        s.waist_height_m /= static_cast<double>(s.cloth.waist.size());
    }
    std::vector<char> stitched(s.cloth.grid.size(), 0);
    for (const model::Stitch& st : s.cloth.seams.stitches) stitched[st.p] = stitched[st.q1] = stitched[st.q2] = 1;
    for (int p : s.cloth.waist)
        if (!stitched[p]) s.held.push_back(p);
    if (s.cloth.waist.empty())
        warnings.push_back(s.spec.source + ": piece.segment.role: no segment has role \"waist\"; nothing holds the garment up");
    if (s.cloth.hem.empty())
        warnings.push_back(s.spec.source + ": piece.segment.role: no segment has role \"hem\"; the report has no hem measures");
    check_start(s);
    return setup;
}

GarmentRun solve_garment(GarmentSetup& s, const sim::ProgressCallback& progress, const sim::IterationCallback& iteration,
                         const StageCallback& on_stage)
{
    GarmentRun run;
    run.x = s.cloth.start;
    for (std::size_t k = 0; k < s.seam_stiffness.size(); ++k) {
        s.model->set_seam_stiffness(s.seam_stiffness[k]);
        if (on_stage) on_stage(static_cast<int>(k) + 1, static_cast<int>(s.seam_stiffness.size()), s.seam_stiffness[k]);
        sim::Problem problem;
        problem.model = sim::ClothRef(&*s.model);
        problem.obstacles = &s.body;
        problem.initial = run.x;
        problem.pinned = s.held;
        sim::SolverOptions o = s.solver;
        // Later stages go on from the state reached, at rest: no perturbation, and static steps
        // from the first (the fall is over; starting again from 1/60 s took as long as the fall).
        if (k > 0) {
            o.perturbation = 0;
            o.time_step = o.fast.static_time_step;
        }
        GarmentStage stage;
        stage.stage = static_cast<int>(k) + 1;
        stage.stiffness = s.seam_stiffness[k];
        stage.result = sim::drape(problem, o, progress, iteration);
        run.x = stage.result.x;
        sim::add_counters(run.total, stage.result);
        run.total.energy = stage.result.energy;
        run.total.equilibrium = stage.result.equilibrium;
        run.total.converged = stage.result.converged;
        run.interrupted = stage.result.interrupted;
        stage.result.x.clear();
        run.stages.push_back(std::move(stage));
        if (run.interrupted) break;
    }
    run.total.x.clear();
    return run;
}

HemMeasures hem_measures(const GarmentSetup& s, const Positions& x)
{
    HemMeasures h;
    if (s.cloth.hem.empty()) return h;
    std::vector<double> r_sum(kHemBins, 0.0), z_sum(kHemBins, 0.0);
    std::vector<int> count(kHemBins, 0);
    const double bin = 2 * std::numbers::pi / kHemBins;
    for (int p : s.cloth.hem) {
        double phi = std::atan2(x[p].y(), x[p].x());
        if (phi < 0) phi += 2 * std::numbers::pi;
        const int b = std::min(kHemBins - 1, static_cast<int>(phi / bin));
        r_sum[b] += radius_of(x[p]);
        z_sum[b] += x[p].z();
        ++count[b];
        h.mean_radius_m += radius_of(x[p]);
        h.mean_height_m += x[p].z();
    }
    h.mean_radius_m /= static_cast<double>(s.cloth.hem.size());
    h.mean_height_m /= static_cast<double>(s.cloth.hem.size());
    // Empty bins (a coarse grid) take the linear interpolation of their filled neighbours.
    h.radius_m.assign(kHemBins, 0.0);
    h.height_m.assign(kHemBins, 0.0);
    std::vector<int> filled;
    for (int b = 0; b < kHemBins; ++b)
        if (count[b] > 0) {
            h.radius_m[b] = r_sum[b] / count[b];
            h.height_m[b] = z_sum[b] / count[b];
            filled.push_back(b);
        }
    for (int b = 0; b < kHemBins; ++b) {
        h.angle_deg.push_back((b + 0.5) * 360.0 / kHemBins);
        if (count[b] > 0) continue;
        int lo = filled.back() - kHemBins, hi = filled.front() + kHemBins;
        for (int f : filled) {
            if (f < b) lo = f;
            if (f > b) {
                hi = f;
                break;
            }
        }
        const int blo = (lo + kHemBins) % kHemBins, bhi = hi % kHemBins;
        const double t = static_cast<double>(b - lo) / (hi - lo);
        h.radius_m[b] = (1 - t) * h.radius_m[blo] + t * h.radius_m[bhi];
        h.height_m[b] = (1 - t) * h.height_m[blo] + t * h.height_m[bhi];
    }
    if (s.waist_radius_m > 0) h.flare = h.mean_radius_m / s.waist_radius_m;
    const auto [zlo, zhi] = std::minmax_element(h.height_m.begin(), h.height_m.end());
    h.length_drop_m = *zhi - *zlo;
    // Nodes: the periodic peaks of r(angle) standing out by a tenth of the hem's reach beyond the
    // waist (as the Cusick nodes by a tenth of the overhang), at least half a spacing.
    h.min_prominence_m = std::max(0.5 * s.cloth.grid.sigma, 0.1 * (h.mean_radius_m - s.waist_radius_m));
    // A peak's index is refined within [0, 72): one past the last bin's centre wraps to [0, 360).
    for (const analysis::Peak& p : analysis::periodic_peaks(h.radius_m, h.min_prominence_m))
        h.node_angle_deg.push_back(std::fmod((p.index + 0.5) * 360.0 / kHemBins, 360.0));
    h.nodes = static_cast<int>(h.node_angle_deg.size());
    return h;
}

nlohmann::json garment_report(const GarmentSetup& s, const GarmentRun& run)
{
    using nlohmann::json;
    const model::GarmentCloth& c = s.cloth;
    const double sigma = c.grid.sigma;
    json rep;
    rep["version"] = WOVEN_VERSION;
    rep["command"] = "garment";
    rep["garment"] = s.spec.name;
    rep["garment_file"] = s.spec.source;
    rep["fabric"] = s.fabric_label;
    rep["spacing_m"] = sigma;
    rep["grid"] = {{"nu", c.grid.nu}, {"nv", c.grid.nv}};
    int particles = 0;
    for (char a : c.active) particles += a;
    rep["particles"] = particles;
    json pieces = json::array();
    for (std::size_t k = 0; k < s.spec.pattern.pieces.size(); ++k)
        pieces.push_back({{"name", s.spec.pattern.pieces[k].name},
                          {"grain_deg", s.spec.pattern.pieces[k].grain * 180 / std::numbers::pi},
                          {"particles", c.cuts[k].count},
                          {"area_m2", c.cuts[k].total_area}});
    rep["pieces"] = pieces;
    rep["body"] = s.spec.body.obj ? json{{"obj", *s.spec.body.obj}}
                                  : json{{"form", "dress-form"},
                                         {"bust_m", s.spec.body.form.bust},
                                         {"waist_m", s.spec.body.form.waist},
                                         {"hip_m", s.spec.body.form.hip},
                                         {"waist_height_m", s.spec.body.form.waist_height},
                                         {"hip_depth_m", s.spec.body.form.hip_depth},
                                         {"depth_ratio", s.spec.body.form.depth_ratio}};
    json stages = json::array();
    for (const GarmentStage& st : run.stages)
        stages.push_back({{"seam_stiffness_N_m", st.stiffness},
                          {"converged", st.result.converged},
                          {"steps", st.result.steps},
                          {"iterations", st.result.iterations},
                          {"wall_time_s", st.result.wall_time},
                          {"energy_J", st.result.energy.total()},
                          {"max_residual_rel", st.result.equilibrium.max_residual_rel}});
    rep["stages"] = stages;
    rep["converged"] = run.total.converged;
    rep["interrupted"] = run.interrupted;
    rep["steps"] = run.total.steps;
    rep["iterations"] = run.total.iterations;
    rep["wall_time_s"] = run.total.wall_time;
    rep["threads"] = s.threads.used;
    // The resident memory (bytes) the run was estimated to need and checked against before it
    // started: the figure a measured peak RSS is compared with.
    rep["memory_estimate_bytes"] = std::llround(s.memory.resident_bytes);
    const model::EnergyTerms& e = run.total.energy;
    rep["energy"] = {{"gravity_J", e.gravity},
                     {"stretch_J", e.stretch},
                     {"repulsion_J", e.repulsion},
                     {"bending_warp_J", e.bending_warp},
                     {"bending_weft_J", e.bending_weft},
                     {"trellis_J", e.trellis},
                     {"twist_J", e.twist},
                     {"seam_J", e.seam},
                     {"total_J", e.total()}};
    rep["waist"] = {{"radius_m", s.waist_radius_m}, {"height_m", s.waist_height_m}, {"particles", c.waist.size()}};
    const HemMeasures h = hem_measures(s, run.x);
    rep["hem"] = {{"particles", c.hem.size()},
                  {"nodes", h.nodes},
                  {"node_angle_deg", h.node_angle_deg},
                  {"min_prominence_m", h.min_prominence_m},
                  {"mean_radius_m", h.mean_radius_m},
                  {"flare", h.flare},
                  {"mean_height_m", h.mean_height_m},
                  {"below_waist_m", s.waist_height_m - h.mean_height_m},
                  {"length_drop_m", h.length_drop_m},
                  {"angle_deg", h.angle_deg},
                  {"radius_m", h.radius_m},
                  {"height_m", h.height_m}};
    // Seams: each stitch's gap and the force k |gap| that holds it (at the last stage's k).
    const std::vector<double> gaps = model::stitch_gaps(s.model->seams(), run.x);
    const double k = s.model->seam_stiffness();
    json seams = json::array();
    double worst = 0;
    for (std::size_t m = 0; m < s.spec.pattern.seams.size(); ++m) {
        double max_gap = 0, sum = 0;
        int n = 0;
        for (std::size_t i = 0; i < gaps.size(); ++i)
            if (s.model->seams().stitches[i].seam == static_cast<int>(m)) {
                max_gap = std::max(max_gap, gaps[i]);
                sum += gaps[i];
                ++n;
            }
        worst = std::max(worst, max_gap);
        seams.push_back({{"name", s.spec.pattern.seams[m].name},
                         {"stitches", n},
                         {"max_gap_m", max_gap},
                         {"mean_gap_m", n ? sum / n : 0.0},
                         {"max_gap_over_spacing", max_gap / sigma},
                         {"max_force_N", k * max_gap},
                         {"mean_force_N", n ? k * sum / n : 0.0}});
    }
    rep["seams"] = seams;
    rep["seam_max_gap_m"] = worst;
    rep["seam_max_gap_over_spacing"] = worst / sigma;
    return rep;
}

geometry::TriangleMesh garment_surface(const GarmentSetup& s, const Positions& x, std::vector<Vec2>* uv)
{
    geometry::TriangleMesh all;
    for (const model::ClothCut& cut : s.cloth.cuts) {
        std::vector<Vec2> piece_uv;
        const geometry::TriangleMesh m = model::cut_surface(s.cloth.grid, cut, x, uv ? &piece_uv : nullptr);
        const int base = static_cast<int>(all.vertices.size());
        all.vertices.insert(all.vertices.end(), m.vertices.begin(), m.vertices.end());
        for (const auto& f : m.faces) all.faces.push_back(f + Eigen::Vector3i::Constant(base));
        if (uv) uv->insert(uv->end(), piece_uv.begin(), piece_uv.end());
    }
    return all;
}

nlohmann::json write_garment_outputs(const GarmentSetup& s, const GarmentRun& run, const std::string& dir, int width, int height,
                                     bool no_render)
{
    io::OutputSet set(dir, {"garment.glb", "garment.png"});
    std::vector<Vec2> uv;
    const geometry::TriangleMesh surface = garment_surface(s, run.x, &uv);
    set.add("garment.glb",
            render::display_glb(render::surface_gltf_mesh(surface, uv), s.body, s.solver.contact_distance, s.fabric.color,
                                "the cloth's vertices", "report.json"));
    if (!no_render) {
        render::ClothSurface cloth;
        cloth.mesh = surface;
        cloth.uv.assign(uv.begin(), uv.end());
        cloth.spacing_m = s.cloth.grid.sigma;
        const render::Image image =
            render_view(scene_view(std::move(cloth), s.body, s.fabric), render::View::FRONT, width, height, "garment picture");
        set.add("garment.png", render::encode_png(image, "garment.png"));
    }
    nlohmann::json rep = garment_report(s, run);
    rep["outputs"] = set.names();
    rep["files"] = set.files_json();
    set.publish("report.json", rep.dump(2) + "\n");
    return rep;
}

GarmentJob garment(const GarmentRequest& request, const std::string& out_dir, int width, int height, bool render, const Monitor& monitor)
{
    const MonitorScope scope(monitor);
    GarmentJob job;
    std::unique_ptr<GarmentSetup> setup = prepare_garment(request, job.warnings);
    make_output_dir(out_dir);
    check_output_targets(out_dir, {"garment.glb", "garment.png", "report.json"});
    std::unique_ptr<Progress> progress;
    const GarmentRun run = solve_garment(
        *setup, [&](const sim::StepInfo& s) { return (*progress)(s); }, [&](const sim::IterationInfo& i) { return progress->iteration(i); },
        [&](int, int, double) {
            progress.reset();
            progress = std::make_unique<Progress>(setup->solver.max_steps, setup->solver.residual_tolerance);
        });
    progress.reset();
    job.report = write_garment_outputs(*setup, run, out_dir, width, height, !render);
    job.interrupted = run.interrupted || interrupt_requested();
    return job;
}

}  // namespace woven::app
