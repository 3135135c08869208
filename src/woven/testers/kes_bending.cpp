#include "woven/testers/kes_bending.hpp"

#include <algorithm>
#include <cmath>

#include "woven/common/error.hpp"
#include "woven/common/units.hpp"
#include "woven/testers/instrument_model.hpp"

namespace woven::testers {

namespace {

/// Node positions (along, up) of the rows bent to turning angle psi per row: segment k runs at
/// angle k psi, segment 0 centred on the origin. d = d/dpsi of each.
void bent_rows(int rows, double sigma, double psi, std::vector<Vec2>& p, std::vector<Vec2>& d)
{
    p.assign(rows, Vec2::Zero());
    d.assign(rows, Vec2::Zero());
    p[0] = Vec2(-0.5 * sigma, 0);
    for (int k = 0; k + 1 < rows; ++k) {
        p[k + 1] = p[k] + sigma * Vec2(std::cos(k * psi), std::sin(k * psi));
        d[k + 1] = d[k] + sigma * k * Vec2(-std::sin(k * psi), std::cos(k * psi));
    }
}

}  // namespace

KesCurveResult kes_bending_test(const kes::FabricData& fabric, Direction dir, const BendingTestOptions& options)
{
    if (!(options.sigma > 0) || !(options.gap > 0) || !(options.width > 0))
        throw InputError("kes bending", "sigma", "expected positive spacing, gap and width");
    if (!(options.step > 0) || !(options.max_curvature >= kes::instrument::kBendingSlopeTo))
        throw InputError("kes bending", "max_curvature", "expected a positive step and a range covering the B window");
    Layout layout;
    layout.direction = dir;
    const int free_span = std::max(3, static_cast<int>(std::lround(options.gap / options.sigma)));  // N - 1
    layout.n_along = free_span + 2;
    layout.sigma = options.gap / free_span;
    layout.n_across = std::max(2, static_cast<int>(std::lround(options.width / layout.sigma)) + 1);
    const double width = (layout.n_across - 1) * layout.sigma;
    model::ClothModel model = instrument_model(fabric, layout.grid(), options.model, /*gravity=*/false);
    const double newton_per_gf = units::newton_per_gram_force(options.model.gram_force);

    std::vector<char> fixed(layout.grid().size(), 0);
    const int N = layout.n_along - 1;
    for (int b = 0; b < layout.n_across; ++b)
        for (int a : {0, 1, N - 1, N}) fixed[layout.index(a, b)] = 1;

    KesCurveResult r;
    r.test = "bending";
    r.direction = dir;
    r.sigma = layout.sigma;
    // The B window and the comparison, as far as the input curve reaches (input_B's data_slope
    // stops there too).
    const kes::Curve& input = input_bending(fabric, dir);
    const double slope_to = std::min(kes::instrument::kBendingSlopeTo, input.x.back());
    if (!(slope_to > kes::instrument::kBendingSlopeFrom))
        throw InputError("kes bending", "bending", "expected the bending curve to reach beyond 0.5 1/cm");
    r.compare_from = kes::instrument::kBendingSlopeFrom;
    r.compare_to = std::min(options.max_curvature, input.x.back());

    const int steps = static_cast<int>(std::lround(options.max_curvature / options.step));
    // FRICTION with a width given: the full loop, the friction state updated after each step.
    const model::SlipLaw& law = dir == Direction::WARP ? model.slip_laws().warp : model.slip_laws().weft;
    const bool loop = law.active();
    const std::vector<double> path = loop_path(options.max_curvature, steps);
    const std::size_t points = loop ? path.size() : static_cast<std::size_t>(steps + 1);
    Positions x(layout.grid().size());
    std::vector<Vec2> rows, drows;
    for (std::size_t k = 0; k < points; ++k) {
        const double K = path[k];               // 1/cm
        const double K_m = K * units::kMToCm;   // 1/m
        const double psi = 2.0 * std::asin(std::clamp(0.5 * K_m * layout.sigma, -1.0, 1.0));
        bent_rows(layout.n_along, layout.sigma, psi, rows, drows);
        for (int a = 0; a < layout.n_along; ++a)
            for (int b = 0; b < layout.n_across; ++b)
                x[layout.index(a, b)] = Vec3(rows[a].x(), b * layout.sigma - 0.5 * width, rows[a].y());
        const StaticResult eq = solve_static(model, x, fixed, options.solve);
        if (!eq.converged) throw RuntimeError("kes bending: the static solve did not converge at K = " + std::to_string(K) + " 1/cm");
        r.iterations += eq.iterations;
        // dE/dalpha = sum over the turning clamp's particles of dE/dx . dx/dalpha,
        // alpha = (N - 1) psi.
        const Eigen::VectorXd g = model.gradient(eq.x);
        double dE_dpsi = 0;
        for (int a : {N - 1, N})
            for (int b = 0; b < layout.n_across; ++b) {
                const int p = layout.index(a, b);
                dE_dpsi += g[3 * p] * drows[a].x() + g[3 * p + 2] * drows[a].y();
            }
        const double dE_dalpha = dE_dpsi / (N - 1);
        const double M = dE_dalpha / width / newton_per_gf;  // N m / m = N -> gf (gf.cm/cm)
        if (loop) {
            model.update_slip(eq.x);
            r.loop_x.push_back(K);
            r.loop_y.push_back(M);
        }
        if (k <= static_cast<std::size_t>(steps)) {
            r.x.push_back(K);
            r.y.push_back(M);
            r.y_input.push_back(curve_value(input, K));
        }
    }
    finish_kes_result(r, input_B(fabric, dir), kes::instrument::kBendingSlopeFrom, slope_to);
    if (loop) {
        const kes::BendingSummary& summary = *(dir == Direction::WARP ? fabric.bending_warp.summary : fabric.bending_weft.summary);
        finish_loop(r, summary.B, law, kes::kBendingRise, steps, kes::instrument::kBendingSlopeFrom, slope_to, 1.0, 0.0, summary.two_HB, 0.0);
    }
    return r;
}

}  // namespace woven::testers
