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
//   repulsion (Eq. 2, 4): pairs closer than sigma, found at run time (ClothModel::close_pairs)
//   gravity (Eq. 6): every active particle
//
// An optional per-particle "active" mask cuts the cloth to an outline: a term exists only where
// its whole stencil is active; inactive particles are not part of the cloth.
#include <array>
#include <span>
#include <utility>
#include <vector>

#include "woven/model/grid.hpp"

namespace woven::model {

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

/// The stencil lists of `grid`; `active` (one entry per particle, or empty: all active) is the mask.
Stencils make_stencils(const Grid& grid, std::vector<char> active = {});

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
