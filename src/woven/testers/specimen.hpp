#pragma once
// What the virtual instruments share: a rectangular specimen laid out on the model's particle
// grid with its length along the warp or the weft threads, and the fabric's fitted curves.
//
// Grid convention (model/cloth_model.hpp): particle (i, j), weft threads along i, warp threads
// along j. A WARP specimen has its length ("along") on j, so its along-threads are warp threads
// and bend with the KES warp curve; a WEFT specimen has its length on i.
#include <string>

#include "woven/kes/curve.hpp"
#include "woven/kes/fabric.hpp"
#include "woven/model/cloth_model.hpp"

namespace woven::testers {

/// The thread direction along a specimen's length.
enum class Direction { WARP, WEFT };

/// "warp" or "weft".
std::string to_string(Direction d);

/// A specimen of n_along x n_across particles at spacing sigma (m).
struct Layout {
    Direction direction = Direction::WARP;
    int n_along = 0, n_across = 0;
    double sigma = 0;

    /// The model grid: nu x nv with nu = n_across (WARP) or n_along (WEFT).
    model::Grid grid() const;
    /// Particle index of (along a, across b).
    int index(int a, int b) const;
};

/// x such that fit.value(x) = y (the fitted curves are increasing and odd).
double inverse_value(const kes::CurveFit& fit, double y);

/// The fabric's fitted first-stage curve of a direction (Sec. 5.1 fit, KES units).
kes::CurveFit fitted_bending(const kes::FabricData& fabric, Direction d);
kes::CurveFit fitted_shear(const kes::FabricData& fabric);

/// The curve as given by the fabric (measured points, or synthesised from summary values).
const kes::Curve& input_bending(const kes::FabricData& fabric, Direction d);

/// The fabric's KES summary value B of a direction (gf.cm^2/cm): the file's, when it gives
/// summary values, otherwise the slope of its curve over the KES window 0.5-1.5 1/cm.
double input_B(const kes::FabricData& fabric, Direction d);
/// The same for G (gf/(cm.deg)), window 0.5-5 degrees.
double input_G(const kes::FabricData& fabric);

/// The curve's value at x, linearly interpolated between its points (the input the simulated
/// curves are compared with).
double curve_value(const kes::Curve& curve, double x);

/// KES slope of a sampled curve over [lo, hi]: (y(hi) - y(lo)) / (hi - lo), y interpolated
/// linearly (kes::data_slope, the definition the input summary values are checked with).
double window_slope(const std::vector<double>& x, const std::vector<double>& y, double lo, double hi);

}  // namespace woven::testers
