#pragma once
// Backtracking line search (Armijo), a free function as TinyAD's Utils/LineSearch.hh.
#include <cmath>

#include "woven/sim/drape.hpp"

namespace woven::sim {

struct LineSearchResult {
    bool accepted = false;
    double fraction = 0;  ///< the accepted step fraction alpha
    double value = 0;     ///< the objective there
};

/// Tries alpha = alpha_max, alpha_max shrink, ... until phi(alpha) <= phi0 + armijo alpha slope
/// (slope: the directional derivative at alpha = 0, < 0 for a descent direction). `phi(alpha)`
/// evaluates the objective at x + alpha d, +inf where it is singular (always rejected); the
/// accepted trial is the last one evaluated, so a caller that keeps its trial state has it.
///
/// Near a minimum the decrease a Newton step promises, alpha |slope| / 2, falls below the
/// round-off of phi itself (a sum of many terms, |phi0| LineSearchOptions::roundoff): Armijo's
/// test then compares noise and accepted ever smaller steps (the 51 x 51 cube's final static
/// solve sat at a residual of 9e-4 m g for 100 iterations, alpha 1e-9). There the first finite
/// trial within the round-off band of phi0 is accepted: the full step of a Newton iteration
/// (a step that promises more is held to Armijo at every fraction).
template <class Phi> LineSearchResult line_search(Phi&& phi, double phi0, double slope, double alpha_max, const LineSearchOptions& o = {})
{
    const double noise = o.roundoff * std::abs(phi0);
    const bool below_roundoff = -alpha_max * slope <= noise;  // the whole step promises less than noise
    double alpha = alpha_max;
    for (int trial = 0; trial < o.max_trials && alpha > o.min_fraction; ++trial, alpha *= o.shrink) {
        const double value = phi(alpha);
        if (value <= phi0 + o.armijo * alpha * slope) return {true, alpha, value};
        if (below_roundoff && value <= phi0 + noise) return {true, alpha, value};
    }
    return {};
}

}  // namespace woven::sim
