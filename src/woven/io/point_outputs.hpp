#pragma once
// A job's main numbers read back from the manifest it wrote: the columns of a sweep's tables
// (batch/sweep_merge) and of the report page's points (app/report.hpp).
#include <string>

#include <nlohmann/json.hpp>

namespace woven::io {

/// The main outputs of a point from its manifest, one flat object per command: drape (energy_J,
/// max_residual_rel, converged, steps, folds...), cusick (drape_coefficient_percent and _std,
/// nodes per run, energy_J...), garment (hem_nodes, flare, length_drop_m, the largest seam gap
/// over the spacing...), kes-test (each test's simulated and input summary values).
nlohmann::json point_outputs(const std::string& command, const nlohmann::json& manifest);

}  // namespace woven::io
