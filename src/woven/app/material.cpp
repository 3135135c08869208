#include "woven/app/material.hpp"

#include <iomanip>
#include <sstream>

#include "woven/common/error.hpp"
#include "woven/testers/kes_shear.hpp"

namespace woven::app {

void resolve_shear_law(const kes::FabricData& fabric, model::ModelOptions& options, std::vector<std::string>& warnings)
{
    options.shear_scale = 1.0;
    if (options.shear_law != model::ShearLaw::DEEMBEDDED) return;
    try {
        const double scale = testers::shear_deembedding(fabric, options);
        if (!(scale >= kPlausibleShearScale[0] && scale <= kPlausibleShearScale[1])) {
            // A factor far from the end effect's few per mille is a failed instrument (a curve
            // too far from linear for the virtual FB1 to read), not a material property.
            std::ostringstream w;
            w << "fabric '" << fabric.name << "': the shear de-embedding factor " << std::setprecision(4) << scale << " is outside the plausible "
              << kPlausibleShearScale[0] << " .. " << kPlausibleShearScale[1]
              << " (1.001 .. 1.013 for the built-in fabrics); the curve is used as measured";
            warnings.push_back(w.str());
            return;
        }
        options.shear_scale = scale;
    } catch (const RuntimeError& e) {
        // The run need not fail with its side instrument: it keeps the law as measured.
        warnings.push_back("fabric '" + fabric.name + "': the shear law could not be de-embedded (" + e.what() + "); the curve is used as measured");
    }
}

std::string shear_law_text(const model::ModelOptions& options)
{
    std::ostringstream s;
    s << "shear law " << to_string(options.shear_law) << " (input curve x " << std::fixed << std::setprecision(4) << options.shear_scale << ")";
    return s.str();
}

}  // namespace woven::app
