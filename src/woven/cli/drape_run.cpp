#include "woven/cli/drape_run.hpp"

#include <iostream>
#include <sstream>

#include "woven/cli/args.hpp"
#include "woven/cli/material.hpp"
#include "woven/cli/progress.hpp"
#include "woven/cli/report.hpp"
#include "woven/cli/scene_view.hpp"
#include "woven/common/error.hpp"
#include "woven/io/drape_files.hpp"
#include "woven/io/fabric_file.hpp"
#include "woven/io/output.hpp"
#include "woven/io/output_set.hpp"
#include "woven/io/start_file.hpp"

namespace woven::cli {

namespace {

/// drape.png: the cloth (a smooth surface through the particles, the fabric's colour) over the
/// obstacles, seen along the scene camera's direction (if it has one), framed tightly.
render::Image render_drape(const Positions& x, const model::Grid& grid, const io::SceneSpec& scene,
                           const kes::FabricData& fabric, int width, int height, const render::ClothSurface* cut_surface = nullptr)
{
    render::ClothSurface cloth = cut_surface ? *cut_surface : render::grid_surface(x, grid.nu, grid.nv);
    return render_view(scene_view(std::move(cloth), scene.obstacles, fabric, &scene.camera), render::View::SCENE, width, height);
}

}  // namespace

std::unique_ptr<DrapeSetup> prepare_drape(const DrapeOptions& options, std::vector<std::string>& warnings, DrapeInputs inputs)
{
    auto setup = std::make_unique<DrapeSetup>();
    DrapeSetup& d = *setup;
    d.scene = inputs.scene ? std::move(*inputs.scene) : io::find_scene(options.scene, &warnings);
    io::SceneSpec& scene = d.scene;
    io::SceneOverrides ov;
    if (const auto g = parse_integer(options.grid, "--grid", 3, 100000)) ov.grid = static_cast<int>(*g);
    ov.fabric = options.fabric;
    if (options.solver) {
        ov.solver = sim::solver_kind_from_string(*options.solver);
        if (!ov.solver) throw InputError(kCommandLine, "--solver", "expected fast or paper");
    }
    if (options.seed) ov.seed = parse_seed(*options.seed, "--seed");
    if (const auto m = parse_integer(options.max_steps, "--max-steps", 0, 1'000'000'000)) ov.max_steps = static_cast<int>(*m);
    if (const auto t = parse_integer(options.threads, "--threads", 0, io::kMaxThreads)) ov.threads = static_cast<int>(*t);
    io::apply_overrides(scene, ov, kCommandLine);
    if (options.perturb) scene.solver.perturbation = parse_number(*options.perturb, "--perturb", 0, io::kMaxPerturbation_m);
    if (options.hysteresis) scene.model.hysteresis = parse_hysteresis(*options.hysteresis, "--hysteresis");
    if (options.bias) scene.model.bias_bending = parse_bias_bending(*options.bias, "--bias");
    if (scene.model.hysteresis == model::Hysteresis::FRICTION && scene.solver.kind == sim::SolverKind::PAPER)
        throw InputError(options.hysteresis || options.solver ? kCommandLine : scene.source_path,
                         options.hysteresis ? "--hysteresis" : options.solver ? "--solver" : "model.hysteresis",
                         "expected loading-branch with the paper solver, or the fast solver with friction (friction inside the weave is the fast solver's)");
    // Threads and memory before anything large is built.
    d.threads = choose_threads(scene.solver.threads);
    scene.solver.threads = d.threads.used;
    check_memory(static_cast<long long>(scene.cloth.nu) * scene.cloth.nv, d.threads.used,
                 options.grid ? kCommandLine : scene.source_path, options.grid ? "--grid" : "cloth.grid");
    std::string fabric_src;
    if (inputs.fabric) {
        d.fabric = std::move(*inputs.fabric);
        fabric_src = inputs.fabric_source;
        d.fabric_label = d.fabric.name;
    } else {
        d.fabric = io::find_fabric(scene.fabric, &warnings);
        fabric_src = fabric_source(scene.fabric);
        d.fabric_label = d.fabric.name.empty() ? scene.fabric : d.fabric.name;
    }

    d.grid = scene.cloth.grid();
    with_fabric_source(fabric_src, [&] {  // fitting errors name the fabric's file
        resolve_shear_law(d.fabric, scene.model);
        d.model.emplace(model::make_cloth_model(d.fabric, d.grid, scene.model));
    });
    // A cloth cut to [cloth.outline]: only the kept particles, each weighing W x its area.
    if (scene.cloth.is_cut()) {
        d.cut = scene.cloth.cut(scene.source_path);
        with_fabric_source(fabric_src, [&] { d.model.emplace(model::make_cloth_model(d.fabric, d.grid, scene.model, d.cut->active, d.cut->area)); });
    }
    d.problem.model = &*d.model;
    if (d.model->has_slip()) d.problem.slip = &*d.model;  // friction: the states evolve with the drape
    d.problem.obstacles = &scene.obstacles;
    d.problem.initial = scene.cloth.initial_positions();
    if (options.start) {  // a drape read back: same scene and grid, the pinned particles where the scene pins them
        io::StartState start = io::load_start(parse_path(*options.start, "--start"), d.grid, d.model->stencils().active, d.problem.initial);
        for (int p : scene.pinned_indices()) start.x[p] = d.problem.initial[p];
        d.problem.initial = start.x;
        d.start_sha256 = start.sha256;
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
    require_finite_positions(run.result.x, "the drape");
    if (d.cut) {
        std::vector<Vec2> uv;
        run.cut_surface.emplace();
        run.cut_surface->mesh = model::cut_surface(d.grid, *d.cut, run.result.x, &uv);
        run.cut_surface->uv.assign(uv.begin(), uv.end());
        run.cut_surface->spacing_m = d.grid.sigma;
    }
    if (const auto box = analysis::box_footprint(d.scene.obstacles))
        run.folds = analysis::analyse_folds(
            run.cut_surface ? run.cut_surface->mesh : analysis::grid_mesh(run.result.x, d.grid.nu, d.grid.nv), *box);
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
    require_finite(report, "the drape", {"folds"});
    return report;
}

nlohmann::json write_drape_outputs(const DrapeRun& run, const std::string& out_dir, const DrapeWriteOptions& options)
{
    const DrapeSetup& d = *run.setup;
    make_output_dir(out_dir);
    std::vector<std::string> targets = kDrapeFiles;
    targets.push_back("report.json");
    check_output_targets(out_dir, targets);
    // Staged under temporary names, then published as one set with report.json last
    // (io::OutputSet). Nothing non-finite is written; an interrupt skips the picture.
    io::OutputSet set(out_dir, kDrapeFiles);
    const auto& cut_surface = run.cut_surface;
    io::add_drape_meshes(set, {&run.result.x, &*d.model, &d.scene.obstacles, d.scene.solver.contact_distance,
                               d.scene.solver.friction, options.ply_ascii ? io::PlyFormat::ASCII : io::PlyFormat::BINARY,
                               d.cut ? &cut_surface->mesh : nullptr, d.cut ? &cut_surface->uv : nullptr,
                               "drape of a cloth cut to its outline, scene " + d.scene.name, d.fabric.color});
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

}  // namespace woven::cli
