// woven.kes_test, woven.cusick, woven.fit: the commands' own code, their report returned as a dict.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>

#include <pybind11/numpy.h>

#include "bindings.hpp"
#include "woven/app/cusick.hpp"
#include "woven/app/fit.hpp"
#include "woven/app/kes_test.hpp"
#include "woven/common/error.hpp"
#include "woven/io/mesh_file.hpp"
#include "woven/io/scene_file.hpp"

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

/// Runs a job whose request reports the fabric's warnings through on_warnings (set here): they
/// are issued as Python warnings once it ends, before its error if it fails. `f` fills the
/// request's monitor and runs the job (run_command).
template <class Request>
void run_job(Request& request, const std::function<void(const app::Monitor&)>& f, py::handle progress = py::none())
{
    std::vector<std::string> warnings;
    request.on_warnings = [&warnings](const std::vector<std::string>& w) { warnings.insert(warnings.end(), w.begin(), w.end()); };
    try {
        run_command(f, progress);
    } catch (...) {
        warn(warnings);
        throw;
    }
    warn(warnings);
}

py::object kes_test(py::object fabric, py::object test, py::object direction, py::object sigma_cm, py::object shear_length_cm,
                    py::object bending_form, py::object discretization, py::object shear_law, py::object hysteresis, bool convergence,
                    py::object threads, py::object out, py::object progress)
{
    const CallLock lock;  // the whole call, its arrays made after the job included (bindings.hpp, CallLock: safe at interpreter exit)
    app::KesTestRequest r;
    const FabricArg f = fabric_arg(fabric);
    r.fabric = f.name;
    r.given_fabric = f.given;
    r.tests = choice_arg(test, "--test", app::kKesTestsNames).value_or(app::KesTests::ALL);
    if (convergence && r.tests != app::KesTests::ALL && r.tests != app::KesTests::CANTILEVER)
        throw InputError(app::kCommandLine, "--convergence", "expected --test cantilever or all (a study of the cantilever test)");
    r.convergence = convergence;
    r.directions = choice_arg(direction, "--direction", app::kKesDirectionsNames).value_or(app::KesDirections::BOTH);
    r.sigma_cm = number_arg(sigma_cm, "--sigma-cm", app::kKesSigmaRange_cm[0], app::kKesSigmaRange_cm[1]);
    r.shear_length_cm = number_arg(shear_length_cm, "--shear-length-cm", app::kKesShearLengthRange_cm[0], app::kKesShearLengthRange_cm[1]);
    r.bending_form = choice_arg(bending_form, "--bending-form", app::kBendingFormNames);
    r.discretization = choice_arg(discretization, "--discretization", model::kDiscretizationNames);
    r.shear_law = choice_arg(shear_law, "--shear-law", model::kShearLawNames);
    r.hysteresis = choice_arg(hysteresis, "--hysteresis", model::kHysteresisNames);
    r.threads = static_cast<int>(integer_arg(threads, "--threads", 0, io::kMaxThreads).value_or(0));
    const OutDir dir(out);
    r.out = dir.path();
    app::KesTestResult result;
    run_job(
        r,
        [&](const app::Monitor& monitor) {
            r.monitor = monitor;
            result = app::kes_test(r);
        },
        progress);
    py::dict report = to_python(result.report);
    // The curves the CSV files hold, as arrays: {"bending_warp": {"K_per_cm": ..., ...}, ...}.
    py::dict curves;
    for (const auto& e : fs::directory_iterator(dir.path()))
        if (e.path().extension() == ".csv") curves[py::str(e.path().stem().string())] = csv_columns(e.path().string());
    report["curves"] = curves;
    return report;
}

