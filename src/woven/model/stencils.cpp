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

Stencils make_stencils(const Grid& grid, std::vector<char> active)
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
    // Trellis: the crossing at (i, j) needs its four neighbours, and (i, j) itself (the
    // crossing is a particle of the cloth, even though the angle does not depend on it).
    for (int j = 0; j < grid.nv; ++j)
        for (int i = 0; i < grid.nu; ++i)
            if (on(i, j) && on(i - 1, j) && on(i + 1, j) && on(i, j - 1) && on(i, j + 1))
                s.crossings.push_back({grid.index(i - 1, j), grid.index(i + 1, j), grid.index(i, j - 1), grid.index(i, j + 1)});

    std::vector<std::vector<int>> rows(n);
    for (int p = 0; p < n; ++p) rows[p].push_back(p);
    add_couplings(s.edges, rows);
    add_couplings(s.warp_bends, rows);
    add_couplings(s.weft_bends, rows);
    add_couplings(s.crossings, rows);
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
