// The particle-obstacle queries of the fast solver (sim/contact.hpp) on oneTBB's threads against
// the obstacles' own serial queries.
#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include <tbb/global_control.h>

#include "woven/geometry/primitives.hpp"
#include "woven/sim/contact.hpp"

namespace woven {
namespace {

/// 20,000 points in a 1 m cube around the obstacles: several oneTBB tasks of obstacle_distances.
Positions random_points()
{
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-0.5, 0.5);
    Positions x(20000);
    for (Vec3& p : x) p = Vec3(u(rng), u(rng), u(rng));
    return x;
}

TEST(ObstacleDistances, AreTheObstaclesOwnDistancesBitForBitOnTwoThreads)
{
    const tbb::global_control two(tbb::global_control::max_allowed_parallelism, 2);
    const Positions x = random_points();
    const geometry::Box box(Vec3(0.05, 0, -0.1), Vec3(0.2, 0.15, 0.1), 0.3);
    const geometry::Sphere sphere(Vec3(0, 0.1, 0), 0.25);
    for (const geometry::Obstacle* obstacle : {static_cast<const geometry::Obstacle*>(&box), static_cast<const geometry::Obstacle*>(&sphere)}) {
        std::vector<double> d;
        sim::obstacle_distances(*obstacle, x, d);
        ASSERT_EQ(x.size(), d.size());
        int inside = 0;
        for (std::size_t i = 0; i < x.size(); ++i) {
            const double expected = obstacle->distance(x[i]);
            EXPECT_EQ(0, std::memcmp(&expected, &d[i], sizeof(double))) << i;
            inside += d[i] < 0;
        }
        EXPECT_GT(inside, 100);  // points on both sides of each surface
        EXPECT_LT(inside, 19900);
    }
}

TEST(ObstacleDistances, OfNoParticlesIsEmpty)
{
    const geometry::Sphere sphere(Vec3::Zero(), 0.25);
    std::vector<double> d(3, 1.0);
    sim::obstacle_distances(sphere, Positions{}, d);
    EXPECT_TRUE(d.empty());
}

}  // namespace
}  // namespace woven
