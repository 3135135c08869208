// woven.drape and woven.DrapeResult: `woven drape` in its stages (cli/drape_run.hpp).
#include <chrono>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "woven/analysis/vertex_fields.hpp"
#include "woven/cli/args.hpp"
#include "woven/cli/drape_run.hpp"
#include "woven/cli/progress.hpp"
#include "woven/io/output.hpp"

namespace woven::python {

namespace {

/// A drape's state and report; save() writes the command's files.
struct DrapeResult {
    std::shared_ptr<cli::DrapeSetup> setup;
    std::shared_ptr<cli::DrapeRun> run;
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
    const cli::DrapeRun& run = *r.run;
    std::vector<std::array<int, 3>> faces;
    if (run.cut_surface) {
        for (const auto& f : run.cut_surface->mesh.faces) faces.push_back({f[0], f[1], f[2]});
    } else {
        faces = io::grid_triangles(r.setup->grid.nu, r.setup->grid.nv);
    }
    py::array_t<std::int32_t> a({static_cast<py::ssize_t>(faces.size()), py::ssize_t(3)});
    auto m = a.mutable_unchecked<2>();
    for (std::size_t k = 0; k < faces.size(); ++k)
        for (int c = 0; c < 3; ++c) m(k, c) = faces[k][c];
    return a;
}

DrapeResult drape(py::object scene, py::object fabric, py::object grid, py::object solver, py::object seed, py::object threads,
                  py::object max_steps, py::object perturb, py::object hysteresis, py::object progress)
{
    cli::DrapeOptions o;
    cli::DrapeInputs in;
    std::vector<std::string> warnings;
    const Scene* given_scene = py::isinstance<Scene>(scene) ? &scene.cast<const Scene&>() : nullptr;
    if (!given_scene) o.scene = option_text(scene).value_or("cube");
    if (py::isinstance<Fabric>(fabric)) {
        const Fabric& f = fabric.cast<const Fabric&>();
        in.fabric = *f.data;
        in.fabric_source = f.source;
    } else {
        o.fabric = option_text(fabric);
    }
    o.grid = option_text(grid);
    o.solver = option_text(solver);
    o.seed = option_text(seed);
    o.threads = option_text(threads);
    o.max_steps = option_text(max_steps);
    o.perturb = option_text(perturb);
    o.hysteresis = option_text(hysteresis);
    if (!progress.is_none() && !PyCallable_Check(progress.ptr())) throw py::type_error("drape(): progress must be callable or None");

    // 1. Validate and build, as the command.
    DrapeResult r;
    run_command([&] {
        if (given_scene) in.scene = given_scene->build(&warnings);
        r.setup = cli::prepare_drape(o, warnings, std::move(in));
    });
    warn(warnings);

    // 2. The solve, without the GIL; each step and Newton iteration takes it back briefly to
    // look for Ctrl-C and to call `progress`.
    const cli::DrapeSetup& setup = *r.setup;
    const double tolerance = setup.scene.solver.residual_tolerance;
    cli::Progress measure(setup.max_steps, tolerance);  // the progress bar's fraction (not drawn)
    const auto start = std::chrono::steady_clock::now();
    bool interrupted = false;
    std::optional<py::error_already_set> error;
    const auto report = [&](py::dict info) {
        if (signal_seen()) {
            interrupted = true;
            return false;
        }
        if (progress.is_none()) return true;
        info["wall_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        try {
            const py::object answer = progress(info);
            if (answer.ptr() == Py_False) {
                interrupted = true;
                return false;
            }
        } catch (py::error_already_set& e) {
            if (e.matches(PyExc_KeyboardInterrupt))
                interrupted = true;
            else
                error = std::move(e);
            return false;
        }
        return true;
    };
    const auto on_step = [&](const sim::StepInfo& s) {
        py::gil_scoped_acquire gil;
        py::dict info;
        info["event"] = "step";
        info["step"] = s.step;
        info["max_steps"] = setup.max_steps;
        info["time_s"] = s.time;
        info["energy_J"] = s.energy;
        info["residual"] = s.max_residual_rel;
        info["tolerance"] = tolerance;
        info["move_m"] = s.max_move;
        info["fraction"] = measure.fraction(s.max_residual_rel);
        return report(info);
    };
    const auto on_iteration = [&](const sim::IterationInfo& i) {
        py::gil_scoped_acquire gil;
        py::dict info;
        info["event"] = "iteration";
        info["step"] = i.step;
        info["iteration"] = i.iteration;
        info["total_iterations"] = i.total_iterations;
        info["time_step_s"] = i.time_step;
        info["residual"] = i.residual_rel;
        info["tolerance"] = i.tolerance;
        return report(info);
    };
    sim::Result result;
    {
        py::gil_scoped_release release;
        result = cli::solve_drape(setup, on_step, on_iteration);
    }
    if (error) throw std::move(*error);

    // 3. The state reached, measured, and its report (report.json without `files`).
    r.run = std::make_shared<cli::DrapeRun>(cli::finish_drape(setup, std::move(result), interrupted));
    r.report = cli::drape_report_json(*r.run, {});
    return r;
}

nlohmann::json save(const DrapeResult& r, py::object out, bool render, bool ply_ascii, py::object width, py::object height)
{
    cli::DrapeWriteOptions w;
    w.no_render = !render;
    w.ply_ascii = ply_ascii;
    w.width = static_cast<int>(cli::parse_integer(option_text(width).value_or(""), "--width", 1, 16384));
    w.height = static_cast<int>(cli::parse_integer(option_text(height).value_or(""), "--height", 1, 16384));
    const std::string dir = cli::parse_path(option_text(out).value_or(""), "--out");
    nlohmann::json report;
    run_command([&] { report = cli::write_drape_outputs(*r.run, dir, w); });
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
            const cli::DrapeSetup& s = *r.setup;
            py::dict d;
            for (const auto& f : analysis::vertex_fields(*s.model, s.scene.obstacles, r.run->result.x, s.scene.solver.contact_distance,
                                                          s.scene.solver.friction).list())
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

    m.def("drape", &drape, py::arg("scene") = "cube", py::kw_only(), py::arg("fabric") = py::none(), py::arg("grid") = py::none(),
          py::arg("solver") = py::none(), py::arg("seed") = py::none(), py::arg("threads") = py::none(),
          py::arg("max_steps") = py::none(), py::arg("perturb") = py::none(), py::arg("hysteresis") = py::none(),
          py::arg("progress") = py::none(),
          R"(Drapes a cloth over a scene's obstacles to static equilibrium, as `woven drape` does.

scene: a built-in scene name, a scene .toml path or a woven.Scene. fabric: a built-in name, a
fabric .toml path or a woven.Fabric (default: the scene's). grid, solver ("fast" or "paper"),
seed, threads (0: all cores), max_steps (0: the solver's default), perturb (m) and hysteresis
("loading-branch" or "friction") are the command's options, checked as it checks them: a bad value raises woven.InputError with its
message ("command line: --grid: ..."). progress, if given, is called with a dict after each step
(event "step": step, max_steps, time_s, energy_J, residual and tolerance in units of m g,
move_m, wall_s, fraction of the way to the tolerance) and before each Newton iteration (event
"iteration": step, iteration, total_iterations, time_step_s, residual, tolerance, wall_s); if it
returns False the drape stops there, as on Ctrl-C. The solver runs without the GIL. Ctrl-C
stops it after the current step or iteration and returns the state reached, with
interrupted True. Returns a woven.DrapeResult.)");
}

}  // namespace woven::python
