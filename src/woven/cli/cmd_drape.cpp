// woven drape [SCENE]: drape a cloth over a scene's obstacles and write drape.obj, drape.ply, drape.glb,
// drape.png and report.json.
#include <cmath>
#include <optional>
#include <iostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "woven/analysis/folds.hpp"
#include "woven/cli/args.hpp"
#include "woven/cli/commands.hpp"
#include "woven/cli/material.hpp"
#include "woven/cli/progress.hpp"
#include "woven/cli/report.hpp"
#include "woven/cli/run_checks.hpp"
#include "woven/cli/scene_view.hpp"
#include "woven/common/error.hpp"
#include "woven/io/drape_files.hpp"
#include "woven/io/fabric_file.hpp"
#include "woven/io/output.hpp"
#include "woven/io/output_set.hpp"
#include "woven/io/scene_file.hpp"
#include "woven/io/surface_file.hpp"
#include "woven/render/drape_view.hpp"

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

int run_drape(const DrapeOptions& options)
{
    // 1. Validate everything: options, scene, fabric, model. Nothing is written before this.
    const int width = static_cast<int>(parse_integer(options.width, "--width", 1, 16384));
    const int height = static_cast<int>(parse_integer(options.height, "--height", 1, 16384));
    const std::string out_dir = parse_path(options.out, "--out");

    std::vector<std::string> warnings;
    io::SceneSpec scene = io::find_scene(options.scene, &warnings);
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
    // Threads and memory before anything large is built.
    const ThreadCount threads = choose_threads(scene.solver.threads);
    scene.solver.threads = threads.used;
    check_memory(static_cast<long long>(scene.cloth.nu) * scene.cloth.nv, threads.used,
                 options.grid ? kCommandLine : scene.source_path, options.grid ? "--grid" : "cloth.grid");
    const kes::FabricData fabric = io::find_fabric(scene.fabric, &warnings);
    print_warnings(warnings);

    const model::Grid grid = scene.cloth.grid();
    std::optional<model::ClothModel> model_storage;  // fitting errors name the fabric's file
    with_fabric_source(fabric_source(scene.fabric), [&] {
        resolve_shear_law(fabric, scene.model);
        model_storage.emplace(model::make_cloth_model(fabric, grid, scene.model));
    });
    // A cloth cut to [cloth.outline]: only the kept particles, each weighing W x its area.
    std::optional<model::ClothCut> cut;
    if (scene.cloth.is_cut()) {
        cut = scene.cloth.cut(scene.source_path);
        with_fabric_source(fabric_source(scene.fabric),
                           [&] { model_storage.emplace(model::make_cloth_model(fabric, grid, scene.model, cut->active, cut->area)); });
    }
    const model::ClothModel& model = *model_storage;
    sim::Problem problem;
    problem.model = &model;
    problem.obstacles = &scene.obstacles;
    problem.initial = scene.cloth.initial_positions();
    problem.pinned = scene.pinned_indices();
    const double energy_initial = model.energy(problem.initial);

    // 2. The output directory, before the (long) solve, so that a bad --out fails early.
    make_output_dir(out_dir);
    check_output_targets(out_dir, {"drape.obj", "drape.ply", "drape.glb", "drape.png", "report.json"});
    io::OutputSet set(out_dir, {"drape.obj", "drape.ply", "drape.glb", "drape.png"});

    // 3. Drape.
    install_interrupt_handler();
    const int max_steps = scene.solver.max_steps > 0 ? scene.solver.max_steps : sim::default_max_steps(scene.solver.kind);
    Progress progress(max_steps, scene.solver.residual_tolerance);
    std::cerr << "woven: draping " << scene.name << " (" << grid.nu << " x " << grid.nv << " particles, fabric "
              << (fabric.name.empty() ? scene.fabric : fabric.name) << ", "
              << sim::to_string(scene.solver.kind) << " solver, " << shear_law_text(scene.model) << ")\n";
    sim::Result result =
        sim::drape(problem, scene.solver, [&progress](const sim::StepInfo& s) { return progress(s); },
                   [&progress](const sim::IterationInfo& i) { return progress.iteration(i); });
    progress.finish();
    bool interrupted = interrupt_requested() || result.interrupted;

    // 4. Outputs: staged under temporary names, then published as one set with report.json
    // last (io::OutputSet). Nothing non-finite is written; an interrupt skips the picture.
    auto out = [&](const std::string& name) { return join_path(out_dir, name); };
    require_finite_positions(result.x, "the drape");
    std::optional<render::ClothSurface> cut_surface;  // a cut cloth: its surface, clipped to the outline
    if (cut) {
        std::vector<Vec2> uv;
        cut_surface.emplace();
        cut_surface->mesh = model::cut_surface(grid, *cut, result.x, &uv);
        cut_surface->uv.assign(uv.begin(), uv.end());
        cut_surface->spacing_m = grid.sigma;
    }
    io::add_drape_meshes(set, {&result.x, &model, &scene.obstacles, scene.solver.contact_distance, scene.solver.friction,
                               options.ply_ascii ? io::PlyFormat::ASCII : io::PlyFormat::BINARY,
                               cut ? &cut_surface->mesh : nullptr, cut ? &cut_surface->uv : nullptr,
                               "drape of a cloth cut to its outline, scene " + scene.name, fabric.color});
    if (!options.no_render && !interrupt_requested()) {
        set.add("drape.png", render::encode_png(render_drape(result.x, grid, scene, fabric, width, height,
                                                             cut_surface ? &*cut_surface : nullptr),
                                                out("drape.png")));
    }
    DrapeReportInput in;
    in.scene = scene.name;
    in.scene_source = scene.source_path;
    in.fabric = fabric.name.empty() ? scene.fabric : fabric.name;
    in.fabric_data = &fabric;
    in.model = &model;
    in.model_options = &scene.model;
    in.obstacles = &scene.obstacles;
    in.solver = &scene.solver;
    in.result = &result;
    in.energy_initial = energy_initial;
    interrupted = interrupted || interrupt_requested();
    in.interrupted = interrupted;
    in.outputs = set.names();
    std::optional<analysis::FoldAnalysis> folds;  // over a box (the paper's cube): the corner folds
    if (const auto box = analysis::box_footprint(scene.obstacles))
        folds = analysis::analyse_folds(cut_surface ? cut_surface->mesh : analysis::grid_mesh(result.x, grid.nu, grid.nv), *box);
    in.folds = folds ? &*folds : nullptr;
    nlohmann::json report = drape_report(in);
    report["threads_requested"] = threads.requested;
    report["perturbation_m"] = scene.solver.kind == sim::SolverKind::FAST ? scene.solver.perturbation : 0.0;
    require_finite(report, "the drape", {"folds"});
    report["files"] = set.files_json();
    set.publish("report.json", report.dump(2) + "\n");

    std::cout << drape_summary(report) << "wrote";
    for (const auto& w : set.names()) std::cout << " " << out(w);
    std::cout << " " << out("report.json");
    std::cout << "\n";
    if (interrupted || interrupt_requested()) {
        std::cerr << "woven: interrupted after " << result.steps << " steps; the outputs hold the state reached"
                  << (result.converged ? "\n" : " (not converged)\n");
        return interrupted_exit_code();
    }
    if (!result.converged)
        std::cerr << "woven: warning: not converged after " << result.steps
                  << " steps (the outputs hold the state reached; raise --max-steps)\n";
    return kExitOk;
}

