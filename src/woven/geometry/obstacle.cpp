#include "woven/geometry/obstacle.hpp"

#include <algorithm>
#include <cmath>

namespace woven::geometry {

double Obstacle::distance(const Vec3& p) const { return closest(p).distance; }

std::optional<double> Obstacle::first_contact(const Vec3& p0, const Vec3& p1) const
{
    constexpr double touch = 1e-9;  // m
    constexpr int max_steps = 10000;
    const double length = (p1 - p0).norm();
    double t = 0;
    for (int i = 0; i < max_steps; ++i) {
        const double d = distance(p0 + t * (p1 - p0));
        if (d <= touch) return t;
        if (length == 0) return std::nullopt;
        t += d / length;
        if (t > 1) {
            return distance(p1) <= 0 ? std::optional<double>(1.0) : std::nullopt;
        }
    }
    return t;
}

void ObstacleSet::add(std::unique_ptr<Obstacle> obstacle)
{
    if (obstacle) obstacles_.push_back(std::move(obstacle));
}

ClosestPoint ObstacleSet::closest(const Vec3& p) const
{
    const Obstacle* best = nullptr;
    double best_d = std::numeric_limits<double>::infinity();
    for (const auto& o : obstacles_) {
        const double d = o->distance(p);
        if (!best || d < best_d) {
            best = o.get();
            best_d = d;
        }
    }
    if (!best) return ClosestPoint{std::numeric_limits<double>::infinity(), p, Vec3::UnitZ()};
    return best->closest(p);
}

double ObstacleSet::distance(const Vec3& p) const
{
    double best = std::numeric_limits<double>::infinity();
    for (const auto& o : obstacles_) best = std::min(best, o->distance(p));
    return best;
}

std::optional<double> ObstacleSet::first_contact(const Vec3& p0, const Vec3& p1) const
{
    std::optional<double> best;
    for (const auto& o : obstacles_) {
        const auto t = o->first_contact(p0, p1);
        if (t && (!best || *t < *best)) best = t;
    }
    return best;
}

Aabb ObstacleSet::bounds() const
{
    Aabb b;
    for (const auto& o : obstacles_) b.extend(o->bounds());
    return b;
}

}  // namespace woven::geometry
