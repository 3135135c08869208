#include "woven/testers/elastica.hpp"

#include <array>
#include <cmath>
#include <numbers>

#include "woven/common/error.hpp"

namespace woven::testers {

namespace {

/// State along the strip: theta, M, x, z.
using State = std::array<double, 4>;

State derivative(const State& y, double s, double L, double w, const CurvatureOfMoment& K)
{
    return {K(y[1]), -w * (L - s) * std::cos(y[0]), std::cos(y[0]), -std::sin(y[0])};
}

/// Integrates from the clamp with M(0) = M0; returns the end state, optionally the shape.
State integrate(double M0, double L, double w, const CurvatureOfMoment& K, int steps, ElasticaSolution* shape)
{
    State y{0.0, M0, 0.0, 0.0};
    const double h = L / steps;
    if (shape) {
        shape->s.assign(1, 0.0);
        shape->x.assign(1, 0.0);
        shape->z.assign(1, 0.0);
        shape->theta.assign(1, 0.0);
    }
    for (int k = 0; k < steps; ++k) {
        const double s = k * h;
        auto add = [](const State& a, const State& b, double f) {
            return State{a[0] + f * b[0], a[1] + f * b[1], a[2] + f * b[2], a[3] + f * b[3]};
        };
        const State k1 = derivative(y, s, L, w, K);
        const State k2 = derivative(add(y, k1, h / 2), s + h / 2, L, w, K);
        const State k3 = derivative(add(y, k2, h / 2), s + h / 2, L, w, K);
        const State k4 = derivative(add(y, k3, h), s + h, L, w, K);
        for (int c = 0; c < 4; ++c) y[c] += h / 6 * (k1[c] + 2 * k2[c] + 2 * k3[c] + k4[c]);
        if (shape) {
            shape->s.push_back(s + h);
            shape->theta.push_back(y[0]);
            shape->x.push_back(y[2]);
            shape->z.push_back(y[3]);
        }
    }
    return y;
}

}  // namespace

ElasticaSolution cantilever_elastica(double length, double w, const CurvatureOfMoment& curvature, int steps)
{
    if (!(length > 0) || !std::isfinite(length)) throw InputError("elastica", "length", "expected a positive overhang in m");
    if (!(w > 0) || !std::isfinite(w)) throw InputError("elastica", "load", "expected a positive weight per unit area in N/m^2");
    if (steps < 10) throw InputError("elastica", "steps", "expected at least 10 integration steps");
    // M(L) increases with M(0); M(0) lies in [0, w L^2 / 2] (the moment of the strip's weight
    // about the clamp is at most that of the straight strip).
    double lo = 0.0, hi = 0.5 * w * length * length;
    for (int it = 0; it < 200 && hi - lo > 1e-15 * hi; ++it) {
        const double mid = 0.5 * (lo + hi);
        (integrate(mid, length, w, curvature, steps, nullptr)[1] > 0 ? hi : lo) = mid;
    }
    ElasticaSolution sol;
    sol.length = length;
    sol.root_moment = 0.5 * (lo + hi);
    const State end = integrate(sol.root_moment, length, w, curvature, steps, &sol);
    sol.tip_x = end[2];
    sol.tip_drop = -end[3];
    sol.chord_angle = std::atan2(sol.tip_drop, sol.tip_x);
    return sol;
}

ElasticaSolution cantilever_elastica_linear(double length, double w, double EI, int steps)
{
    if (!(EI > 0) || !std::isfinite(EI)) throw InputError("elastica", "EI", "expected a positive flexural rigidity in N m");
    return cantilever_elastica(
        length, w, [EI](double M) { return M / EI; }, steps);
}

double elastica_overhang_for_chord_angle(double chord_angle, double w, const CurvatureOfMoment& curvature)
{
    if (!(chord_angle > 0 && chord_angle < std::numbers::pi / 2))
        throw InputError("elastica", "chord_angle", "expected an angle in (0, pi/2) rad");
    constexpr int kSteps = 1000;
    // Bracket: the chord angle grows with the overhang.
    double lo = 1e-4, hi = 1e-3;
    while (cantilever_elastica(hi, w, curvature, kSteps).chord_angle < chord_angle) {
        lo = hi;
        hi *= 2;
        if (hi > 1e3) throw RuntimeError("elastica: no overhang below 1 km reaches the chord angle");
    }
    for (int it = 0; it < 100 && hi - lo > 1e-12 * hi; ++it) {
        const double mid = 0.5 * (lo + hi);
        (cantilever_elastica(mid, w, curvature, kSteps).chord_angle < chord_angle ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

double overhang_ratio_for_chord_angle(double chord_angle)
{
    // Dimensionless: w = 1, EI = 1, so c = 1 and the overhang is L/c.
    return elastica_overhang_for_chord_angle(chord_angle, 1.0, [](double M) { return M; });
}

}  // namespace woven::testers
