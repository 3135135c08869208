#include "woven/sim/contact.hpp"

#include <cmath>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace woven::sim {

double Barrier::value(double d) const
{
    if (d <= 0) return std::numeric_limits<double>::infinity();
    if (d >= d_hat) return 0;
    const double e = d - d_hat;
    return -kappa * e * e * std::log(d / d_hat);
}

double Barrier::d1(double d) const
{
    if (d >= d_hat || d <= 0) return 0;
    const double e = d - d_hat;
    return -kappa * (2.0 * e * std::log(d / d_hat) + e * e / d);
}

double Barrier::d2(double d) const
{
    if (d >= d_hat || d <= 0) return 0;
    const double e = d - d_hat;
    return -kappa * (2.0 * std::log(d / d_hat) + 4.0 * e / d - e * e / (d * d));
}

namespace {
/// f1 = f0' of the smoothed slip norm: 2y/eps - y^2/eps^2 below eps, 1 beyond.
double slip_f1(double y, double eps) { return y >= eps ? 1.0 : y / eps * (2.0 - y / eps); }
}  // namespace

double FrictionContact::value(const Vec3& x, double eps) const
{
    const double y = (tangent * (x - anchor)).norm();
    const double f0 = y >= eps ? y : y * y / eps - y * y * y / (3.0 * eps * eps) + eps / 3.0;
    return bound * f0;
}

Vec3 FrictionContact::gradient(const Vec3& x, double eps) const
{
    const Vec3 u = tangent * (x - anchor);
    const double y = u.norm();
    if (y == 0) return Vec3::Zero();
    return bound * slip_f1(y, eps) / y * u;
}

Mat3 FrictionContact::hessian(const Vec3& x, double eps) const
{
    // The exact Hessian adds a negative rank-one term along u; dropping it keeps it PSD.
    const double y = (tangent * (x - anchor)).norm();
    const double f1_over_y = y >= eps ? 1.0 / y : (2.0 - y / eps) / eps;
    return bound * f1_over_y * tangent;
}

std::vector<FrictionContact> friction_contacts(const std::vector<Contact>& contacts, const Positions& x, const Barrier& barrier, double mu)
{
    std::vector<FrictionContact> out;
    if (mu <= 0) return out;
    for (const Contact& c : contacts) {
        const double lambda = -barrier.d1(c.distance);
        if (lambda <= 0) continue;
        out.push_back({c.particle, x[c.particle], Mat3::Identity() - c.normal * c.normal.transpose(), mu * lambda});
    }
    return out;
}

namespace {
/// Particles per oneTBB task of obstacle_distances (a box query costs tens of nanoseconds).
constexpr std::size_t kDistanceGrain = 2048;
}  // namespace

void obstacle_distances(const geometry::Obstacle& obstacle, const Positions& x, std::vector<double>& d)
{
    d.resize(x.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, x.size(), kDistanceGrain), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i < r.end(); ++i) d[i] = obstacle.distance(x[i]);
    });
}

std::vector<Contact> find_contacts(const geometry::ObstacleSet& obstacles, const Positions& x, double d_hat)
{
    std::vector<Contact> contacts;
    std::vector<double> distance;
    for (size_t o = 0; o < obstacles.size(); ++o) {
        const geometry::Obstacle& ob = obstacles[o];
        obstacle_distances(ob, x, distance);
        for (size_t i = 0; i < x.size(); ++i) {
            if (distance[i] >= d_hat) continue;
            const geometry::ClosestPoint c = ob.closest(x[i]);
            contacts.push_back({static_cast<int>(i), c.distance, c.normal});
        }
    }
    return contacts;
}

double min_obstacle_distance(const geometry::ObstacleSet& obstacles, const Positions& x)
{
    double d = std::numeric_limits<double>::infinity();
    for (size_t o = 0; o < obstacles.size(); ++o)
        for (const Vec3& p : x) d = std::min(d, obstacles[o].distance(p));
    return d;
}

double collision_free_fraction(const geometry::ObstacleSet& obstacles, const Positions& x, const Positions& dx, double safety)
{
    double alpha = 1.0;
    std::vector<double> distance;
    for (size_t o = 0; o < obstacles.size(); ++o) {
        const geometry::Obstacle& ob = obstacles[o];
        obstacle_distances(ob, x, distance);
        for (size_t i = 0; i < x.size(); ++i) {
            const double len = dx[i].norm();
            if (len == 0) continue;
            // Cheap rejection: a move shorter than the distance cannot reach the surface.
            const double d = distance[i];
            if (len * alpha < d) continue;
            if (auto t = ob.first_contact(x[i], x[i] + alpha * dx[i])) alpha *= safety * *t;
        }
    }
    return alpha;
}

}  // namespace woven::sim
