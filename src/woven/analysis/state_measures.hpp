#pragma once
// Geometric measures of a draped state: how far it reaches into the obstacles, how many
// particles touch them, the threads' strains and the bounding box.
#include <vector>

#include "woven/common/types.hpp"
#include "woven/geometry/obstacle.hpp"
#include "woven/model/grid.hpp"

namespace woven::analysis {

/// Geometric measures of a draped state (SI).
struct StateMeasures {
    double max_penetration = 0;  ///< m: largest max(0, -distance) over particles and obstacles
    int contact_particles = 0;   ///< particles within `contact_distance` of an obstacle
    double strain_max = 0;       ///< largest thread strain |x_i - x_j| / sigma - 1 over the 4-connected edges
    double strain_min = 0;       ///< smallest (most compressed)
    double strain_mean = 0;      ///< mean
    double strain_max_abs = 0;   ///< largest |strain|
    Vec3 bbox_min = Vec3::Zero(), bbox_max = Vec3::Zero();  ///< m
};
/// Over the particles marked in `active` (empty: all; a cloth cut to an outline: the kept ones)
/// and the threads between them.
StateMeasures measure_state(const Positions& x, const model::Grid& grid, const geometry::ObstacleSet& obstacles,
                            double contact_distance, const std::vector<char>& active = {});

}  // namespace woven::analysis
