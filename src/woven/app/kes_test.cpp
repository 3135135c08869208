// The kes-test job (kes_test.hpp): the virtual instruments run on the model against the
// fabric's input values.
#include "woven/app/kes_test.hpp"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "woven/app/drape_report.hpp"
#include "woven/app/material.hpp"
#include "woven/app/progress.hpp"
#include "woven/app/run_checks.hpp"
#include "woven/common/error.hpp"
#include "woven/common/format.hpp"
#include "woven/common/units.hpp"
#include "woven/io/fabric_file.hpp"
#include "woven/io/output.hpp"
#include "woven/io/output_checks.hpp"
#include "woven/io/output_set.hpp"
#include "woven/io/scene_file.hpp"
#include "woven/render/image.hpp"
#include "woven/render/instrument_plots.hpp"
#include "woven/render/plot.hpp"
#include "woven/sim/thread_count.hpp"
#include "woven/testers/cantilever.hpp"
#include "woven/testers/kes_bending.hpp"
#include "woven/testers/kes_protocol.hpp"
#include "woven/testers/kes_shear.hpp"

namespace woven::app {

namespace {

nlohmann::json finite_or_null(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); }

/// The loop of a FRICTION run: every step, simulated and input (KesCurveResult::loop_y_input).
std::string loop_csv(const testers::KesCurveResult& r, const std::string& x_name, const std::string& y_name)
{
    std::ostringstream s;
    s.precision(10);
    s << "step," << x_name << ",simulated_" << y_name << ",input_" << y_name << "\n";
    for (std::size_t k = 0; k < r.loop_x.size(); ++k) s << k << "," << r.loop_x[k] << "," << r.loop_y[k] << "," << r.loop_y_input[k] << "\n";
    return s.str();
}

render::Image loop_plot(const std::string& title, const std::string& x_label, const std::string& y_label,
                        const std::vector<testers::KesCurveResult>& results)
{
    std::vector<render::KesCurveView> runs;
    for (const auto& r : results)
        if (r.loop) runs.push_back({testers::to_string(r.direction), r.loop_x, r.loop_y, r.loop_x, r.loop_y_input});
    return render::plot(render::kes_loop_plot(title, x_label, y_label, runs, false), 900, 620);
}

std::string curve_csv(const testers::KesCurveResult& r, const std::string& x_name, const std::string& y_name)
{
    std::ostringstream s;
    s.precision(10);
    s << x_name << ",simulated_" << y_name << ",input_" << y_name << (r.y_central.empty() ? "" : ",simulated_central_" + y_name) << "\n";
    const bool central = r.y_central.size() == r.x.size();
    for (std::size_t k = 0; k < r.x.size(); ++k) {
        s << r.x[k] << "," << r.y[k] << "," << r.y_input[k];
        if (central) s << "," << r.y_central[k];
        s << "\n";
    }
    return s.str();
}

render::Image curve_plot(const std::string& title, const std::string& x_label, const std::string& y_label,
                         const std::vector<testers::KesCurveResult>& results, const kes::FabricData& fabric, bool bending)
{
    std::vector<render::KesCurveView> runs;
    for (const auto& r : results) {
        const kes::Curve& in = bending ? testers::input_bending(fabric, r.direction) : fabric.shear.curve;
        runs.push_back({testers::to_string(r.direction), r.x, r.y, in.x, in.y});
    }
    return render::plot(render::kes_curve_plot(title, x_label, y_label, runs, bending), 900, 620);
}

/// Refuses (exit 2, the estimate and the limit) a run whose largest specimen would not fit in
/// the memory the process has (issue 36): the particle counts as the testers lay them out
/// (testers::kes_specimen_sizes).
void check_specimen_memory(const kes::FabricData& fabric, const testers::KesProtocolOptions& po, bool sigma_given, bool shear_length_given)
{
    const testers::KesSpecimenSizes n = testers::kes_specimen_sizes(fabric, po);
    long long largest = 0;
    std::string field = "--sigma-cm";
    auto consider = [&](long long count, const std::string& f) {
        if (count > largest) {
            largest = count;
            field = f;
        }
    };
    consider(n.shear, shear_length_given && !sigma_given ? "--shear-length-cm" : "--sigma-cm");
    consider(n.bending, "--sigma-cm");
    consider(n.cantilever, "--sigma-cm");
    check_memory_estimate(testers::estimate_tester_memory(largest), largest, kCommandLine, field,
                          field == "--sigma-cm" ? "use a larger --sigma-cm" : "use a shorter --shear-length-cm");
}

/// kes-report.json's cantilever_convergence rows of a study (overhang_ratio, sigma_m,
/// bending_length_m, elastica_bending_length_m, rel_error, order).
KesConvergence convergence_json(const testers::CantileverConvergence& study)
{
    nlohmann::json rows = nlohmann::json::array();
    for (const testers::ConvergencePoint& p : study.points)
        rows.push_back({{"direction", testers::to_string(study.direction)},
                        {"overhang_ratio", p.overhang_ratio},
                        {"sigma_m", p.sigma},
                        {"bending_length_m", p.bending_length},
                        {"elastica_bending_length_m", p.elastica_bending_length},
                        {"rel_error", p.rel_error},
                        {"order", p.order ? nlohmann::json(*p.order) : nlohmann::json()}});
    return {testers::to_string(study.direction), study.bending_length, std::move(rows)};
}

/// A run under way: the request's values resolved, the fabric and the files the tests produced
/// so far.
struct KesRun {
    KesRun(const KesTestRequest& r, kes::FabricData f, std::string n)
        : request(r), fabric(std::move(f)), name(std::move(n)), activity("kes-test " + name)
    {
    }
    const KesTestRequest& request;
    kes::FabricData fabric;
    std::string name;
    model::ModelOptions mo;
    std::vector<KesTestRow> rows;
    std::vector<std::pair<std::string, std::string>> csv;  // name, contents
    std::vector<std::pair<std::string, render::Image>> png;
    Activity activity;
};

bool runs(KesTests tests, KesTests one) { return tests == KesTests::ALL || tests == one; }

/// The model the specimens are made of: the request's choices over the model's defaults;
/// kes-test shows the loops: friction unless asked otherwise (the model's default is the loading
/// branch).
model::ModelOptions kes_model_options(const KesTestRequest& r)
{
    model::ModelOptions mo;
    if (r.bending_form) mo.bending_form = *r.bending_form;
    if (r.discretization) mo.discretization = *r.discretization;
    if (r.shear_law) mo.shear_law = *r.shear_law;
    mo.hysteresis = r.hysteresis.value_or(model::Hysteresis::FRICTION);
    return mo;
}

/// The set: every file a kes-test run can write (those this run does not write are removed
/// when it publishes, kes-report.json last: io::OutputSet).
std::vector<std::string> kes_members()
{
    std::vector<std::string> members;
    for (const char* t : {"cantilever", "bending", "shear"}) {
        for (const char* d : {"warp", "weft"}) members.push_back(std::string(t) + "_" + d + ".csv");
        members.push_back(std::string(t) + ".png");
    }
    for (const char* t : {"bending", "shear"}) {
        for (const char* d : {"warp", "weft"}) members.push_back(std::string(t) + "_loop_" + d + ".csv");
        members.push_back(std::string(t) + "_loop.png");
    }
    return members;
}

/// The cantilevers' files: each strip's shape beside the elastica's (CSV), and their plot.
void add_cantilever_files(KesRun& k, const std::vector<testers::CantileverResult>& results)
{
    render::Plot p;
    p.title = "Cantilever (ASTM D1388), " + k.name + ": strip at the 41.5 degree chord";
    p.x_label = "along the strip (cm)";
    p.y_label = "height (cm)";
    for (const testers::CantileverResult& r : results) {
        const std::string direction = testers::to_string(r.direction);
        std::ostringstream s;
        s.precision(10);
        s << "source,s_m,x_m,z_m\n";
        for (std::size_t a = 0; a < r.shape.x.size(); ++a)
            s << "simulated," << (a - 0.5) * r.shape.sigma << "," << r.shape.x[a] << "," << r.shape.z[a] << "\n";
        for (std::size_t e = 0; e < r.elastica.s.size(); e += 10)
            s << "elastica," << r.elastica.s[e] << "," << r.elastica.x[e] << "," << r.elastica.z[e] << "\n";
        k.csv.emplace_back("cantilever_" + direction + ".csv", s.str());
        render::Series sim, el;
        for (std::size_t a = 0; a < r.shape.x.size(); ++a) {
            sim.x.push_back(r.shape.x[a] * units::kMToCm);
            sim.y.push_back(r.shape.z[a] * units::kMToCm);
        }
        for (std::size_t e = 0; e < r.elastica.s.size(); e += 10) {
            el.x.push_back(r.elastica.x[e] * units::kMToCm);
            el.y.push_back(r.elastica.z[e] * units::kMToCm);
        }
        sim.style = render::Series::Style::POINTS;
        sim.label = "simulated " + direction + " (c " + format_g(r.bending_length * units::kMToCm, 4) + " cm)";
        el.label = "elastica " + direction + " (c " + format_g(r.elastica_bending_length * units::kMToCm, 4) + " cm)";
        p.series.push_back(el);
        p.series.push_back(sim);
    }
    k.png.emplace_back("cantilever.png", render::plot(p, 900, 620));
}

bool any_loop(const std::vector<testers::KesCurveResult>& results)
{
    return std::any_of(results.begin(), results.end(), [](const auto& r) { return r.loop; });
}

/// The bending tests' files: each curve and loop (CSV), their plots.
void add_bending_files(KesRun& k, const std::vector<testers::KesCurveResult>& results)
{
    for (const testers::KesCurveResult& r : results) {
        const testers::Direction d = r.direction;
        k.csv.emplace_back("bending_" + testers::to_string(d) + ".csv", curve_csv(r, "K_per_cm", "M_gf_cm_per_cm"));
        if (r.loop) k.csv.emplace_back("bending_loop_" + testers::to_string(d) + ".csv", loop_csv(r, "K_per_cm", "M_gf_cm_per_cm"));
    }
    k.png.emplace_back("bending.png",
                       curve_plot("KES-FB2 pure bending, " + k.name, "curvature K (1/cm)", "moment M (gf.cm/cm)", results, k.fabric, true));
    if (any_loop(results))
        k.png.emplace_back("bending_loop.png", loop_plot("KES-FB2 loop 0 -> +2.5 -> -2.5 -> 0 1/cm (friction), " + k.name,
                                                         "curvature K (1/cm)", "moment M (gf.cm/cm)", results));
}

/// The shear tests' files.
void add_shear_files(KesRun& k, const std::vector<testers::KesCurveResult>& results)
{
    for (const testers::KesCurveResult& r : results) {
        const testers::Direction d = r.direction;
        k.csv.emplace_back("shear_" + testers::to_string(d) + ".csv", curve_csv(r, "phi_deg", "F_gf_per_cm"));
        if (r.loop) k.csv.emplace_back("shear_loop_" + testers::to_string(d) + ".csv", loop_csv(r, "phi_deg", "F_gf_per_cm"));
    }
    k.png.emplace_back("shear.png", curve_plot("KES-FB1 shear, " + k.name, "shear angle (deg)", "force F (gf/cm)", results, k.fabric, false));
    if (any_loop(results))
        k.png.emplace_back("shear_loop.png", loop_plot("KES-FB1 loop 0 -> +8 -> -8 -> 0 degrees (friction), " + k.name, "shear angle (deg)",
                                                       "force F (gf/cm)", results));
}

/// One entry of kes-report.json's `tests`.
nlohmann::json test_json(const KesTestRow& r)
{
    nlohmann::json t = {{"test", r.test},
                        {"direction", r.direction},
                        {"sigma_m", finite_or_null(r.sigma_m)},
                        {"unit", r.unit},
                        {"input_summary", finite_or_null(r.input)},
                        {"simulated_summary", finite_or_null(r.simulated)},
                        {"summary_rel_error", finite_or_null(r.rel)},
                        {"curve_max_rel_error", finite_or_null(r.curve)}};
    if (r.central) {
        t["central_summary"] = finite_or_null(*r.central);
        t["central_rel_error"] = finite_or_null(*r.central_rel);
    }
    if (r.test != "cantilever") {
        // Hysteresis: null where no loop was run (loading-branch, or a curve given as points).
        t["input_hysteresis"] = nullptr;
        t["simulated_hysteresis"] = nullptr;
        t["hysteresis_rel_error"] = nullptr;
        t["loop_max_rel_error"] = nullptr;
        if (r.loop) {
            const KesLoopRow& l = *r.loop;
            if (r.test == "bending") {
                t["input_hysteresis"] = {{"2HB", finite_or_null(l.input_hysteresis)}};
                t["simulated_hysteresis"] = {{"2HB", finite_or_null(l.simulated_hysteresis)}};
            } else {
                t["input_hysteresis"] = {{"2HG", finite_or_null(l.input_hysteresis)}, {"2HG5", finite_or_null(l.input_hysteresis5)}};
                t["simulated_hysteresis"] = {{"2HG", finite_or_null(l.simulated_hysteresis)}, {"2HG5", finite_or_null(l.simulated_hysteresis5)}};
            }
            t["hysteresis_rel_error"] = finite_or_null(l.hysteresis_rel_error);
            t["loop_max_rel_error"] = finite_or_null(l.loop_max_rel_error);
        }
    }
    if (r.bending_length_m) {
        t["bending_length_m"] = finite_or_null(*r.bending_length_m);
        t["elastica_bending_length_m"] = finite_or_null(*r.elastica_bending_length_m);
    }
    return t;
}

/// kes-report.json without its `files`.
nlohmann::json kes_report(const KesRun& k, const std::vector<KesConvergence>& convergence)
{
    const model::ModelOptions& mo = k.mo;
    const GivenFabric& given = k.request.given_fabric;
    nlohmann::json report = {{"version", WOVEN_VERSION},
                             {"command", "kes-test"},
                             {"fabric", k.name},
                             {"fabric_source", given.data ? given.source : k.request.fabric},
                             {"bending_form", mo.bending_form == model::BendingForm::WORK ? "work" : "secant"},
                             {"discretization", model::to_string(mo.discretization)},
                             {"shear_law", to_string(mo.shear_law)},
                             {"shear_scale", mo.shear_scale},
                             {"hysteresis", model::to_string(mo.hysteresis)}};
    nlohmann::json tests = nlohmann::json::array();
    for (const KesTestRow& r : k.rows) tests.push_back(test_json(r));
    report["tests"] = tests;
    if (k.request.convergence) {
        nlohmann::json rows = nlohmann::json::array();
        for (const KesConvergence& c : convergence)
            for (const auto& row : c.rows) rows.push_back(row);
        report["cantilever_convergence"] = rows;
    }
    return report;
}

/// The request's values checked (InputError "command line: --<option>: ..." as the command's).
void check_kes_request(const KesTestRequest& r)
{
    if (r.convergence && !runs(r.tests, KesTests::CANTILEVER))
        throw InputError(kCommandLine, "--convergence", "expected --test cantilever or all (a study of the cantilever test)");
    if (r.sigma_cm) number_in_range(*r.sigma_cm, "--sigma-cm", kKesSigmaRange_cm[0], kKesSigmaRange_cm[1]);
    if (r.shear_length_cm) number_in_range(*r.shear_length_cm, "--shear-length-cm", kKesShearLengthRange_cm[0], kKesShearLengthRange_cm[1]);
    path_given(r.out, "--out");
    integer_in_range(r.threads, "--threads", 0, io::kMaxThreads);
}

}  // namespace

