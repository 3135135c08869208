// Lagged Coulomb friction of the fast solver: the smoothed potential's derivatives, and a cloth
// on an inclined plane that sticks when mu > tan(slope) and slides when mu < tan(slope).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include <Eigen/Eigenvalues>

#include "sim/sim_fixtures.hpp"
#include "woven/sim/contact.hpp"

namespace woven {
namespace {

sim::FrictionContact example_contact()
{
    const Vec3 n = Vec3(0.3, -0.2, 1.0).normalized();
    return sim::FrictionContact{0, Vec3(0.1, 0.2, 0.3), Mat3::Identity() - n * n.transpose(), 0.02};
}

TEST(Friction, GradientMatchesFiniteDifferencesWhenStickingAndSliding)
{
    const sim::FrictionContact f = example_contact();
    const double eps = 1e-4;
    // Slips of 0.2 eps, 0.9 eps (sticking, smoothed) and 3 eps (sliding).
    for (double slip : {0.2, 0.9, 3.0}) {
        const Vec3 x = f.anchor + f.tangent * Vec3(1.0, 0.5, 0.2).normalized() * slip * eps / (f.tangent * Vec3(1.0, 0.5, 0.2).normalized()).norm();
        const Vec3 g = f.gradient(x, eps);
        const double h = 1e-9;
        for (int k = 0; k < 3; ++k) {
            Vec3 e = Vec3::Zero();
            e[k] = h;
            const double fd = (f.value(x + e, eps) - f.value(x - e, eps)) / (2 * h);
            EXPECT_NEAR(g[k], fd, 1e-6 * f.bound) << "slip " << slip << " eps, component " << k;
        }
        // The force never exceeds mu lambda and equals it when sliding.
        EXPECT_LE(g.norm(), f.bound * (1 + 1e-12));
        if (slip > 1) {
            EXPECT_NEAR(g.norm(), f.bound, 1e-12 * f.bound);
        }
        // The Hessian is PSD and has no normal component.
        const Mat3 H = f.hessian(x, eps);
        Eigen::SelfAdjointEigenSolver<Mat3> es(0.5 * (H + H.transpose()));
        EXPECT_GT(es.eigenvalues().minCoeff(), -1e-12 * H.norm());
        const Vec3 n = Vec3(0.3, -0.2, 1.0).normalized();
        EXPECT_LT((H * n).norm(), 1e-9 * H.norm());
    }
}

TEST(Friction, PotentialIsC1AtTheSmoothingSlip)
{
    const sim::FrictionContact f = example_contact();
    const double eps = 1e-4;
    const Vec3 dir = (f.tangent * Vec3(0.2, 1.0, 0.0)).normalized();
    const Vec3 below = f.anchor + dir * eps * (1 - 1e-9), above = f.anchor + dir * eps * (1 + 1e-9);
    EXPECT_NEAR(f.value(below, eps), f.value(above, eps), 1e-8 * f.bound * eps);  // the points are 2e-9 eps apart
    EXPECT_NEAR((f.gradient(below, eps) - f.gradient(above, eps)).norm(), 0.0, 1e-7 * f.bound);
    // At zero slip: no force.
    EXPECT_EQ(f.gradient(f.anchor, eps).norm(), 0.0);
}

/// A small sheet resting on a plane through the origin tilted by `slope` about y, draped with
/// friction mu; returns how far its centre moved (m) and whether it converged.
std::pair<double, bool> slide_on_incline(double slope, double mu, int max_steps)
{
    const model::Grid grid = test::square_grid(5, 0.2);
    const model::ClothModel m = model::make_cloth_model(test::cotton_like(), grid, {});
    const Eigen::AngleAxisd tilt(slope, Vec3::UnitY());
    const Vec3 n = tilt * Vec3::UnitZ();
    geometry::ObstacleSet obstacles;
    obstacles.add(std::make_unique<geometry::Plane>(Vec3::Zero(), n));
    Positions start = model::flat_grid(grid, Vec3::Zero());
    for (Vec3& p : start) p = tilt * p + 0.7e-3 * n;  // within the contact distance (1 mm)
    sim::SolverOptions o;
    o.friction = mu;
    o.max_steps = max_steps;
    const sim::Problem problem{&m, &obstacles, start, {}};
    const sim::Result r = sim::drape(problem, o);
    const int centre = grid.index(2, 2);
    EXPECT_GT(sim::min_obstacle_distance(obstacles, r.x), 0.0);
    return {(r.x[centre] - start[centre]).norm(), r.converged};
}

TEST(Friction, ClothSticksOnASlopeFlatterThanItsFrictionAngle)
{
    // tan(15 deg) = 0.27 < 0.5: static friction holds the cloth.
    const auto [moved, converged] = slide_on_incline(15.0 * std::numbers::pi / 180.0, 0.5, 0);
    EXPECT_TRUE(converged);
    EXPECT_LT(moved, 2e-3) << "m";
}

TEST(Friction, ClothSlidesOnASlopeSteeperThanItsFrictionAngle)
{
    // tan(15 deg) = 0.27 > 0.1: the cloth slides (and never comes to rest on an endless plane).
    const auto [moved, converged] = slide_on_incline(15.0 * std::numbers::pi / 180.0, 0.1, 30);
    EXPECT_FALSE(converged);
    EXPECT_GT(moved, 2e-2) << "m";
}

}  // namespace
}  // namespace woven
