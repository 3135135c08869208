#pragma once
// Internal to the instruments: the model of a specimen, and the summary of a simulated curve.
#include "woven/kes/fabric.hpp"
#include "woven/model/cloth_model.hpp"
#include "woven/testers/kes_bending.hpp"

namespace woven::testers {

/// The model under test for a specimen grid: options as given, gravity switched off when
/// `gravity` is false (KES instruments hold the specimen vertical). The stretch scale C0 is
/// the model's default for the grid, chosen as under standard gravity when gravity is off
/// (choose_C0 would otherwise give no stretch well at all).
model::ClothModel instrument_model(const kes::FabricData& fabric, const model::Grid& grid, const model::ModelOptions& options,
                                   bool gravity);

/// Fills the summary of a simulated KES curve: its slope over [lo, hi] against the input
/// summary, and the largest relative difference from the input curve over the comparison
/// range (points with y_input > 0).
void finish_kes_result(KesCurveResult& r, double input_summary, double lo, double hi);

/// The legs of a loop run: `steps` per half amplitude, 0 -> +max -> -max -> 0.
std::vector<double> loop_path(double max, int steps);

/// Fills a loop's summaries (KesCurveResult's loop fields), r.loop_x/loop_y set, the input loop
/// of `law` (half widths in the curve's x units) around the mean slope `slope`; `steps` per
/// half amplitude; widths at `at` (and `at5` if > 0).
void finish_loop(KesCurveResult& r, double slope, const model::SlipLaw& law, double rise, int steps, double lo, double hi, double at, double at5,
                 double input_width, double input_width5);

}  // namespace woven::testers
