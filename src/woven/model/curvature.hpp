#pragma once
// Thread curvature from the bending angle, the paper's Eq. (13) with its sign corrected
// (docs/MODEL.md "Eq. 13's sign"): the printed small-angle branch -(pi/4)^2 beta/theta + alpha + (pi/4) beta tends
// to -infinity and is not C1; the branch used here is C0 and C1 at pi/4 and -> +infinity at 0:
//
//   K(theta) = (pi/4)^2 beta / theta + alpha - (pi/4) beta,   0 < theta <= pi/4
//   K(theta) = (2/sigma) cos(theta/2),                        pi/4 < theta <= pi
//   alpha = (2/sigma) cos(pi/8),  beta = (1/sigma) sin(pi/8)
//
// theta: the angle at the middle particle of three along a thread (pi when straight).
#include <numbers>

namespace woven::model {

/// K and its first two derivatives with respect to theta. Units: 1/[sigma].
struct CurvatureValue {
    double K = 0;
    double dK = 0;   ///< dK/dtheta
    double d2K = 0;  ///< d2K/dtheta2
};

/// Corrected Eq. (13). sigma in the unit the curvature is wanted per (the paper: cm).
CurvatureValue thread_curvature(double theta, double sigma);

/// Eq. (13), upper branch (theta > pi/4), written once: the circle through three particles
/// spaced sigma, K = (2/sigma) cos(theta/2) = sqrt(2 (1 + c)) / sigma with c = cos(theta).
/// As a function of c it is smooth at a straight thread (c = -1), where theta is not.
double circle_curvature(double c, double sigma);

/// cos(pi/4): the upper branch holds for c < kBranchCosine.
inline constexpr double kBranchCosine = std::numbers::sqrt2 / 2.0;

}  // namespace woven::model
