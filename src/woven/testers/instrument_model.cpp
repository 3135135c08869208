#include "woven/testers/instrument_model.hpp"

#include <algorithm>
#include <cmath>

#include "woven/common/units.hpp"
#include "woven/testers/specimen.hpp"

namespace woven::testers {

model::ClothModel instrument_model(const kes::FabricData& fabric, const model::Grid& grid, const model::ModelOptions& options, bool gravity)
{
    model::ModelOptions mo = options;
    if (!gravity) {
        if (!(mo.C0 > 0)) {
            const double W = fabric.areal_density_mg_cm2 * units::kMgPerCm2ToKgPerM2;
            const double hang = 0.5 * std::max(grid.nu - 1, grid.nv - 1) * grid.sigma;
            mo.C0 = model::choose_C0(W, units::kStandardGravity, grid.sigma, hang);
        }
        mo.gravity = 0;
    }
    return model::make_cloth_model(fabric, grid, mo);
}

void finish_kes_result(KesCurveResult& r, double input_summary, double lo, double hi)
{
    r.input_summary = input_summary;
    r.simulated_summary = window_slope(r.x, r.y, lo, hi);
    r.summary_rel_error = (r.simulated_summary - input_summary) / input_summary;
    r.curve_max_rel_error = 0;
    for (size_t k = 0; k < r.x.size(); ++k) {
        if (r.x[k] < r.compare_from - 1e-12 || r.x[k] > r.compare_to + 1e-12 || !(r.y_input[k] > 0)) continue;
        r.curve_max_rel_error = std::max(r.curve_max_rel_error, std::abs(r.y[k] - r.y_input[k]) / r.y_input[k]);
    }
}

double input_loop_value(double slope, const model::SlipLaw& law, double rise, int leg, double x_max, double x)
{
    const auto r = [](double u) { u = std::clamp(u, 0.0, 1.0); return 1.0 - (1.0 - u) * (1.0 - u); };
    const double h = law.half_width(x);
    if (leg == 0) return slope * x + (x < 0 ? -1.0 : 1.0) * h * r(std::abs(x) / rise);
    if (leg == 1) return slope * x + h * (1.0 - 2.0 * r((x_max - x) / (2.0 * rise)));
    return slope * x - h * (1.0 - 2.0 * r((x + x_max) / (2.0 * rise)));
}

std::vector<double> loop_path(double max, int steps)
{
    std::vector<double> path;
    for (int k = 0; k <= steps; ++k) path.push_back(max * k / steps);
    for (int k = 1; k <= 2 * steps; ++k) path.push_back(max - max * k / steps);
    for (int k = 1; k <= steps; ++k) path.push_back(-max + max * k / steps);
    return path;
}

namespace {
/// The leg [from, to] of the loop as increasing x.
void leg(const KesCurveResult& r, int from, int to, std::vector<double>& x, std::vector<double>& y)
{
    x.assign(r.loop_x.begin() + from, r.loop_x.begin() + to + 1);
    y.assign(r.loop_y.begin() + from, r.loop_y.begin() + to + 1);
    if (x.front() > x.back()) {
        std::reverse(x.begin(), x.end());
        std::reverse(y.begin(), y.end());
    }
}
double at_x(const std::vector<double>& x, const std::vector<double>& y, double v) { return curve_value(kes::Curve{x, y}, v); }
}  // namespace

void finish_loop(KesCurveResult& r, double slope, const model::SlipLaw& law, double rise, int steps, double lo, double hi, double at, double at5,
                 double input_width, double input_width5)
{
    r.loop = true;
    const double x_max = r.loop_x[steps];
    // Legs: 0 .. steps (virgin), steps .. 3 steps (down), 3 steps .. 4 steps (up, negative side).
    std::vector<double> x0, y0, x1, y1, x2, y2;
    leg(r, 0, steps, x0, y0);
    leg(r, steps, 3 * steps, x1, y1);
    leg(r, 3 * steps, 4 * steps, x2, y2);
    r.loop_y_input.clear();
    double amplitude = 0, worst = 0;
    for (std::size_t k = 0; k < r.loop_x.size(); ++k) {
        const int which = k <= static_cast<std::size_t>(steps) ? 0 : (k <= static_cast<std::size_t>(3 * steps) ? 1 : 2);
        r.loop_y_input.push_back(input_loop_value(slope, law, rise, which, x_max, r.loop_x[k]));
        amplitude = std::max(amplitude, std::abs(r.loop_y_input.back()));
        worst = std::max(worst, std::abs(r.loop_y[k] - r.loop_y_input.back()));
    }
    r.loop_max_rel_error = amplitude > 0 ? worst / amplitude : 0;
    // Widths: at +a between the virgin leg and the down leg, at -a between the up and the down leg.
    const auto width = [&](double a) { return 0.5 * ((at_x(x0, y0, a) - at_x(x1, y1, a)) + (at_x(x2, y2, -a) - at_x(x1, y1, -a))); };
    r.hysteresis_at = at;
    r.hysteresis5_at = at5;
    r.input_hysteresis = input_width;
    r.input_hysteresis5 = at5 > 0 ? input_width5 : 0;
    r.simulated_hysteresis = width(at);
    r.simulated_hysteresis5 = at5 > 0 ? width(at5) : 0;
    const double e1 = (r.simulated_hysteresis - input_width) / input_width;
    const double e5 = at5 > 0 && input_width5 > 0 ? (r.simulated_hysteresis5 - input_width5) / input_width5 : 0;
    r.hysteresis_rel_error = std::abs(e5) > std::abs(e1) ? e5 : e1;
    // B (G) as KES reads it from a loop: the mean slope of both branches on both sides.
    const auto neg = [](std::vector<double> v) { for (double& t : v) t = -t; return v; };
    const double s_pos = 0.5 * (window_slope(x0, y0, lo, hi) + window_slope(x1, y1, lo, hi));
    std::vector<double> mx1 = neg(x1), my1 = neg(y1), mx2 = neg(x2), my2 = neg(y2);
    std::reverse(mx1.begin(), mx1.end()), std::reverse(my1.begin(), my1.end());
    std::reverse(mx2.begin(), mx2.end()), std::reverse(my2.begin(), my2.end());
    const double s_neg = 0.5 * (window_slope(mx1, my1, lo, hi) + window_slope(mx2, my2, lo, hi));
    r.simulated_summary = 0.5 * (s_pos + s_neg);
    r.summary_rel_error = (r.simulated_summary - r.input_summary) / r.input_summary;
}

}  // namespace woven::testers
