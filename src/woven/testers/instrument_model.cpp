#include "woven/testers/instrument_model.hpp"

#include <algorithm>
#include <cmath>

#include "woven/common/units.hpp"

namespace woven::testers {

model::ClothModel instrument_model(const kes::FabricData& fabric, const model::Grid& grid, const model::ModelOptions& options, bool gravity)
{
    model::ModelOptions mo = options;
    if (!gravity) {
        if (!(mo.C0 > 0)) {
            const double W = fabric.areal_density_mg_cm2 * units::kMgPerCm2ToKgPerM2;
            const double hang = 0.5 * std::max(grid.nu - 1, grid.nv - 1) * grid.sigma;
            mo.C0 = model::choose_C0(W, units::kStandardGravity, grid.sigma, hang);
        }
        mo.gravity = 0;
    }
    return model::make_cloth_model(fabric, grid, mo);
}

void finish_kes_result(KesCurveResult& r, double input_summary, double lo, double hi)
{
    r.input_summary = input_summary;
    r.simulated_summary = window_slope(r.x, r.y, lo, hi);
    r.summary_rel_error = (r.simulated_summary - input_summary) / input_summary;
    r.curve_max_rel_error = 0;
    for (size_t k = 0; k < r.x.size(); ++k) {
        if (r.x[k] < r.compare_from - 1e-12 || r.x[k] > r.compare_to + 1e-12 || !(r.y_input[k] > 0)) continue;
        r.curve_max_rel_error = std::max(r.curve_max_rel_error, std::abs(r.y[k] - r.y_input[k]) / r.y_input[k]);
    }
}

}  // namespace woven::testers
