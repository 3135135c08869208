// Analytic obstacles: hand-computed distances, gradients, closest points, first_contact, input checks.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <numbers>
#include <random>

#include "test_support.hpp"
#include "woven/common/error.hpp"
#include "woven/geometry/mesh_ops.hpp"
#include "woven/geometry/primitives.hpp"

namespace woven::geometry {
namespace {

using testing::expect_consistent_closest;
using testing::expect_contact_consistent;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// ---------------------------------------------------------------- Plane

TEST(Plane, DistanceClosestAndNormal)
{
    const Plane plane(Vec3(0, 0, 1), Vec3(0, 0, 2));
    EXPECT_NEAR(plane.distance(Vec3(3, 4, 1.5)), 0.5, 1e-15);
    EXPECT_NEAR(plane.distance(Vec3(-3, 4, 0.25)), -0.75, 1e-15);
    const ClosestPoint c = plane.closest(Vec3(3, 4, 1.5));
    EXPECT_LT((c.point - Vec3(3, 4, 1)).norm(), 1e-15);
    EXPECT_LT((c.normal - Vec3::UnitZ()).norm(), 1e-15);

    const Plane tilted(Vec3::Zero(), Vec3(1, 1, 0));
    EXPECT_NEAR(tilted.distance(Vec3(1, 1, 7)), std::sqrt(2.0), 1e-15);
    for (const Vec3& p : {Vec3(1, 1, 7), Vec3(-2, 0.5, 0.3), Vec3(0.1, -0.1, 0)}) expect_consistent_closest(tilted, p);
}

TEST(Plane, FirstContact)
{
    const Plane plane(Vec3(0, 0, 1), Vec3::UnitZ());
    auto t = plane.first_contact(Vec3(0, 0, 3), Vec3(1, 0, -1));
    ASSERT_TRUE(t);
    EXPECT_NEAR(*t, 0.5, 1e-15);
    EXPECT_FALSE(plane.first_contact(Vec3(0, 0, 3), Vec3(5, 0, 1.5)));
    EXPECT_FALSE(plane.first_contact(Vec3(0, 0, 3), Vec3(0, 0, 4)));
    EXPECT_EQ(plane.first_contact(Vec3(0, 0, 0.5), Vec3(0, 0, 4)), 0.0);  // starts inside
}

TEST(Plane, TessellationIsClosedSquareWithTopOnThePlane)
{
    const Plane plane(Vec3(1, 2, 0.5), Vec3::UnitZ(), 4.0);
    const TriangleMesh m = plane.tessellate();
    EXPECT_TRUE(is_closed(m));
    EXPECT_NEAR(signed_volume(m), 4.0 * 4.0 * 0.04, 1e-12);
    const Aabb b = plane.bounds();
    EXPECT_LT((b.lo - Vec3(-1, 0, 0.46)).norm(), 1e-12);
    EXPECT_LT((b.hi - Vec3(3, 4, 0.5)).norm(), 1e-12);
    EXPECT_EQ(plane.kind(), "plane");
}

// ---------------------------------------------------------------- Box

class BoxTest : public ::testing::Test {
protected:
    const Vec3 centre{1, 2, 3};
    const double yaw = 0.3;
    const Box box{centre, Vec3(0.5, 1.0, 1.5), yaw};
    // Box-frame coordinates to world.
    Vec3 world(double x, double y, double z) const
    {
        const double c = std::cos(yaw), s = std::sin(yaw);
        return centre + Vec3(c * x - s * y, s * x + c * y, z);
    }
};

TEST_F(BoxTest, DistanceAtHandPoints)
{
    EXPECT_NEAR(box.distance(world(0, 0, 0)), -0.5, 1e-14);            // centre: nearest faces at x = +-0.5
    EXPECT_NEAR(box.distance(world(0.2, 0, 0)), -0.3, 1e-14);          // inside
    EXPECT_NEAR(box.distance(world(0.1, -0.7, 1.3)), -0.2, 1e-14);     // inside, nearest face z = 1.5
    EXPECT_NEAR(box.distance(world(0.8, 0.1, 0.2)), 0.3, 1e-14);       // outside a face
    EXPECT_NEAR(box.distance(world(0.8, 1.4, 0)), 0.5, 1e-14);         // outside an edge: hypot(0.3, 0.4)
    EXPECT_NEAR(box.distance(world(-0.8, -1.4, -2.7)), 1.3, 1e-14);    // outside a corner: |(0.3, 0.4, 1.2)|
    EXPECT_NEAR(box.distance(world(0.5, 0.3, 0.2)), 0.0, 1e-14);       // on a face
    EXPECT_NEAR(box.distance(world(0.5, 1.0, 1.5)), 0.0, 1e-14);       // on a corner
}

TEST_F(BoxTest, ClosestPointsAndNormals)
{
    const ClosestPoint edge = box.closest(world(0.8, 1.4, 0));
    EXPECT_LT((edge.point - world(0.5, 1.0, 0)).norm(), 1e-14);
    const ClosestPoint inside = box.closest(world(0.1, -0.7, 1.3));
    EXPECT_LT((inside.point - world(0.1, -0.7, 1.5)).norm(), 1e-14);
    EXPECT_LT((inside.normal - Vec3::UnitZ()).norm(), 1e-14);
    const ClosestPoint on_face = box.closest(world(0.5, 0.3, 0.2));
    EXPECT_LT((on_face.normal - Vec3(std::cos(yaw), std::sin(yaw), 0)).norm(), 1e-14);
    for (const Vec3& p : {world(0.2, 0, 0), world(0.1, -0.7, 1.3), world(0.8, 0.1, 0.2), world(0.8, 1.4, 0),
                          world(-0.8, -1.4, -2.7), world(0.45, 0.93, 1.41), world(0.51, 1.01, 1.51)}) {
        expect_consistent_closest(box, p);
    }
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> u(-2.5, 2.5);
    for (int i = 0; i < 200; ++i) expect_consistent_closest(box, world(u(rng), u(rng), u(rng)));
}

TEST_F(BoxTest, BoundsOfRotatedBox)
{
    const Aabb b = box.bounds();
    const double ex = std::cos(yaw) * 0.5 + std::sin(yaw) * 1.0, ey = std::sin(yaw) * 0.5 + std::cos(yaw) * 1.0;
    EXPECT_LT((b.lo - (centre - Vec3(ex, ey, 1.5))).norm(), 1e-14);
    EXPECT_LT((b.hi - (centre + Vec3(ex, ey, 1.5))).norm(), 1e-14);
    const TriangleMesh m = box.tessellate();
    EXPECT_EQ(m.faces.size(), 12u);
    EXPECT_TRUE(is_closed(m));
    EXPECT_NEAR(signed_volume(m), 1.0 * 2.0 * 3.0, 1e-12);
}

TEST(Box, FirstContact)
{
    const Box box(Vec3::Zero(), Vec3(1, 1, 1));
    auto t = box.first_contact(Vec3(-3, 0.5, 0), Vec3(1, 0.5, 0));
    ASSERT_TRUE(t);
    EXPECT_NEAR(*t, 0.5, 1e-15);
    EXPECT_FALSE(box.first_contact(Vec3(-3, 1.5, 0), Vec3(3, 1.5, 0)));   // passes beside
    EXPECT_FALSE(box.first_contact(Vec3(-3, 0, 0), Vec3(-1.5, 0, 0)));    // stops short
    EXPECT_EQ(box.first_contact(Vec3(0.2, 0, 0), Vec3(3, 0, 0)), 0.0);    // starts inside

    const Box diamond(Vec3::Zero(), Vec3(1, 1, 1), std::numbers::pi / 4);
    t = diamond.first_contact(Vec3(-3, 0, 0), Vec3(3, 0, 0));
    ASSERT_TRUE(t);
    EXPECT_NEAR(*t, (3 - std::sqrt(2.0)) / 6, 1e-15);
}

TEST(Box, GrazingSegmentTerminatesWithoutContact)
{
    const Box box(Vec3::Zero(), Vec3(1, 1, 1), 0.2);
    const Vec3 n(std::cos(0.2), std::sin(0.2), 0), along(-std::sin(0.2), std::cos(0.2), 0);
    const Vec3 p0 = (1 + 1e-7) * n - 5 * along, p1 = (1 + 1e-7) * n + 5 * along;
    // Returning at all is the point (the test is analytic, no march); no wall time is asserted.
    EXPECT_FALSE(box.first_contact(p0, p1));
    EXPECT_TRUE(box.first_contact(p0, p1 - 2e-7 * n));  // dips 1e-7 m into the face
}

// ---------------------------------------------------------------- Sphere

TEST(Sphere, DistanceClosestNormal)
{
    const Sphere s(Vec3(0.1, -0.2, 0.3), 0.25);
    EXPECT_NEAR(s.distance(Vec3(0.1, -0.2, 0.3)), -0.25, 1e-15);
    EXPECT_NEAR(s.distance(Vec3(0.1, -0.2 + 0.1, 0.3)), -0.15, 1e-15);
    EXPECT_NEAR(s.distance(Vec3(0.1 + 0.3, -0.2 + 0.4, 0.3)), 0.25, 1e-15);
    EXPECT_NEAR(s.distance(Vec3(0.1, -0.2, 0.55)), 0.0, 1e-15);
    const ClosestPoint c = s.closest(Vec3(0.1 + 0.3, -0.2 + 0.4, 0.3));
    EXPECT_LT((c.point - Vec3(0.1 + 0.15, -0.2 + 0.2, 0.3)).norm(), 1e-15);
    EXPECT_LT((c.normal - Vec3(0.6, 0.8, 0)).norm(), 1e-15);
    std::mt19937 rng(2);
    std::uniform_real_distribution<double> u(-0.6, 0.6);
    for (int i = 0; i < 100; ++i) expect_consistent_closest(s, Vec3(u(rng), u(rng), u(rng)));
    EXPECT_EQ(s.tessellate().faces.size(), 48u * 24u * 2u - 2u * 48u);
    EXPECT_TRUE(is_closed(s.tessellate()));
    EXPECT_GT(signed_volume(s.tessellate()), 0.98 * 4.0 / 3.0 * std::numbers::pi * std::pow(0.25, 3));
}

TEST(Sphere, FirstContact)
{
    const Sphere s(Vec3::Zero(), 1.0);
    auto t = s.first_contact(Vec3(-3, 0, 0), Vec3(3, 0, 0));
    ASSERT_TRUE(t);
    EXPECT_NEAR(*t, 1.0 / 3.0, 1e-15);
    t = s.first_contact(Vec3(-3, 0.6, 0), Vec3(1, 0.6, 0));  // enters at x = -0.8
    ASSERT_TRUE(t);
    EXPECT_NEAR(*t, 2.2 / 4.0, 1e-15);
    EXPECT_FALSE(s.first_contact(Vec3(-3, 1.01, 0), Vec3(3, 1.01, 0)));
    EXPECT_FALSE(s.first_contact(Vec3(-3, 0, 0), Vec3(-1.5, 0, 0)));
    EXPECT_FALSE(s.first_contact(Vec3(3, 0, 0), Vec3(5, 0, 0)));  // moving away
    EXPECT_EQ(s.first_contact(Vec3(0.5, 0, 0), Vec3(5, 0, 0)), 0.0);
}

// ---------------------------------------------------------------- Cylinder

class CylinderTest : public ::testing::Test {
protected:
    const Vec3 base{1, 0, 0};
    const Vec3 axis = Vec3(0, 1, 1).normalized();
    const Vec3 side = Vec3::UnitX();  // perpendicular to the axis
    const Cylinder cyl{base, 0.3, 1.0, Vec3(0, 2, 2)};
    Vec3 at(double s, double rho) const { return base + s * axis + rho * side; }
};

TEST_F(CylinderTest, DistanceAtHandPoints)
{
    EXPECT_NEAR(cyl.distance(at(0.5, 0)), -0.3, 1e-14);     // on the axis, mid-height
    EXPECT_NEAR(cyl.distance(at(0.9, 0.1)), -0.1, 1e-14);   // nearer the top cap
    EXPECT_NEAR(cyl.distance(at(0.5, 0.25)), -0.05, 1e-14); // nearer the side
    EXPECT_NEAR(cyl.distance(at(0.5, 0.7)), 0.4, 1e-14);    // beside
    EXPECT_NEAR(cyl.distance(at(1.3, 0.1)), 0.3, 1e-14);    // above the top cap
    EXPECT_NEAR(cyl.distance(at(1.3, 0.7)), 0.5, 1e-14);    // beyond the top rim: hypot(0.3, 0.4)
    EXPECT_NEAR(cyl.distance(at(-0.4, 0.3)), 0.4, 1e-14);   // straight below the bottom rim
    EXPECT_NEAR(cyl.distance(at(0.2, 0.3)), 0.0, 1e-14);    // on the side
    EXPECT_NEAR(cyl.distance(at(1.0, 0.3)), 0.0, 1e-14);    // on the rim
}

TEST_F(CylinderTest, ClosestPointsAndNormals)
{
    const ClosestPoint rim = cyl.closest(at(1.3, 0.7));
    EXPECT_LT((rim.point - at(1.0, 0.3)).norm(), 1e-14);
    EXPECT_LT((rim.normal - (0.6 * axis + 0.8 * side)).norm(), 1e-14);
    const ClosestPoint cap = cyl.closest(at(0.9, 0.1));
    EXPECT_LT((cap.point - at(1.0, 0.1)).norm(), 1e-14);
    EXPECT_LT((cap.normal - axis).norm(), 1e-14);
    const ClosestPoint bottom = cyl.closest(at(0.05, 0.1));
    EXPECT_LT((bottom.normal + axis).norm(), 1e-14);
    for (const Vec3& p : {at(0.9, 0.1), at(0.5, 0.25), at(0.5, 0.7), at(1.3, 0.1), at(1.3, 0.7), at(-0.4, 0.3), at(-0.2, 0.5)}) {
        expect_consistent_closest(cyl, p);
    }
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1.0, 2.0);
    for (int i = 0; i < 200; ++i) expect_consistent_closest(cyl, Vec3(u(rng), u(rng), u(rng)));
}

TEST_F(CylinderTest, BoundsAndTessellation)
{
    const Aabb b = cyl.bounds();
    const Vec3 top = base + axis;
    const Vec3 e(0.3, 0.3 * std::sqrt(0.5), 0.3 * std::sqrt(0.5));
    EXPECT_LT((b.lo - (base.cwiseMin(top) - e)).norm(), 1e-14);
    EXPECT_LT((b.hi - (base.cwiseMax(top) + e)).norm(), 1e-14);
    const TriangleMesh m = cyl.tessellate();
    EXPECT_TRUE(is_closed(m));
    // A regular 64-gon prism: 0.5 n R^2 sin(2 pi / n) * h.
    EXPECT_NEAR(signed_volume(m), 0.5 * 64 * 0.09 * std::sin(2 * std::numbers::pi / 64) * 1.0, 1e-12);
    for (const Vec3& v : m.vertices) EXPECT_LT(std::abs(cyl.distance(v)), 1e-14);
}

TEST(Cylinder, FastSegmentThroughThinDiscIsCaught)
{
    const Cylinder disc(Vec3(0, 0, 0.5), 0.09, 0.003);  // 3 mm drape-tester disc, top at z = 0.503
    const auto t = disc.first_contact(Vec3(0.05, 0.02, 10.0), Vec3(0.05, 0.02, -10.0));
    ASSERT_TRUE(t);
    EXPECT_NEAR(*t, (10.0 - 0.503) / 20.0, 1e-15);
    // Oblique and fast, entering through the rim side.
    const auto t2 = disc.first_contact(Vec3(-5.0, 0, 0.5015 - 0.001), Vec3(5.0, 0, 0.5015 + 0.001));
    ASSERT_TRUE(t2);
    EXPECT_NEAR(*t2, (5.0 - 0.09) / 10.0, 1e-12);
    EXPECT_FALSE(disc.first_contact(Vec3(0.0, 0.0, 0.5035), Vec3(0.0, 5.0, 0.5035)));  // grazes 0.5 mm above
    EXPECT_FALSE(disc.first_contact(Vec3(0.1, 0.0, 10.0), Vec3(0.1, 0.0, -10.0)));      // passes outside the rim
    std::mt19937 rng(4);
    std::uniform_real_distribution<double> u(-0.2, 0.2);
    int hits = 0;
    for (int i = 0; i < 300; ++i) {
        const Vec3 p0(u(rng), u(rng), 0.5 + 2 * u(rng) + 0.5), p1(u(rng), u(rng), 0.5 - 2 * u(rng) - 0.5);
        if (disc.distance(p0) <= 0) continue;
        if (expect_contact_consistent(disc, p0, p1, 20000)) ++hits;
    }
    EXPECT_GT(hits, 50);
}

TEST(Cylinder, GrazingSegmentsTerminate)
{
    const Cylinder c(Vec3::Zero(), 0.5, 1.0);
    EXPECT_FALSE(c.first_contact(Vec3(0.5 + 1e-9, -3, 0.5), Vec3(0.5 + 1e-9, 3, 0.5)));  // tangent to the side
    EXPECT_FALSE(c.first_contact(Vec3(-3, 0, 1 + 1e-9), Vec3(3, 0, 1 + 1e-9)));          // over the top cap
    EXPECT_FALSE(c.first_contact(Vec3(0.5 + 1e-9, 0, -3), Vec3(0.5 + 1e-9, 0, 3)));       // along the side
    const auto t = c.first_contact(Vec3(0.5 - 1e-9, 0, -3), Vec3(0.5 - 1e-9, 0, 3));
    ASSERT_TRUE(t);
    EXPECT_NEAR(*t, 0.5, 1e-12);
}

// ---------------------------------------------------------------- all primitives

TEST(Primitives, FirstContactAgreesWithDenseSampling)
{
    const Plane plane(Vec3(0, 0, -0.4), Vec3(0.1, 0.2, 1));
    const Box box(Vec3(0.1, 0, 0), Vec3(0.3, 0.2, 0.1), 0.7);
    const Sphere sphere(Vec3(0, 0.1, 0), 0.3);
    const Cylinder cyl(Vec3(0, 0, -0.2), 0.25, 0.4, Vec3(1, 0, 1));
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (const Obstacle* o : std::initializer_list<const Obstacle*>{&plane, &box, &sphere, &cyl}) {
        int hits = 0, misses = 0;
        for (int i = 0; i < 400; ++i) {
            const Vec3 p0(u(rng), u(rng), u(rng)), p1(u(rng), u(rng), u(rng));
            if (o->distance(p0) <= 0) continue;
            (expect_contact_consistent(*o, p0, p1) ? hits : misses)++;
        }
        EXPECT_GT(hits, 20) << o->kind();
        EXPECT_GT(misses, 20) << o->kind();
    }
}

/// A sphere that keeps Obstacle's default (marching) first_contact.
class MarchingSphere : public Obstacle {
public:
    explicit MarchingSphere(Sphere s) : s_(std::move(s)) { }
    ClosestPoint closest(const Vec3& p) const override { return s_.closest(p); }
    Aabb bounds() const override { return s_.bounds(); }
    TriangleMesh tessellate() const override { return s_.tessellate(); }
    std::string kind() const override { return "sphere"; }

private:
    Sphere s_;
};

TEST(Obstacle, DefaultMarchMatchesAnalyticAndTerminatesWhenGrazing)
{
    const Sphere s(Vec3::Zero(), 1.0);
    const MarchingSphere m(s);
    const auto t = m.first_contact(Vec3(-3, 0.6, 0), Vec3(1, 0.6, 0));
    ASSERT_TRUE(t);
    EXPECT_NEAR(*t, *s.first_contact(Vec3(-3, 0.6, 0), Vec3(1, 0.6, 0)), 1e-8);
    EXPECT_FALSE(m.first_contact(Vec3(-3, 1.5, 0), Vec3(3, 1.5, 0)));
    // Grazing 1e-6 m above the surface: the march is capped and answers early, never late.
    const auto g = m.first_contact(Vec3(-3, 1 + 1e-6, 0), Vec3(3, 1 + 1e-6, 0));
    if (g) {
        EXPECT_LE(*g, 0.5);
    }
}

// ---------------------------------------------------------------- input checks

TEST(Primitives, BadInputThrowsInputError)
{
    EXPECT_THROW(Plane(Vec3::Zero(), Vec3::Zero()), InputError);
    EXPECT_THROW(Plane(Vec3(kNaN, 0, 0), Vec3::UnitZ()), InputError);
    EXPECT_THROW(Plane(Vec3::Zero(), Vec3::UnitZ(), 0.0), InputError);
    EXPECT_THROW(Box(Vec3::Zero(), Vec3(1, 0, 1)), InputError);
    EXPECT_THROW(Box(Vec3::Zero(), Vec3(1, -1, 1)), InputError);
    EXPECT_THROW(Box(Vec3::Zero(), Vec3(1, 1, 1), kNaN), InputError);
    EXPECT_THROW(Box(Vec3(0, std::numeric_limits<double>::infinity(), 0), Vec3(1, 1, 1)), InputError);
    EXPECT_THROW(Sphere(Vec3::Zero(), 0.0), InputError);
    EXPECT_THROW(Sphere(Vec3::Zero(), -1.0), InputError);
    EXPECT_THROW(Sphere(Vec3::Zero(), kNaN), InputError);
    EXPECT_THROW(Cylinder(Vec3::Zero(), 0.0, 1.0), InputError);
    EXPECT_THROW(Cylinder(Vec3::Zero(), 1.0, 0.0), InputError);
    EXPECT_THROW(Cylinder(Vec3::Zero(), 1.0, 1.0, Vec3::Zero()), InputError);
    try {
        Sphere(Vec3::Zero(), -1.0);
        FAIL() << "no exception";
    } catch (const InputError& e) {
        EXPECT_EQ(e.field(), "radius");
    }
}

TEST(Transform, ScaleThenRotateXYZThenTranslate)
{
    TriangleMesh m;
    m.vertices = {Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
    m.faces = {Eigen::Vector3i(0, 1, 2)};
    const TriangleMesh a = transform(m, 2.0, Vec3(0, 0, 90), Vec3(1, 0, 0));
    EXPECT_LT((a.vertices[0] - Vec3(1, 2, 0)).norm(), 1e-14);
    const TriangleMesh b = transform(m, 1.0, Vec3(90, 90, 0), Vec3::Zero());
    EXPECT_LT((b.vertices[1] - Vec3(1, 0, 0)).norm(), 1e-14);  // (0,1,0) -x-> (0,0,1) -y-> (1,0,0)
    EXPECT_EQ(b.faces, m.faces);
}

}  // namespace
}  // namespace woven::geometry
