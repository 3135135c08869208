#include "woven/kes/fit.hpp"

namespace woven::kes {

FittedFabric fit_fabric(const FabricData& fabric)
{
    const std::string where = "fabric '" + fabric.name + "'";
    FittedFabric f;
    f.name = fabric.name;
    f.areal_density_mg_cm2 = fabric.areal_density_mg_cm2;
    f.bending_warp = fit_first_stage(fabric.bending_warp.curve, bending_fit_options(), where + ": bending.warp");
    f.bending_weft = fit_first_stage(fabric.bending_weft.curve, bending_fit_options(), where + ": bending.weft");
    f.shear = fit_first_stage(fabric.shear.curve, shear_fit_options(), where + ": shear");
    f.bias_B = fabric.bias_B;
    return f;
}

}  // namespace woven::kes
