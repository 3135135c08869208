// woven drape [SCENE]: drape a cloth over a scene's obstacles and write drape.obj, drape.ply,
// drape.png and report.json.
#include <cmath>
#include <iostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "woven/cli/commands.hpp"
#include "woven/cli/progress.hpp"
#include "woven/cli/report.hpp"
#include "woven/common/error.hpp"
#include "woven/io/fabric_file.hpp"
#include "woven/io/output.hpp"
#include "woven/io/scene_file.hpp"
#include "woven/render/raytracer.hpp"

namespace woven::cli {

namespace {

/// The cloth grid as a render mesh (the triangles of io::cloth_obj), uv in thread counts.
render::RenderMesh cloth_mesh(const Positions& x, const model::Grid& grid)
{
    render::RenderMesh m;
    m.mesh.vertices.assign(x.begin(), x.end());
    for (int j = 0; j + 1 < grid.nv; ++j)
        for (int i = 0; i + 1 < grid.nu; ++i) {
            const int a = grid.index(i, j), b = grid.index(i + 1, j), c = grid.index(i + 1, j + 1),
                      d = grid.index(i, j + 1);
            m.mesh.faces.emplace_back(a, b, c);
            m.mesh.faces.emplace_back(a, c, d);
        }
    m.uv.reserve(x.size());
    for (int j = 0; j < grid.nv; ++j)
        for (int i = 0; i < grid.nu; ++i) m.uv.emplace_back(double(i), double(j));
    m.color = Vec3(0.70, 0.28, 0.16);  // warm terracotta
    m.cloth = true;
    return m;
}

render::Image render_drape(const Positions& x, const model::Grid& grid, const io::SceneSpec& scene, int width,
                           int height)
{
    // The picture gives the cloth a thickness: particles closer than 0.2 sigma to an obstacle
    // are drawn lifted to 0.2 sigma, so that a curved surface (the chair's arms) does not show
    // through the flat triangles between particles. The OBJ/PLY keep the computed positions.
    Positions shown = x;
    const double thickness = 0.2 * grid.sigma;
    for (Vec3& p : shown)
        for (std::size_t k = 0; k < scene.obstacles.size(); ++k) {
            const geometry::Obstacle& o = scene.obstacles[k];
            if (o.distance(p) >= thickness) continue;
            const geometry::ClosestPoint c = o.closest(p);
            p += (thickness - c.distance) * c.normal;
        }
    std::vector<render::RenderMesh> meshes;
    meshes.push_back(cloth_mesh(shown, grid));
    geometry::Aabb frame;
    for (const Vec3& p : x) frame.extend(p);
    for (std::size_t k = 0; k < scene.obstacles.size(); ++k) {
        const geometry::Obstacle& o = scene.obstacles[k];
        render::RenderMesh m;
        m.mesh = o.tessellate();
        const bool ground = o.kind() == "plane";
        m.color = ground ? Vec3(0.85, 0.85, 0.83) : Vec3(0.72, 0.72, 0.72);
        meshes.push_back(std::move(m));
        if (!ground) frame.extend(o.bounds());  // planes are large: framing ignores them
    }
    render::Camera camera;
    if (scene.camera.given) {
        camera.eye = scene.camera.eye;
        camera.target = scene.camera.target;
        camera.fov_deg = scene.camera.fov_deg;
    } else {
        camera = render::frame_box(frame.lo, frame.hi);
    }
    render::RenderOptions ro;
    ro.width = width;
    ro.height = height;
    return woven::render::render(meshes, camera, ro);
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
        render::write_png(render_drape(result.x, grid, scene, options.width, options.height), out("drape.png"));
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