void add_drape_command(CLI::App& app, int& exit_code)
{
    auto o = std::make_shared<DrapeOptions>();
    CLI::App* sub = app.add_subcommand("drape", "Drape a cloth over a scene's obstacles to static equilibrium");
    sub->footer("Writes drape.obj, drape.ply (with per-vertex fields), drape.glb (glTF 2.0, y-up), drape.png and report.json (last, naming every file with its SHA-256) "
                "to --out. Ctrl-C (SIGINT) or SIGTERM stops after the current step, writes the state reached and exits "
                "with 130 or 143 (a second signal quits at once, leaving the previous outputs as they were).");
    sub->add_option("SCENE", o->scene, "A built-in scene name (see `woven scenes`) or a scene .toml file")
        ->capture_default_str();
    sub->add_option("--fabric", o->fabric, "Fabric: a built-in name or a fabric .toml file (overrides the scene's)");
    sub->add_option("--grid", o->grid, "Particles along the cloth's longer side (the cloth's size is kept)");
    sub->add_option("--solver", o->solver, "Solver: fast (implicit steps, projected Newton) or paper (Sec. 3)")
        ->check(CLI::IsMember({"fast", "paper"}));
    sub->add_option("--seed", o->seed, "Random seed: the fast solver's start perturbation (--perturb), the paper solver's stochastic phase");
    sub->add_option("--threads", o->threads, "Worker threads (0: all cores available to the process)");
    sub->add_option("--max-steps", o->max_steps, "Step limit (0: the solver's default)");
    sub->add_option("--perturb", o->perturb,
                    "Fast solver: amplitude of the seeded random perturbation of the start, m (0: none; the seed is --seed)");
    sub->add_option("--out", o->out, "Output directory")->capture_default_str();
    sub->add_flag("--no-render", o->no_render, "Do not render drape.png");
    sub->add_flag("--ply-ascii", o->ply_ascii, "Write drape.ply as ASCII PLY (default: binary little-endian)");
    sub->add_option("--width", o->width, "Picture width, pixels")->capture_default_str();
    sub->add_option("--height", o->height, "Picture height, pixels")->capture_default_str();
    sub->callback([o, &exit_code] { exit_code = run_drape(*o); });
}

}  // namespace woven::cli
