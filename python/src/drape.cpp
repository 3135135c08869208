// woven.drape and woven.DrapeResult: `woven drape` in its stages (app/drape.hpp).
#include <filesystem>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "woven/app/drape.hpp"
#include "woven/app/progress.hpp"
#include "woven/geometry/mesh_ops.hpp"
#include "woven/io/drape_files.hpp"
#include "woven/io/output.hpp"
#include "woven/io/output_checks.hpp"
#include "woven/io/sha256.hpp"
#include "woven/io/values.hpp"
#include "woven/sim/solver.hpp"

namespace woven::python {

namespace {

/// A drape's state and report; save() writes the command's files.
struct DrapeResult {
    std::shared_ptr<app::DrapeSetup> setup;
    std::shared_ptr<app::DrapeRun> run;
    nlohmann::json report;
};

py::array_t<double> points_array(const std::vector<Vec3, Eigen::aligned_allocator<Vec3>>& x)
{
    py::array_t<double> a({static_cast<py::ssize_t>(x.size()), py::ssize_t(3)});
    auto m = a.mutable_unchecked<2>();
    for (std::size_t k = 0; k < x.size(); ++k)
        for (int c = 0; c < 3; ++c) m(k, c) = x[k][c];
    return a;
}

py::array_t<std::int32_t> faces_array(const DrapeResult& r)
{
    const app::DrapeRun& run = *r.run;
    const std::vector<Eigen::Vector3i> faces = run.cut_surface ? run.cut_surface->mesh.faces
                                        : geometry::grid_mesh(run.result.x, r.setup->grid.nu, r.setup->grid.nv).faces;
    py::array_t<std::int32_t> a({static_cast<py::ssize_t>(faces.size()), py::ssize_t(3)});
    auto m = a.mutable_unchecked<2>();
    for (std::size_t k = 0; k < faces.size(); ++k)
        for (int c = 0; c < 3; ++c) m(k, c) = faces[k][c];
    return a;
}

/// woven.drape's and woven.Drape's scene, fabric and options, checked and built as the command
/// builds them (app::prepare_drape). Call with a CallLock held.
std::shared_ptr<app::DrapeSetup> setup_drape(py::object scene, py::object fabric, py::object grid, py::object solver, py::object seed,
                                             py::object threads, py::object max_steps, py::object perturb, py::object hysteresis,
                                             py::object bias = py::none(), py::object initial_positions = py::none(),
                                             const char* caller = "drape()")
{
    // The options, typed, to the command's request builder: each checked once, an error naming
    // the keyword ("grid: expected ...").
    app::DrapeValues values;
    values.grid = given_integer(grid);
    values.solver = option_text(solver);
    values.seed = given_seed(seed);
    values.threads = given_integer(threads);
    values.max_steps = given_integer(max_steps);
    values.perturb_m = given_number(perturb);
    values.hysteresis = option_text(hysteresis);
    values.bias = option_text(bias);
    std::vector<std::string> warnings;
    const Scene* given_scene = py::isinstance<Scene>(scene) ? &scene.cast<const Scene&>() : nullptr;
    const std::string scene_name = given_scene ? std::string() : option_text(scene).value_or("cube");
    std::optional<io::SceneSpec> spec;
    run_command([&](const app::Monitor&) {  // the scene, then the options
        spec = given_scene ? given_scene->build(&warnings) : io::find_scene(scene_name, &warnings);
    });
    app::DrapeRequest in = app::drape_request(values, app::Naming::KEYWORDS);
    in.scene = scene_name;
    in.scene_spec = std::move(spec);
    if (py::isinstance<Fabric>(fabric)) {
        const Fabric& f = fabric.cast<const Fabric&>();
        in.fabric_data = *f.data;
        in.fabric_source = f.source;
    } else {
        in.fabric = option_text(fabric);
    }
    if (!initial_positions.is_none()) {  // an (n, 3) array of positions in m
        const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(initial_positions);
        if (!a || a.ndim() != 2 || a.shape(1) != 3)
            throw py::type_error(std::string(caller)
                                 + ": initial_positions must be an (n, 3) array of positions in m, n the grid's particles");
        Positions x(static_cast<std::size_t>(a.shape(0)));
        const auto v = a.unchecked<2>();
        for (py::ssize_t k = 0; k < a.shape(0); ++k) x[static_cast<std::size_t>(k)] = Vec3(v(k, 0), v(k, 1), v(k, 2));
        in.initial_sha256 = io::sha256_hex(std::string_view(reinterpret_cast<const char*>(a.data()), static_cast<std::size_t>(a.nbytes())));
        in.initial = std::move(x);
    }
    std::shared_ptr<app::DrapeSetup> setup;
    run_command([&](const app::Monitor& monitor) {
        in.monitor = monitor;
        setup = app::prepare_drape(std::move(in), warnings);
    });
    warn(warnings);
    return setup;
}

/// The solver's callbacks for a Python progress callable: each step and Newton iteration takes
/// the GIL back briefly to look for Ctrl-C and to call `progress`.
class SolveCallbacks {
public:
    SolveCallbacks(py::object progress, const app::DrapeSetup& setup)
        : progress_(std::move(progress)), measure_(setup.max_steps, setup.scene.solver.residual_tolerance)
    {
        if (!progress_.is_none() && !PyCallable_Check(progress_.ptr())) throw py::type_error("progress must be callable or None");
    }
    sim::ProgressCallback on_step()
    {
        return [this](const sim::StepInfo& s) {
            if (interpreter_finalizing()) return false;
            py::gil_scoped_acquire gil;
            return report(measure_.step_event(s));
        };
    }
    sim::IterationCallback on_iteration()
    {
        return [this](const sim::IterationInfo& i) {
            if (interpreter_finalizing()) return false;
            py::gil_scoped_acquire gil;
            return report(measure_.iteration_event(i));
        };
    }
    bool interrupted() const { return interrupted_; }
    /// Raises what the callable raised (other than KeyboardInterrupt), if it did.
    void raise_error()
    {
        if (error_) throw std::move(*error_);
    }

private:
    bool report(const app::ProgressEvent& e)
    {
        if (signal_seen()) {
            interrupted_ = true;
            return false;
        }
        if (progress_.is_none()) return true;
        if (call_progress(progress_, event_dict(e), error_)) return true;
        if (!error_) interrupted_ = true;
        return false;
    }

