#include "woven/testers/drape_model.hpp"

#include <iomanip>
#include <sstream>
#include <utility>

#include "woven/common/error.hpp"
#include "woven/testers/kes_shear.hpp"

namespace woven::testers {

void resolve_shear_law(const kes::FabricData& fabric, model::ModelOptions& options, std::vector<std::string>& warnings)
{
    options.shear_scale = 1.0;
    if (options.shear_law != model::ShearLaw::DEEMBEDDED) return;
    try {
        const double scale = shear_deembedding(fabric, options);
        if (!(scale >= kPlausibleShearScale[0] && scale <= kPlausibleShearScale[1])) {
            // A factor far from the end effect's few per mille is a failed instrument (a curve
            // too far from linear for the virtual FB1 to read), not a material property.
            std::ostringstream w;
            w << "fabric '" << fabric.name << "': the shear de-embedding factor " << std::setprecision(4) << scale
              << " is outside the plausible " << kPlausibleShearScale[0] << " .. " << kPlausibleShearScale[1]
              << " (1.001 .. 1.013 for the built-in fabrics); the curve is used as measured";
            warnings.push_back(w.str());
            return;
        }
        options.shear_scale = scale;
    } catch (const RuntimeError& e) {
        // The run need not fail with its side instrument: it keeps the law as measured.
        warnings.push_back("fabric '" + fabric.name + "': the shear law could not be de-embedded (" + e.what()
                           + "); the curve is used as measured");
    }
}

model::ClothModel make_drape_model(const kes::FabricData& fabric, const model::Grid& grid, const model::ModelOptions& options,
                                   std::vector<std::string>& warnings, std::vector<char> active, const std::vector<double>& area_m2,
                                   model::ModelOptions* options_used)
{
    model::ModelOptions resolved = options;
    resolve_shear_law(fabric, resolved, warnings);
    if (options_used) *options_used = resolved;
    return model::make_cloth_model(fabric, grid, resolved, std::move(active), area_m2);
}

}  // namespace woven::testers
