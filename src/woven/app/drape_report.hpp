#pragma once
// What `woven drape` reports (report.json and the summary on stdout), and the fabric's key KES
// values shared with `woven fabrics`.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "woven/analysis/folds.hpp"
#include "woven/analysis/state_measures.hpp"
#include "woven/common/types.hpp"
#include "woven/geometry/obstacle.hpp"
#include "woven/kes/fabric.hpp"
#include "woven/model/cloth_model.hpp"
#include "woven/sim/drape.hpp"

namespace woven::app {

/// A fabric's summary values in KES units: from the file's summary when it gave one, else the
/// KES slope of the curve over the instrument's window (B: 0.5-1.5 1/cm, G: 0.5-5 deg).
struct KesValues {
    double W = 0;        ///< mg/cm^2
    double B_warp = 0;   ///< gf.cm^2/cm
    double B_weft = 0;   ///< gf.cm^2/cm
    double G = 0;        ///< gf/(cm.deg)
};
KesValues kes_values(const kes::FabricData& fabric);

/// A solver run's outcome and counters as a report writes them: `converged`, `steps`,
/// `iterations`, `wall_time_s` and, with `fast_counters` (the fast solver's), `factorizations`,
/// `cg_iterations`, `softened_steps`. Non-finite numbers become null (require_finite refuses them).
nlohmann::json solver_result_json(const sim::Result& result, bool fast_counters);

/// Everything report.json holds.
struct DrapeReportInput {
    std::string scene;          ///< scene name
    std::string scene_source;   ///< the file it came from
    std::string fabric;         ///< fabric name
    const kes::FabricData* fabric_data = nullptr;
    const model::ClothModel* model = nullptr;
    const model::ModelOptions* model_options = nullptr;  ///< those `model` was built with (report: `model`)
    const geometry::ObstacleSet* obstacles = nullptr;
    const sim::SolverOptions* solver = nullptr;
    const sim::Result* result = nullptr;
    double energy_initial = 0;  ///< J
    bool interrupted = false;
    std::vector<std::string> outputs;  ///< files written besides report.json
    const analysis::FoldAnalysis* folds = nullptr;  ///< the corner folds over a box, or null (report: null)
};

/// report.json's `folds`: `heights_m`, `depths_m`, `prominence_m`, `corners` (four: `billows`
/// per height, `angles_deg` and `standout_m` per height and billow), `sections`,
/// `lowest_point_m`, `hanging_m` (+x, +y, -x, -y sides), `projected_area_m2`.
nlohmann::json folds_json(const analysis::FoldAnalysis& folds, const analysis::FoldOptions& options = {});

/// One line per corner: "corner 0 (+x +y): 1 billow at 0.40 m (+2.1 deg, 0.081 m); ...".
std::string folds_summary(const nlohmann::json& folds);

/// report.json's `model`: the model the run used, so that it can be rerun and checked from its
/// folder: `discretization` (convergent|paper), `bending_form` (work|secant), `shear_law`
/// (deembedded|measured), `shear_scale` (the factor on the input shear curve), `gram_force`
/// (paper|standard) and `dyn_per_gram_force`, `tensile_stiffness_N_m` (E_t; 0 for the paper's
/// discretisation, whose threads are C0's stretch well), `C0_J`, `gravity_m_s2`, `sigma_m`.
/// `options`: those the model was built with (bending form, shear law, gram-force; the rest is
/// read from the model, as it used them).
nlohmann::json model_json(const model::ClothModel& model, const model::ModelOptions& options);

/// report.json (keys documented in README.md).
nlohmann::json drape_report(const DrapeReportInput& in);

/// The short human summary printed on stdout, from the report.
std::string drape_summary(const nlohmann::json& report);

}  // namespace woven::app
