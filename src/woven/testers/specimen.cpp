#include "woven/testers/specimen.hpp"

#include <cmath>

#include "woven/common/error.hpp"

namespace woven::testers {

std::string to_string(Direction d) { return d == Direction::WARP ? "warp" : "weft"; }

model::Grid Layout::grid() const
{
    model::Grid g;
    g.nu = direction == Direction::WARP ? n_across : n_along;
    g.nv = direction == Direction::WARP ? n_along : n_across;
    g.sigma = sigma;
    return g;
}

int Layout::index(int a, int b) const { return direction == Direction::WARP ? b + n_across * a : a + n_along * b; }

double inverse_value(const kes::CurveFit& fit, double y)
{
    if (y < 0) return -inverse_value(fit, -y);
    if (y == 0) return 0;
    for (const kes::Segment& s : fit.segments()) {
        const bool last = &s == &fit.segments().back();
        if (!last && s.value(s.x_end) < y) continue;
        // c2 x^2 + c1 x + c0 = y on this segment, the root where the slope is positive.
        const double r = y - s.c0;
        if (s.c2 == 0) return r / s.c1;
        const double disc = s.c1 * s.c1 + 4.0 * s.c2 * r;
        return 2.0 * r / (s.c1 + std::sqrt(std::max(disc, 0.0)));
    }
    return 0;  // unreachable: the last segment is the line
}

kes::CurveFit fitted_bending(const kes::FabricData& fabric, Direction d)
{
    const std::string field = d == Direction::WARP ? "bending.warp" : "bending.weft";
    return kes::fit_first_stage(input_bending(fabric, d), kes::bending_fit_options(), "fabric '" + fabric.name + "': " + field);
}

kes::CurveFit fitted_shear(const kes::FabricData& fabric)
{
    return kes::fit_first_stage(fabric.shear.curve, kes::shear_fit_options(), "fabric '" + fabric.name + "': shear");
}

const kes::Curve& input_bending(const kes::FabricData& fabric, Direction d)
{
    return d == Direction::WARP ? fabric.bending_warp.curve : fabric.bending_weft.curve;
}

double input_B(const kes::FabricData& fabric, Direction d)
{
    const auto& m = d == Direction::WARP ? fabric.bending_warp : fabric.bending_weft;
    if (m.summary) return m.summary->B;
    return kes::data_slope(m.curve, kes::instrument::kBendingSlopeFrom, kes::instrument::kBendingSlopeTo);
}

double input_G(const kes::FabricData& fabric)
{
    if (fabric.shear.summary) return fabric.shear.summary->G;
    return kes::data_slope(fabric.shear.curve, kes::instrument::kShearSlopeFrom, kes::instrument::kShearSlopeTo);
}

double curve_value(const kes::Curve& c, double x)
{
    if (x <= c.x.front()) return c.y.front();
    for (std::size_t k = 1; k < c.x.size(); ++k)
        if (x <= c.x[k]) return c.y[k - 1] + (x - c.x[k - 1]) / (c.x[k] - c.x[k - 1]) * (c.y[k] - c.y[k - 1]);
    return c.y.back();
}

double window_slope(const std::vector<double>& x, const std::vector<double>& y, double lo, double hi)
{
    if (x.size() < 2 || x.size() != y.size() || x.front() > lo || x.back() < hi)
        throw InputError("window_slope", "x", "needs samples covering the window");
    kes::Curve c{x, y};
    return kes::data_slope(c, lo, hi);
}

}  // namespace woven::testers
