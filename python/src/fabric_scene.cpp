// woven.Fabric, woven.Scene, woven.fabrics(), woven.scenes().
#include <cstdio>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "woven/app/drape_report.hpp"
#include "woven/app/run_checks.hpp"
#include "woven/io/fabric_file.hpp"
#include "woven/io/values.hpp"

namespace woven::python {

namespace {

/// values (a dict, or None) updated by the keyword arguments: what woven.Fabric(...) and
/// woven.Scene(...) take.
py::dict merged_values(const py::args& args, const py::kwargs& kwargs, const char* what)
{
    if (args.size() > 1) throw py::type_error(std::string(what) + "() takes at most one positional argument (a dict of the file's keys)");
    py::dict d;
    if (args.size() == 1 && !args[0].is_none()) {
        if (!PyDict_Check(args[0].ptr()))
            throw InputError(what == std::string("Fabric") ? kPythonFabric : kPythonScene, "",
                             "expected a dict of the file's keys, got " + py::str(py::type::handle_of(args[0]).attr("__name__")).cast<std::string>());
        d = py::dict(args[0]);  // a copy: the caller's dict stays as it was
    }
    for (auto [k, v] : kwargs) d[k] = v;
    return d;
}

Fabric fabric_from_python(const py::args& args, const py::kwargs& kwargs)
{
    const nlohmann::json values = to_values(merged_values(args, kwargs, "Fabric"), kPythonFabric);
    std::vector<std::string> warnings;
    Fabric f;
    without_gil([&] { f.data = std::make_shared<const kes::FabricData>(io::fabric_from_values(values, kPythonFabric, &warnings)); });
    f.source = kPythonFabric;
    warn(warnings);
    return f;
}

Fabric load_fabric(py::handle name_or_path)
{
    const std::string name = option_text(name_or_path).value_or("");
    std::vector<std::string> warnings;
    Fabric f;
    without_gil([&] { f.data = std::make_shared<const kes::FabricData>(io::find_fabric(name, &warnings)); });
    f.source = app::fabric_source(name);
    warn(warnings);
    return f;
}

Scene scene_from_python(const py::args& args, const py::kwargs& kwargs)
{
    Scene s;
    s.values = to_values(merged_values(args, kwargs, "Scene"), kPythonScene);
    s.base_dir = py::module_::import("os").attr("getcwd")().cast<std::string>();
    std::vector<std::string> warnings;
    without_gil([&] { s.spec = std::make_shared<const io::SceneSpec>(s.build(&warnings)); });
    warn(warnings);
    return s;
}

Scene load_scene(py::handle name_or_path)
{
    Scene s;
    s.name_or_path = option_text(name_or_path).value_or("");
    std::vector<std::string> warnings;
    without_gil([&] { s.spec = std::make_shared<const io::SceneSpec>(s.build(&warnings)); });
    warn(warnings);
    return s;
}

/// A curve as a (n, 2) float64 array: x, y in KES units.
py::array_t<double> curve_array(const kes::Curve& c)
{
    py::array_t<double> a({static_cast<py::ssize_t>(c.x.size()), py::ssize_t(2)});
    auto m = a.mutable_unchecked<2>();
    for (std::size_t k = 0; k < c.x.size(); ++k) {
        m(k, 0) = c.x[k];
        m(k, 1) = c.y[k];
    }
    return a;
}

template <class S, class F> py::object summary_value(const std::optional<S>& s, F get)
{
    return s ? py::object(py::float_(get(*s))) : py::object(py::none());
}

}  // namespace

void bind_fabric_scene(py::module_& m)
{
    m.def("fabrics", &io::builtin_fabric_names, "The names of the built-in fabrics (`woven fabrics`), sorted.");
    m.def("scenes", &io::builtin_scene_names, "The names of the built-in scenes (`woven scenes`), sorted.");

    py::class_<Fabric>(m, "Fabric", R"(A fabric: its KES values and curves, as `woven` reads them.

Fabric.load(name_or_path) reads a built-in fabric (see woven.fabrics()) or a fabric .toml file
(docs/FABRIC-FORMAT.md). Fabric(values=None, /, **keys) makes one from a dict and/or keyword
arguments with the file's keys and tables, checked as the file is (name, source,
areal_density_mg_cm2, bending={"warp": {"B": ..., "2HB": ...}, "weft": {...}},
shear={"G": ..., "2HG": ..., "2HG5": ...}, ...). Bad values raise woven.InputError (a
ValueError) with woven's message; unknown keys and unusual values give woven.InputWarning.)")
        .def(py::init(&fabric_from_python))
        .def_static("load", &load_fabric, py::arg("name_or_path"),
                    "A built-in fabric by name, or a fabric .toml file (a path: ends in .toml or contains '/').")
        .def_property_readonly("name", [](const Fabric& f) { return f.data->name; }, "The fabric's name.")
        .def_property_readonly("description", [](const Fabric& f) { return f.data->description; }, "Free text.")
        .def_property_readonly("source", [](const Fabric& f) { return f.data->source; }, "Where the numbers come from (a citation).")
        .def_property_readonly("representative", [](const Fabric& f) { return f.data->representative; },
                               "Which numbers are representative rather than measured.")
        .def_property_readonly("origin", [](const Fabric& f) { return f.source; },
                               "What it was read from: the file's path, \"built-in fabric 'name'\" or \"Python fabric\".")
        .def_property_readonly("areal_density_mg_cm2", [](const Fabric& f) { return f.data->areal_density_mg_cm2; },
                               "W, areal density, mg/cm^2.")
        .def_property_readonly("W", [](const Fabric& f) { return f.data->areal_density_mg_cm2; }, "W, mg/cm^2 (areal_density_mg_cm2).")
        .def_property_readonly("thickness_mm", [](const Fabric& f) { return f.data->thickness_mm; }, "Thickness, mm (None when not given).")
        .def_property_readonly("color", [](const Fabric& f) { return f.data->color; }, "Display colour, sRGB in 0..1 (None when not given).")
        .def_property_readonly("B_warp", [](const Fabric& f) { return app::kes_values(*f.data).B_warp; },
                               "KES-FB2 bending rigidity B, warp, gf.cm^2/cm (the summary value, or the curve's slope over 0.5-1.5 1/cm).")
        .def_property_readonly("B_weft", [](const Fabric& f) { return app::kes_values(*f.data).B_weft; },
                               "KES-FB2 bending rigidity B, weft, gf.cm^2/cm.")
        .def_property_readonly("G", [](const Fabric& f) { return app::kes_values(*f.data).G; },
                               "KES-FB1 shear rigidity G, gf/(cm.deg) (the summary value, or the curve's slope over 0.5-5 deg).")
        .def_property_readonly("two_HB_warp", [](const Fabric& f) { return summary_value(f.data->bending_warp.summary, [](const kes::BendingSummary& s) { return s.two_HB; }); },
                               "2HB, warp, gf.cm/cm (None when the file gave the curve).")
        .def_property_readonly("two_HB_weft", [](const Fabric& f) { return summary_value(f.data->bending_weft.summary, [](const kes::BendingSummary& s) { return s.two_HB; }); },
                               "2HB, weft, gf.cm/cm (None when the file gave the curve).")
        .def_property_readonly("two_HG", [](const Fabric& f) { return summary_value(f.data->shear.summary, [](const kes::ShearSummary& s) { return s.two_HG; }); },
                               "2HG, gf/cm (None when the file gave the curve).")
        .def_property_readonly("two_HG5", [](const Fabric& f) { return summary_value(f.data->shear.summary, [](const kes::ShearSummary& s) { return s.two_HG5; }); },
                               "2HG5, gf/cm (None when the file gave the curve).")
        .def_property_readonly("bending_warp_curve", [](const Fabric& f) { return curve_array(f.data->bending_warp.curve); },
                               "The first-stage KES-FB2 curve, warp: (n, 2) array of curvature (1/cm), moment (gf.cm/cm).")
        .def_property_readonly("bending_weft_curve", [](const Fabric& f) { return curve_array(f.data->bending_weft.curve); },
                               "The first-stage KES-FB2 curve, weft: (n, 2) array of curvature (1/cm), moment (gf.cm/cm).")
        .def_property_readonly("shear_curve", [](const Fabric& f) { return curve_array(f.data->shear.curve); },
                               "The first-stage KES-FB1 curve: (n, 2) array of shear angle (deg), force (gf/cm).")
        .def("__repr__", [](const Fabric& f) {
            const app::KesValues v = app::kes_values(*f.data);
            char b[200];
            std::snprintf(b, sizeof b, "': W %.4g mg/cm2, B %.4g / %.4g gf.cm2/cm (warp / weft), G %.4g gf/(cm.deg)>", v.W, v.B_warp,
                          v.B_weft, v.G);
            return "<woven.Fabric '" + f.data->name + b;
        });

    py::class_<Scene>(m, "Scene", R"(A scene: the cloth, its fabric, the obstacles, solver and model settings.

Scene.load(name_or_path) reads a built-in scene (see woven.scenes()) or a scene .toml file
(docs/SCENE-FORMAT.md). Scene(values=None, /, **keys) makes one from a dict and/or keyword
arguments with the file's keys and tables (cloth={...}, obstacle=[{...}, ...], solver={...},
...), checked as the file is; relative mesh and fabric paths resolve against the current
directory. Bad values raise woven.InputError (a ValueError) with woven's message.)")
        .def(py::init(&scene_from_python))
        .def_static("load", &load_scene, py::arg("name_or_path"), "A scene .toml file, or a built-in scene by name.")
        .def_property_readonly("name", [](const Scene& s) { return s.spec->name; }, "The scene's name.")
        .def_property_readonly("description", [](const Scene& s) { return s.spec->description; }, "Free text.")
        .def_property_readonly("source", [](const Scene& s) { return s.spec->source_path; },
                               "What it was read from (a path, scenes/<name>.toml, or \"Python scene\").")
        .def_property_readonly("fabric", [](const Scene& s) { return s.spec->fabric; }, "The scene's fabric: a built-in name or a path.")
        .def_property_readonly("grid", [](const Scene& s) { return py::make_tuple(s.spec->cloth.nu, s.spec->cloth.nv); },
                               "Particles along u (weft) and v (warp).")
        .def_property_readonly("size_m", [](const Scene& s) { return py::make_tuple(s.spec->cloth.size_u, s.spec->cloth.size_v); },
                               "The cloth's size along u and v, m.")
        .def_property_readonly("sigma_m", [](const Scene& s) { return s.spec->cloth.sigma(); }, "Particle spacing, m.")
        .def_property_readonly("obstacles", [](const Scene& s) { return s.spec->obstacle_kinds; }, "The obstacles' types, in file order.")
        .def_property_readonly("solver", [](const Scene& s) { return std::string(sim::to_string(s.spec->solver.kind)); },
                               "The solver: fast or paper.")
        .def_property_readonly("seed", [](const Scene& s) { return s.spec->solver.seed; }, "The random seed.")
        .def_property_readonly("max_steps", [](const Scene& s) { return s.spec->solver.max_steps; }, "Step limit (0: the solver's default).")
        .def("__repr__", [](const Scene& s) {
            return "<woven.Scene '" + s.spec->name + "': " + std::to_string(s.spec->cloth.nu) + " x " + std::to_string(s.spec->cloth.nv) +
                   " particles, fabric " + s.spec->fabric + ", " + std::to_string(s.spec->obstacle_kinds.size()) + " obstacles>";
        });
}

}  // namespace woven::python
