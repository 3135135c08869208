#pragma once
// The particle grid (docs/MODEL.md "The grid"), stated once here: particle
// (i, j) has index i + nu * j; weft threads run along i (u direction), warp threads along j
// (v direction); the rest spacing sigma is the distance of 4-connected particles.
#include "woven/common/types.hpp"

namespace woven::model {

/// The particle grid: nu x nv particles at rest spacing sigma (m).
struct Grid {
    int nu = 0, nv = 0;
    double sigma = 0;  ///< m
    int index(int i, int j) const { return i + nu * j; }
    int size() const { return nu * nv; }
};

/// The flat grid at height centre.z(), centred at (centre.x(), centre.y()), rotated by `yaw`
/// (rad) about the vertical: one position per particle (m).
Positions flat_grid(const Grid& grid, const Vec3& centre, double yaw = 0.0);

}  // namespace woven::model
