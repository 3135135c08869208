#pragma once
// Fitting a fabric (paper Sec. 5.1): its three first-stage KES curves, each fitted piecewise
// (quadratic segment(s) from the origin, then the outer line). The model's bending and trellis
// energies are built from this, and `woven fit` shows it.
#include <optional>
#include <string>

#include "woven/kes/curve.hpp"
#include "woven/kes/fabric.hpp"

namespace woven::kes {

/// A fabric with its curves fitted, in KES units.
struct FittedFabric {
    std::string name;
    double areal_density_mg_cm2 = 0;  ///< W, mg/cm^2
    CurveFit bending_warp;            ///< KES-FB2 warp: curvature K (1/cm) -> moment M (gf.cm/cm)
    CurveFit bending_weft;            ///< KES-FB2 weft: the same
    CurveFit shear;                   ///< KES-FB1: shear angle (deg) -> force F (gf/cm)
    std::optional<double> bias_B;     ///< KES-FB2 on a 45-degree specimen: B (gf.cm^2/cm), when measured
};

/// Fits the fabric's bending (warp, weft) and shear curves (Sec. 5.1) with bending_fit_options
/// and shear_fit_options. Throws InputError naming the fabric and the curve
/// ("fabric 'NAME': bending.warp: ...") when a curve cannot be fitted.
FittedFabric fit_fabric(const FabricData& fabric);

}  // namespace woven::kes
