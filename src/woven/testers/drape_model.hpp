#pragma once
// The model `woven drape`, `woven cusick` and the Python module build from a fabric: the shear
// law resolved (model::ShearLaw::DEEMBEDDED: the factor found by a virtual KES-FB1) before the
// model is built. model::make_cloth_model applies ModelOptions::shear_scale as given; a C++
// program that wants the command's model calls make_drape_model (or resolve_shear_law first).
#include <string>
#include <vector>

#include "woven/kes/fabric.hpp"
#include "woven/model/cloth_model.hpp"

namespace woven::testers {

/// De-embedding factors taken as the end effect they stand for (docs/VALIDATION.md: 1.0012 ..
/// 1.0126 for the built-in fabrics); a factor outside is a failed virtual instrument.
inline constexpr double kPlausibleShearScale[2] = {0.98, 1.10};

/// Sets options.shear_scale for options.shear_law: DEEMBEDDED runs the virtual FB1
/// (shear_deembedding at kDeembeddingSpacing, a fraction of a second); MEASURED and the paper's
/// discretization keep 1. Adds a warning to `warnings` if the virtual FB1 fails or finds a
/// factor outside kPlausibleShearScale (the curve is then used as measured: 1).
void resolve_shear_law(const kes::FabricData& fabric, model::ModelOptions& options, std::vector<std::string>& warnings);

/// The command's model: resolve_shear_law on a copy of `options`, then model::make_cloth_model
/// (`active`, `area_m2` as there). `options_used`, when given, receives the options resolved.
model::ClothModel make_drape_model(const kes::FabricData& fabric, const model::Grid& grid, const model::ModelOptions& options,
                                   std::vector<std::string>& warnings, std::vector<char> active = {},
                                   const std::vector<double>& area_m2 = {}, model::ModelOptions* options_used = nullptr);

}  // namespace woven::testers