py::object cusick(py::object fabric, py::object specimen_cm, py::object disc_cm, py::object spacing_cm, py::object seeds, py::object seed,
                  py::object threads, py::object max_steps, py::object shear_law, py::object hysteresis, py::object protocol,
                  py::object shakes, bool render, py::object out, py::object progress, py::object bias, py::object clamp,
                  py::object clamp_margin, py::object clamp_gap_mm, py::object start, bool search, py::object modes, py::object jobs,
                  py::object solver, py::object discretization, py::object fall_s, py::object thread_compression, py::object grid_rotation_deg)
{
    const CallLock lock;  // the whole call, its arrays made after the job included (bindings.hpp, CallLock: safe at interpreter exit)
    app::CusickRequest r;
    const FabricArg f = fabric_arg(fabric);
    r.fabric = f.name;
    r.given_fabric = f.given;
    r.specimen_cm = positive_arg(specimen_cm, "--specimen-cm", app::kCusickMaxDiameter_cm).value_or(30);
    r.disc_cm = positive_arg(disc_cm, "--disc-cm", app::kCusickMaxDiameter_cm).value_or(18);
    r.spacing_cm = positive_arg(spacing_cm, "--spacing-cm", app::kCusickMaxSpacing_cm);
    r.seeds = static_cast<int>(integer_arg(seeds, "--seeds", app::kCusickSeedsRange[0], app::kCusickSeedsRange[1]).value_or(1));
    r.seed = seed_arg(seed, "--seed").value_or(1);
    if (const auto t = integer_arg(threads, "--threads", app::kCusickThreadsRange[0], app::kCusickThreadsRange[1])) r.threads = static_cast<int>(*t);
    if (const auto m = integer_arg(max_steps, "--max-steps", app::kCusickMaxStepsRange[0], app::kCusickMaxStepsRange[1]))
        r.max_steps = static_cast<int>(*m);
    r.shear_law = choice_arg(shear_law, "--shear-law", model::kShearLawNames);
    r.hysteresis = choice_arg(hysteresis, "--hysteresis", model::kHysteresisNames);
    r.protocol = choice_arg(protocol, "--protocol", testers::kCusickProtocolNames);
    if (const auto n = integer_arg(shakes, "--shakes", app::kCusickShakesRange[0], app::kCusickShakesRange[1])) r.shakes = static_cast<int>(*n);
    r.bias = choice_arg(bias, "--bias", model::kBiasBendingNames);
    r.solver = choice_arg(solver, "--solver", sim::kSolverKindNames);
    r.discretization = choice_arg(discretization, "--discretization", model::kDiscretizationNames);
    r.fall_s = number_arg(fall_s, "--fall-s", 0, io::kMaxFallDuration_s);
    r.thread_compression = number_arg(thread_compression, "--thread-compression", app::kThreadCompressionRange[0], app::kThreadCompressionRange[1]);
    r.grid_rotation_deg = number_arg(grid_rotation_deg, "--grid-rotation-deg", app::kCusickGridRotationRange[0], app::kCusickGridRotationRange[1]);
    r.clamp = choice_arg(clamp, "--clamp", testers::kCusickClampNames);
    r.clamp_margin = number_arg(clamp_margin, "--clamp-margin", app::kCusickClampMarginRange[0], app::kCusickClampMarginRange[1]);
    r.clamp_gap_mm = positive_arg(clamp_gap_mm, "--clamp-gap-mm", 1e3 * testers::CusickOptions{}.solver.contact_distance);
    if (const auto path = option_text(start)) r.start = *path;
    r.search = search;
    if (!modes.is_none()) {  // a list of fold counts; the job checks them (and that search is on)
        if (py::isinstance<py::str>(modes) || !py::isinstance<py::iterable>(modes))
            throw InputError(app::kCommandLine, "--modes",
                             "expected a list of fold counts such as [3, 5, 7], got " + py::repr(modes).cast<std::string>());
        std::vector<int> m;
        for (py::handle h : modes) m.push_back(static_cast<int>(*integer_arg(h, "--modes", 2, 64)));
        r.modes = std::move(m);
    }
    if (const auto j = integer_arg(jobs, "--jobs", app::kCusickJobsRange[0], app::kCusickJobsRange[1])) r.jobs = static_cast<int>(*j);
    r.render = render;
    const OutDir dir(out);
    r.out = dir.path();
    app::CusickResult result;
    run_job(
        r,
        [&](const app::Monitor& monitor) {
            r.monitor = monitor;
            result = app::cusick(r);
        },
        progress);
    py::dict report = to_python(result.report);
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
    const CallLock lock;  // the whole call (bindings.hpp, CallLock: safe at interpreter exit)
    app::FitRequest request;
    const FabricArg f = fabric_arg(fabric);
    request.fabric = f.name;
    request.given_fabric = f.given;
    request.sigma_cm = number_arg(sigma_cm, "--sigma-cm", app::kFitSigmaRange_cm[0], app::kFitSigmaRange_cm[1]).value_or(2);
    const OutDir dir(out);
    request.out = dir.path();
    app::FitResult result;
    run_job(request, [&](const app::Monitor& monitor) {
        request.monitor = monitor;
        result = app::fit(request);
    });
    nlohmann::json report = std::move(result.report);
    report["summary"] = result.summary;  // each curve's fit and the energies' constants
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
          py::arg("progress") = py::none(), py::arg("bias") = py::none(), py::arg("clamp") = py::none(),
          py::arg("clamp_margin") = py::none(), py::arg("clamp_gap_mm") = py::none(), py::arg("start") = py::none(),
          py::arg("search") = false, py::arg("modes") = py::none(), py::arg("jobs") = py::none(), py::arg("solver") = py::none(),
          py::arg("discretization") = py::none(), py::arg("fall_s") = py::none(), py::arg("thread_compression") = py::none(),
          py::arg("grid_rotation_deg") = py::none(),
          R"(The Cusick drape test (BS 5058, ISO 9073-9) on a simulated specimen, as `woven cusick`.

fabric: a built-in name, a fabric .toml path or a woven.Fabric. Every option of the command is a
keyword, checked as it checks it (an error names the keyword): hysteresis ("loading-branch" or
"friction"), protocol ("release" or "lowered"), shakes, bias ("threads" or "fabric"), clamp
("pinned" or "discs"), clamp_margin (spacings), clamp_gap_mm, start (a cusick.obj path), search
(True: the search of rest states), modes (with search: a list of guide counts, e.g. [3, 5, 7]),
jobs (with search: starts run at once), solver ("fast" or "paper"), discretization
("convergent" or "paper"), fall_s (s), thread_compression (0 to 1) and grid_rotation_deg. Returns cusick.json as a dict:
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