KesTestResult kes_test(const KesTestRequest& request)
{
    const auto started = std::chrono::steady_clock::now();
    const MonitorScope monitor(request.monitor);
    // Everything is checked before anything runs or is written: every value first, then the
    // fabric, the memory the largest specimen needs and the output folder.
    check_kes_request(request);
    testers::KesProtocolOptions po;
    po.directions.clear();
    if (request.directions != KesDirections::WEFT) po.directions.push_back(testers::Direction::WARP);
    if (request.directions != KesDirections::WARP) po.directions.push_back(testers::Direction::WEFT);
    po.cantilever = runs(request.tests, KesTests::CANTILEVER);
    po.bending = runs(request.tests, KesTests::BENDING);
    po.shear = runs(request.tests, KesTests::SHEAR);
    po.convergence = request.convergence;
    if (request.sigma_cm) po.sigma = *request.sigma_cm * units::kCmToM;
    if (request.shear_length_cm) po.shear_length = *request.shear_length_cm * units::kCmToM;
    std::vector<std::string> warnings;
    kes::FabricData fabric = command_fabric(request.fabric, request.given_fabric, &warnings);
    if (request.on_warnings) request.on_warnings(warnings);
    warnings.clear();  // delivered
    check_specimen_memory(fabric, po, request.sigma_cm.has_value(), request.shear_length_cm.has_value());
    std::string name = fabric.name.empty() ? std::filesystem::path(request.fabric).stem().string() : fabric.name;
    std::string safe;
    for (char c : name) safe += (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-') ? c : '_';
    const std::string dir = request.out ? request.out->string() : join_path("out", "kes-" + safe);
    std::vector<std::string> members = kes_members();
    make_output_dir(dir);
    members.push_back("kes-report.json");
    check_output_targets(dir, members);
    members.pop_back();
    io::OutputSet set(dir, members);

    model::ModelOptions mo = kes_model_options(request);
    with_fabric_source(command_fabric_source(request.fabric, request.given_fabric), [&] { resolve_shear_law(fabric, mo, warnings); });
    if (request.on_warnings && !warnings.empty()) request.on_warnings(warnings);

    KesRun k(request, std::move(fabric), name);
    k.mo = mo;
    po.model = mo;
    const sim::ThreadCount thread_count(request.threads, request.threads);
    testers::KesProtocolResult measured =
        testers::run_kes_tests(k.fabric, po, [&k](double fraction, const std::string& what) { k.activity.update(fraction, what); });
    k.rows = measured.rows;
    if (po.cantilever) add_cantilever_files(k, measured.cantilever);
    if (po.bending) add_bending_files(k, measured.bending);
    if (po.shear) add_shear_files(k, measured.shear);
    KesTestResult result;
    for (const testers::CantileverConvergence& study : measured.convergence) result.convergence.push_back(convergence_json(study));

    // Every number written is finite (a test that could not measure is null in the report, as
    // documented; its tables must hold numbers), then one set, kes-report.json last.
    nlohmann::json report = kes_report(k, result.convergence);
    for (const auto& [f, text] : k.csv) io::require_finite_csv(text, f, "kes-test");
    for (const auto& [f, text] : k.csv) set.add(f, text);
    for (const auto& [f, image] : k.png) set.add(f, render::encode_png(image, join_path(dir, f)));
    report["wall_time_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();  // the job's, to the report's writing
    report["files"] = set.files_json();
    set.publish("kes-report.json", report.dump(2) + "\n");
    result.fabric_name = k.name;
    result.model = k.mo;
    result.rows = std::move(k.rows);
    result.report = std::move(report);
    result.out_dir = dir;
    result.files = static_cast<int>(set.names().size()) + 1;
    return result;
}

}  // namespace woven::app
