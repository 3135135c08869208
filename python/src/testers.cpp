// woven.kes_test, woven.cusick, woven.fit: the commands' own code, their report returned as a dict.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>

#include <pybind11/numpy.h>

#include "bindings.hpp"
#include "woven/common/error.hpp"
#include "woven/io/mesh_file.hpp"

namespace woven::python {

namespace {

namespace fs = std::filesystem;

/// The folder a command writes to: `out`, or a temporary one removed when done.
class OutDir {
public:
    explicit OutDir(py::handle out)
    {
        if (const auto o = option_text(out)) {
            path_ = *o;
            return;
        }
        std::string tmpl = (fs::temp_directory_path() / "woven-XXXXXX").string();
        if (!::mkdtemp(tmpl.data())) throw RuntimeError("cannot create a temporary directory in " + fs::temp_directory_path().string());
        path_ = tmpl;
        temporary_ = true;
    }
    ~OutDir()
    {
        std::error_code ec;
        if (temporary_) fs::remove_all(path_, ec);
    }
    OutDir(const OutDir&) = delete;
    OutDir& operator=(const OutDir&) = delete;
    const std::string& path() const { return path_; }

private:
    std::string path_;
    bool temporary_ = false;
};

nlohmann::json read_json(const std::string& path)
{
    std::ifstream in(path);
    if (!in) throw RuntimeError(path + ": not written");
    return nlohmann::json::parse(in);
}

/// A CSV the commands write (a header of names, then numbers) as {column: float64 array};
/// anything that is not a number reads as nan.
py::dict csv_columns(const std::string& path)
{
    std::ifstream in(path);
    std::string line;
    std::vector<std::string> names;
    if (!std::getline(in, line)) return py::dict();
    for (std::size_t at = 0;;) {
        const std::size_t comma = line.find(',', at);
        names.push_back(line.substr(at, comma == std::string::npos ? std::string::npos : comma - at));
        if (comma == std::string::npos) break;
        at = comma + 1;
    }
    std::vector<std::vector<double>> columns(names.size());
    while (std::getline(in, line)) {
        if (line.empty()) continue;
        std::size_t at = 0;
        for (std::size_t c = 0; c < names.size(); ++c) {
            const std::size_t comma = line.find(',', at);
            const std::string cell = line.substr(at, comma == std::string::npos ? std::string::npos : comma - at);
            char* end = nullptr;
            const double v = std::strtod(cell.c_str(), &end);
            columns[c].push_back(end != cell.c_str() && *end == '\0' ? v : std::numeric_limits<double>::quiet_NaN());
            at = comma == std::string::npos ? line.size() : comma + 1;
        }
    }
    py::dict d;
    for (std::size_t c = 0; c < names.size(); ++c)
        d[py::str(names[c])] = py::array_t<double>(static_cast<py::ssize_t>(columns[c].size()), columns[c].data());
    return d;
}

py::object kes_test(py::object fabric, py::object test, py::object direction, py::object sigma_cm, py::object shear_length_cm,
                    py::object bending_form, py::object discretization, py::object shear_law, py::object hysteresis, bool convergence,
                    py::object threads, py::object out, py::object progress)
{
    cli::KesTestOptions o;
    const FabricArg f = fabric_arg(fabric);
    o.fabric = f.name;
    o.given_fabric = f.given;
    o.test = option_text(test).value_or("all");
    o.direction = option_text(direction).value_or("both");
    o.sigma_cm = option_text(sigma_cm);
    o.shear_length_cm = option_text(shear_length_cm);
    o.bending_form = option_text(bending_form);
    o.discretization = option_text(discretization);
    o.shear_law = option_text(shear_law);
    o.hysteresis = option_text(hysteresis);
    o.convergence = convergence;
    o.threads = option_text(threads);
    const OutDir dir(out);
    o.out = dir.path();
    run_command([&] { cli::run_kes_test(o); }, nullptr, progress);
    py::dict report = to_python(read_json((fs::path(dir.path()) / "kes-report.json").string()));
    // The curves the CSV files hold, as arrays: {"bending_warp": {"K_per_cm": ..., ...}, ...}.
    py::dict curves;
    for (const auto& e : fs::directory_iterator(dir.path()))
        if (e.path().extension() == ".csv") curves[py::str(e.path().stem().string())] = csv_columns(e.path().string());
    report["curves"] = curves;
    return report;
}

py::object cusick(py::object fabric, py::object specimen_cm, py::object disc_cm, py::object spacing_cm, py::object seeds, py::object seed,
                  py::object threads, py::object max_steps, py::object shear_law, py::object hysteresis, py::object protocol,
                  py::object shakes, bool render, py::object out, py::object progress)
{
    cli::CusickCommandOptions o;
    const FabricArg f = fabric_arg(fabric);
    o.fabric = f.name;
    o.given_fabric = f.given;
    o.specimen_cm = option_text(specimen_cm).value_or("30");
    o.disc_cm = option_text(disc_cm).value_or("18");
    o.spacing_cm = option_text(spacing_cm);
    o.seeds = option_text(seeds).value_or("1");
    o.seed = option_text(seed).value_or("1");
    o.threads = option_text(threads);
    o.max_steps = option_text(max_steps);
    o.shear_law = option_text(shear_law);
    o.hysteresis = option_text(hysteresis);
    o.protocol = option_text(protocol);
    o.shakes = option_text(shakes);
    o.no_render = !render;
    const OutDir dir(out);
    o.out = dir.path();
    run_command([&] { cli::run_cusick(o); }, nullptr, progress);
    py::dict report = to_python(read_json((fs::path(dir.path()) / "cusick.json").string()));
    // The draped specimen (cusick.obj) as arrays, m, z up.
    const fs::path obj = fs::path(dir.path()) / "cusick.obj";
    if (fs::exists(obj)) {
        const geometry::TriangleMesh mesh = io::load_obj_mesh(obj.string());
        py::array_t<double> v({static_cast<py::ssize_t>(mesh.vertices.size()), py::ssize_t(3)});
        auto rv = v.mutable_unchecked<2>();
        for (std::size_t k = 0; k < mesh.vertices.size(); ++k)
            for (int c = 0; c < 3; ++c) rv(k, c) = mesh.vertices[k][c];
        py::array_t<std::int32_t> f({static_cast<py::ssize_t>(mesh.faces.size()), py::ssize_t(3)});
        auto rf = f.mutable_unchecked<2>();
        for (std::size_t k = 0; k < mesh.faces.size(); ++k)
            for (int c = 0; c < 3; ++c) rf(k, c) = mesh.faces[k][c];
        report["vertices"] = v;
        report["faces"] = f;
    }
    return report;
}

py::object fit(py::object fabric, py::object sigma_cm, py::object out)
{
    cli::FitOptions o;
    const FabricArg f = fabric_arg(fabric);
    o.fabric = f.name;
    o.given_fabric = f.given;
    o.sigma_cm = option_text(sigma_cm).value_or("2");
    const OutDir dir(out);
    o.out = dir.path();
    std::string printed;
    run_command([&] { cli::run_fit(o); }, &printed);
    nlohmann::json report = read_json((fs::path(dir.path()) / "report.json").string());
    // What the command prints: the fits and the energies' constants, less its "wrote" line.
    if (const auto k = printed.rfind("wrote "); k != std::string::npos) printed.erase(k);
    report["summary"] = printed;
    return to_python(report);
}

}  // namespace

void bind_testers(py::module_& m)
{
    m.def("kes_test", &kes_test, py::arg("fabric"), py::kw_only(), py::arg("test") = "all", py::arg("direction") = "both",
          py::arg("sigma_cm") = py::none(), py::arg("shear_length_cm") = py::none(), py::arg("bending_form") = py::none(),
          py::arg("discretization") = py::none(), py::arg("shear_law") = py::none(), py::arg("hysteresis") = py::none(),
          py::arg("convergence") = false, py::arg("threads") = py::none(), py::arg("out") = py::none(), py::arg("progress") = py::none(),
          R"(The virtual cantilever, KES-FB2 bending and KES-FB1 shear tests on the model, as `woven kes-test`.

fabric: a built-in name, a fabric .toml path or a woven.Fabric. The keyword arguments are the
command's options (test: cantilever, bending, shear or all; direction: warp, weft or both; ...),
checked as it checks them. Returns kes-report.json as a dict (tests: input vs simulated summary
values) with `curves`: each CSV file's columns as float64 arrays ({"bending_warp": {"K_per_cm":
..., ...}, ...}). The files (curves as CSV, plots) are written to out when given, else to a
temporary folder that is removed. progress, if given, is called with a dict about every 0.1 s
(event "activity": label, detail, fraction, wall_s). Nothing is printed.

