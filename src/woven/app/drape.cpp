#include "woven/app/drape.hpp"

#include <iostream>
#include <sstream>
#include <utility>

#include "woven/app/drape_report.hpp"
#include "woven/app/material.hpp"
#include "woven/app/progress.hpp"
#include "woven/app/scene_view.hpp"
#include "woven/common/error.hpp"
#include "woven/geometry/mesh_ops.hpp"
#include "woven/io/drape_files.hpp"
#include "woven/io/fabric_file.hpp"
#include "woven/io/output.hpp"
#include "woven/io/output_checks.hpp"
#include "woven/io/output_set.hpp"
#include "woven/io/start_file.hpp"
#include "woven/render/gltf_file.hpp"

namespace woven::app {

namespace {

/// drape.png: the cloth (a smooth surface through the particles, the fabric's colour) over the
/// obstacles, seen along the scene camera's direction (if it has one), framed tightly.
render::Image render_drape(const Positions& x, const model::Grid& grid, const io::SceneSpec& scene,
                           const kes::FabricData& fabric, int width, int height, const render::ClothSurface* cut_surface = nullptr)
{
    render::ClothSurface cloth = cut_surface ? *cut_surface : render::grid_surface(x, grid.nu, grid.nv);
    return render_view(scene_view(std::move(cloth), scene.obstacles, fabric, &scene.camera), render::View::SCENE, width, height,
                       "drape.png");
}

}  // namespace

DrapeRequest drape_request(const DrapeValues& v, Naming naming)
{
    const auto name = [naming](std::string_view option) { return value_name(naming, option); };
    DrapeRequest r;
    r.naming = naming;
    if (v.grid) r.grid = static_cast<int>(integer_value(*v.grid, name("--grid"), kGridRange[0], kGridRange[1]));
    if (v.solver) r.solver = named_choice(*v.solver, name("--solver"), sim::kSolverKindNames);
    if (v.seed) r.seed = seed_value(*v.seed, name("--seed"));
    if (v.max_steps) r.max_steps = static_cast<int>(integer_value(*v.max_steps, name("--max-steps"), kMaxStepsRange[0], kMaxStepsRange[1]));
    if (v.threads) r.threads = static_cast<int>(integer_value(*v.threads, name("--threads"), 0, io::kMaxThreads));
    if (v.perturb_m) r.perturb_m = number_value(*v.perturb_m, name("--perturb"), 0, io::kMaxPerturbation_m);
    if (v.hysteresis) r.hysteresis = named_choice(*v.hysteresis, name("--hysteresis"), model::kHysteresisNames);
    if (v.bias) r.bias = named_choice(*v.bias, name("--bias"), model::kBiasBendingNames);
    if (v.start) r.start = path_given(*v.start, name("--start"));
    return r;
}

std::unique_ptr<DrapeSetup> prepare_drape(DrapeRequest request, std::vector<std::string>& warnings)
{
    const MonitorScope monitor(request.monitor);
    const DrapeRequest& r = request;
    const auto name = [&r](std::string_view option) { return value_name(r.naming, option); };
    auto setup = std::make_unique<DrapeSetup>();
    DrapeSetup& d = *setup;
    d.scene = r.scene_spec ? std::move(*request.scene_spec) : io::find_scene(r.scene, &warnings);
    io::SceneSpec& scene = d.scene;
    // The options' values come checked (drape_request); the scene checks the grid it makes.
    io::SceneOverrides ov;
    ov.grid = r.grid;
    ov.fabric = r.fabric;
    ov.solver = r.solver;
    ov.seed = r.seed;
    ov.max_steps = r.max_steps;
    ov.threads = r.threads;
    const ValueName grid_name = name("--grid");
    io::apply_overrides(scene, ov, grid_name.source, grid_name.field);
    if (r.perturb_m) scene.solver.perturbation = *r.perturb_m;
    if (r.hysteresis) scene.model.hysteresis = *r.hysteresis;
    if (r.bias) scene.model.bias_bending = *r.bias;
    if (scene.model.hysteresis == model::Hysteresis::FRICTION && scene.solver.kind == sim::SolverKind::PAPER) {
        const ValueName which = r.hysteresis ? name("--hysteresis")
            : r.solver                       ? name("--solver")
                                             : ValueName(scene.source_path, "model.hysteresis");
        throw InputError(which.source, which.field,
                         "expected loading-branch with the paper solver, or the fast solver with friction (friction inside the weave is "
                         "the fast solver's)");
    }
    // Threads and memory before anything large is built.
    d.threads = choose_threads(scene.solver.threads, warnings);
    scene.solver.threads = d.threads.used;
    check_memory(static_cast<long long>(scene.cloth.nu) * scene.cloth.nv, d.threads.used, r.grid ? grid_name.source : scene.source_path,
                 r.grid ? grid_name.field : "cloth.grid");
    std::string fabric_src;
    if (r.fabric_data) {
        d.fabric = std::move(*request.fabric_data);
        fabric_src = r.fabric_source;
        d.fabric_label = d.fabric.name;
    } else {
        d.fabric = io::find_fabric(scene.fabric, &warnings);
        fabric_src = fabric_source(scene.fabric);
        d.fabric_label = d.fabric.name.empty() ? scene.fabric : d.fabric.name;
    }

    d.grid = scene.cloth.grid();
    with_fabric_source(fabric_src, [&] {  // fitting errors name the fabric's file
        resolve_shear_law(d.fabric, scene.model, warnings);
        d.model.emplace(model::make_cloth_model(d.fabric, d.grid, scene.model));
    });
    // A cloth cut to [cloth.outline]: only the kept particles, each weighing W x its area.
    if (scene.cloth.is_cut()) {
        d.cut = scene.cloth.cut(scene.source_path);
        with_fabric_source(fabric_src, [&] { d.model.emplace(model::make_cloth_model(d.fabric, d.grid, scene.model, d.cut->active, d.cut->area)); });
    }
    d.problem.model = sim::ClothRef::evolving(*d.model);  // friction: the states evolve with the drape
    d.problem.obstacles = &scene.obstacles;
    d.problem.initial = scene.cloth.initial_positions();
    // A start instead of the scene's: a drape read back (--start) or positions (Python); the
    // scene's pinned particles stay where it pins them.
    std::optional<Positions> start;
    // Checked as the flat start is: within the scene's bounds, outside every obstacle.
    const io::StartBounds bounds{&scene.obstacles, Vec3::Zero(), io::kMaxCoordinate_m};
    if (r.start) {
        const std::string path = r.start->string();
        io::StartState read = io::load_start(path, d.grid, d.model->stencils().active, d.problem.initial);
        io::check_start_positions(read.x, d.model->stencils().active, scene.pinned_indices(), bounds, path, "v",
                                  [&](int p) { return "line " + std::to_string(read.line[static_cast<std::size_t>(p)]); });
        start = std::move(read.x);
        d.start_sha256 = read.sha256;
    } else if (r.initial) {
        if (static_cast<int>(r.initial->size()) != d.grid.size())
            throw InputError("initial_positions", "shape",
                             "expected " + std::to_string(d.grid.size()) + " rows, one per particle of the " + std::to_string(d.grid.nu) + " x " +
                                 std::to_string(d.grid.nv) + " grid, got " + std::to_string(r.initial->size()));
        io::check_start_positions(*r.initial, d.model->stencils().active, scene.pinned_indices(), bounds, "initial_positions", "values",
                                  [](int p) { return "row " + std::to_string(p); });
        start = std::move(request.initial);
        d.start_sha256 = r.initial_sha256;
    }
    if (start) {
        for (int p : scene.pinned_indices()) (*start)[p] = d.problem.initial[p];
        d.problem.initial = std::move(*start);
    }
    d.problem.pinned = scene.pinned_indices();
    d.energy_initial = d.model->energy(d.problem.initial);
    d.max_steps = scene.solver.max_steps > 0 ? scene.solver.max_steps : sim::default_max_steps(scene.solver.kind);
    return setup;
}

std::string drape_banner(const DrapeSetup& d)
{
    std::ostringstream s;
    s << "draping " << d.scene.name << " (" << d.grid.nu << " x " << d.grid.nv << " particles, fabric " << d.fabric_label << ", "
      << sim::to_string(d.scene.solver.kind) << " solver, " << shear_law_text(d.scene.model)
      << (d.scene.model.hysteresis == model::Hysteresis::FRICTION ? ", friction inside the weave" : "") << ")";
    return s.str();
}

sim::Result solve_drape(const DrapeSetup& d, const sim::ProgressCallback& progress, const sim::IterationCallback& iteration)
{
    return sim::drape(d.problem, d.scene.solver, progress, iteration);
}

DrapeRun finish_drape(const DrapeSetup& d, sim::Result result, bool interrupted)
{
    DrapeRun run;
    run.setup = &d;
    run.result = std::move(result);
    run.interrupted = interrupted || run.result.interrupted;
    io::require_finite_positions(run.result.x, "the drape");
    if (d.cut) {
        std::vector<Vec2> uv;
        run.cut_surface.emplace();
        run.cut_surface->mesh = model::cut_surface(d.grid, *d.cut, run.result.x, &uv);
        run.cut_surface->uv.assign(uv.begin(), uv.end());
        run.cut_surface->spacing_m = d.grid.sigma;
    }
    if (const auto box = analysis::box_footprint(d.scene.obstacles))
        run.folds = analysis::analyse_folds(
            run.cut_surface ? run.cut_surface->mesh : geometry::grid_mesh(run.result.x, d.grid.nu, d.grid.nv), *box);
    return run;
}

nlohmann::json drape_report_json(const DrapeRun& run, const std::vector<std::string>& outputs)
{
    const DrapeSetup& d = *run.setup;
    DrapeReportInput in;
    in.scene = d.scene.name;
    in.scene_source = d.scene.source_path;
    in.fabric = d.fabric_label;
    in.fabric_data = &d.fabric;
    in.model = &*d.model;
    in.model_options = &d.scene.model;
    in.obstacles = &d.scene.obstacles;
    in.solver = &d.scene.solver;
    in.result = &run.result;
    in.energy_initial = d.energy_initial;
    in.interrupted = run.interrupted || interrupt_requested();  // a signal while the files were written
    in.outputs = outputs;
    in.folds = run.folds ? &*run.folds : nullptr;
    nlohmann::json report = drape_report(in);
    report["threads_requested"] = d.threads.requested;
    // The path the cloth takes (with friction inside the weave the drape depends on it): the
    // paper's drop, the cloth released at rest from its start (flat above the cube).
    report["protocol"] = "drop";
    report["start_sha256"] = d.start_sha256;  // empty: the scene's own start
    report["perturbation_m"] = d.scene.solver.kind == sim::SolverKind::FAST ? d.scene.solver.perturbation : 0.0;
    io::require_finite(report, "the drape", {"folds"});
    return report;
}

nlohmann::json write_drape_outputs(const DrapeRun& run, const std::string& out_dir, const DrapeWriteOptions& options)
{
    const MonitorScope monitor(options.monitor);
    const DrapeSetup& d = *run.setup;
    integer_in_range(options.width, "--width", kPictureSizeRange[0], kPictureSizeRange[1]);
    integer_in_range(options.height, "--height", kPictureSizeRange[0], kPictureSizeRange[1]);
    path_given(out_dir, "--out");
    make_output_dir(out_dir);
    std::vector<std::string> targets = kDrapeFiles;
    targets.push_back("report.json");
    check_output_targets(out_dir, targets);
    // Staged under temporary names, then published as one set with report.json last
    // (io::OutputSet). Nothing non-finite is written; an interrupt skips the picture.
    io::OutputSet set(out_dir, kDrapeFiles);
    const auto& cut_surface = run.cut_surface;
    const auto fields = io::add_drape_meshes(
        set, {&run.result.x, &*d.model, &d.scene.obstacles, d.scene.solver.contact_distance, d.scene.solver.friction,
              options.ply_ascii ? io::PlyFormat::ASCII : io::PlyFormat::BINARY, d.cut ? &cut_surface->mesh : nullptr,
              d.cut ? &cut_surface->uv : nullptr, "drape of a cloth cut to its outline, scene " + d.scene.name});
    set.add("drape.glb", render::display_glb(d.cut ? render::surface_gltf_mesh(cut_surface->mesh, cut_surface->uv)
                                                   : render::cloth_gltf_mesh(run.result.x, d.grid.nu, d.grid.nv, fields),
                                             d.scene.obstacles, d.scene.solver.contact_distance, d.fabric.color,
                                             "the cloth's vertices", "drape.obj and drape.ply hold the particles as solved"));
    if (!options.no_render && !run.interrupted && !interrupt_requested()) {
        set.add("drape.png", render::encode_png(render_drape(run.result.x, d.grid, d.scene, d.fabric, options.width,
                                                             options.height, cut_surface ? &*cut_surface : nullptr),
                                                join_path(out_dir, "drape.png")));
    }
    nlohmann::json report = drape_report_json(run, set.names());
    report["files"] = set.files_json();
    set.publish("report.json", report.dump(2) + "\n");
    return report;
}

}  // namespace woven::app
