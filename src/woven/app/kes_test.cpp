// The kes-test job (kes_test.hpp): the virtual instruments run on the model against the
// fabric's input values.
#include "woven/app/kes_test.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "woven/app/drape_report.hpp"
#include "woven/app/material.hpp"
#include "woven/app/progress.hpp"
#include "woven/app/resources.hpp"
#include "woven/app/run_checks.hpp"
#include "woven/common/error.hpp"
#include "woven/common/units.hpp"
#include "woven/io/fabric_file.hpp"
#include "woven/io/output.hpp"
#include "woven/io/output_set.hpp"
#include "woven/io/scene_file.hpp"
#include "woven/render/image.hpp"
#include "woven/render/instrument_plots.hpp"
#include "woven/render/plot.hpp"
#include "woven/sim/thread_count.hpp"
#include "woven/testers/cantilever.hpp"
#include "woven/testers/kes_bending.hpp"
#include "woven/testers/kes_shear.hpp"

namespace woven::app {

namespace {

constexpr double kDefaultCantileverSigmaCm = 0.25;
constexpr double kDefaultBendingSigmaCm = 0.1;
constexpr double kDefaultShearSigmaCm = 0.25;

std::string fmt(double v, int digits = 6)
{
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*g", digits, v);
    return buf;
}

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

/// Shape error of the simulated strip against the elastica: max |z_sim - z_el(s)| over the
/// strip's rows, relative to the elastica's tip drop.
double shape_error(const testers::CantileverShape& sim, const testers::ElasticaSolution& el, double clamp_z)
{
    double e = 0;
    for (std::size_t a = 2; a < sim.z.size(); ++a) {
        const double s = (static_cast<double>(a) - 0.5) * sim.sigma;
        const double t = std::min(s, el.s.back()) / el.s.back() * (el.s.size() - 1);
        const std::size_t k = std::min<std::size_t>(static_cast<std::size_t>(t), el.s.size() - 2);
        const double f = t - k;
        const double z_el = el.z[k] + f * (el.z[k + 1] - el.z[k]);
        e = std::max(e, std::abs((sim.z[a] - clamp_z) - z_el) / el.tip_drop);
    }
    return e;
}

/// Refuses (exit 2, the estimate and the limit) a run whose largest specimen would not fit in
/// the memory the process has (issue 36): the particle counts as the testers lay them out
/// (kes_shear.hpp, kes_bending.hpp, cantilever.hpp), the cantilever's overhang taken as three
/// Peirce bending lengths (B / W)^(1/3) (its 41.5 degree chord is near two), its convergence
/// study at a quarter of the spacing.
void check_specimen_memory(const kes::FabricData& fabric, bool cantilever, bool bending, bool shear, bool convergence,
                           std::optional<double> sigma_cm, double shear_length_m, bool shear_length_given)
{
    long long largest = 0;
    std::string field = "--sigma-cm";
    auto consider = [&](long long n, const std::string& f) {
        if (n > largest) {
            largest = n;
            field = f;
        }
    };
    auto rounded = [](double v) { return static_cast<long long>(std::llround(v)); };
    if (shear) {
        const double s = (sigma_cm ? *sigma_cm : kDefaultShearSigmaCm) * units::kCmToM;
        const double gap = testers::ShearTestOptions{}.gap;
        const long long N = std::max(2LL, rounded(gap / s));
        consider((N + 1) * std::max(2LL, rounded(shear_length_m / (gap / N)) + 1), shear_length_given && !sigma_cm ? "--shear-length-cm" : "--sigma-cm");
    }
    if (bending) {
        const testers::BendingTestOptions b;
        const double s = (sigma_cm ? *sigma_cm : kDefaultBendingSigmaCm) * units::kCmToM;
        const long long span = std::max(3LL, rounded(b.gap / s));
        consider((span + 2) * std::max(2LL, rounded(b.width / (b.gap / span)) + 1), "--sigma-cm");
    }
    if (cantilever) {
        const KesValues v = kes_values(fabric);
        const double c_m = std::cbrt(std::max(v.B_warp, v.B_weft) / (v.W * 1e-3)) * units::kCmToM;
        double s = (sigma_cm ? *sigma_cm : kDefaultCantileverSigmaCm) * units::kCmToM;
        if (convergence) s = (sigma_cm ? *sigma_cm : 2 * kDefaultCantileverSigmaCm) * units::kCmToM / 4;
        const double w = testers::CantileverOptions{}.width;
        if (std::isfinite(c_m)) consider(std::max(3LL, rounded(3 * c_m / s)) * std::max(2LL, rounded(w / s) + 1), "--sigma-cm");
    }
    check_memory_estimate(estimate_tester_memory(largest), largest, kCommandLine, field,
                          field == "--sigma-cm" ? "use a larger --sigma-cm" : "use a shorter --shear-length-cm");
}

/// The cantilever's convergence study: at overhangs L/c = 1 .. 3 (c the elastica's bending
/// length), the bending length from the tip chord angle (converted with the linear elastica,
/// testers::bending_length_from_chord) of the simulated strip and of the exact elastica of the
/// input curve, at spacings S, S/2, S/4; the observed order between successive spacings.
KesConvergence cantilever_convergence(const kes::FabricData& fabric, testers::Direction d, const testers::CantileverOptions& base,
                                      const model::ModelOptions& mo)
{
    const double g = mo.gravity > 0 ? mo.gravity : units::kStandardGravity;
    const double w = testers::weight_per_area(fabric, g);
    const testers::CurvatureOfMoment law = testers::fabric_curvature_law(fabric, d, model::BendingForm::WORK, mo.gram_force);
    const double c = 0.5 * testers::elastica_overhang_for_chord_angle(testers::kPeirceChordAngle, w, law);
    nlohmann::json rows = nlohmann::json::array();
    for (double ratio : {1.0, 1.5, 2.0, 2.5, 3.0}) {
        const double L = ratio * c;
        const testers::ElasticaSolution el = testers::cantilever_elastica(L, w, law);
        const double c_exact = testers::bending_length_from_chord(L, el.chord_angle);
        double prev_err = 0, prev_sigma = 0;
        for (int level = 0; level < 3; ++level) {
            testers::CantileverOptions o = base;
            o.sigma = base.sigma / (1 << level);
            const testers::CantileverShape sh = testers::cantilever_at_overhang(fabric, d, L, o);
            const double c_sim = testers::bending_length_from_chord(L, sh.chord_angle);
            const double err = (c_sim - c_exact) / c_exact;
            double order = NAN;
            if (level > 0 && err != 0 && prev_err != 0) order = std::log(std::abs(prev_err / err)) / std::log(prev_sigma / sh.sigma);
            rows.push_back({{"direction", testers::to_string(d)},
                            {"overhang_ratio", ratio},
                            {"sigma_m", sh.sigma},
                            {"bending_length_m", c_sim},
                            {"elastica_bending_length_m", c_exact},
                            {"rel_error", err},
                            {"order", finite_or_null(order)}});
            prev_err = err;
            prev_sigma = sh.sigma;
        }
    }
    return {testers::to_string(d), c, std::move(rows)};
}

/// A run under way: the request's values resolved, the fabric, what the tests produced so far
/// and the word on the wait (the share of (test, direction) runs done and the Newton iterations
/// of the one running).
struct KesRun {
    KesRun(const KesTestRequest& r, kes::FabricData f, std::string n, int units)
        : request(r), fabric(std::move(f)), name(std::move(n)), activity("kes-test " + name), units(units)
    {
    }
    const KesTestRequest& request;
    kes::FabricData fabric;
    std::string name;
    std::vector<testers::Direction> directions;
    model::ModelOptions mo;
    double gf_cm2_per_cm = 0;  ///< N m per gf.cm2/cm
    std::vector<KesTestRow> rows;
    std::vector<std::pair<std::string, std::string>> csv;  // name, contents
    std::vector<std::pair<std::string, render::Image>> png;
    Activity activity;
    int units = 1, units_done = 0, iterations = 0;
    std::string running;