>>> import woven
>>> r = woven.kes_test("cotton", test="cantilever", direction="warp", sigma_cm=1, threads=1)
>>> r["tests"][0]["test"], r["tests"][0]["direction"]
('cantilever', 'warp')
>>> sorted(r["curves"])
['cantilever_warp']
)");
    m.def("cusick", &cusick, py::arg("fabric"), py::kw_only(), py::arg("specimen_cm") = 30, py::arg("disc_cm") = 18,
          py::arg("spacing_cm") = py::none(), py::arg("seeds") = 1, py::arg("seed") = 1, py::arg("threads") = py::none(),
          py::arg("max_steps") = py::none(), py::arg("shear_law") = py::none(), py::arg("hysteresis") = py::none(),
          py::arg("protocol") = py::none(), py::arg("shakes") = py::none(), py::arg("render") = true, py::arg("out") = py::none(),
          py::arg("progress") = py::none(),
          R"(The Cusick drape test (BS 5058, ISO 9073-9) on a simulated specimen, as `woven cusick`.

fabric: a built-in name, a fabric .toml path or a woven.Fabric. hysteresis ("loading-branch" or
"friction"), protocol ("release" or "lowered") and shakes are the command's options. Returns cusick.json as a dict:
drape_coefficient_percent, nodes, node_angles_deg, runs (one per seed), interrupted, ... The
files (cusick.obj, shadow.png, drape.png) are written to out when given, else to a temporary
folder that is removed; `vertices` (n, 3) float64 m and `faces` (m, 3) int32 are the draped
specimen (cusick.obj). progress, if given, gets woven.drape's step and iteration dicts (and
"activity" dicts while the picture is drawn); False from it stops as Ctrl-C does. Ctrl-C stops
it after the current step; the runs done are returned, with interrupted True.

>>> import woven
>>> c = woven.cusick("cotton", spacing_cm=2, threads=1, render=False)
>>> 0 < c["drape_coefficient_percent"] < 100, c["vertices"].shape[1], c["faces"].dtype.name
(True, 3, 'int32')
)");
    m.def("fit", &fit, py::arg("fabric"), py::kw_only(), py::arg("sigma_cm") = 2, py::arg("out") = py::none(),
          R"(Fits a fabric's three KES curves and builds the model's energies for spacing sigma_cm, as `woven fit`.

Returns its report.json as a dict, with `summary`: the text the command prints (each curve's
fit, the trellis continuation). The plots and energy tables (CSV) are written to out when given,
else to a temporary folder that is removed.)");
}

}  // namespace woven::python
