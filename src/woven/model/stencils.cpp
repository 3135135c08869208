#include "woven/model/stencils.hpp"

#include <algorithm>
#include <cassert>

namespace woven::model {

namespace {

template <class List> void add_couplings(const List& list, std::vector<std::vector<int>>& rows)
{
    for (const auto& s : list)
        for (int p : s)
            for (int q : s) rows[p].push_back(q);
}

}  // namespace

bool Stencils::coupled(int p, int q) const
{
    const std::span<const int> row = coupled_with(p);
    return std::binary_search(row.begin(), row.end(), q);
}

Stencils make_stencils(const Grid& grid, std::vector<char> active, Discretization d, bool slip, bool twist)
{
    const int n = grid.size();
    if (active.empty()) active.assign(n, 1);
    assert(static_cast<int>(active.size()) == n);
    Stencils s;
    s.active = std::move(active);
    auto on = [&](int i, int j) { return i >= 0 && j >= 0 && i < grid.nu && j < grid.nv && s.active[grid.index(i, j)]; };
    for (int j = 0; j < grid.nv; ++j)
        for (int i = 0; i < grid.nu; ++i) {
            if (!on(i, j)) continue;
            const int p = grid.index(i, j);
            s.particles.push_back(p);
            if (on(i + 1, j)) s.edges.push_back({p, grid.index(i + 1, j)});
            if (on(i, j + 1)) s.edges.push_back({p, grid.index(i, j + 1)});
        }
    for (int j = 0; j < grid.nv; ++j)
        for (int i = 0; i < grid.nu; ++i) {
            if (on(i, j - 1) && on(i, j) && on(i, j + 1)) s.warp_bends.push_back({grid.index(i, j - 1), grid.index(i, j), grid.index(i, j + 1)});
            if (on(i - 1, j) && on(i, j) && on(i + 1, j)) s.weft_bends.push_back({grid.index(i - 1, j), grid.index(i, j), grid.index(i + 1, j)});
        }
    // Weights (Discretization). A grid cell (i, j)-(i+1, j+1) is cloth when its four corners are.
    auto cell = [&](int i, int j) { return on(i, j) && on(i + 1, j) && on(i, j + 1) && on(i + 1, j + 1) ? 1.0 : 0.0; };
    bool any_cell = false;
    for (int j = 0; j + 1 < grid.nv && !any_cell; ++j)
        for (int i = 0; i + 1 < grid.nu && !any_cell; ++i) any_cell = cell(i, j) > 0;
    // A grid without a single cell (one particle, one thread) has no area to share out: it
    // keeps the paper's convention.
    const bool convergent = d == Discretization::CONVERGENT && any_cell;
    auto dual_area = [&](int i, int j) {  // in sigma^2: a quarter of each cloth cell around (i, j)
        return 0.25 * (cell(i - 1, j - 1) + cell(i, j - 1) + cell(i - 1, j) + cell(i, j));
    };
    auto weight = [&](int i, int j) { return convergent ? std::max(dual_area(i, j), 0.25) : 1.0; };

    // Trellis: the crossing at (i, j) needs its four neighbours, and (i, j) itself (the
    // crossing is a particle of the cloth, even though the angle does not depend on it).
    // CONVERGENT: a missing neighbour is replaced by (i, j) itself (a one-sided crossing angle).
    for (int j = 0; j < grid.nv; ++j)
        for (int i = 0; i < grid.nu; ++i) {
            if (!on(i, j)) continue;
            const int p = grid.index(i, j);
            if (on(i - 1, j) && on(i + 1, j) && on(i, j - 1) && on(i, j + 1)) {
                s.crossings.push_back({grid.index(i - 1, j), grid.index(i + 1, j), grid.index(i, j - 1), grid.index(i, j + 1)});
                s.crossing_weights.push_back(weight(i, j));
            } else if (convergent && (on(i - 1, j) || on(i + 1, j)) && (on(i, j - 1) || on(i, j + 1))) {
                s.crossings.push_back({on(i - 1, j) ? grid.index(i - 1, j) : p, on(i + 1, j) ? grid.index(i + 1, j) : p,
                                       on(i, j - 1) ? grid.index(i, j - 1) : p, on(i, j + 1) ? grid.index(i, j + 1) : p});
                s.crossing_weights.push_back(weight(i, j));
            }
        }
    s.particle_areas.assign(n, 0.0);
    for (int p : s.particles) s.particle_areas[p] = convergent ? dual_area(p % grid.nu, p / grid.nu) : 1.0;
    for (const Stencil<2>& e : s.edges) {
        double w = 1.0;
        if (convergent) {
            // The cloth cells on the two sides of the segment, each half a spacing wide.
            const int i = e[0] % grid.nu, j = e[0] / grid.nu;
            const bool along_i = e[1] == e[0] + 1;
            w = along_i ? 0.5 * (cell(i, j - 1) + cell(i, j)) : 0.5 * (cell(i - 1, j) + cell(i, j));
            if (w == 0) w = 0.5;  // a thread with no cloth beside it: half a width
        }
        s.edge_weights.push_back(w);
    }
    if (slip) {
        auto across = [&](const Stencil<3>& b, int di, int dj) -> Stencil<5> {
            const int i = b[1] % grid.nu, j = b[1] / grid.nu;
            return {b[0], b[1], b[2], on(i - di, j - dj) ? grid.index(i - di, j - dj) : b[1], on(i + di, j + dj) ? grid.index(i + di, j + dj) : b[1]};
        };
        for (const Stencil<3>& b : s.warp_bends) s.warp_slip_bends.push_back(across(b, 1, 0));
        for (const Stencil<3>& b : s.weft_bends) s.weft_slip_bends.push_back(across(b, 0, 1));
    }
    if (twist)
        for (int j = 0; j + 1 < grid.nv; ++j)
            for (int i = 0; i + 1 < grid.nu; ++i)
                if (cell(i, j) > 0) s.cells.push_back({grid.index(i, j), grid.index(i + 1, j), grid.index(i, j + 1), grid.index(i + 1, j + 1)});
    for (const Stencil<3>& b : s.warp_bends) s.warp_weights.push_back(weight(b[1] % grid.nu, b[1] / grid.nu));
    for (const Stencil<3>& b : s.weft_bends) s.weft_weights.push_back(weight(b[1] % grid.nu, b[1] / grid.nu));

    std::vector<std::vector<int>> rows(n);
    for (int p = 0; p < n; ++p) rows[p].push_back(p);
    add_couplings(s.edges, rows);
    add_couplings(s.warp_bends, rows);
    add_couplings(s.weft_bends, rows);
    add_couplings(s.crossings, rows);
    add_couplings(s.warp_slip_bends, rows);
    add_couplings(s.weft_slip_bends, rows);
    add_couplings(s.cells, rows);
    s.coupled_begin_.assign(n + 1, 0);
    for (int p = 0; p < n; ++p) {
        std::sort(rows[p].begin(), rows[p].end());
        rows[p].erase(std::unique(rows[p].begin(), rows[p].end()), rows[p].end());
        s.coupled_begin_[p + 1] = s.coupled_begin_[p] + static_cast<int>(rows[p].size());
    }
    s.coupled_.reserve(s.coupled_begin_[n]);
    for (const auto& row : rows) s.coupled_.insert(s.coupled_.end(), row.begin(), row.end());
    return s;
}

}  // namespace woven::model