    void begin_unit(const std::string& what)
    {
        running = what;
        iterations = 0;
        activity.update(double(units_done) / units, running);
    }
    std::function<void()> on_iteration()
    {
        return [this] { activity.update(double(units_done) / units, running + ", iteration " + std::to_string(++iterations)); };
    }
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

void run_cantilevers(KesRun& k)
{
    const std::optional<double>& sigma_cm = k.request.sigma_cm;
    testers::CantileverOptions co;
    co.sigma = (sigma_cm ? *sigma_cm : kDefaultCantileverSigmaCm) * units::kCmToM;
    co.model = k.mo;
    co.solve.on_iteration = k.on_iteration();
    render::Plot p;
    p.title = "Cantilever (ASTM D1388), " + k.name + ": strip at the 41.5 degree chord";
    p.x_label = "along the strip (cm)";
    p.y_label = "height (cm)";
    for (testers::Direction d : k.directions) {
        k.begin_unit("cantilever " + testers::to_string(d));
        const testers::CantileverResult r = testers::cantilever_test(k.fabric, d, co);
        ++k.units_done;
        KesTestRow row;
        row.test = "cantilever";
        row.direction = testers::to_string(d);
        row.unit = "gf.cm2/cm";
        row.sigma_m = r.shape.sigma;
        row.input = r.elastica_flexural_rigidity / k.gf_cm2_per_cm;
        row.simulated = r.flexural_rigidity / k.gf_cm2_per_cm;
        row.rel = (r.bending_length - r.elastica_bending_length) / r.elastica_bending_length;
        row.curve = shape_error(r.shape, r.elastica, 0.5 * (r.shape.z[0] + r.shape.z[1]));
        row.bending_length_m = r.bending_length;
        row.elastica_bending_length_m = r.elastica_bending_length;
        row.solves_or_iterations = r.solves;
        k.rows.push_back(row);
        std::ostringstream s;
        s.precision(10);
        s << "source,s_m,x_m,z_m\n";
        for (std::size_t a = 0; a < r.shape.x.size(); ++a)
            s << "simulated," << (a - 0.5) * r.shape.sigma << "," << r.shape.x[a] << "," << r.shape.z[a] << "\n";
        for (std::size_t e = 0; e < r.elastica.s.size(); e += 10)
            s << "elastica," << r.elastica.s[e] << "," << r.elastica.x[e] << "," << r.elastica.z[e] << "\n";
        k.csv.emplace_back("cantilever_" + row.direction + ".csv", s.str());
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
        sim.label = "simulated " + row.direction + " (c " + fmt(r.bending_length * units::kMToCm, 4) + " cm)";
        el.label = "elastica " + row.direction + " (c " + fmt(r.elastica_bending_length * units::kMToCm, 4) + " cm)";
        p.series.push_back(el);
        p.series.push_back(sim);
    }
    k.png.emplace_back("cantilever.png", render::plot(p, 900, 620));
}

/// The table's rows of bending or shear results.
void add_kes_rows(KesRun& k, const std::vector<testers::KesCurveResult>& results, const std::string& unit)
{
    for (const auto& r : results) {
        KesTestRow row;
        row.test = r.test;
        row.direction = testers::to_string(r.direction);
        row.unit = unit;
        row.sigma_m = r.sigma;
        row.input = r.input_summary;
        row.simulated = r.simulated_summary;
        row.rel = r.summary_rel_error;
        row.curve = r.curve_max_rel_error;
        row.solves_or_iterations = r.iterations;
        if (!r.y_central.empty()) {
            row.central = r.central_summary;
            row.central_rel = r.central_rel_error;
        }
        if (r.loop)
            row.loop = KesLoopRow{r.hysteresis5_at > 0,      r.input_hysteresis,     r.simulated_hysteresis, r.input_hysteresis5,
                                  r.simulated_hysteresis5,   r.hysteresis_rel_error, r.loop_max_rel_error};
        k.rows.push_back(row);
    }
}

bool any_loop(const std::vector<testers::KesCurveResult>& results)
{
    return std::any_of(results.begin(), results.end(), [](const auto& r) { return r.loop; });
}

void run_bending_tests(KesRun& k)
{
    testers::BendingTestOptions bo;
    bo.sigma = (k.request.sigma_cm ? *k.request.sigma_cm : kDefaultBendingSigmaCm) * units::kCmToM;
    bo.model = k.mo;
    bo.solve.on_iteration = k.on_iteration();
    std::vector<testers::KesCurveResult> results;
    for (testers::Direction d : k.directions) {
        k.begin_unit("bending " + testers::to_string(d));
        results.push_back(testers::kes_bending_test(k.fabric, d, bo));
        ++k.units_done;
        k.csv.emplace_back("bending_" + testers::to_string(d) + ".csv", curve_csv(results.back(), "K_per_cm", "M_gf_cm_per_cm"));
        if (results.back().loop)
            k.csv.emplace_back("bending_loop_" + testers::to_string(d) + ".csv", loop_csv(results.back(), "K_per_cm", "M_gf_cm_per_cm"));
    }
    add_kes_rows(k, results, "gf.cm2/cm");
    k.png.emplace_back("bending.png",
                       curve_plot("KES-FB2 pure bending, " + k.name, "curvature K (1/cm)", "moment M (gf.cm/cm)", results, k.fabric, true));
    if (any_loop(results))
        k.png.emplace_back("bending_loop.png", loop_plot("KES-FB2 loop 0 -> +2.5 -> -2.5 -> 0 1/cm (friction), " + k.name,
                                                         "curvature K (1/cm)", "moment M (gf.cm/cm)", results));
}

void run_shear_tests(KesRun& k, double shear_length_m)
{
    testers::ShearTestOptions so;
    so.sigma = (k.request.sigma_cm ? *k.request.sigma_cm : kDefaultShearSigmaCm) * units::kCmToM;
    so.length = shear_length_m;
    so.model = k.mo;
    so.solve.on_iteration = k.on_iteration();
    std::vector<testers::KesCurveResult> results;
    for (testers::Direction d : k.directions) {
        k.begin_unit("shear " + testers::to_string(d));
        results.push_back(testers::kes_shear_test(k.fabric, d, so));
        ++k.units_done;
        k.csv.emplace_back("shear_" + testers::to_string(d) + ".csv", curve_csv(results.back(), "phi_deg", "F_gf_per_cm"));
        if (results.back().loop)
            k.csv.emplace_back("shear_loop_" + testers::to_string(d) + ".csv", loop_csv(results.back(), "phi_deg", "F_gf_per_cm"));
    }
    add_kes_rows(k, results, "gf/(cm.deg)");
    k.png.emplace_back("shear.png", curve_plot("KES-FB1 shear, " + k.name, "shear angle (deg)", "force F (gf/cm)", results, k.fabric, false));
    if (any_loop(results))
        k.png.emplace_back("shear_loop.png", loop_plot("KES-FB1 loop 0 -> +8 -> -8 -> 0 degrees (friction), " + k.name, "shear angle (deg)",
                                                       "force F (gf/cm)", results));
}

std::vector<KesConvergence> run_convergence(KesRun& k)
{
    testers::CantileverOptions co;
    co.sigma = (k.request.sigma_cm ? *k.request.sigma_cm : 2 * kDefaultCantileverSigmaCm) * units::kCmToM;
    co.model = k.mo;
    co.solve.on_iteration = k.on_iteration();
    std::vector<KesConvergence> studies;
    for (testers::Direction d : k.directions) {
        k.begin_unit("convergence " + testers::to_string(d));
        studies.push_back(cantilever_convergence(k.fabric, d, co, k.mo));
        ++k.units_done;
    }
    return studies;
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
    const MonitorScope monitor(request.monitor);
    // Everything is checked before anything runs or is written: every value first, then the
    // fabric, the memory the largest specimen needs and the output folder.
    check_kes_request(request);
    const bool run_cantilever = runs(request.tests, KesTests::CANTILEVER);
    const bool run_bending = runs(request.tests, KesTests::BENDING);
    const bool run_shear = runs(request.tests, KesTests::SHEAR);
    std::vector<testers::Direction> directions;
    if (request.directions != KesDirections::WEFT) directions.push_back(testers::Direction::WARP);
    if (request.directions != KesDirections::WARP) directions.push_back(testers::Direction::WEFT);
    const double shear_length_m = request.shear_length_cm ? *request.shear_length_cm * units::kCmToM : testers::ShearTestOptions{}.length;
    std::vector<std::string> warnings;
    kes::FabricData fabric = command_fabric(request.fabric, request.given_fabric, &warnings);
    if (request.on_warnings) request.on_warnings(warnings);
    warnings.clear();  // delivered
    check_specimen_memory(fabric, run_cantilever, run_bending, run_shear, request.convergence, request.sigma_cm, shear_length_m,
                          request.shear_length_cm.has_value());
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

    const int units = (int(run_cantilever) + int(run_bending) + int(run_shear) + int(request.convergence)) * int(directions.size());
    KesRun k(request, std::move(fabric), name, units);
    k.directions = directions;
    k.mo = mo;
    k.gf_cm2_per_cm = units::newton_per_gram_force(k.mo.gram_force) * units::kCmToM;
    const sim::ThreadCount thread_count(request.threads, request.threads);
    if (run_cantilever) run_cantilevers(k);
    if (run_bending) run_bending_tests(k);
    if (run_shear) run_shear_tests(k, shear_length_m);
    KesTestResult result;
    if (request.convergence) result.convergence = run_convergence(k);

    // Every number written is finite (a test that could not measure is null in the report, as
    // documented; its tables must hold numbers), then one set, kes-report.json last.
    nlohmann::json report = kes_report(k, result.convergence);
    for (const auto& [f, text] : k.csv) require_finite_csv(text, f, "kes-test");
    for (const auto& [f, text] : k.csv) set.add(f, text);
    for (const auto& [f, image] : k.png) set.add(f, render::encode_png(image, join_path(dir, f)));
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
