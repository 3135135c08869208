// ObstacleSet: nearest-obstacle queries, earliest contact, bounds.
#include <gtest/gtest.h>

#include "woven/geometry/primitives.hpp"

namespace woven::geometry {
namespace {

TEST(ObstacleSet, NearestObstacleAnswers)
{
    ObstacleSet set;
    EXPECT_TRUE(set.empty());
    EXPECT_TRUE(std::isinf(set.distance(Vec3::Zero())));
    EXPECT_FALSE(set.first_contact(Vec3::Zero(), Vec3::UnitX()));
    EXPECT_TRUE(set.bounds().empty());

    set.add(std::make_unique<Plane>(Vec3::Zero(), Vec3::UnitZ()));
    set.add(std::make_unique<Sphere>(Vec3(0, 0, 1), 0.5));
    set.add(nullptr);
    ASSERT_EQ(set.size(), 2u);
    EXPECT_EQ(set[1].kind(), "sphere");

    // Above the sphere: the sphere is nearer (0.3) than the floor (1.8).
    ClosestPoint c = set.closest(Vec3(0, 0, 1.8));
    EXPECT_NEAR(c.distance, 0.3, 1e-15);
    EXPECT_LT((c.point - Vec3(0, 0, 1.5)).norm(), 1e-15);
    EXPECT_NEAR(set.distance(Vec3(0, 0, 1.8)), 0.3, 1e-15);
    // Far to the side, low: the floor is nearer.
    c = set.closest(Vec3(3, 0, 0.2));
    EXPECT_NEAR(c.distance, 0.2, 1e-15);
    EXPECT_LT((c.normal - Vec3::UnitZ()).norm(), 1e-15);

    // A drop onto the sphere hits it (t = 0.25) before the floor (t = 1).
    auto t = set.first_contact(Vec3(0, 0, 2.0), Vec3(0, 0, 0.0));
    ASSERT_TRUE(t);
    EXPECT_NEAR(*t, 0.25, 1e-15);
    t = set.first_contact(Vec3(2, 0, 2.0), Vec3(2, 0, -2.0));
    ASSERT_TRUE(t);
    EXPECT_NEAR(*t, 0.5, 1e-15);

    const Aabb b = set.bounds();
    EXPECT_LT((b.lo - Vec3(-3, -3, -0.06)).norm(), 1e-12);  // floor square (6 m) and slab
    EXPECT_LT((b.hi - Vec3(3, 3, 1.5)).norm(), 1e-12);      // sphere top
}

}  // namespace
}  // namespace woven::geometry
