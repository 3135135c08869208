#pragma once
// Backtracking line search (Armijo), a free function as TinyAD's Utils/LineSearch.hh.
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
template <class Phi> LineSearchResult line_search(Phi&& phi, double phi0, double slope, double alpha_max, const LineSearchOptions& o = {})
{
    double alpha = alpha_max;
    for (int trial = 0; trial < o.max_trials && alpha > o.min_fraction; ++trial, alpha *= o.shrink) {
        const double value = phi(alpha);
        if (value <= phi0 + o.armijo * alpha * slope) return {true, alpha, value};
    }
    return {};
}

}  // namespace woven::sim
