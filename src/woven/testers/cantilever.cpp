#include "woven/testers/cantilever.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "woven/common/error.hpp"
#include "woven/common/units.hpp"

namespace woven::testers {

double weight_per_area(const kes::FabricData& fabric, double gravity)
{
    return fabric.areal_density_mg_cm2 * units::kMgPerCm2ToKgPerM2 * gravity;
}

CurvatureOfMoment fabric_curvature_law(const kes::FabricData& fabric, Direction d, model::BendingForm form, units::GramForce gf)
{
    const kes::CurveFit fit = fitted_bending(fabric, d);
    const double newton_per_gf = units::newton_per_gram_force(gf);  // M: gf.cm/cm = gf -> N m/m = N
    if (form == model::BendingForm::WORK)
        return [fit, newton_per_gf](double M) { return inverse_value(fit, M / newton_per_gf) * units::kMToCm; };
    // Secant energy M K / 2: its derivative (M + K M') / 2 is the moment the model carries.
    return [fit, newton_per_gf](double M) {
        const double target = std::abs(M) / newton_per_gf;
        auto moment = [&](double K) { return 0.5 * (fit.value(K) + K * fit.slope(K)); };
        double lo = 0, hi = std::max(1e-6, inverse_value(fit, target));
        while (moment(hi) < target) hi *= 2;
        for (int it = 0; it < 200 && hi - lo > 1e-15 * hi; ++it) {
            const double mid = 0.5 * (lo + hi);
            (moment(mid) < target ? lo : hi) = mid;
        }
        const double K = 0.5 * (lo + hi) * units::kMToCm;
        return M < 0 ? -K : K;
    };
}

double bending_length_from_chord(double overhang, double chord_angle) { return overhang / overhang_ratio_for_chord_angle(chord_angle); }

namespace {

/// Places the strip on an elastica-like start: row a at arc length (a - 1/2) sigma from the
/// clamp line, on the curve (s, z(s)) given by `shape`; the pinned rows 0 and 1 horizontal.
Positions start_positions(const Layout& layout, const ElasticaSolution& shape)
{
    Positions x(layout.grid().size());
    const double width = (layout.n_across - 1) * layout.sigma;
    for (int a = 0; a < layout.n_along; ++a) {
        const double s = (a - 0.5) * layout.sigma;
        double px = s, pz = 0;
        if (a >= 2 && !shape.s.empty()) {
            const double t = std::min(s, shape.s.back());
            auto it = std::upper_bound(shape.s.begin(), shape.s.end(), t);
            const size_t k = std::clamp<size_t>(static_cast<size_t>(it - shape.s.begin()), 1, shape.s.size() - 1);
            const double f = (t - shape.s[k - 1]) / (shape.s[k] - shape.s[k - 1]);
            px = shape.x[k - 1] + f * (shape.x[k] - shape.x[k - 1]);
            pz = shape.z[k - 1] + f * (shape.z[k] - shape.z[k - 1]);
        }
        for (int b = 0; b < layout.n_across; ++b) x[layout.index(a, b)] = Vec3(px, b * layout.sigma - 0.5 * width, pz);
    }
    return x;
}

}  // namespace

CantileverShape cantilever_with_rows(const kes::FabricData& fabric, Direction d, double overhang, int rows,
                                     const CantileverOptions& options)
{
    if (!(overhang > 0)) throw InputError("cantilever", "overhang", "expected a positive overhang in m");
    if (rows < 2) throw InputError("cantilever", "rows", "expected at least 2 rows beyond the clamp");
    Layout layout;
    layout.direction = d;
    layout.n_along = rows + 1;
    layout.sigma = overhang / (rows - 0.5);
    layout.n_across = std::max(2, static_cast<int>(std::lround(options.width / layout.sigma)) + 1);
    const model::Grid grid = layout.grid();
    model::ModelOptions mo = options.model;
    if (!(mo.gravity > 0)) mo.gravity = units::kStandardGravity;
    const model::ClothModel model = model::make_cloth_model(fabric, grid, mo);

    // Start on the exact elastica of the same overhang (the equilibrium is close to it).
    const double w = weight_per_area(fabric, mo.gravity);
    const ElasticaSolution guess = cantilever_elastica(overhang, w, fabric_curvature_law(fabric, d, mo.bending_form, mo.gram_force), 400);
    const Positions x0 = start_positions(layout, guess);
    std::vector<char> fixed(grid.size(), 0);
    for (int b = 0; b < layout.n_across; ++b) fixed[layout.index(0, b)] = fixed[layout.index(1, b)] = 1;
    const StaticResult eq = solve_static(model, x0, fixed, options.solve);
    if (!eq.converged) {
        char m[160];
        std::snprintf(m, sizeof m,
                      "cantilever: the static solve did not converge (residual %.3g of a particle's weight after %d iterations)",
                      eq.max_residual_rel, eq.iterations);
        throw RuntimeError(m);
    }

    CantileverShape shape;
    shape.overhang = overhang;
    shape.sigma = layout.sigma;
    shape.rows = rows;
    shape.iterations = eq.iterations;
    for (int a = 0; a < layout.n_along; ++a) {
        Vec3 c = Vec3::Zero();
        for (int b = 0; b < layout.n_across; ++b) c += eq.x[layout.index(a, b)];
        c /= layout.n_across;
        shape.x.push_back(c.x());
        shape.z.push_back(c.z());
    }
    // Clamp line: midway between the pinned rows (at the origin by construction).
    const double cx = 0.5 * (shape.x[0] + shape.x[1]), cz = 0.5 * (shape.z[0] + shape.z[1]);
    shape.tip_x = shape.x.back() - cx;
    shape.tip_drop = cz - shape.z.back();
    shape.chord_angle = std::atan2(shape.tip_drop, shape.tip_x);
    return shape;
}

CantileverShape cantilever_at_overhang(const kes::FabricData& fabric, Direction d, double overhang, const CantileverOptions& options)
{
    const int rows = std::max(2, static_cast<int>(std::lround(overhang / options.sigma + 0.5)));
    return cantilever_with_rows(fabric, d, overhang, rows, options);
}

CantileverResult cantilever_test(const kes::FabricData& fabric, Direction d, const CantileverOptions& options)
{
    if (!(options.sigma > 0)) throw InputError("cantilever", "sigma", "expected a positive spacing in m");
    CantileverResult r;
    r.direction = d;
    const double g = options.model.gravity > 0 ? options.model.gravity : units::kStandardGravity;
    const double w = weight_per_area(fabric, g);
    // The exact reference: the elastica of the input curve itself (WORK form, M(K)).
    const CurvatureOfMoment law = fabric_curvature_law(fabric, d, model::BendingForm::WORK, options.model.gram_force);
    r.elastica_overhang = elastica_overhang_for_chord_angle(options.chord_angle, w, law);
    r.elastica = cantilever_elastica(r.elastica_overhang, w, law);
    r.elastica_bending_length = 0.5 * r.elastica_overhang;
    r.elastica_flexural_rigidity = w * std::pow(r.elastica_bending_length, 3);

    // Simulated: fixed row count, secant iteration on the overhang (the spacing follows).
    const int rows = std::max(3, static_cast<int>(std::lround(r.elastica_overhang / options.sigma + 0.5)));
    double L0 = r.elastica_overhang, L1 = 1.02 * r.elastica_overhang;
    CantileverShape s0 = cantilever_with_rows(fabric, d, L0, rows, options);
    CantileverShape s1 = cantilever_with_rows(fabric, d, L1, rows, options);
    r.solves = 2;
    for (int it = 0; it < 30; ++it) {
        const double f0 = s0.chord_angle - options.chord_angle, f1 = s1.chord_angle - options.chord_angle;
        if (std::abs(f1) < 1e-9) break;
        if (f1 == f0) throw RuntimeError("cantilever: the chord angle does not change with the overhang");
        double L2 = L1 - f1 * (L1 - L0) / (f1 - f0);
        L2 = std::clamp(L2, 0.5 * L1, 2.0 * L1);
        L0 = L1;
        s0 = std::move(s1);
        L1 = L2;
        s1 = cantilever_with_rows(fabric, d, L1, rows, options);
        ++r.solves;
    }
    if (std::abs(s1.chord_angle - options.chord_angle) > 1e-6) throw RuntimeError("cantilever: the overhang search did not converge");
    r.shape = std::move(s1);
    r.overhang = r.shape.overhang;
    r.bending_length = 0.5 * r.overhang;
    r.flexural_rigidity = w * std::pow(r.bending_length, 3);
    return r;
}

}  // namespace woven::testers
