#include "woven/testers/kes_shear.hpp"

#include <algorithm>
#include <cmath>

#include "woven/common/error.hpp"
#include "woven/common/units.hpp"
#include "woven/testers/instrument_model.hpp"

namespace woven::testers {

namespace {
/// The G window's upper end: kShearSlopeTo, or where the input curve ends if that is sooner (0
/// without a curve); input_G's data_slope stops there too.
double shear_window_end(const kes::Curve& curve)
{
    return std::min(kes::instrument::kShearSlopeTo, curve.x.empty() ? 0.0 : curve.x.back());
}
}  // namespace

KesCurveResult kes_shear_test(const kes::FabricData& fabric, Direction dir, const ShearTestOptions& options)
{
    if (!(options.sigma > 0) || !(options.gap > 0) || !(options.length > 0))
        throw InputError("kes shear", "sigma", "expected positive spacing, gap and length");
    const double slope_from = kes::instrument::kShearSlopeFrom;
    const double slope_to = shear_window_end(fabric.shear.curve);
    if (!(slope_to > slope_from)) throw InputError("kes shear", "shear", "expected the shear curve to reach beyond 0.5 degrees");
    std::vector<double> angles = options.angles;
    if (angles.empty()) {
        if (!(options.step > 0) || !(options.max_angle >= kes::instrument::kShearSlopeTo) || options.max_angle >= 60)
            throw InputError("kes shear", "max_angle", "expected a positive step and a range covering the G window");
        const int steps = static_cast<int>(std::lround(options.max_angle / options.step));
        for (int k = 0; k <= steps; ++k) angles.push_back(k * options.max_angle / steps);
    }
    if (!std::is_sorted(angles.begin(), angles.end()) || !(angles.front() >= 0) || angles.front() > slope_from || angles.back() < slope_to ||
        !(angles.back() < 60))
        throw InputError("kes shear", "angles", "expected increasing angles in [0, 60) degrees covering the G window");
    if (!(options.pretension >= 0)) throw InputError("kes shear", "pretension", "expected a non-negative pre-tension in gf/cm");
    Layout layout;
    layout.direction = dir;
    const int N = std::max(2, static_cast<int>(std::lround(options.gap / options.sigma)));
    layout.sigma = options.gap / N;
    layout.n_across = N + 1;
    layout.n_along = std::max(2, static_cast<int>(std::lround(options.length / layout.sigma)) + 1);
    const double length = (layout.n_along - 1) * layout.sigma;
    const double area = length * N * layout.sigma;
    model::ClothModel model = instrument_model(fabric, layout.grid(), options.model, /*gravity=*/false);
    const double newton_per_gf = units::newton_per_gram_force(options.model.gram_force);
    const double gf_per_cm = newton_per_gf * units::kMToCm;  // 1 gf/cm in N/m

    // Residuals against the pre-tension a crossing thread carries (much above its weight).
    StaticOptions solve = options.solve;
    if (!(solve.reference_force > 0)) solve.reference_force = std::max(options.pretension, 1.0) * gf_per_cm * layout.sigma;
    std::vector<char> fixed(layout.grid().size(), 0);
    for (int a = 0; a < layout.n_along; ++a) fixed[layout.index(a, 0)] = fixed[layout.index(a, N)] = 1;

    KesCurveResult r;
    r.test = "shear";
    r.direction = dir;
    r.sigma = layout.sigma;
    r.compare_from = kes::instrument::kShearSlopeFrom;
    r.compare_to = std::min(angles.back(), fabric.shear.curve.x.back());  // where the input curve was measured

    Positions x(layout.grid().size());
    auto place = [&](double sep, double phi) {
        const double c = sep / N;
        for (int a = 0; a < layout.n_along; ++a)
            for (int b = 0; b <= N; ++b)
                x[layout.index(a, b)] = Vec3(a * layout.sigma - 0.5 * length + b * c * std::sin(phi), b * c * std::cos(phi), 0.0);
    };
    // Normal reaction on the moving clamp (N) at separation sep, phi = 0.
    auto tension = [&](double sep) {
        place(sep, 0.0);
        const StaticResult eq = solve_static(model, x, fixed, solve);
        if (!eq.converged) throw RuntimeError("kes shear: the static solve did not converge at the pre-tension");
        r.iterations += eq.iterations;
        const Eigen::VectorXd g = model.gradient(eq.x);
        double f = 0;
        for (int a = 0; a < layout.n_along; ++a) f += g[3 * layout.index(a, N) + 1];
        return f / length;  // N/m
    };
    // Pre-tension: the separation whose crossing threads carry the target tension. The stretch
    // force grows as a power of the strain; iterate on that power (secant in log-log).
    const double target = options.pretension * gf_per_cm;
    const double rest = N * layout.sigma;
    double sep = rest;
    if (target > 0) {
        double e0 = 1e-3, f0 = tension(rest * (1 + e0));
        double e1 = 2e-3, f1 = tension(rest * (1 + e1));
        for (int it = 0; it < 40 && std::abs(f1 - target) > 1e-6 * target; ++it) {
            const double p = (f1 > 0 && f0 > 0 && f1 != f0) ? std::log(f1 / f0) / std::log(e1 / e0) : 1.0;
            const double e2 = e1 * std::pow(target / std::max(f1, 1e-300), 1.0 / std::max(p, 0.5));
            e0 = e1, f0 = f1;
            e1 = std::clamp(e2, 1e-9, 0.2);
            f1 = tension(rest * (1 + e1));
        }
        if (std::abs(f1 - target) > 1e-4 * target) throw RuntimeError("kes shear: the pre-tension could not be set");
        sep = rest * (1 + e1);
    }

    // FRICTION with a width given (and the full sweep asked): the full loop, the friction
    // state updated after each step from the virgin state.
    const bool loop = model.slip_laws().shear.active() && options.angles.empty();
    const int steps = static_cast<int>(angles.size()) - 1;
    std::vector<double> path = angles;
    if (loop) {
        path = loop_path(angles.back(), steps);
        model.reset_slip();
    }
    for (std::size_t k = 0; k < path.size(); ++k) {
        const double phi_deg = path[k];
        const double phi = phi_deg * units::kDegToRad;
        place(sep, phi);
        const StaticResult eq = solve_static(model, x, fixed, solve);
        if (!eq.converged)
            throw RuntimeError("kes shear: the static solve did not converge at phi = " + std::to_string(phi_deg) + " degrees");
        r.iterations += eq.iterations;
        // dE/dphi: the moving clamp's particles move by sep (cos phi, -sin phi) per radian.
        const Eigen::VectorXd g = model.gradient(eq.x);
        double dE = 0, dE_central = 0;
        int central = 0;  // particles of the middle half, each standing for sigma of clamp
        for (int a = 0; a < layout.n_along; ++a) {
            const int p = layout.index(a, N);
            const double dE_p = sep * (g[3 * p] * std::cos(phi) - g[3 * p + 1] * std::sin(phi));
            dE += dE_p;
            if (4 * a >= layout.n_along - 1 && 4 * a <= 3 * (layout.n_along - 1)) {
                dE_central += dE_p;
                ++central;
            }
        }
        const double F = dE / (area * std::cos(phi)) / gf_per_cm;
        if (loop) {
            model.update_slip(eq.x);
            r.loop_x.push_back(phi_deg);
            r.loop_y.push_back(F);
        }
        if (k < angles.size()) {
            r.x.push_back(phi_deg);
            r.y.push_back(F);
            r.y_central.push_back(dE_central / (central * layout.sigma * N * layout.sigma * std::cos(phi)) / gf_per_cm);
            r.y_input.push_back(curve_value(fabric.shear.curve, phi_deg));
        }
    }
    finish_kes_result(r, input_G(fabric), slope_from, slope_to);
    if (loop) {
        // The input half widths in degrees (the model's law is in q = sin(phi)).
        const kes::ShearSummary& s = *fabric.shear.summary;
        const model::SlipLaw law = model::make_slip_law(slope_from, 0.5 * s.two_HG, kes::instrument::kShearSlopeTo, 0.5 * s.two_HG5, kes::kShearRise);
        finish_loop(r, s.G, law, kes::kShearRise, steps, slope_from, slope_to, slope_from, kes::instrument::kShearSlopeTo, s.two_HG, s.two_HG5);
    }
    r.central_summary = window_slope(r.x, r.y_central, slope_from, slope_to);
    r.central_rel_error = (r.central_summary - r.input_summary) / r.input_summary;
    return r;
}

double shear_deembedding(const kes::FabricData& fabric, const model::ModelOptions& model, double sigma, double tolerance)
{
    const double window_end = shear_window_end(fabric.shear.curve);
    if (model.discretization == model::Discretization::PAPER || !(window_end > kes::instrument::kShearSlopeFrom)) return 1.0;
    ShearTestOptions o;
    o.sigma = sigma;
    o.model = model;
    // FRICTION: the elastic part is the mean line; it is de-embedded, and the friction
    // elements are scaled with it (model::ModelOptions::hysteresis).
    if (model.hysteresis == model::Hysteresis::FRICTION) {
        o.model.hysteresis = model::Hysteresis::LOADING_BRANCH;
        const kes::FabricData mean = kes::without_hysteresis(fabric);
        return shear_deembedding(mean, o.model, sigma, tolerance);
    }
    o.angles = {kes::instrument::kShearSlopeFrom, window_end};  // the G window's ends
    double scale = 1.0;
    for (int it = 0; it < 8; ++it) {
        o.model.shear_scale = scale;
        const KesCurveResult r = kes_shear_test(fabric, Direction::WARP, o);
        if (!(r.simulated_summary > 0) || !std::isfinite(r.simulated_summary))
            throw RuntimeError("kes shear: the de-embedding read a non-positive G");
        const double ratio = r.input_summary / r.simulated_summary;
        if (std::abs(ratio - 1) <= tolerance) return scale;
        scale *= ratio;
    }
    return scale;
}

}  // namespace woven::testers
