#pragma once
// Obstacle contact for the solvers: a smooth log barrier on the particle-obstacle distance
// (active below the contact distance d^, infinite at contact) and a continuous collision bound
// on a step, so that no particle ever enters an obstacle.
#include <vector>

#include "woven/common/types.hpp"
#include "woven/geometry/obstacle.hpp"

namespace woven::sim {

/// b(d) = -kappa (d - d^)^2 ln(d / d^) for 0 < d < d^, 0 beyond, +inf at d <= 0; the barrier
/// of incremental-potential contact (Li et al. 2020). Value and first two derivatives in d.
struct Barrier {
    double d_hat = 1e-3;  ///< activation distance (m)
    double kappa = 1.0;   ///< stiffness (J/m^2)
    double value(double d) const;
    double d1(double d) const;
    double d2(double d) const;
};

/// One active contact of a particle with an obstacle.
struct Contact {
    int particle = 0;
    double distance = 0;  ///< m
    Vec3 normal;          ///< outward unit normal of the obstacle at the closest point
};

/// Contacts of all particles closer than `d_hat` to any obstacle (one per particle and obstacle).
std::vector<Contact> find_contacts(const geometry::ObstacleSet& obstacles, const Positions& x, double d_hat);

/// Smallest distance of any particle to any obstacle (m); +inf without obstacles.
double min_obstacle_distance(const geometry::ObstacleSet& obstacles, const Positions& x);

/// Largest fraction alpha in (0, 1] of the step x -> x + dx that no particle crosses into an
/// obstacle along (continuous collision check), scaled by `safety` (< 1) to stay off the surface.
double collision_free_fraction(const geometry::ObstacleSet& obstacles, const Positions& x, const Positions& dx, double safety = 0.8);

}  // namespace woven::sim
