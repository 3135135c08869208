#pragma once
// Obstacles the cloth drapes over: the abstract signed-distance interface and a set of obstacles.
// All lengths in m.
#include <cstddef>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "woven/common/types.hpp"
#include "woven/geometry/triangle_mesh.hpp"

namespace woven::geometry {

/// Axis-aligned bounding box (m). Default-constructed it is empty (lo = +inf, hi = -inf).
struct Aabb {
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());   ///< lower corner
    Vec3 hi = Vec3::Constant(-std::numeric_limits<double>::infinity());  ///< upper corner

    /// True when the box contains no point (some lo > hi).
    bool empty() const { return (lo.array() > hi.array()).any(); }
    /// Grows the box to contain p.
    void extend(const Vec3& p)
    {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    /// Grows the box to contain another box (an empty one changes nothing).
    void extend(const Aabb& b)
    {
        if (b.empty()) return;
        lo = lo.cwiseMin(b.lo);
        hi = hi.cwiseMax(b.hi);
    }
};

/// Result of a closest-point query.
struct ClosestPoint {
    double distance = std::numeric_limits<double>::infinity();  ///< signed distance (m): > 0 outside, < 0 inside
    Vec3 point = Vec3::Zero();                                  ///< closest point on the surface (m)
    Vec3 normal = Vec3::UnitZ();                                ///< outward unit normal = gradient of the distance
};

/// A rigid obstacle described by its (signed) distance field.
/// Implementations are immutable after construction and safe to query from several threads.
class Obstacle {
public:
    virtual ~Obstacle() = default;

    /// Signed distance, closest surface point and outward normal (the distance gradient) at p.
    /// Where the gradient is undefined (e.g. the medial axis) one of the valid one-sided
    /// gradients is returned.
    virtual ClosestPoint closest(const Vec3& p) const = 0;

    /// Signed distance at p (m); the default is closest(p).distance, primitives override it cheaply.
    virtual double distance(const Vec3& p) const;

    /// Smallest t in [0,1] at which the segment p0 + t (p1 - p0) reaches distance <= 0 (touches
    /// the surface), for p0 outside; 0 when p0 is already inside or on the surface; std::nullopt
    /// if the segment never touches. Continuous collision check: it never misses a crossing, even
    /// of a thin disc by a long segment. The default is a conservative-advancement march on
    /// distance() (capped at 10000 steps, after which it returns the last safe t, i.e. early
    /// rather than late); every concrete obstacle overrides it with an exact test.
    virtual std::optional<double> first_contact(const Vec3& p0, const Vec3& p1) const;

    /// Bounding box of the solid (for a Plane: of its rendered square).
    virtual Aabb bounds() const = 0;

    /// Closed triangle mesh for rendering, faces counter-clockwise seen from outside (m).
    virtual TriangleMesh tessellate() const = 0;

    /// "plane", "box", "sphere", "cylinder" or "mesh".
    virtual std::string kind() const = 0;
};

/// Several obstacles, owned; queries answer for the union of the solids (nearest obstacle).
class ObstacleSet {
public:
    /// Adds an obstacle (a null pointer is ignored).
    void add(std::unique_ptr<Obstacle> obstacle);
    /// Number of obstacles.
    std::size_t size() const { return obstacles_.size(); }
    /// True when the set holds no obstacle.
    bool empty() const { return obstacles_.empty(); }
    /// The i-th obstacle in insertion order (i < size()).
    const Obstacle& operator[](std::size_t i) const { return *obstacles_[i]; }

    /// closest() of the obstacle with the smallest signed distance at p; for an empty set the
    /// distance is +infinity, the point is p and the normal +z.
    ClosestPoint closest(const Vec3& p) const;
    /// Smallest signed distance over the obstacles (+infinity for an empty set).
    double distance(const Vec3& p) const;
    /// Minimum of first_contact over the obstacles (std::nullopt if none is touched).
    std::optional<double> first_contact(const Vec3& p0, const Vec3& p1) const;
    /// Union of the obstacles' bounds (empty for an empty set).
    Aabb bounds() const;

private:
    std::vector<std::unique_ptr<Obstacle>> obstacles_;
};

}  // namespace woven::geometry
