// woven kes-test FABRIC: the virtual instruments (testers/) run on the model: the cantilever
// (ASTM D1388), KES-FB2 pure bending and KES-FB1 shear, each a static simulation of a specimen
// of the model's particles, against the fabric's input values.
#include <algorithm>
#include <cctype>
#include <cstdarg>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "woven/cli/args.hpp"
#include "woven/cli/commands.hpp"
#include "woven/cli/material.hpp"
#include "woven/cli/progress.hpp"
#include "woven/cli/report.hpp"
#include "woven/cli/resources.hpp"
#include "woven/cli/run_checks.hpp"
#include "woven/common/error.hpp"
#include "woven/common/units.hpp"
#include "woven/io/fabric_file.hpp"
#include "woven/io/output.hpp"
#include "woven/io/output_set.hpp"
#include "woven/io/scene_file.hpp"
#include "woven/render/image.hpp"
#include "woven/render/plot.hpp"
#include "woven/sim/thread_count.hpp"
#include "woven/testers/cantilever.hpp"
#include "woven/testers/kes_bending.hpp"
#include "woven/testers/kes_shear.hpp"

namespace woven::cli {

namespace {

/// printf into std::cout, not C's stdout: the Python module captures std::cout (nothing of a
/// command reaches the interpreter's stdout).
[[gnu::format(printf, 1, 2)]] void print_out(const char* format, ...)
{
    char line[512];
    va_list args;
    va_start(args, format);
    std::vsnprintf(line, sizeof line, format, args);
    va_end(args);
    std::cout << line;
}

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

/// One line of the table and one entry of kes-report.json.
struct Row {
    std::string test, direction, unit;
    double sigma_m = 0, input = 0, simulated = 0, rel = 0, curve = 0;
    std::optional<double> bending_length_m, elastica_bending_length_m;
    std::optional<double> central, central_rel;  ///< shear: the middle half of the clamp (kes_shear.hpp)
    int solves_or_iterations = 0;
    const testers::KesCurveResult* loop = nullptr;  ///< bending, shear with a loop run (FRICTION)
};

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
    render::Plot p;
    p.title = title;
    p.x_label = x_label;
    p.y_label = y_label;
    std::vector<render::Series> inputs, sims;
    for (const auto& r : results) {
        if (!r.loop) continue;
        render::Series in, sim;
        in.x = r.loop_x;
        in.y = r.loop_y_input;
        in.style = render::Series::Style::LINE;
        in.label = "input loop " + testers::to_string(r.direction);
        sim.x = r.loop_x;
        sim.y = r.loop_y;
        sim.style = render::Series::Style::POINTS;
        sim.label = "simulated " + testers::to_string(r.direction);
        // One input loop where the directions share it (shear): drawn and labelled once.
        if (std::none_of(inputs.begin(), inputs.end(), [&](const render::Series& s) { return s.x == in.x && s.y == in.y; }))
            inputs.push_back(in);
        sims.push_back(sim);
    }
    if (inputs.size() == 1 && sims.size() > 1) inputs[0].label = "input loop";
    for (auto& s : inputs) p.series.push_back(std::move(s));
    for (auto& s : sims) p.series.push_back(std::move(s));
    return render::plot(p, 900, 620);
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
    render::Plot p;
    p.title = title;
    p.x_label = x_label;
    p.y_label = y_label;
    for (const auto& r : results) {
        const kes::Curve& in = bending ? testers::input_bending(fabric, r.direction) : fabric.shear.curve;
        render::Series data;
        data.x = in.x;
        data.y = in.y;
        data.style = render::Series::Style::POINTS;
        data.label = "input " + (bending ? testers::to_string(r.direction) : std::string("curve"));
        render::Series sim;
        sim.x = r.x;
        sim.y = r.y;
        sim.style = render::Series::Style::LINE_AND_POINTS;
        sim.label = "simulated " + testers::to_string(r.direction);
        if (bending || &r == &results.front()) p.series.push_back(data);
        p.series.push_back(sim);
    }
    return render::plot(p, 900, 620);
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
nlohmann::json cantilever_convergence(const kes::FabricData& fabric, testers::Direction d, const testers::CantileverOptions& base,
                                      const model::ModelOptions& mo)
{
    const double g = mo.gravity > 0 ? mo.gravity : units::kStandardGravity;
    const double w = testers::weight_per_area(fabric, g);
    const testers::CurvatureOfMoment law = testers::fabric_curvature_law(fabric, d, model::BendingForm::WORK, mo.gram_force);
    const double c = 0.5 * testers::elastica_overhang_for_chord_angle(testers::kPeirceChordAngle, w, law);
    nlohmann::json rows = nlohmann::json::array();
    print_out("cantilever convergence, %s: c = %.5g cm (elastica, 41.5 degree chord)\n", testers::to_string(d).c_str(),
                c * units::kMToCm);
    print_out("%6s %10s %12s %12s %10s %7s\n", "L/c", "sigma_cm", "c_sim_cm", "c_exact_cm", "rel_err", "order");
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
            print_out("%6.2f %10.5g %12.6g %12.6g %+9.4f%% %7.3g\n", ratio, sh.sigma * units::kMToCm, c_sim * units::kMToCm,
                        c_exact * units::kMToCm, 100 * err, order);
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
    return rows;
}

}  // namespace

int run_kes_test(const KesTestOptions& options)
{
    // Everything is checked before anything runs or is written: every option first, then the
    // fabric, the memory the largest specimen needs and the output folder.
    const bool run_cantilever = options.test == "all" || options.test == "cantilever";
    const bool run_bending = options.test == "all" || options.test == "bending";
    const bool run_shear = options.test == "all" || options.test == "shear";
    if (!run_cantilever && !run_bending && !run_shear)
        throw InputError(kCommandLine, "--test", "expected cantilever, bending, shear or all, got '" + options.test + "'");
    if (options.convergence && !run_cantilever)
        throw InputError(kCommandLine, "--convergence", "expected --test cantilever or all (a study of the cantilever test)");
    std::vector<testers::Direction> directions;
    if (options.direction == "warp" || options.direction == "both") directions.push_back(testers::Direction::WARP);
    if (options.direction == "weft" || options.direction == "both") directions.push_back(testers::Direction::WEFT);
    if (directions.empty()) throw InputError(kCommandLine, "--direction", "expected warp, weft or both, got '" + options.direction + "'");
    const std::optional<double> sigma_cm = options.sigma_cm ? std::optional<double>(parse_number(*options.sigma_cm, "--sigma-cm", 0.02, 2.0)) : std::nullopt;
    const double shear_length_m =
        options.shear_length_cm ? parse_number(*options.shear_length_cm, "--shear-length-cm", 5, 200) * units::kCmToM : testers::ShearTestOptions{}.length;
    model::ModelOptions mo;
    if (options.bending_form)
        mo.bending_form = parse_choice(*options.bending_form, "--bending-form", {"work", "secant"}) == 0 ? model::BendingForm::WORK
                                                                                                        : model::BendingForm::SECANT;
    if (options.discretization)
        mo.discretization = parse_choice(*options.discretization, "--discretization", model::kDiscretizationNames);
    if (options.shear_law)
        mo.shear_law = parse_shear_law(*options.shear_law, "--shear-law");
    // kes-test shows the loops: friction unless asked otherwise (the model's default is the
    // loading branch).
    mo.hysteresis = model::Hysteresis::FRICTION;
    if (options.hysteresis) mo.hysteresis = parse_hysteresis(*options.hysteresis, "--hysteresis");
    if (options.out) parse_path(*options.out, "--out");
    const int threads = options.threads ? static_cast<int>(*parse_integer(options.threads, "--threads", 0, io::kMaxThreads)) : 0;
    std::vector<std::string> warnings;
    const kes::FabricData fabric = command_fabric(options.fabric, options.given_fabric, &warnings);
    print_warnings(warnings);
    check_specimen_memory(fabric, run_cantilever, run_bending, run_shear, options.convergence, sigma_cm, shear_length_m,
                          options.shear_length_cm.has_value());
    std::string name = fabric.name.empty() ? std::filesystem::path(options.fabric).stem().string() : fabric.name;
    std::string safe;
    for (char c : name) safe += (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-') ? c : '_';
    const std::string dir = options.out ? *options.out : join_path("out", "kes-" + safe);
    // The set: every file a kes-test run can write (those this run does not write are removed
    // when it publishes, kes-report.json last: io::OutputSet).
    std::vector<std::string> members;
    for (const char* t : {"cantilever", "bending", "shear"}) {
        for (const char* d : {"warp", "weft"}) members.push_back(std::string(t) + "_" + d + ".csv");
        members.push_back(std::string(t) + ".png");
    }
    for (const char* t : {"bending", "shear"}) {
        for (const char* d : {"warp", "weft"}) members.push_back(std::string(t) + "_loop_" + d + ".csv");
        members.push_back(std::string(t) + "_loop.png");
    }
    make_output_dir(dir);
    members.push_back("kes-report.json");
    check_output_targets(dir, members);
    members.pop_back();
    io::OutputSet set(dir, members);
    with_fabric_source(command_fabric_source(options.fabric, options.given_fabric), [&] { resolve_shear_law(fabric, mo); });

    const double gf_cm2_per_cm = units::newton_per_gram_force(mo.gram_force) * units::kCmToM;  // N m per gf.cm2/cm
    std::vector<Row> rows;
    std::vector<std::pair<std::string, std::string>> csv;  // name, contents
    std::vector<std::pair<std::string, render::Image>> png;
    // Kept to the end: the rows point at their loops.
    std::vector<testers::KesCurveResult> bending_results, shear_results;
    bending_results.reserve(directions.size());
    shear_results.reserve(directions.size());

    // Word on the wait (a test can take minutes): the share of (test, direction) runs done and
    // the Newton iterations of the one running.
    Activity activity("kes-test " + name);
    const sim::ThreadCount thread_count(threads, threads);
    const int units = (int(run_cantilever) + int(run_bending) + int(run_shear) + int(options.convergence)) * int(directions.size());
    int units_done = 0, iterations = 0;
    std::string running;
    const auto begin_unit = [&](const std::string& what) {
        running = what;
        iterations = 0;
        activity.update(double(units_done) / units, running);
    };
    const auto on_iteration = [&] { activity.update(double(units_done) / units, running + ", iteration " + std::to_string(++iterations)); };

    if (run_cantilever) {
        testers::CantileverOptions co;
        co.sigma = (sigma_cm ? *sigma_cm : kDefaultCantileverSigmaCm) * units::kCmToM;
        co.model = mo;
        co.solve.on_iteration = on_iteration;
        render::Plot p;
        p.title = "Cantilever (ASTM D1388), " + name + ": strip at the 41.5 degree chord";
        p.x_label = "along the strip (cm)";
        p.y_label = "height (cm)";
        for (testers::Direction d : directions) {
            begin_unit("cantilever " + testers::to_string(d));
            const testers::CantileverResult r = testers::cantilever_test(fabric, d, co);
            ++units_done;
            Row row;
            row.test = "cantilever";
            row.direction = testers::to_string(d);
            row.unit = "gf.cm2/cm";
            row.sigma_m = r.shape.sigma;
            row.input = r.elastica_flexural_rigidity / gf_cm2_per_cm;
            row.simulated = r.flexural_rigidity / gf_cm2_per_cm;
            row.rel = (r.bending_length - r.elastica_bending_length) / r.elastica_bending_length;
            row.curve = shape_error(r.shape, r.elastica, 0.5 * (r.shape.z[0] + r.shape.z[1]));
            row.bending_length_m = r.bending_length;
            row.elastica_bending_length_m = r.elastica_bending_length;
            row.solves_or_iterations = r.solves;
            rows.push_back(row);
            std::ostringstream s;
            s.precision(10);
            s << "source,s_m,x_m,z_m\n";
            for (std::size_t a = 0; a < r.shape.x.size(); ++a)
                s << "simulated," << (a - 0.5) * r.shape.sigma << "," << r.shape.x[a] << "," << r.shape.z[a] << "\n";
            for (std::size_t k = 0; k < r.elastica.s.size(); k += 10)
                s << "elastica," << r.elastica.s[k] << "," << r.elastica.x[k] << "," << r.elastica.z[k] << "\n";
            csv.emplace_back("cantilever_" + row.direction + ".csv", s.str());
            render::Series sim, el;
            for (std::size_t a = 0; a < r.shape.x.size(); ++a) {
                sim.x.push_back(r.shape.x[a] * units::kMToCm);
                sim.y.push_back(r.shape.z[a] * units::kMToCm);
            }
            for (std::size_t k = 0; k < r.elastica.s.size(); k += 10) {
                el.x.push_back(r.elastica.x[k] * units::kMToCm);
                el.y.push_back(r.elastica.z[k] * units::kMToCm);
            }
            sim.style = render::Series::Style::POINTS;
            sim.label = "simulated " + row.direction + " (c " + fmt(r.bending_length * units::kMToCm, 4) + " cm)";
            el.label = "elastica " + row.direction + " (c " + fmt(r.elastica_bending_length * units::kMToCm, 4) + " cm)";
            p.series.push_back(el);
            p.series.push_back(sim);
        }
        png.emplace_back("cantilever.png", render::plot(p, 900, 620));
    }
    auto kes_rows = [&](const std::vector<testers::KesCurveResult>& results, const std::string& unit) {
        for (const auto& r : results) {
            Row row;
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
            if (r.loop) row.loop = &r;
            rows.push_back(row);
        }
    };
    if (run_bending) {
        testers::BendingTestOptions bo;
        bo.sigma = (sigma_cm ? *sigma_cm : kDefaultBendingSigmaCm) * units::kCmToM;
        bo.model = mo;
        bo.solve.on_iteration = on_iteration;
        std::vector<testers::KesCurveResult>& results = bending_results;
        for (testers::Direction d : directions) {
            begin_unit("bending " + testers::to_string(d));
            results.push_back(testers::kes_bending_test(fabric, d, bo));
            ++units_done;
            csv.emplace_back("bending_" + testers::to_string(d) + ".csv", curve_csv(results.back(), "K_per_cm", "M_gf_cm_per_cm"));
            if (results.back().loop)
                csv.emplace_back("bending_loop_" + testers::to_string(d) + ".csv", loop_csv(results.back(), "K_per_cm", "M_gf_cm_per_cm"));
        }
        kes_rows(results, "gf.cm2/cm");
        png.emplace_back("bending.png",
                         curve_plot("KES-FB2 pure bending, " + name, "curvature K (1/cm)", "moment M (gf.cm/cm)", results, fabric, true));
        if (std::any_of(results.begin(), results.end(), [](const auto& r) { return r.loop; }))
            png.emplace_back("bending_loop.png", loop_plot("KES-FB2 loop 0 -> +2.5 -> -2.5 -> 0 1/cm (friction), " + name, "curvature K (1/cm)",
                                                           "moment M (gf.cm/cm)", results));
    }
    if (run_shear) {
        testers::ShearTestOptions so;
        so.sigma = (sigma_cm ? *sigma_cm : kDefaultShearSigmaCm) * units::kCmToM;
        so.length = shear_length_m;
        so.model = mo;
        so.solve.on_iteration = on_iteration;
        std::vector<testers::KesCurveResult>& results = shear_results;
        for (testers::Direction d : directions) {
            begin_unit("shear " + testers::to_string(d));
            results.push_back(testers::kes_shear_test(fabric, d, so));
            ++units_done;
            csv.emplace_back("shear_" + testers::to_string(d) + ".csv", curve_csv(results.back(), "phi_deg", "F_gf_per_cm"));
            if (results.back().loop)
                csv.emplace_back("shear_loop_" + testers::to_string(d) + ".csv", loop_csv(results.back(), "phi_deg", "F_gf_per_cm"));
        }
        kes_rows(results, "gf/(cm.deg)");
        png.emplace_back("shear.png", curve_plot("KES-FB1 shear, " + name, "shear angle (deg)", "force F (gf/cm)", results, fabric, false));
        if (std::any_of(results.begin(), results.end(), [](const auto& r) { return r.loop; }))
            png.emplace_back("shear_loop.png", loop_plot("KES-FB1 loop 0 -> +8 -> -8 -> 0 degrees (friction), " + name, "shear angle (deg)",
                                                         "force F (gf/cm)", results));
    }

    nlohmann::json convergence = nlohmann::json::array();
    if (options.convergence) {
        testers::CantileverOptions co;
        co.sigma = (sigma_cm ? *sigma_cm : 2 * kDefaultCantileverSigmaCm) * units::kCmToM;
        co.model = mo;
        co.solve.on_iteration = on_iteration;
        for (testers::Direction d : directions) {
            begin_unit("convergence " + testers::to_string(d));
            for (auto& row : cantilever_convergence(fabric, d, co, mo)) convergence.push_back(row);
            ++units_done;
        }
    }

    // Table.
    std::cout << "fabric " << name << " (bending form " << (mo.bending_form == model::BendingForm::WORK ? "work" : "secant")
              << ", discretization " << model::to_string(mo.discretization) << ", "
              << shear_law_text(mo) << ", hysteresis " << model::to_string(mo.hysteresis) << ")\n";
    print_out("%-10s %-5s %8s %12s %12s %9s %9s  %s\n", "test", "dir", "sigma_cm", "input", "simulated", "rel_err", "curve_err", "unit");
    for (const Row& r : rows) {
        print_out("%-10s %-5s %8.4g %12.6g %12.6g %+9.4f%% %8.4f%%  %s\n", r.test.c_str(), r.direction.c_str(), r.sigma_m * units::kMToCm,
                    r.input, r.simulated, 100 * r.rel, 100 * r.curve, r.unit.c_str());
        if (r.central)
            print_out("%-10s %-5s %8.4g %12.6g %12.6g %+9.4f%% %9s  %s\n", "  centre", r.direction.c_str(), r.sigma_m * units::kMToCm, r.input,
                        *r.central, 100 * *r.central_rel, "", r.unit.c_str());
        if (r.loop) {
            const testers::KesCurveResult& l = *r.loop;
            const bool shear = l.hysteresis5_at > 0;
            print_out("%-10s %-5s %8.4g %12.6g %12.6g %+9.4f%% %8.4f%%  %s\n", shear ? "  2HG" : "  2HB", r.direction.c_str(),
                        r.sigma_m * units::kMToCm, l.input_hysteresis, l.simulated_hysteresis,
                        100 * (l.simulated_hysteresis - l.input_hysteresis) / l.input_hysteresis, 100 * l.loop_max_rel_error,
                        shear ? "gf/cm" : "gf.cm/cm");
            if (shear)
                print_out("%-10s %-5s %8.4g %12.6g %12.6g %+9.4f%% %9s  %s\n", "  2HG5", r.direction.c_str(), r.sigma_m * units::kMToCm,
                            l.input_hysteresis5, l.simulated_hysteresis5, 100 * (l.simulated_hysteresis5 - l.input_hysteresis5) / l.input_hysteresis5,
                            "", "gf/cm");
        }
    }
    std::cout << "cantilever: input = the exact elastica's flexural rigidity W g c^3 for the input curve, rel_err = bending length vs the "
                 "elastica's, curve_err = largest shape difference / tip drop; bending, shear: input = the file's B, G (or its curve's KES "
                 "slope), curve_err = largest relative difference from the input curve over 0.5..2.5 1/cm, 0.5..8 deg; shear centre: the middle "
                 "half of the moving clamp, away from the specimen's free short edges (the material's law); 2HB, 2HG, 2HG5 (friction): the "
                 "loop's widths at 1 1/cm, 0.5 and 5 deg, simulated (B, G: the loop's mean branch slope), curve_err = the loop's largest "
                 "difference from the input loop / its amplitude\n";

    // Files: staged atomically, kes-report.json last.
    nlohmann::json report = {{"version", WOVEN_VERSION},
                             {"command", "kes-test"},
                             {"fabric", name},
                             {"fabric_source", options.given_fabric.data ? options.given_fabric.source : options.fabric},
                             {"bending_form", mo.bending_form == model::BendingForm::WORK ? "work" : "secant"},
                             {"discretization", model::to_string(mo.discretization)},
                             {"shear_law", to_string(mo.shear_law)},
                             {"shear_scale", mo.shear_scale},
                             {"hysteresis", model::to_string(mo.hysteresis)}};
    nlohmann::json tests = nlohmann::json::array();
    for (const Row& r : rows) {
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
                const testers::KesCurveResult& l = *r.loop;
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
        tests.push_back(t);
    }
    report["tests"] = tests;
    if (options.convergence) report["cantilever_convergence"] = convergence;
    // Every number written is finite (a test that could not measure is null in the report, as
    // documented; its tables must hold numbers), then one set, kes-report.json last.
    for (const auto& [f, text] : csv) require_finite_csv(text, f, "kes-test");
    for (const auto& [f, text] : csv) set.add(f, text);
    for (const auto& [f, image] : png) set.add(f, render::encode_png(image, join_path(dir, f)));
    report["files"] = set.files_json();
    set.publish("kes-report.json", report.dump(2) + "\n");
    const std::size_t written = set.names().size() + 1;
    std::cout << "wrote " << written << " files to " << dir << "\n";
    return kExitOk;
}

void add_kes_test_command(CLI::App& app, int& exit_code)
{
    auto options = std::make_shared<KesTestOptions>();
    CLI::App* sub = app.add_subcommand("kes-test", "Run the virtual cantilever, KES-FB2 bending and KES-FB1 shear tests on the model");
    sub->footer("Each test is a static simulation of a specimen of the model's particles (docs/VALIDATION.md says how each maps onto the "
                "grid). Prints input vs simulated summary values and writes to --out (default out/kes-<name>): <test>_<direction>.csv, "
                "cantilever.png, bending.png, shear.png and kes-report.json (list 'tests': test, direction, sigma_m, input_summary, "
                "simulated_summary, summary_rel_error, curve_max_rel_error; cantilever also bending_length_m, elastica_bending_length_m; shear also central_summary, central_rel_error: the middle half of the clamp, away from the free short edges; bending and shear also "
                "input_hysteresis and simulated_hysteresis ({\"2HB\": gf.cm/cm} or {\"2HG\", \"2HG5\": gf/cm}), hysteresis_rel_error (the worst) and "
                "loop_max_rel_error, null without a loop). With --hysteresis friction (the default) bending and shear run full loops "
                "(0 -> +2.5 -> -2.5 -> 0 1/cm, 0 -> +8 -> -8 -> 0 degrees) for the curves given with a hysteresis width: <test>_loop_<direction>.csv "
                "and <test>_loop.png. The files are one set: "
                "kes-report.json is written last and names every file with its size and SHA-256; files of an earlier run's other tests are removed.");
    sub->add_option("FABRIC", options->fabric, "A built-in fabric name (see `woven fabrics`) or a fabric .toml file")->required();
    sub->add_option("--test", options->test, "cantilever, bending, shear or all")->capture_default_str();
    sub->add_option("--direction", options->direction, "warp, weft or both")->capture_default_str();
    sub->add_option("--sigma-cm", options->sigma_cm,
                    "Particle spacing of the specimens, cm (default: cantilever 0.25, bending 0.1, shear 0.25)");
    sub->add_option("--shear-length-cm", options->shear_length_cm,
                    "FB1 specimen length along the clamps, cm (default 20, the instrument's; longer shows the free ends' effect on G)");
    sub->add_option("--bending-form", options->bending_form, "work or secant (default: the model's, work)");
    sub->add_option("--discretization", options->discretization, "convergent or paper (default: the model's, convergent)");
    sub->add_option("--shear-law", options->shear_law,
                    "deembedded (the material's law, raised by the FB1 specimen's end effect: the default) or measured (the input curve as read)");
    sub->add_option("--hysteresis", options->hysteresis,
                    "friction (the default here: the mean line plus friction elements, full KES loops) or loading-branch (the loading "
                    "branch as an elastic energy, the loading sweep only)");
    sub->add_option("--threads", options->threads, "Worker threads: oneTBB, OpenMP and the BLAS (0: all cores, the default)")
        ->type_name("INT");
    sub->add_option("--out", options->out, "Output directory (default out/kes-<name>)");
    sub->add_flag("--convergence", options->convergence,
                  "Also the cantilever's grid convergence: bending length vs the exact elastica at L/c = 1..3 and spacings S, S/2, S/4 "
                  "(S = --sigma-cm, default 0.5), with the observed order (in kes-report.json: cantilever_convergence)");
    sub->callback([options, &exit_code] { exit_code = run_kes_test(*options); });
}

}  // namespace woven::cli
