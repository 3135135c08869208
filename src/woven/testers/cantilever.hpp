#pragma once
// Virtual cantilever bending test (ASTM D1388 / BS 3356, Peirce 1930): a strip of the fabric,
// 2.5 cm wide, clamped with zero slope and drooping under its own weight. The overhang L at
// which the chord from the clamp edge to the tip reaches 41.5 degrees gives the bending length
// c = L / 2 and the flexural rigidity G = W g c^3.
//
// Clamped, not pushed over a ledge: the exact reference (the elastica, testers/elastica.hpp)
// is that of a clamp with zero slope, and a ledge only approximates it (the strip on the
// platform lifts near the edge unless weighted down, the edge falls between particles); ASTM
// weights the strip on the platform with a slide for the same reason.
//
// How the strip maps onto the grid (docs/VALIDATION.md):
//
//      clamp line (s = 0)
//          |
//   row 0  |  row 1    row 2   ...   row N  (tip)         rows along the strip, sigma' apart
//    o-----|----o--------o-----...-----o                  rows 0 and 1 pinned, horizontal
//          |
//   The clamp line is midway between the two pinned rows: the first free bending angle (at
//   row 1) then stands for the strip's first sigma' of length, [0, sigma'], and the tip row
//   N at s = (N - 1/2) sigma' = L carries the last half spacing: the staggered (midpoint)
//   placement under which the discrete strip converges at second order. N is chosen from the
//   nominal spacing and the expected overhang, and sigma' = L / (N - 1/2) is then adjusted
//   continuously to find the overhang of the 41.5 degree chord. Across the width: round(w /
//   sigma) + 1 particles (the bending is uniform across; at least 2).
#include <vector>

#include "woven/kes/fabric.hpp"
#include "woven/model/cloth_model.hpp"
#include "woven/testers/elastica.hpp"
#include "woven/testers/specimen.hpp"
#include "woven/testers/static_solve.hpp"

namespace woven::testers {

/// Settings of the cantilever test (SI).
struct CantileverOptions {
    double sigma = 0.0025;                   ///< nominal particle spacing, m
    double width = 0.025;                    ///< strip width, m (ASTM D1388: 2.5 cm)
    double chord_angle = kPeirceChordAngle;  ///< rad
    model::ModelOptions model;               ///< bending form, gravity, ... of the model under test
    StaticOptions solve;
};

/// The strip at equilibrium at one overhang.
struct CantileverShape {
    double overhang = 0;             ///< L, m, from the clamp line to the tip row
    double sigma = 0;                ///< the spacing used, m
    int rows = 0;                    ///< N: rows beyond the pinned row 0
    double tip_x = 0, tip_drop = 0;  ///< tip (mean of the tip row) relative to the clamp line, m
    double chord_angle = 0;          ///< rad
    std::vector<double> x, z;        ///< centre line: along the strip and up, m, rows 0..N
    int iterations = 0;              ///< Newton iterations
};

/// The equilibrium of a strip of overhang L (m) at spacing close to options.sigma (sigma' =
/// L / (N - 1/2), N = round(L / sigma + 1/2)).
CantileverShape cantilever_at_overhang(const kes::FabricData& fabric, Direction d, double overhang, const CantileverOptions& options);

/// The same with N rows given (sigma' = L / (N - 1/2)).
CantileverShape cantilever_with_rows(const kes::FabricData& fabric, Direction d, double overhang, int rows,
                                     const CantileverOptions& options);

/// The test: the overhang of the 41.5 degree chord, simulated and exact.
struct CantileverResult {
    Direction direction = Direction::WARP;
    double overhang = 0;                    ///< simulated L at the chord angle, m
    double bending_length = 0;              ///< c = L / 2, m
    double flexural_rigidity = 0;           ///< G = W g c^3, N m (per unit width)
    double elastica_overhang = 0;           ///< the exact elastica's L for the same fabric, m
    double elastica_bending_length = 0;     ///< m
    double elastica_flexural_rigidity = 0;  ///< N m
    CantileverShape shape;                  ///< the simulated strip at its overhang
    ElasticaSolution elastica;              ///< the exact strip at its overhang
    int solves = 0;                         ///< static solves made
};

/// Runs the test: the elastica's overhang first, then the simulated one by a secant search on
/// the spacing at fixed row count.
CantileverResult cantilever_test(const kes::FabricData& fabric, Direction d, const CantileverOptions& options);

/// The fabric's law K(M) in SI (1/m of N m/m) from its fitted curve, as the continuum model
/// it stands for: WORK form, M(K) itself; SECANT form (Eq. 12), the derivative of the secant
/// energy, (M + K dM/dK) / 2.
CurvatureOfMoment fabric_curvature_law(const kes::FabricData& fabric, Direction d, model::BendingForm form, units::GramForce gf);

/// Weight per unit area W g (N/m^2) of the fabric under gravity g.
double weight_per_area(const kes::FabricData& fabric, double gravity);

/// Bending length from a chord angle at overhang L for a linear fabric: c = L / (L/c)(angle).
double bending_length_from_chord(double overhang, double chord_angle);

}  // namespace woven::testers
