#pragma once
// The exact elastica of a uniformly loaded inextensible cantilever (the reference of the
// cantilever test, ASTM D1388 / Peirce 1930):
//
//   dtheta/ds = K(M),   dM/ds = -w (L - s) cos(theta),   theta(0) = 0,   M(L) = 0
//
// s: arc length from the clamp (m), theta: slope below the horizontal (rad), M: bending moment
// per unit width (N m / m), w: weight per unit area (N/m^2), K(M): curvature of the fabric at
// moment M (1/m; for a linear fabric K = M / EI, EI per unit width in N m). For linear K this
// is EI theta'' = -w (L - s) cos theta with theta'(L) = 0. Solved by shooting on M(0) with a
// fixed-step fourth-order Runge-Kutta integration and bisection.
#include <functional>
#include <vector>

namespace woven::testers {

/// Curvature (1/m) as a function of bending moment per unit width (N): increasing, K(0) = 0.
using CurvatureOfMoment = std::function<double(double)>;

/// The cantilever's shape and tip, all SI.
struct ElasticaSolution {
    double length = 0;                   ///< L, m
    double root_moment = 0;              ///< M(0), N m / m
    double tip_x = 0;                    ///< horizontal distance of the tip from the clamp, m
    double tip_drop = 0;                 ///< vertical drop of the tip below the clamp, m (> 0)
    double chord_angle = 0;              ///< atan(tip_drop / tip_x), rad
    std::vector<double> s, x, z, theta;  ///< the shape: arc length, position (z up), slope
};

/// Solves the elastica for overhang `length` (m), weight per unit area `w` (N/m^2) and the
/// fabric's law K(M). `steps`: Runge-Kutta steps along the strip. Throws InputError for
/// non-positive length or load.
ElasticaSolution cantilever_elastica(double length, double w, const CurvatureOfMoment& curvature, int steps = 2000);

/// The same for a linear fabric of flexural rigidity EI (N m per unit width: K = M / EI).
ElasticaSolution cantilever_elastica_linear(double length, double w, double EI, int steps = 2000);

/// The overhang (m) at which the tip chord angle reaches `chord_angle` (rad, in (0, pi/2)):
/// bisection on L. Peirce's rule (ASTM D1388): at 41.5 degrees, L = 2 c with c the bending
/// length.
double elastica_overhang_for_chord_angle(double chord_angle, double w, const CurvatureOfMoment& curvature);

/// For a linear fabric, L/c as a function of the tip chord angle: the inverse of the chord
/// angle of the dimensionless elastica (lambda = (L/c)^3 = w L^3 / EI). Converts a measured
/// chord angle at a known overhang into a bending length c = L / ratio. Tabulated once on
/// first use.
double overhang_ratio_for_chord_angle(double chord_angle);

/// Peirce's chord angle of ASTM D1388 (41.5 degrees), rad.
inline constexpr double kPeirceChordAngle = 41.5 * 3.14159265358979323846 / 180.0;

}  // namespace woven::testers
