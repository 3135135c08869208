// Geometric measures of a draped state (analysis/state_measures.hpp) on a state built by hand.
#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include "woven/analysis/state_measures.hpp"
#include "woven/geometry/primitives.hpp"

namespace woven::analysis {
namespace {

TEST(StateMeasures, PenetrationContactsStrainsAndBox)
{
    // A 3 x 2 grid at 0.1 m over the floor z = 0: particle 1 moved 0.02 m along +x (its threads
    // to 0 and 2: +20 % and -20 %), particle 4 0.005 m into the floor, particle 5 0.001 m above.
    const model::Grid grid{3, 2, 0.1};
    Positions x;
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 3; ++i) x.push_back(Vec3(0.1 * i, 0.1 * j, 0.05));
    x[1].x() += 0.02;
    x[4].z() = -0.005;
    x[5].z() = 0.001;
    geometry::ObstacleSet obstacles;
    obstacles.add(std::make_unique<geometry::Plane>(Vec3::Zero(), Vec3::UnitZ()));
    const StateMeasures m = measure_state(x, grid, obstacles, 0.002);
    EXPECT_NEAR(m.max_penetration, 0.005, 1e-15);
    EXPECT_EQ(m.contact_particles, 2);  // 4 (inside) and 5 (1 mm away), not the others (5 cm)
    EXPECT_NEAR(m.strain_max, 0.2, 1e-12);
    EXPECT_NEAR(m.strain_min, -0.2, 1e-12);
    EXPECT_NEAR(m.strain_max_abs, 0.2, 1e-12);
    EXPECT_NEAR(m.bbox_min.z(), -0.005, 1e-15);
    EXPECT_NEAR(m.bbox_max.x(), 0.2, 1e-15);
    // The mean over the 7 threads (4 along i, 3 along j).
    double sum = 0;
    auto s = [&](int a, int b) { sum += (x[a] - x[b]).norm() / 0.1 - 1; };
    s(0, 1), s(1, 2), s(3, 4), s(4, 5), s(0, 3), s(1, 4), s(2, 5);
    EXPECT_NEAR(m.strain_mean, sum / 7, 1e-14);
    // Only the kept particles and the threads between them: 0, 3 (one vertical thread, unstrained).
    const StateMeasures kept = measure_state(x, grid, obstacles, 0.002, {1, 0, 0, 1, 0, 0});
    EXPECT_EQ(kept.contact_particles, 0);
    EXPECT_EQ(kept.max_penetration, 0);
    EXPECT_NEAR(kept.strain_max, 0, 1e-12);
    EXPECT_NEAR(kept.strain_mean, 0, 1e-12);
    EXPECT_NEAR(kept.bbox_max.y(), 0.1, 1e-15);
}

}  // namespace
}  // namespace woven::analysis
