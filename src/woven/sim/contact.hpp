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

/// Lagged Coulomb friction of one contact over a step (incremental-potential friction, Li et al.
/// 2020): with the normal force lambda and the tangent plane frozen at the step's start, the
/// tangential slip u = T (x - anchor) costs D(u) = mu lambda f0(|u|), where f0 is |u| smoothed
/// below eps (C1): the friction force grows from 0 to mu lambda over a slip of eps (sticking)
/// and is mu lambda beyond (sliding).
struct FrictionContact {
    int particle = 0;
    Vec3 anchor;       ///< the particle's position at the step's start
    Mat3 tangent;      ///< I - n n^T
    double bound = 0;  ///< mu lambda (N): the largest friction force
    /// D, dD/dx and a PSD Hessian (mu lambda f1(y)/y T) at x, for slip smoothing eps (m).
    double value(const Vec3& x, double eps) const;
    Vec3 gradient(const Vec3& x, double eps) const;
    Mat3 hessian(const Vec3& x, double eps) const;
};

/// d[i] = the obstacle's distance to x[i] for every particle, the queries on oneTBB's threads
/// (obstacles are safe to query from several threads; a mesh's query walks a BVH). Callers sum
/// over d in particle order, so results do not depend on the thread count.
void obstacle_distances(const geometry::Obstacle& obstacle, const Positions& x, std::vector<double>& d);

/// Contacts of all particles closer than `d_hat` to any obstacle (one per particle and obstacle).
std::vector<Contact> find_contacts(const geometry::ObstacleSet& obstacles, const Positions& x, double d_hat);

/// Friction contacts at the start of a step: one per barrier contact, with lambda = -b'(d).
std::vector<FrictionContact> friction_contacts(const std::vector<Contact>& contacts, const Positions& x, const Barrier& barrier, double mu);

/// Smallest distance of any particle to any obstacle (m); +inf without obstacles.
double min_obstacle_distance(const geometry::ObstacleSet& obstacles, const Positions& x);

/// Largest fraction alpha in (0, 1] of the step x -> x + dx that no particle crosses into an
/// obstacle along (continuous collision check), scaled by `safety` (< 1) to stay off the surface.
double collision_free_fraction(const geometry::ObstacleSet& obstacles, const Positions& x, const Positions& dx, double safety = 0.8);

}  // namespace woven::sim
