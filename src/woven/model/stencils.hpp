#pragma once
// Which particles each term of Eq. (1) touches, defined once for the model, the assembly and
// both solvers (grid convention: grid.hpp):
//
//   edge, stretching (Eq. 3, 5):        (i,j) ---- (i+1,j)        (i,j)
//                                                                   |
//                                                                 (i,j+1)
//   warp bend (Eq. 7, 12, warp curve):  (i,j-1) ---- (i,j) ---- (i,j+1)     middle second
//   weft bend (weft curve):             (i-1,j) ---- (i,j) ---- (i+1,j)     middle second
//   crossing, trellising (Eq. 8, 15):            U = (i,j+1)
//                                                 |
//                                 L = (i-1,j) -- (i,j) -- R = (i+1,j)      order L R D U;
//                                                 |                        (i,j) not in it
//                                                D = (i,j-1)
//   cell, twisting (beyond the paper):           (i,j+1) -- (i+1,j+1)
//                                                  |            |        order (i,j) (i+1,j)
//                                                (i,j) ---- (i+1,j)      (i,j+1) (i+1,j+1)
//   repulsion (Eq. 2, 4): pairs closer than sigma, found at run time (ClothModel::close_pairs)
//   gravity (Eq. 6): every active particle
//
// An optional per-particle "active" mask cuts the cloth to an outline: a term exists only where
// its whole stencil is active; inactive particles are not part of the cloth.
#include <array>
#include <span>
#include <utility>
#include <vector>

#include "woven/common/choice.hpp"
#include "woven/model/grid.hpp"

namespace woven::model {

/// How the grid stands for the continuous cloth (ModelOptions::discretization).
///   PAPER: the paper's literal convention: every particle a full sigma x sigma patch (mass
///     W sigma^2, edges and corners too), every term at full weight, trellis only at crossings
///     with four neighbours. A free edge then carries half a spacing too much cloth.
///   CONVERGENT: each particle stands for its dual cell, the part of the cloth nearer to it
///     than to any other particle (the quarter cells of the grid cells around it that belong to
///     the cloth): mass W x its area, so the cloth weighs W x its area; every term is weighted
///     by the share of cloth it stands for (a bend or crossing: its dual cell's area over
///     sigma^2, 1/2 on an edge, 1/4 at a corner; a thread segment: the cells on its two
///     sides over 2); the crossings of edge particles are measured one-sidedly (the missing
///     neighbour replaced by the particle itself). The discrete energy is then a
///     second-order quadrature of the continuum's (docs/VALIDATION.md).
enum class Discretization { PAPER, CONVERGENT };
/// The discretizations' names: "convergent", "paper" (scene files, the command line, reports).
inline constexpr std::array<Named<Discretization>, 2> kDiscretizationNames{{{Discretization::CONVERGENT, "convergent"},
                                                                            {Discretization::PAPER, "paper"}}};
/// Its name in kDiscretizationNames.
inline const char* to_string(Discretization d) { return name_of(kDiscretizationNames, d); }

/// The particle indices of one term's stencil, in the order of the sketches above.
template <int N> using Stencil = std::array<int, N>;

/// The stencil lists of a grid, each in grid order (j outer, i inner).
struct Stencils {
    std::vector<char> active;            ///< one per grid particle: part of the cloth
    std::vector<int> particles;          ///< the active particles, ascending (gravity)
    std::vector<Stencil<2>> edges;       ///< 4-connected pairs (stretching)
    std::vector<Stencil<3>> warp_bends;  ///< (i,j-1), (i,j), (i,j+1)
    std::vector<Stencil<3>> weft_bends;  ///< (i-1,j), (i,j), (i+1,j)
    std::vector<Stencil<4>> crossings;   ///< L, R, D, U around (i,j)
    /// With twist (make_stencils' `twist`), the grid cells whose four corners are cloth, each of
    /// weight 1 (a whole sigma x sigma cell).
    std::vector<Stencil<4>> cells;
    /// With slip (make_stencils' `slip`), one per warp (weft) bend, in its order: the bend's
    /// three particles and the two across the thread at its middle, (i-1,j), (i+1,j) for a
    /// warp bend, (i,j-1), (i,j+1) for a weft bend (a missing one replaced by the middle
    /// particle; both missing: the middle twice, a bend without friction). slip.hpp.
    std::vector<Stencil<5>> warp_slip_bends, weft_slip_bends;
    /// The share of cloth each stencil stands for (its term's weight), one per stencil of the
    /// list of the same name, and each particle's area in units of sigma^2: all 1 for PAPER
    /// (see Discretization).
    std::vector<double> edge_weights, warp_weights, weft_weights, crossing_weights, particle_areas;

    /// The particles sharing a stencil with p, p itself included, ascending (the sparsity of
    /// the Hessian, one row of blocks per particle; an inactive particle is coupled to itself).
    std::span<const int> coupled_with(int p) const
    {
        return {coupled_.data() + coupled_begin_[p], coupled_.data() + coupled_begin_[p + 1]};
    }
    /// Whether p and q share a stencil (or p == q).
    bool coupled(int p, int q) const;

    std::vector<int> coupled_begin_, coupled_;  ///< compressed rows of coupled_with
};

/// The stencil lists of `grid`; `active` (one entry per particle, or empty: all active) is the
/// mask. PAPER: a term exists only where its whole stencil is active. CONVERGENT: the same
/// edges and bends, and a crossing at every active particle with an active neighbour along
/// each thread (one-sided where one is missing); weights as Discretization says.
/// `slip`: also the five-particle bends of the friction elements (slip.hpp), coupled in the
/// pattern; `twist`: also the cells (TwistTerm).
Stencils make_stencils(const Grid& grid, std::vector<char> active = {}, Discretization d = Discretization::PAPER, bool slip = false,
    bool twist = false);

/// For each particle, the stencils of one list that contain it and its place (role) in each.
struct Incidence {
    struct Entry {
        int stencil;  ///< index into the list
        int role;     ///< the particle's position in that stencil
    };
    std::vector<int> begin;  ///< entries of particle p: [begin[p], begin[p + 1])
    std::vector<Entry> entries;
    std::span<const Entry> of(int p) const { return {entries.data() + begin[p], entries.data() + begin[p + 1]}; }
};

/// The incidence of a stencil list over `particles` particles (entries in list order).
template <class List> Incidence make_incidence(const List& stencils, int particles)
{
    constexpr int N = static_cast<int>(std::tuple_size_v<typename List::value_type>);
    Incidence inc;
    inc.begin.assign(particles + 1, 0);
    for (const auto& s : stencils)
        for (int p : s) ++inc.begin[p + 1];
    for (int p = 0; p < particles; ++p) inc.begin[p + 1] += inc.begin[p];
    inc.entries.resize(inc.begin[particles]);
    std::vector<int> fill(inc.begin.begin(), inc.begin.end() - 1);
    for (int k = 0; k < static_cast<int>(stencils.size()); ++k)
        for (int r = 0; r < N; ++r) inc.entries[fill[stencils[k][r]]++] = {k, r};
    return inc;
}

}  // namespace woven::model