    py::object progress_;
    app::Progress measure_;  ///< the events, with the progress bar's fraction (none sent to a sink)
    bool interrupted_ = false;
    std::optional<py::error_already_set> error_;
};

DrapeResult drape(py::object scene, py::object fabric, py::object grid, py::object solver, py::object seed, py::object threads,
                  py::object max_steps, py::object perturb, py::object hysteresis, py::object progress, py::object bias,
                  py::object initial_positions)
{
    if (!progress.is_none() && !PyCallable_Check(progress.ptr())) throw py::type_error("drape(): progress must be callable or None");
    // 1. Validate and build, as the command (one call at a time: bindings.hpp).
    const CallLock lock;
    DrapeResult r;
    r.setup = setup_drape(scene, fabric, grid, solver, seed, threads, max_steps, perturb, hysteresis, bias, initial_positions);

    // 2. The solve, without the GIL.
    const app::DrapeSetup& setup = *r.setup;
    SolveCallbacks callbacks(progress, setup);
    sim::Result result;
    std::exception_ptr failure;
    {
        py::gil_scoped_release release;
        try {
            result = app::solve_drape(setup, callbacks.on_step(), callbacks.on_iteration());
        } catch (...) {
            failure = std::current_exception();
        }
        wait_out_finalization();  // a daemon thread's drape at interpreter exit
    }
    if (failure) std::rethrow_exception(failure);
    callbacks.raise_error();

    // 3. The state reached, measured, and its report (report.json without `files`).
    r.run = std::make_shared<app::DrapeRun>(app::finish_drape(setup, std::move(result), callbacks.interrupted()));
    r.report = app::drape_report_json(*r.run, {});
    return r;
}

/// woven.Drape: a drape stepped from Python, on the solver object (sim::Solver) itself.
struct Stepper {
    std::shared_ptr<app::DrapeSetup> setup;
    std::unique_ptr<sim::Solver> solver;  ///< after setup: its problem points into it
};

std::shared_ptr<Stepper> make_stepper(py::object scene, py::object fabric, py::object grid, py::object solver, py::object seed,
                                      py::object threads, py::object max_steps, py::object perturb, py::object hysteresis, py::object bias,
                                      py::object initial_positions)
{
    const CallLock lock;
    auto st = std::make_shared<Stepper>();
    st->setup = setup_drape(scene, fabric, grid, solver, seed, threads, max_steps, perturb, hysteresis, bias, initial_positions, "Drape()");
    run_command([&](const app::Monitor&) { st->solver = sim::make_solver(st->setup->problem, st->setup->scene.solver); });
    return st;
}

bool step(Stepper& st, int steps, py::object progress)
{
    const CallLock lock;
    if (steps < 1) throw InputError("Drape.step", "steps", "expected at least 1 step, got " + std::to_string(steps));
    SolveCallbacks callbacks(progress, *st.setup);
    const sim::ProgressCallback on_step = callbacks.on_step();
    const sim::IterationCallback on_iteration = callbacks.on_iteration();
    {
        py::gil_scoped_release release;  // the callbacks take it back briefly (Ctrl-C, progress)
        sim::Solver& solver = *st.solver;
        for (int k = 0; k < steps; ++k) {
            if (!solver.step(on_iteration)) break;
            if (solver.report_due() && !on_step(solver.step_info())) break;
            if (solver.converged()) break;
        }
    }
    callbacks.raise_error();
    io::require_finite_positions(st.solver->positions(), "the drape");
    return st.solver->converged();
}

void set_obstacles(Stepper& st, py::iterable obstacles)
{
    const CallLock lock;
    // Built twice from the same values: one set for the solver, one for the scene (the report,
    // the folds and the picture read the scene's).
    geometry::ObstacleSet for_solver, for_scene;
    std::vector<std::string> kinds;
    const std::string base = std::filesystem::current_path().string();
    for (py::handle h : obstacles) {
        if (!py::isinstance<Obstacle>(h)) throw py::type_error("Drape.obstacles: expected woven.Obstacle objects");
        const Obstacle& o = h.cast<const Obstacle&>();
        std::string kind;
        for_solver.add(io::obstacle_from_values(o.values, kPythonObstacle, base, &kind));
        for_scene.add(io::obstacle_from_values(o.values, kPythonObstacle, base, nullptr));
        kinds.push_back(kind);
    }
    try {
        st.solver->set_obstacles(std::move(for_solver));
    } catch (const InputError& e) {
        throw InputError("Drape", "obstacles", e.what());
    }
    st.setup->scene.obstacles = std::move(for_scene);
    st.setup->scene.obstacle_kinds = std::move(kinds);
}

DrapeResult stepper_result(const Stepper& st)
{
    const CallLock lock;
    DrapeResult r;
    r.setup = st.setup;
    sim::Result result = st.solver->result();
    const bool interrupted = result.interrupted;
    r.run = std::make_shared<app::DrapeRun>(app::finish_drape(*st.setup, std::move(result), interrupted));
    r.report = app::drape_report_json(*r.run, {});
    return r;
}

nlohmann::json save(const DrapeResult& r, py::object out, bool render, bool ply_ascii, py::object width, py::object height)
{
    app::DrapeWriteOptions w;
    w.no_render = !render;
    w.ply_ascii = ply_ascii;
    w.width = static_cast<int>(integer_arg(width, "--width", app::kPictureSizeRange[0], app::kPictureSizeRange[1]).value_or(0));
    w.height = static_cast<int>(integer_arg(height, "--height", app::kPictureSizeRange[0], app::kPictureSizeRange[1]).value_or(0));
    const std::string dir = option_text(out).value_or("");
    nlohmann::json report;
    run_command([&](const app::Monitor& monitor) {
        w.monitor = monitor;
        report = app::write_drape_outputs(*r.run, dir, w);
    });
    return report;
}

}  // namespace

void bind_drape(py::module_& m)
{
    py::class_<DrapeResult>(m, "DrapeResult", R"(A drape's state reached and its report (woven.drape).

positions and faces are the cloth's mesh as drape.obj holds it (the particles and the grid's
triangles; for a cloth cut to an outline, its surface clipped to the outline); particles and
fields are per grid particle, as in drape.ply. save(dir) writes the files `woven drape` writes.)")
        .def_property_readonly("positions", [](const DrapeResult& r) {
            return points_array(r.run->cut_surface ? r.run->cut_surface->mesh.vertices : r.run->result.x);
        }, "The cloth mesh's vertices, (n, 3) float64, metres, z up (drape.obj's v lines).")
        .def_property_readonly("faces", &faces_array, "The cloth mesh's triangles, (m, 3) int32, 0-based indices into positions.")
        .def_property_readonly("particles", [](const DrapeResult& r) { return points_array(r.run->result.x); },
                               "Every grid particle, (nu * nv, 3) float64, metres; particle (i, j) is row i + nu * j.")
        .def_property_readonly("grid", [](const DrapeResult& r) { return py::make_tuple(r.setup->grid.nu, r.setup->grid.nv); },
                               "(nu, nv): particles along u (weft, i) and v (warp, j).")
        .def_property_readonly("fields", [](const DrapeResult& r) {
            const app::DrapeSetup& s = *r.setup;
            py::dict d;
            io::DrapeMeshes meshes;
            meshes.x = &r.run->result.x;
            meshes.model = &*s.model;
            meshes.obstacles = &s.scene.obstacles;
            meshes.contact_distance = s.scene.solver.contact_distance;
            meshes.friction = s.scene.solver.friction;
            for (const auto& f : io::drape_vertex_fields(meshes).list())
                d[py::str(f.name)] = py::array_t<double>(static_cast<py::ssize_t>(f.values.size()), f.values.data());
            return d;
        }, "Per-particle fields, as drape.ply holds them (SI units): strain_warp, strain_weft, trellis_angle, curvature_warp, "
           "curvature_weft, contact, residual_force; each (nu * nv,) float64.")
        .def_property_readonly("report", [](const DrapeResult& r) { return to_python(r.report); },
                               "report.json as a dict (README \"report.json\"); `outputs` is empty and `files` absent until save().")
        .def_property_readonly("converged", [](const DrapeResult& r) { return r.run->result.converged; }, "True when the drape reached equilibrium.")
        .def_property_readonly("interrupted", [](const DrapeResult& r) { return r.run->interrupted; },
                               "True when Ctrl-C or the progress callable stopped it: the state is the one reached.")
        .def_property_readonly("steps", [](const DrapeResult& r) { return r.run->result.steps; }, "Steps taken.")
        .def("save", [](const DrapeResult& r, py::object out, bool render, bool ply_ascii, py::object width, py::object height) {
            return to_python(save(r, out, render, ply_ascii, width, height));
        }, py::arg("out"), py::arg("render") = true, py::arg("ply_ascii") = false, py::arg("width") = 1024, py::arg("height") = 768,
           R"(Writes the files `woven drape --out OUT` writes: drape.obj, drape.ply, drape.glb, drape.png (unless
render is False, or the drape was interrupted) and report.json last, as one set. Returns the
report written (with `files`: each file's size and SHA-256).)")
        .def("__repr__", [](const DrapeResult& r) {
            return "<woven.DrapeResult " + r.report.value("scene", std::string()) + ", " + r.report.value("fabric", std::string()) + ", " +
                   std::to_string(r.setup->grid.nu) + " x " + std::to_string(r.setup->grid.nv) + ", " +
                   (r.run->result.converged ? "converged" : "not converged") + (r.run->interrupted ? ", interrupted" : "") + ", " +
                   std::to_string(r.run->result.steps) + " steps>";
        });

    py::class_<Stepper, std::shared_ptr<Stepper>>(m, "Drape", R"(A drape advanced step by step, its obstacles movable between steps.

Drape(scene, *, fabric, grid, solver, seed, threads, max_steps, perturb, hysteresis, bias,
initial_positions) takes woven.drape's arguments (checked as the command checks them) and
holds the start; step(n) takes at most n solver steps (sim::Solver's step, on this thread
without the GIL), stopping early at rest: step by step, the drape is woven.drape's, bit for
bit. max_steps is the progress dict's limit; step() itself takes the steps asked for. Once at
rest, a further step() steps on from the state reached (after moving an obstacle, say).

>>> import woven
>>> d = woven.Drape("cube", fabric="cotton", grid=11, seed=1, threads=1)
>>> d.steps, d.positions.shape, d.converged
(0, (121, 3), False)
>>> while not d.converged and d.steps < 100:
...     _ = d.step()
>>> d.converged, d.residual <= d.tolerance
(True, True)
>>> d.obstacles
['plane', 'box']
>>> d.obstacles = [woven.Obstacle.plane(), woven.Obstacle.box((0, 0, 0.2), (0.5, 0.5, 0.4))]
>>> d.converged
False
>>> top = d.positions[:, 2].max()
>>> _ = d.step(50)
>>> bool(d.positions[:, 2].max() < top - 0.05)
True
>>> d.result().report["steps"] == d.steps
True

Replacing the obstacles refuses (woven.InputError) a set that a free particle lies inside:
the cloth is kept out of obstacles, not pushed out of them.)")
        .def(py::init(&make_stepper), py::arg("scene") = "cube", py::kw_only(), py::arg("fabric") = py::none(),
             py::arg("grid") = py::none(), py::arg("solver") = py::none(), py::arg("seed") = py::none(), py::arg("threads") = py::none(),
             py::arg("max_steps") = py::none(), py::arg("perturb") = py::none(), py::arg("hysteresis") = py::none(),
             py::arg("bias") = py::none(), py::arg("initial_positions") = py::none())
        .def("step", &step, py::arg("steps") = 1, py::kw_only(), py::arg("progress") = py::none(),
             "Takes at most `steps` solver steps (fewer when it comes to rest, or progress or Ctrl-C stops it); progress as "
             "woven.drape's. Returns converged.")
        .def_property_readonly(
            "positions", [](const Stepper& st) { return points_array(st.solver->positions()); },
            "Every grid particle, (nu * nv, 3) float64, metres, z up; particle (i, j) is row i + nu * j.")
        .def_property_readonly(
            "grid", [](const Stepper& st) { return py::make_tuple(st.setup->grid.nu, st.setup->grid.nv); }, "(nu, nv).")
        .def_property_readonly(
            "energy", [](const Stepper& st) { return st.solver->energy(); }, "The model's energy at the state, J.")
        .def_property_readonly(
            "residual", [](const Stepper& st) { return st.solver->residual(); },
            "The largest residual force on a free particle over its weight m g (report.json's max_residual_rel).")
        .def_property_readonly(
            "tolerance", [](const Stepper& st) { return st.setup->scene.solver.residual_tolerance; },
            "The residual at which the drape is at rest.")
        .def_property_readonly(
            "steps", [](const Stepper& st) { return st.solver->steps(); }, "Solver steps taken so far.")
        .def_property_readonly(
            "time_s", [](const Stepper& st) { return st.solver->time(); }, "Simulated time so far, s.")
        .def_property_readonly(
            "converged", [](const Stepper& st) { return st.solver->converged(); },
            "True when the last step ended at rest (False again after the obstacles change).")
        .def_property(
            "obstacles", [](const Stepper& st) { return st.setup->scene.obstacle_kinds; }, &set_obstacles,
            "The obstacles' types; set it to a list of woven.Obstacle to replace them between steps.")
        .def("result", &stepper_result,
             "The state reached as a woven.DrapeResult (its report, fields and save()); it shares this drape's scene.")
        .def("__repr__", [](const Stepper& st) {
            return "<woven.Drape " + st.setup->scene.name + ", " + std::to_string(st.setup->grid.nu) + " x "
                + std::to_string(st.setup->grid.nv) + ", " + std::to_string(st.solver->steps()) + " steps"
                + (st.solver->converged() ? ", converged>" : ">");
        });

    m.def("drape", &drape, py::arg("scene") = "cube", py::kw_only(), py::arg("fabric") = py::none(), py::arg("grid") = py::none(),
          py::arg("solver") = py::none(), py::arg("seed") = py::none(), py::arg("threads") = py::none(),
          py::arg("max_steps") = py::none(), py::arg("perturb") = py::none(), py::arg("hysteresis") = py::none(),
          py::arg("progress") = py::none(), py::arg("bias") = py::none(), py::arg("initial_positions") = py::none(),
          R"(Drapes a cloth over a scene's obstacles to static equilibrium, as `woven drape` does.

scene: a built-in scene name, a scene .toml path or a woven.Scene. fabric: a built-in name, a
fabric .toml path or a woven.Fabric (default: the scene's). grid, solver ("fast" or "paper"),
seed, threads (0: all cores), max_steps (0: the solver's default), perturb (m) and hysteresis
("loading-branch" or "friction") and bias ("threads" or "fabric": bias bending) are the
command's options, checked by the command's own request builder: a bad value raises
woven.InputError naming the keyword ("grid: expected an integer in [3, 100000], got '2'"). progress, if given, is called with a dict after each step
(event "step": step, max_steps, time_s, energy_J, residual and tolerance in units of m g,
move_m, wall_s, fraction of the way to the tolerance) and before each Newton iteration (event
"iteration": step, iteration, total_iterations, time_step_s, residual, tolerance, wall_s); if it
returns False the drape stops there, as on Ctrl-C. The solver runs without the GIL. Ctrl-C
stops it after the current step or iteration and returns the state reached, with
interrupted True. initial_positions, an (n, 3) array in m (n the grid's particles, as
DrapeResult.particles), starts the cloth there instead of the scene's flat start (the scene's
pinned particles stay where it pins them); report["start_sha256"] is the SHA-256 of its float64
bytes. Returns a woven.DrapeResult.)");
}

}  // namespace woven::python
