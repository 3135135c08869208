// The fit job (woven fit FABRIC): the paper's Sec. 5.1 fit of a fabric's KES curves, and the bending and
// trellis energy functions built from them (Sec. 5.2-5.4), as plots, CSV tables and text.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "woven/app/fit.hpp"

#include "woven/app/drape_report.hpp"
#include "woven/app/files.hpp"
#include "woven/app/run_checks.hpp"
#include "woven/common/error.hpp"
#include "woven/common/format.hpp"
#include "woven/io/fabric_file.hpp"
#include "woven/io/output.hpp"
#include "woven/io/output_checks.hpp"
#include "woven/io/output_set.hpp"
#include "woven/io/scene_file.hpp"
#include "woven/kes/fit.hpp"
#include "woven/model/curvature.hpp"
#include "woven/model/energy_functions.hpp"
#include "woven/render/instrument_plots.hpp"

namespace woven::app {

namespace {

/// One KES curve and its fit, with the units and names used in plots and text.
struct CurveView {
    std::string key;      ///< file prefix: bending_warp, bending_weft, shear
    std::string title;    ///< human name
    const kes::Curve* data;
    const kes::CurveFit* fit;
    std::string x_label, y_label;  ///< with units
    std::string x_unit, y_unit;
    std::string rigidity_name, rigidity_unit;  ///< B or G
    double rigidity = 0;
};

struct Output {
    std::string name;
    std::string contents;                 ///< CSV text, or empty for a PNG
    std::optional<render::Image> image;   ///< PNG
};

render::Image fit_plot(const CurveView& c)
{
    render::CurveFitView v = curve_fit_view(*c.data, *c.fit, 400, true);
    v.title = c.title + " (" + c.key + "): KES first-stage curve and fit";
    v.x_label = c.x_label;
    v.y_label = c.y_label;
    v.fit_colour = Vec3(0.12, 0.47, 0.71);
    return render::plot(render::curve_fit_plot(v));
}

std::string describe_fit(const CurveView& c)
{
    std::ostringstream s;
    const auto& segs = c.fit->segments();
    s << c.title << " (" << c.key << "): x " << format_g(c.data->x.front()) << " .. " << format_g(c.data->x.back()) << " " << c.x_unit
      << ", " << c.data->x.size() << " points, " << segs.size() << " segment" << (segs.size() == 1 ? "" : "s")
      << ", y = c0 + c1 x + c2 x^2 (x in " << c.x_unit << ", y in " << c.y_unit << ")\n";
    for (std::size_t k = 0; k < segs.size(); ++k) {
        const auto& sg = segs[k];
        const bool outer = k + 1 == segs.size();
        const std::string end = std::isfinite(sg.x_end) ? format_g(sg.x_end, 4) : format_g(c.fit->data_max_x(), 4) + "..";
        s << "  [" << format_g(sg.x_begin, 4) << ", " << end << "]  c0 " << format_g(sg.c0) << "  c1 " << format_g(sg.c1)
          << "  c2 " << format_g(sg.c2) << (outer ? "  (outer line, extended linearly)" : "") << "\n";
    }
    s << "  max fit error " << format_g(kes::max_fit_error(*c.fit, *c.data), 4) << " " << c.y_unit << "\n";
    s << "  outer line slope " << format_g(c.fit->line().c1, 4) << " " << c.rigidity_unit << " vs KES " << c.rigidity_name
      << " " << format_g(c.rigidity, 4) << " " << c.rigidity_unit << "\n";
    return s.str();
}

void bending_energy_outputs(const std::string& key, const std::string& title, const model::BendingEnergy& b,
                            std::vector<Output>& out)
{
    const double sigma_cm = b.sigma_cm();
    std::ostringstream csv;
    csv << "theta_rad,B_J,K_per_cm\n";
    render::Series s;
    const int n = 500;
    const double lo = 0.3, hi = std::numbers::pi;
    for (int k = 0; k <= n; ++k) {
        const double theta = lo + (hi - lo) * k / n;
        const double B = b.of_angle(theta);
        const double K = model::thread_curvature(theta, sigma_cm).K;
        csv << format_g(theta, 10) << "," << format_g(B, 10) << "," << format_g(K, 10) << "\n";
        s.x.push_back(theta);
        s.y.push_back(B);
    }
    s.label = "B(theta), sigma = " + format_g(sigma_cm, 4) + " cm";
    render::Plot p;
    p.title = "Bending energy of one thread angle, " + title + " (Eq. 12, corrected Eq. 13)";
    p.x_label = "thread angle theta (rad; pi = straight)";
    p.y_label = "B (J)";
    p.series = {s};
    out.push_back({key + "_energy.csv", csv.str(), std::nullopt});
    out.push_back({key + "_energy.png", "", render::plot(p)});
}

void trellis_energy_outputs(const model::TrellisEnergy& t, double sigma_cm, std::vector<Output>& out)
{
    std::ostringstream csv;
    csv << "phi_rad,phi_deg,T_J\n";
    render::Series s;
    const int n = 520;
    const double hi = 1.04;
    for (int k = 0; k <= n; ++k) {
        const double phi = hi * k / n;
        const double T = t.of_angle(phi).value;
        csv << format_g(phi, 10) << "," << format_g(phi * 180.0 / std::numbers::pi, 10) << "," << format_g(T, 10) << "\n";
        s.x.push_back(phi);
        s.y.push_back(T);
    }
    s.label = "T(phi), sigma = " + format_g(sigma_cm, 4) + " cm";
    const double phi_e = t.last_measured_angle();
    // Clip the singular end (T -> inf at 1.05 rad) so the measured part stays readable.
    double y_max = t.of_angle(std::max(phi_e, 0.95)).value;
    if (!(std::isfinite(y_max) && y_max > 0)) y_max = 1.0;
    render::Series mark;
    mark.x = {phi_e, phi_e};
    mark.y = {0.0, y_max};
    mark.color = Vec3(0.84, 0.15, 0.16);
    mark.label = "phi_e = " + format_g(phi_e * 180.0 / std::numbers::pi, 3) + " deg (last measured angle)";
    render::Series singular;
    singular.x = {model::TrellisEnergy::kSingularAngle, model::TrellisEnergy::kSingularAngle};
    singular.y = {0.0, y_max};
    singular.color = Vec3(0.5, 0.5, 0.5);
    singular.label = "singular angle 1.05 rad";
    render::Plot p;
    p.title = "Trellis energy of one crossing (Eq. 15; singular at 1.05 rad)";
    p.x_label = "trellis angle phi (rad)";
    p.y_label = "T (J)";
    p.series = {s, mark, singular};
    p.y_max = y_max;
    out.push_back({"trellis_energy.csv", csv.str(), std::nullopt});
    out.push_back({"trellis_energy.png", "", render::plot(p)});
}

}  // namespace

render::CurveFitView curve_fit_view(const kes::Curve& data, const kes::CurveFit& fit, int n, bool junctions)
{
    render::CurveFitView v;
    v.data_x = data.x;
    v.data_y = data.y;
    const double x_hi = std::max(fit.data_max_x(), data.x.empty() ? 0.0 : data.x.back());
    for (int k = 0; k <= n; ++k) {
        v.fit_x.push_back(x_hi * k / n);
        v.fit_y.push_back(fit.value(x_hi * k / n));
    }
    const auto& segs = fit.segments();
    for (std::size_t k = 0; junctions && k + 1 < segs.size(); ++k) {
        v.junction_x.push_back(segs[k].x_end);
        v.junction_y.push_back(fit.value(segs[k].x_end));
    }
    return v;
}

namespace {

FitResult fit_and_write(const FitRequest& request)
{
    const auto started = std::chrono::steady_clock::now();
    const double sigma_cm = number_in_range(request.sigma_cm, "--sigma-cm", kFitSigmaRange_cm[0], kFitSigmaRange_cm[1]);
    const std::optional<std::string> out = path_given(request.out, "--out");
    std::vector<std::string> warnings;
    const kes::FabricData fabric = command_fabric(request.fabric, request.given_fabric, &warnings);
    if (request.on_warnings) request.on_warnings(warnings);
    std::string name = fabric.name;
    if (name.empty()) name = std::filesystem::path(request.fabric).stem().string();
    // The default folder is named after the fabric: made safe, it cannot leave out/.
    const std::string dir = out.value_or(join_path("out", "fit-" + safe_file_name(name)));

    // Everything is computed (and so validated) before anything is written.
    const kes::FittedFabric fit = kes::fit_fabric(fabric);
    const double sigma_m = sigma_cm * units::kCmToM;
    const model::ModelOptions mo;
    const model::BendingEnergy warp(fit.bending_warp, sigma_m, mo.bending_form, mo.gram_force);
    const model::BendingEnergy weft(fit.bending_weft, sigma_m, mo.bending_form, mo.gram_force);
    const model::TrellisEnergy trellis(fit.shear, sigma_m, mo.gram_force);
    const KesValues kv = kes_values(fabric);
    const std::vector<CurveView> curves = {
        {"bending_warp", "Bending, warp", &fabric.bending_warp.curve, &fit.bending_warp,
         "curvature K (1/cm)", "moment M (gf.cm/cm)", "1/cm", "gf.cm/cm", "B", "gf.cm2/cm", kv.B_warp},
        {"bending_weft", "Bending, weft", &fabric.bending_weft.curve, &fit.bending_weft,
         "curvature K (1/cm)", "moment M (gf.cm/cm)", "1/cm", "gf.cm/cm", "B", "gf.cm2/cm", kv.B_weft},
        {"shear", "Shear", &fabric.shear.curve, &fit.shear, "shear angle (deg)", "force F (gf/cm)", "deg",
         "gf/cm", "G", "gf/(cm.deg)", kv.G},
    };
    std::vector<Output> outputs;
    std::string text = "fabric " + name + ": W " + format_g(kv.W, 4) + " mg/cm2; energies for sigma = " +
                       format_g(sigma_cm, 4) + " cm\n";
    for (const auto& c : curves) {
        outputs.push_back({c.key + "_fit.png", "", fit_plot(c)});
        text += describe_fit(c);
    }
    bending_energy_outputs("bending_warp", "warp", warp, outputs);
    bending_energy_outputs("bending_weft", "weft", weft, outputs);
    trellis_energy_outputs(trellis, sigma_cm, outputs);
    text += "trellis: phi_e " + format_g(trellis.last_measured_angle(), 4) + " rad, continuation T = a / (1.05 - phi) + b "
            "with a " + format_g(trellis.continuation_a(), 4) + " J.rad, b " + format_g(trellis.continuation_b(), 4) + " J\n";

    // Every number written is finite (exit 1 and nothing published otherwise).
    for (const auto& o : outputs)
        if (!o.image) io::require_finite_csv(o.contents, o.name, "fit");

    // One set: staged, then published with report.json last (io::OutputSet).
    make_output_dir(dir);
    std::vector<std::string> names;
    for (const auto& o : outputs) names.push_back(o.name);
    names.push_back("report.json");
    check_output_targets(dir, names);
    names.pop_back();
    io::OutputSet set(dir, names);
    for (const auto& o : outputs) {
        if (o.image) {
            set.add(o.name, render::encode_png(*o.image, join_path(dir, o.name)));
        } else {
            set.add(o.name, o.contents);
        }
    }
    nlohmann::json report = {{"version", WOVEN_VERSION}, {"command", "fit"}, {"fabric", name},
                             {"fabric_source", command_fabric_source(request.fabric, request.given_fabric)}, {"sigma_cm", sigma_cm}};
    report["wall_time_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();  // the job's, to the report's writing
    io::require_finite(report, "fit");
    report["files"] = set.files_json();
    set.publish("report.json", report.dump(2) + "\n");
    return {std::move(report), std::move(text), dir, static_cast<int>(outputs.size()) + 1};
}

}  // namespace

FitResult fit(const FitRequest& request)
{
    const MonitorScope monitor(request.monitor);
    FitResult result;  // an error of the fitting stage names the fabric's file
    with_fabric_source(command_fabric_source(request.fabric, request.given_fabric), [&] { result = fit_and_write(request); });
    return result;
}


}  // namespace woven::app
