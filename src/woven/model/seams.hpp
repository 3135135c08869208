#pragma once
// Seams: edges of pattern pieces sewn together (docs/GARMENT-FORMAT.md). A seam joins two cut
// edges along their outline, by arc length. The particles of a cut edge lie inside the outline
// (up to a spacing from it); each one's point on the outline, P(p), is extrapolated along the
// threads from it and its inward thread neighbours, a linear combination of three particles
// (exact for an unstrained cloth):
//
//     P(p) = x_p + a (x_p - x_pu) + b (x_p - x_pv)     a, b in [0, 1): the outline's offset
//                                                       from p along the weft and the warp, in sigma
// Each stitch holds the outline point of a particle p of one edge to the point of the other
// edge at the same fraction of its length, between the outline points of two consecutive
// particles q1, q2 of that edge at fraction w (the edges may carry different numbers of
// particles):
//
//     edge A   ... o-------P(p)-------o ...            gap d = P(p) - ((1 - w) P(q1) + w P(q2))
//                           |                          E = k |d|^2 / 2          (J, k in N/m)
//     edge B   ...  o---P(q1)--*------P(q2)---o ...    (* the point at p's fraction)
//
// d = sum_i c_i x_i over nine particles (three per outline point; a missing neighbour has
// c = 0). The energy is quadratic in the positions: its Hessian k c c^T (x) I is constant and
// positive semi-definite (projected = exact). The stiffness k is ramped up by the caller
// (ClothModel::set_seam_stiffness) over successive drapes and then held.
#include <array>
#include <vector>

#include "woven/common/types.hpp"
#include "woven/model/stencils.hpp"
#include "woven/model/terms.hpp"

namespace woven::model {

/// One stitch: P(p) held to (1 - w) P(q1) + w P(q2) (beyond an edge's end, w < 0 or > 1: the
/// end particles' line extended).
struct Stitch {
    int p = 0, q1 = 0, q2 = 0;
    double w = 0;  ///< in [0, 1] but at an edge's ends
    int seam = 0;  ///< which seam of the garment it belongs to (reports)
    /// The gap d = sum_i c[i] x[ids[i]]: P(p)'s three particles, then P(q1)'s and P(q2)'s.
    Stencil<9> ids{};
    std::array<double, 9> c{};
};

/// The seams of a cloth: its stitches and the particle pairs the repulsion leaves out (two
/// edges sewn together lie on each other: their particles closer than sigma are not pressed
/// apart).
struct SeamSet {
    std::vector<Stitch> stitches;
    std::vector<Stencil<2>> unrepelled;  ///< pairs (a < b), ascending
    bool empty() const { return stitches.empty(); }
};

/// The energy of one stitch (see the sketch), on its nine particles Stitch::ids.
class SeamTerm : public TermFunctions<SeamTerm, 9> {
public:
    /// `stiffness` k in N/m (>= 0), `c` the stitch's coefficients.
    SeamTerm(double stiffness, const std::array<double, 9>& c) : k_(stiffness), c_(c) {}
    Local<9> evaluate(const VecN<27>& x, Derivatives what) const;
    /// The gap vector d = sum_i c_i x_i (m).
    static Vec3 gap(const VecN<27>& x, const std::array<double, 9>& c)
    {
        Vec3 d = Vec3::Zero();
        for (int i = 0; i < 9; ++i) d += c[i] * x.segment<3>(3 * i);
        return d;
    }

private:
    double k_;
    std::array<double, 9> c_;
};

/// The gap |d| of each stitch at x (m), in the stitches' order.
std::vector<double> stitch_gaps(const SeamSet& seams, const Positions& x);

/// `stencils` with each stitch's three particles coupled (the Hessian's sparsity pattern,
/// Stencils::coupled_with), so that a Newton solve sees the seams whole.
void couple_stitches(Stencils& stencils, const std::vector<Stitch>& stitches);

}  // namespace woven::model
