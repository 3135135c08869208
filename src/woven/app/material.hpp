#pragma once
// The material law a run's model carries, resolved from the fabric's measurements before the
// model is built: the shear law de-embedded from the KES-FB1 reading (model::ShearLaw).
#include <string>
#include <vector>

#include "woven/kes/fabric.hpp"
#include "woven/model/cloth_model.hpp"
#include "woven/testers/drape_model.hpp"

namespace woven::app {

/// The shear law resolved before the model is built: testers/drape_model.hpp (where a C++
/// program using the installed library finds it too).
using testers::kPlausibleShearScale;
using testers::resolve_shear_law;

/// "shear law deembedded (input curve x 1.0081)", for a run's progress lines.
std::string shear_law_text(const model::ModelOptions& options);

}  // namespace woven::app
