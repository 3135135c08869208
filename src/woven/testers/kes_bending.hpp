#pragma once
// Virtual KES-FB2 pure bending test: a specimen 20 cm wide with 1 cm between the clamps,
// gravity off (the instrument holds it vertical), bent to curvature K = 0 .. 2.5 1/cm in steps
// by turning one clamp, at static equilibrium at each step. The moment per unit width is the
// clamp's reaction, the derivative of the equilibrium energy with respect to the clamp's
// rotation (by the envelope theorem, the pinned particles' energy gradient times their
// motion per unit rotation), in gf.cm/cm; B is its KES slope between 0.5 and 1.5 1/cm.
//
// How the specimen maps onto the grid:
//   along the bend (the thread direction tested): N + 1 rows; rows 0, 1 form the fixed clamp,
//   rows N-1, N the turning clamp; the clamp lines are midway between each pinned pair, so the
//   gap is (N - 1) sigma' with N - 1 = max(2, round(gap / sigma)) and sigma' = gap / (N - 1)
//   (the free rows 2 .. N-2 and the bending angles at rows 1 .. N-1 are the specimen between
//   the clamps). Across: round(width / sigma') + 1 particles over the full width.
//   At curvature K the pinned rows are placed on the circle of radius 1/K with chords sigma',
//   the clamp rotation being alpha = (N - 1) psi, psi = 2 asin(K sigma' / 2) the turning angle
//   per row. Eq. (13) then gives every bending angle the curvature K exactly, so the curve
//   measured by a WORK-form model is M(K) cos(psi / 2): a second-order error (K sigma')^2 / 8.
#include <vector>

#include "woven/kes/fabric.hpp"
#include "woven/model/cloth_model.hpp"
#include "woven/testers/specimen.hpp"
#include "woven/testers/static_solve.hpp"

namespace woven::testers {

/// A simulated KES curve beside the input one (KES units).
struct KesCurveResult {
    std::string test;  ///< "bending" or "shear"
    Direction direction = Direction::WARP;
    double sigma = 0;                         ///< spacing used, m
    std::vector<double> x;                    ///< imposed K (1/cm) or phi (deg)
    std::vector<double> y;                    ///< simulated M (gf.cm/cm) or F (gf/cm)
    std::vector<double> y_input;              ///< the input curve at x (its points, linearly interpolated)
    double input_summary = 0;                 ///< B or G of the input (file summary, else curve slope)
    double simulated_summary = 0;             ///< the simulated curve's KES slope
    double summary_rel_error = 0;             ///< (simulated - input) / input
    double curve_max_rel_error = 0;           ///< max |y - y_input| / y_input over the comparison range
    double compare_from = 0, compare_to = 0;  ///< the comparison range (x units)
    int iterations = 0;                       ///< Newton iterations over all steps
    /// Shear only: the force per unit length on the middle half of the moving clamp, away
    /// from the specimen's free short edges (kes_shear.hpp), its KES slope and error against
    /// the input; empty / 0 for bending.
    std::vector<double> y_central;
    double central_summary = 0, central_rel_error = 0;

    /// The full loop (model::Hysteresis::FRICTION with the curve's hysteresis width given):
    /// 0 -> +max -> -max -> 0 at equilibrium at every step, the friction state updated between
    /// steps (ClothModel::update_slip). x, y above are then its first leg; simulated_summary is
    /// the mean of the four branch slopes over the KES window (both branches, both signs), as
    /// KES reads B and G from a loop. Otherwise `loop` is false and the fields below are empty.
    bool loop = false;
    std::vector<double> loop_x, loop_y;  ///< every step of the loop, in order
    std::vector<double> loop_y_input;    ///< the input loop (input_loop_value) at loop_x
    /// Where the widths are read (x units): 1 1/cm (2HB); 0.5 and 5 degrees (2HG, 2HG5).
    double hysteresis_at = 0, hysteresis5_at = 0;
    /// The input's 2HB (2HG) and 2HG5 (0 for bending), and the simulated loop's widths there,
    /// each the mean of the widths at +x and -x.
    double input_hysteresis = 0, input_hysteresis5 = 0;
    double simulated_hysteresis = 0, simulated_hysteresis5 = 0;
    double hysteresis_rel_error = 0;  ///< the worse (larger |.|) of the widths' relative errors
    /// max |y - y_input| over the loop / max |y_input| (the loop's amplitude: a loop crosses 0,
    /// where a pointwise relative error has no meaning).
    double loop_max_rel_error = 0;
};

/// The input loop of a curve given by summary values (docs/FABRIC-FORMAT.md): around the mean
/// line S x, half width h(|x|) (2HB/2; for shear linear through 2HG/2 at 0.5 and 2HG5/2 at 5
/// degrees), the virgin leg rising as h r(|x|/x1), r(u) = 1 - (1 - u)^2, x1 = kes::kBendingRise
/// (kShearRise), a reversal from a saturated turning point x_r as Masing's rule has it,
/// h (1 - 2 r(|x - x_r| / (2 x1))). `leg`: 0 the virgin leg, 1 down from +x_max, 2 up from -x_max.
double input_loop_value(double slope, const model::SlipLaw& half_width, double rise, int leg, double x_max, double x);

/// Settings of the FB2 test (SI unless stated).
struct BendingTestOptions {
    double sigma = 0.001;        ///< nominal spacing, m
    double width = 0.20;         ///< m
    double gap = 0.01;           ///< between the clamp lines, m
    double max_curvature = 2.5;  ///< 1/cm
    double step = 0.1;           ///< 1/cm
    model::ModelOptions model;   ///< gravity is switched off
    StaticOptions solve;
};

/// Runs the FB2 test on a direction of the fabric.
KesCurveResult kes_bending_test(const kes::FabricData& fabric, Direction d, const BendingTestOptions& options);

}  // namespace woven::testers
