#include "woven/model/curvature.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace woven::model {

CurvatureValue thread_curvature(double theta, double sigma)
{
    constexpr double kQuarterPi = std::numbers::pi / 4.0;
    if (theta > kQuarterPi) {
        // Circle through the three particles: K = (2/sigma) cos(theta/2), K'' = -K/4.
        const double K = circle_curvature(std::cos(theta), sigma);
        return {K, -1.0 / sigma * std::sin(theta / 2.0), -0.25 * K};
    }
    if (theta <= 0) {
        const double inf = std::numeric_limits<double>::infinity();
        return {inf, -inf, inf};
    }
    const double alpha = 2.0 / sigma * std::cos(std::numbers::pi / 8.0);
    const double beta = 1.0 / sigma * std::sin(std::numbers::pi / 8.0);
    const double a = kQuarterPi * kQuarterPi * beta;  // the a of a/theta + b (Sec. 5.2)
    return {a / theta + alpha - kQuarterPi * beta, -a / (theta * theta), 2.0 * a / (theta * theta * theta)};
}

double circle_curvature(double c, double sigma) { return std::sqrt(std::max(0.0, 2.0 * (1.0 + c))) / sigma; }

}  // namespace woven::model
