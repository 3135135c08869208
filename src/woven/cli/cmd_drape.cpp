// woven drape [SCENE]: drape a cloth over a scene's obstacles and write drape.obj, drape.ply,
// drape.png and report.json.
#include <cmath>
#include <optional>
#include <iostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "woven/analysis/folds.hpp"
#include "woven/cli/commands.hpp"
#include "woven/cli/progress.hpp"
#include "woven/cli/report.hpp"
#include "woven/common/error.hpp"
#include "woven/io/fabric_file.hpp"
#include "woven/io/output.hpp"
#include "woven/io/scene_file.hpp"
#include "woven/render/drape_view.hpp"

namespace woven::cli {

namespace {

/// drape.png: the cloth (a smooth surface through the particles, the fabric's colour) over the
/// obstacles, seen along the scene camera's direction (if it has one), framed tightly.
render::Image render_drape(const Positions& x, const model::Grid& grid, const io::SceneSpec& scene,
                           const kes::FabricData& fabric, int width, int height)
{
    render::DrapeScene ds;
    ds.cloth = render::grid_surface(x, grid.nu, grid.nv);
    ds.cloth_color = render::fabric_color(fabric.color);
    ds.obstacles = &scene.obstacles;
    if (scene.camera.given) {
        render::Camera c;
        c.eye = scene.camera.eye;
        c.target = scene.camera.target;
        c.fov_deg = scene.camera.fov_deg;
        ds.scene_camera = c;
    }
    render::RenderOptions ro;
    ro.width = width;
    ro.height = height;
    return render::render_drape(ds, render::view_camera(ds, render::View::SCENE, double(width) / height), ro);
}

}  // namespace

int run_drape(const DrapeOptions& options)
{
    // 1. Validate everything: options, scene, fabric, model. Nothing is written before this.
    const std::string cl = "command line";
    if (options.width < 1 || options.width > 16384) throw InputError(cl, "--width", "expected 1 .. 16384 pixels");
    if (options.height < 1 || options.height > 16384) throw InputError(cl, "--height", "expected 1 .. 16384 pixels");
    if (options.out.empty()) throw InputError(cl, "--out", "expected a directory");

    std::vector<std::string> warnings;
    io::SceneSpec scene = io::find_scene(options.scene, &warnings);
    io::SceneOverrides ov;
    ov.grid = options.grid;
    ov.fabric = options.fabric;
    if (options.solver) {
        if (*options.solver == "fast")
            ov.solver = sim::SolverKind::FAST;
        else if (*options.solver == "paper")
            ov.solver = sim::SolverKind::PAPER;
        else
            throw InputError(cl, "--solver", "expected fast or paper");
    }
    ov.seed = options.seed;
    ov.max_steps = options.max_steps;
    ov.threads = options.threads;
    io::apply_overrides(scene, ov, cl);
    const kes::FabricData fabric = io::find_fabric(scene.fabric, &warnings);
    print_warnings(warnings);

    const model::Grid grid = scene.cloth.grid();
    const model::ClothModel model = model::make_cloth_model(fabric, grid, scene.model);
    sim::Problem problem;
    problem.model = &model;
    problem.obstacles = &scene.obstacles;
    problem.initial = scene.cloth.initial_positions();
    problem.pinned = scene.pinned_indices();
    const double energy_initial = model.energy(problem.initial);

    // 2. The output directory, before the (long) solve, so that a bad --out fails early.
    make_output_dir(options.out);

    // 3. Drape.
    install_interrupt_handler();
    const int max_steps = scene.solver.max_steps > 0 ? scene.solver.max_steps
                          : scene.solver.kind == sim::SolverKind::FAST ? 400
                                                                        : 200000;
    Progress progress(max_steps);
    std::cerr << "woven: draping " << scene.name << " (" << grid.nu << " x " << grid.nv << " particles, fabric "
              << (fabric.name.empty() ? scene.fabric : fabric.name) << ", "
              << (scene.solver.kind == sim::SolverKind::FAST ? "fast" : "paper") << " solver)\n";
    sim::Result result = sim::drape(problem, scene.solver, [&progress](const sim::StepInfo& s) { return progress(s); });
    progress.finish();
    const bool interrupted = interrupt_requested() || result.interrupted;

    // 4. Outputs (each written atomically).
    std::vector<std::string> written;
    auto out = [&](const std::string& name) { return join_path(options.out, name); };
    io::write_file_atomic(out("drape.obj"), io::cloth_obj(result.x, grid.nu, grid.nv));
    written.push_back("drape.obj");
    io::write_file_atomic(out("drape.ply"), io::cloth_ply(result.x, grid.nu, grid.nv));
    written.push_back("drape.ply");
    if (!options.no_render) {
        render::write_png(render_drape(result.x, grid, scene, fabric, options.width, options.height), out("drape.png"));
        written.push_back("drape.png");
    }
    DrapeReportInput in;
    in.scene = scene.name;
    in.scene_source = scene.source_path;
    in.fabric = fabric.name.empty() ? scene.fabric : fabric.name;
    in.fabric_data = &fabric;
    in.model = &model;
    in.obstacles = &scene.obstacles;
    in.solver = &scene.solver;
    in.result = &result;
    in.energy_initial = energy_initial;
    in.interrupted = interrupted;
    in.outputs = written;
    std::optional<analysis::FoldAnalysis> folds;  // over a box (the paper's cube): the corner folds
    if (const auto box = analysis::box_footprint(scene.obstacles))
        folds = analysis::analyse_folds(analysis::grid_mesh(result.x, grid.nu, grid.nv), *box);
    in.folds = folds ? &*folds : nullptr;
    const nlohmann::json report = drape_report(in);
    io::write_file_atomic(out("report.json"), report.dump(2) + "\n");
    written.push_back("report.json");

    std::cout << drape_summary(report) << "wrote";
    for (const auto& w : written) std::cout << " " << out(w);
    std::cout << "\n";
    if (interrupted) {
        std::cerr << "woven: interrupted after " << result.steps << " steps; the outputs hold the state reached "
                  << "(not converged)\n";
        return kExitInterrupted;
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
    sub->footer("Writes drape.obj, drape.ply, drape.png and report.json to --out. Ctrl-C stops after the current "
                "step, writes the state reached and exits with code 130 (a second Ctrl-C quits at once).");
    sub->add_option("SCENE", o->scene, "A built-in scene name (see `woven scenes`) or a scene .toml file")
        ->capture_default_str();
    sub->add_option("--fabric", o->fabric, "Fabric: a built-in name or a fabric .toml file (overrides the scene's)");
    sub->add_option("--grid", o->grid, "Particles along the cloth's longer side (the cloth's size is kept)");
    sub->add_option("--solver", o->solver, "Solver: fast (implicit steps, projected Newton) or paper (Sec. 3)")
        ->check(CLI::IsMember({"fast", "paper"}));
    sub->add_option("--seed", o->seed, "Random seed (the paper solver's stochastic phase)")->check(CLI::NonNegativeNumber);
    sub->add_option("--threads", o->threads, "Worker threads (0: all cores)")->check(CLI::NonNegativeNumber);
    sub->add_option("--max-steps", o->max_steps, "Step limit (0: the solver's default)");
    sub->add_option("--out", o->out, "Output directory")->capture_default_str();
    sub->add_flag("--no-render", o->no_render, "Do not render drape.png");
    sub->add_option("--width", o->width, "Picture width, pixels")->capture_default_str();
    sub->add_option("--height", o->height, "Picture height, pixels")->capture_default_str();
    sub->callback([o, &exit_code] { exit_code = run_drape(*o); });
}

}  // namespace woven::cli
