#pragma once
// Shared checks for the geometry tests.
#include <gtest/gtest.h>

#include <random>

#include "woven/geometry/obstacle.hpp"

namespace woven::geometry::testing {

/// Central finite-difference gradient of obstacle.distance at p (step h).
inline Vec3 fd_gradient(const Obstacle& o, const Vec3& p, double h = 1e-6)
{
    Vec3 g;
    for (int k = 0; k < 3; ++k) {
        Vec3 a = p, b = p;
        a[k] += h;
        b[k] -= h;
        g[k] = (o.distance(a) - o.distance(b)) / (2 * h);
    }
    return g;
}

/// closest(p) is consistent: distance() agrees, the point lies on the surface, p = point +
/// distance * normal, the normal is a unit vector equal to the finite-difference gradient.
inline void expect_consistent_closest(const Obstacle& o, const Vec3& p, double gradient_tol = 1e-6)
{
    SCOPED_TRACE(::testing::Message() << o.kind() << " at p = " << p.transpose());
    const ClosestPoint c = o.closest(p);
    EXPECT_NEAR(o.distance(p), c.distance, 1e-12);
    EXPECT_NEAR(c.normal.norm(), 1.0, 1e-12);
    EXPECT_LT(std::abs(o.distance(c.point)), 1e-9);
    EXPECT_LT((p - (c.point + c.distance * c.normal)).norm(), 1e-9);
    EXPECT_LT((fd_gradient(o, p) - c.normal).norm(), gradient_tol);
}

/// Checks first_contact(p0, p1) against a dense sampling of the distance along the segment:
/// no sample before the returned t is inside, the point at t touches the surface, and if the
/// call says "no contact" no sample is inside. Returns the result.
inline std::optional<double> expect_contact_consistent(const Obstacle& o, const Vec3& p0, const Vec3& p1, int samples = 2000)
{
    SCOPED_TRACE(::testing::Message() << o.kind() << " segment " << p0.transpose() << " -> " << p1.transpose());
    const auto t = o.first_contact(p0, p1);
    const double end = t ? *t : 1.0;
    for (int i = 0; i <= samples; ++i) {
        const double s = end * i / samples;
        if (t && s >= *t - 1e-12) break;
        EXPECT_GT(o.distance(p0 + s * (p1 - p0)), -1e-12) << "inside at s = " << s << " before the reported contact";
    }
    if (t) {
        EXPECT_GE(*t, 0.0);
        EXPECT_LE(*t, 1.0);
        EXPECT_LT(std::abs(o.distance(p0 + *t * (p1 - p0))), 1e-9);
    }
    return t;
}

}  // namespace woven::geometry::testing
