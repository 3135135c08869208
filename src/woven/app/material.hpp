#pragma once
// The material law a run's model carries, resolved from the fabric's measurements before the
// model is built: the shear law de-embedded from the KES-FB1 reading (model::ShearLaw).
#include <string>
#include <vector>

#include "woven/kes/fabric.hpp"
#include "woven/model/cloth_model.hpp"

namespace woven::app {

/// De-embedding factors taken as the end effect they stand for (docs/VALIDATION.md: 1.0012 ..
/// 1.0126 for the built-in fabrics); a factor outside is a failed virtual instrument.
inline constexpr double kPlausibleShearScale[2] = {0.98, 1.10};

/// Sets options.shear_scale for options.shear_law: DEEMBEDDED runs the virtual FB1
/// (testers::shear_deembedding at testers::kDeembeddingSpacing, a fraction of a second);
/// MEASURED and the paper's discretization keep 1. Adds a warning to `warnings` if the virtual
/// FB1 fails or finds a factor outside kPlausibleShearScale (the curve is then used as
/// measured: 1).
void resolve_shear_law(const kes::FabricData& fabric, model::ModelOptions& options, std::vector<std::string>& warnings);

/// "shear law deembedded (input curve x 1.0081)", for a run's progress lines.
std::string shear_law_text(const model::ModelOptions& options);

}  // namespace woven::app
