// model::thread_curvature: the corrected Eq. (13) (MODEL-NOTES "Eq. (13) as printed has a sign
// error").
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "woven/model/curvature.hpp"

namespace woven::model {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kQuarter = kPi / 4;

/// The small-angle branch exactly as printed in the paper: -(pi/4)^2 beta/theta + alpha + (pi/4) beta.
double printed_eq13(double theta, double sigma)
{
    const double alpha = 2.0 / sigma * std::cos(kPi / 8), beta = 1.0 / sigma * std::sin(kPi / 8);
    return -kQuarter * kQuarter * beta / theta + alpha + kQuarter * beta;
}

class Curvature : public testing::TestWithParam<double> {};  // sigma

TEST_P(Curvature, ContinuousInValueAndSlopeAtQuarterPi)
{
    const double sigma = GetParam();
    const CurvatureValue below = thread_curvature(kQuarter, sigma);                       // theta <= pi/4: a/theta + b
    const CurvatureValue above = thread_curvature(std::nextafter(kQuarter, 4.0), sigma);  // circle branch
    EXPECT_NEAR(below.K, above.K, 1e-9 * std::abs(above.K));
    EXPECT_NEAR(below.dK, above.dK, 1e-9 * std::abs(above.dK));
    // Both equal the closed forms: K = alpha = (2/sigma) cos(pi/8), dK/dtheta = -beta.
    EXPECT_NEAR(below.K, 2.0 / sigma * std::cos(kPi / 8), 1e-12 / sigma);
    EXPECT_NEAR(below.dK, -1.0 / sigma * std::sin(kPi / 8), 1e-12 / sigma);
}

TEST_P(Curvature, MonotoneDecreasingOnZeroToPi)
{
    const double sigma = GetParam();
    double previous = thread_curvature(1e-4, sigma).K;
    for (int k = 1; k <= 20000; ++k) {
        const double theta = 1e-4 + (kPi - 1e-4) * k / 20000.0;
        const CurvatureValue v = thread_curvature(theta, sigma);
        ASSERT_LT(v.K, previous) << "theta " << theta;
        ASSERT_LT(v.dK, 0.0) << "theta " << theta;
        previous = v.K;
    }
}

TEST_P(Curvature, InfiniteAtZeroAndZeroWhenStraight)
{
    const double sigma = GetParam();
    EXPECT_GT(thread_curvature(1e-6, sigma).K, 1e5 / sigma);
    EXPECT_GT(thread_curvature(1e-9, sigma).K, thread_curvature(1e-6, sigma).K);
    EXPECT_TRUE(std::isinf(thread_curvature(0.0, sigma).K));
    EXPECT_NEAR(thread_curvature(kPi, sigma).K, 0.0, 1e-15 / sigma);  // 2/sigma cos(pi/2), rounded
    EXPECT_NEAR(thread_curvature(kPi, sigma).dK, -1.0 / sigma, 1e-15 / sigma);
    // Above pi/4: the circle through three particles spaced sigma, K = 1/R = 4 area / (a b c).
    for (double theta : {kQuarter + 0.01, 1.0, 2.0, 3.0}) {
        const double ax = sigma, bx = sigma * std::cos(theta), by = sigma * std::sin(theta);
        const double c = std::hypot(ax - bx, by), area = 0.5 * ax * by;
        EXPECT_NEAR(thread_curvature(theta, sigma).K, 4.0 * area / (sigma * sigma * c), 1e-12 / sigma) << theta;
    }
}

TEST_P(Curvature, DiffersFromThePrintedBranch)
{
    const double sigma = GetParam();
    // The printed branch meets the circle branch in value at pi/4 but with slope +beta (not C1),
    // and tends to -infinity; the corrected one tends to +infinity.
    EXPECT_NEAR(printed_eq13(kQuarter, sigma), thread_curvature(kQuarter, sigma).K, 1e-12 / sigma);
    const double h = 1e-6;
    const double printed_slope = (printed_eq13(kQuarter + h, sigma) - printed_eq13(kQuarter - h, sigma)) / (2 * h);
    EXPECT_NEAR(printed_slope, std::sin(kPi / 8) / sigma, 1e-6 / sigma);
    EXPECT_LT(thread_curvature(kQuarter, sigma).dK, 0.0);
    EXPECT_LT(printed_eq13(1e-6, sigma), -1e5 / sigma);
    EXPECT_GT(thread_curvature(1e-6, sigma).K, 1e5 / sigma);
    for (double theta : {0.05, 0.2, 0.5, 0.7}) {
        EXPECT_GT(thread_curvature(theta, sigma).K - printed_eq13(theta, sigma), 0.01 / sigma) << theta;
    }
}

TEST_P(Curvature, DerivativesMatchFiniteDifferencesOnBothBranches)
{
    const double sigma = GetParam();
    for (double theta : {1e-3, 0.01, 0.1, 0.4, kQuarter - 1e-3, kQuarter + 1e-3, 1.0, 2.0, 3.0, kPi - 1e-3}) {
        const double h = 1e-6 * theta;
        const CurvatureValue v = thread_curvature(theta, sigma), p = thread_curvature(theta + h, sigma),
                             m = thread_curvature(theta - h, sigma);
        EXPECT_NEAR((p.K - m.K) / (2 * h), v.dK, 1e-7 * std::abs(v.dK)) << theta;
        EXPECT_NEAR((p.dK - m.dK) / (2 * h), v.d2K, 1e-7 * std::abs(v.d2K) + 1e-9 / sigma) << theta;
    }
}

TEST_P(Curvature, ScalesAsOneOverSigma)
{
    const double sigma = GetParam();
    for (double theta : {0.1, kQuarter, 1.5, 3.0}) {
        EXPECT_NEAR(thread_curvature(theta, sigma).K * sigma, thread_curvature(theta, 1.0).K, 1e-13 * thread_curvature(theta, 1.0).K);
    }
}

INSTANTIATE_TEST_SUITE_P(Sigmas, Curvature, testing::Values(2.0 /* cm: the paper's cloth */, 0.02 /* m */, 1.0, 0.5));

}  // namespace
}  // namespace woven::model
