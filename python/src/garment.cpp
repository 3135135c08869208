// woven.garment: `woven garment`'s own code (app/garment.hpp), its report returned as a dict.
#include "woven/app/garment.hpp"

#include <cstdlib>
#include <filesystem>

#include "bindings.hpp"
#include "woven/common/error.hpp"

namespace woven::python {

namespace {

namespace fs = std::filesystem;

py::object garment(py::object file, py::object fabric, py::object spacing_cm, py::object threads, py::object max_steps, py::object seed,
                   bool render, py::object out, py::object progress)
{
    const CallLock lock;  // the whole call (bindings.hpp, CallLock: safe at interpreter exit)
    app::GarmentRequest r;
    const std::optional<std::string> path = option_text(file);
    if (!path) throw InputError("garment", "file", "expected a garment .toml file");
    r.file = *path;
    r.fabric = option_text(fabric);
    // The command's option is --spacing; the keyword, spacing_cm, names the value here.
    r.spacing_cm = number_arg(spacing_cm, app::value_name(app::Naming::KEYWORDS, "--spacing", "spacing_cm"), io::kGarmentSpacingCm[0],
                              io::kGarmentSpacingCm[1]);
    if (const auto t = integer_arg(threads, "--threads", 0, io::kMaxThreads)) r.threads = static_cast<int>(*t);
    if (const auto m = integer_arg(max_steps, "--max-steps", 0, 1'000'000'000)) r.max_steps = static_cast<int>(*m);
    r.seed = seed_arg(seed, "--seed");
    std::string dir;
    bool temporary = false;
    if (const auto o = option_text(out)) {
        dir = *o;
    } else {
        std::string tmpl = (fs::temp_directory_path() / "woven-XXXXXX").string();
        if (!::mkdtemp(tmpl.data())) throw RuntimeError("cannot create a temporary directory in " + fs::temp_directory_path().string());
        dir = tmpl;
        temporary = true;
    }
    app::GarmentJob job;
    try {
        run_command([&](const app::Monitor& monitor) { job = app::garment(r, dir, 800, 1000, render, monitor); }, progress);
    } catch (...) {
        std::error_code ec;
        if (temporary) fs::remove_all(dir, ec);
        throw;
    }
    std::error_code ec;
    if (temporary) fs::remove_all(dir, ec);
    warn(job.warnings);
    py::dict report = to_python(job.report);
    report["interrupted"] = job.interrupted;
    return report;
}

}  // namespace

void bind_garment(py::module_& m)
{
    m.def("garment", &garment, py::arg("file"), py::kw_only(), py::arg("fabric") = py::none(), py::arg("spacing_cm") = py::none(),
          py::arg("threads") = py::none(), py::arg("max_steps") = py::none(), py::arg("seed") = py::none(), py::arg("render") = true,
          py::arg("out") = py::none(), py::arg("progress") = py::none(),
          R"(A garment's pattern pieces cut from the fabric, sewn around the body and draped, as `woven garment FILE`
(docs/GARMENT-FORMAT.md).

file: a garment .toml file. fabric (a built-in name or a fabric .toml path), spacing_cm, threads,
max_steps and seed override the file's, as the command's options. Returns report.json as a dict:
hem (nodes, flare, radius_m per 5-degree bin, below_waist_m, length_drop_m), seams (each one's
max_gap_m, max_force_N), stages, energy, ... The files (garment.glb, garment.png) are written to
out when given, else to a temporary folder that is removed. progress, if given, gets
woven.drape's step and iteration dicts; False from it stops as Ctrl-C does.

>>> import woven
>>> r = woven.garment("examples/garments/tube-skirt.toml", spacing_cm=5, threads=1, render=False)  # doctest: +SKIP
>>> r["hem"]["nodes"], round(r["hem"]["flare"], 2)  # doctest: +SKIP
)");
}

}  // namespace woven::python
