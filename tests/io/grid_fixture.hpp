#pragma once
// A small cloth grid with per-vertex fields, for the writers' tests (PLY here, glTF in
// tests/render).
#include <vector>

#include "woven/analysis/vertex_fields.hpp"
#include "woven/common/types.hpp"
#include "woven/model/grid.hpp"

namespace woven::test {

inline constexpr int kNu = 4, kNv = 3;

/// A 4 x 3 grid spacing 0.1 m at z = 0.5, with one particle lifted, and two fields.
inline Positions grid()
{
    Positions x = model::flat_grid(model::Grid{kNu, kNv, 0.1}, Vec3(0.2, -0.1, 0.5));
    x[5].z() += 0.03;
    return x;
}

inline std::vector<analysis::VertexField> fields()
{
    analysis::VertexField a{"strain_warp", "1", {}}, b{"contact", "1", {}};
    for (int p = 0; p < kNu * kNv; ++p) {
        a.values.push_back(0.001 * p - 0.004);
        b.values.push_back(p % 2);
    }
    return {a, b};
}

}  // namespace woven::test
