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

std::unique_ptr<DrapeSetup> prepare_drape(DrapeRequest request, std::vector<std::string>& warnings)
{
    const MonitorScope monitor(request.monitor);
    const DrapeRequest& r = request;
    auto setup = std::make_unique<DrapeSetup>();
    DrapeSetup& d = *setup;
    d.scene = r.scene_spec ? std::move(*request.scene_spec) : io::find_scene(r.scene, &warnings);
    io::SceneSpec& scene = d.scene;
    io::SceneOverrides ov;
    if (r.grid) ov.grid = static_cast<int>(integer_in_range(*r.grid, "--grid", kGridRange[0], kGridRange[1]));
    ov.fabric = r.fabric;
    ov.solver = r.solver;
    ov.seed = r.seed;
    if (r.max_steps) ov.max_steps = static_cast<int>(integer_in_range(*r.max_steps, "--max-steps", kMaxStepsRange[0], kMaxStepsRange[1]));
    if (r.threads) ov.threads = static_cast<int>(integer_in_range(*r.threads, "--threads", 0, io::kMaxThreads));
    io::apply_overrides(scene, ov, kCommandLine);
    if (r.perturb_m) scene.solver.perturbation = number_in_range(*r.perturb_m, "--perturb", 0, io::kMaxPerturbation_m);
    if (r.hysteresis) scene.model.hysteresis = *r.hysteresis;
    if (r.bias) scene.model.bias_bending = *r.bias;
    if (scene.model.hysteresis == model::Hysteresis::FRICTION && scene.solver.kind == sim::SolverKind::PAPER)
        throw InputError(r.hysteresis || r.solver ? kCommandLine : scene.source_path,
                         r.hysteresis ? "--hysteresis" : r.solver ? "--solver" : "model.hysteresis",
                         "expected loading-branch with the paper solver, or the fast solver with friction (friction inside the weave is the fast solver's)");
    // Threads and memory before anything large is built.
    d.threads = choose_threads(scene.solver.threads, warnings);
    scene.solver.threads = d.threads.used;
    check_memory(static_cast<long long>(scene.cloth.nu) * scene.cloth.nv, d.threads.used,
                 r.grid ? kCommandLine : scene.source_path, r.grid ? "--grid" : "cloth.grid");
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
        const std::string path = path_given(r.start->string(), "--start");
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

SteppedDrape::SteppedDrape(const DrapeSetup& setup) : setup_(setup), x_(setup.problem.initial)
{
    totals_.x = x_;
    totals_.energy = setup.model->evaluate(x_);
    totals_.equilibrium.max_residual_rel = sim::max_residual_relative(*setup.model, setup.scene.obstacles, x_, setup.problem.pinned,
                                                                       setup.scene.solver.contact_distance, setup.scene.solver.friction);
}

SteppedDrape::~SteppedDrape() { stop_worker(); }

void SteppedDrape::stop_worker()
{
    if (!worker_.joinable()) return;
    {
        const std::lock_guard lock(mutex_);
        stop_ = true;
        progress_ = nullptr;
        iteration_ = nullptr;
    }
    cv_.notify_all();
    worker_.join();
}

void SteppedDrape::start(int budget, const sim::ProgressCallback* progress, const sim::IterationCallback* iteration)
{
    stop_worker();
    finished_ = paused_ = stop_ = pause_due_ = false;
    budget_ = budget;  // before the worker runs
    progress_ = progress;
    iteration_ = iteration;
    base_ = totals_;
    sim::Problem problem = setup_.problem;
    problem.initial = x_;
    sim::SolverOptions options = setup_.scene.solver;
    if (started_) options.perturbation = 0;  // a further run starts from the state reached as it is
    started_ = true;
    ended_ = false;
    worker_ = std::thread([this, problem, options] {
        // The worker pauses when its budget is spent at the next callback after the step (the
        // next step's first iteration), so that a run that ends at that step ends first.
        const auto pause_if_due = [this](std::unique_lock<std::mutex>& lock) {
            if (!pause_due_ || stop_) return;
            pause_due_ = false;
            paused_ = true;
            cv_.notify_all();
            cv_.wait(lock, [this] { return budget_ > 0 || stop_; });
            paused_ = false;
        };
        const auto on_step = [this, pause_if_due](const sim::StepInfo& info) {
            std::unique_lock lock(mutex_);
            pause_if_due(lock);
            if (stop_) return false;
            const bool go = !progress_ || (*progress_)(info);
            if (info.x) x_ = *info.x;
            totals_.steps = base_.steps + info.step;
            totals_.simulated_time = base_.simulated_time + info.time;
            totals_.energy = setup_.model->evaluate(x_);
            totals_.equilibrium.max_residual_rel = info.max_residual_rel;
            totals_.equilibrium.max_move = info.max_move;
            if (--budget_ <= 0) pause_due_ = true;
            return go && !stop_;
        };
        const auto on_iteration = [this, pause_if_due](const sim::IterationInfo& info) {
            std::unique_lock lock(mutex_);
            pause_if_due(lock);
            if (stop_) return false;
            return !iteration_ || (*iteration_)(info);
        };
        sim::Result r;
        std::exception_ptr failure;
        try {
            r = sim::drape(problem, options, on_step, on_iteration);
        } catch (...) {
            failure = std::current_exception();  // raised by advance() on the caller's thread
        }
        const std::lock_guard lock(mutex_);
        run_result_ = std::move(r);
        failure_ = failure;
        finished_ = true;
        cv_.notify_all();
    });
}

void SteppedDrape::advance(int steps, const sim::ProgressCallback& progress, const sim::IterationCallback& iteration,
                           const std::function<bool()>& keep_waiting)
{
    if (steps < 1) throw InputError(kCommandLine, "steps", "expected at least 1 step, got " + std::to_string(steps));
    if (ended_) {
        start(steps, &progress, &iteration);
    } else {
        const std::lock_guard lock(mutex_);
        progress_ = &progress;
        iteration_ = &iteration;
        budget_ = steps;
    }
    std::unique_lock lock(mutex_);
    cv_.notify_all();
    while (!cv_.wait_for(lock, std::chrono::milliseconds(100), [this] { return (paused_ && budget_ <= 0) || finished_; })) {
        lock.unlock();
        const bool go = !keep_waiting || keep_waiting();
        lock.lock();
        if (!go) stop_ = true;
        cv_.notify_all();
    }
    progress_ = nullptr;
    iteration_ = nullptr;
    if (finished_) {
        lock.unlock();
        worker_.join();
        if (failure_) {
            ended_ = true;
            std::rethrow_exception(std::exchange(failure_, nullptr));
        }
        const sim::Result& r = run_result_;
        x_ = r.x;
        totals_ = base_;
        sim::add_counters(totals_, r);
        totals_.x = x_;
        totals_.energy = r.energy;
        totals_.equilibrium = r.equilibrium;
        totals_.converged = r.converged;
        totals_.interrupted = r.interrupted;
        ended_ = true;
    } else {
        totals_.x = x_;
        totals_.converged = false;
    }
}

void replace_obstacles(DrapeSetup& d, geometry::ObstacleSet obstacles, std::vector<std::string> kinds, const Positions& x,
                       const std::string& source)
{
    std::vector<char> pinned(x.size(), 0);
    for (int p : d.problem.pinned) pinned.at(static_cast<std::size_t>(p)) = 1;
    for (std::size_t i = 0; i < x.size(); ++i) {
        if (pinned[i] || !d.model->active(static_cast<int>(i))) continue;
        const double dist = obstacles.distance(x[i]);
        if (!(dist > 0))
            throw InputError(source, "obstacles",
                             "particle " + std::to_string(i) + " lies inside an obstacle (distance " + std::to_string(dist) +
                                 " m); the cloth is kept out of obstacles, not pushed out of them: move an obstacle in smaller steps");
    }
    d.scene.obstacles = std::move(obstacles);  // in place: a paused run's solver holds a reference to it
    d.scene.obstacle_kinds = std::move(kinds);
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
