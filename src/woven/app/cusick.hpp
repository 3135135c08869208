#pragma once
// The cusick job (woven cusick, woven.cusick): the Cusick drape test (BS 5058, ISO 9073-9) on a
// simulated specimen (testers/cusick.hpp): drape coefficient, nodes, the shadow picture, a
// render and the mesh, written as one output set with cusick.json last.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "woven/app/files.hpp"
#include "woven/app/progress.hpp"
#include "woven/model/cloth_model.hpp"
#include "woven/testers/cusick.hpp"

namespace woven::app {

/// The limits of a cusick request's values (the command's options check the same).
inline constexpr double kCusickMaxDiameter_cm = 200;  ///< --specimen-cm, --disc-cm: (0, 200]
inline constexpr double kCusickMaxSpacing_cm = 10;    ///< --spacing-cm: (0, 10]
inline constexpr long long kCusickSeedsRange[2] = {1, 1000};
inline constexpr long long kCusickThreadsRange[2] = {0, 4096};
inline constexpr long long kCusickMaxStepsRange[2] = {0, 1000000};
inline constexpr long long kCusickShakesRange[2] = {0, 100};
inline constexpr long long kCusickJobsRange[2] = {1, 64};
inline constexpr double kCusickClampMarginRange[2] = {-2, 2};  ///< spacings
inline constexpr double kCusickGridRotationRange[2] = {-360, 360};  ///< --grid-rotation-deg
inline constexpr double kThreadCompressionRange[2] = {0, 1};        ///< --thread-compression

/// One run (one seed): what the command prints for it.
struct CusickRunLine {
    int run = 0, runs = 0;
    std::uint64_t seed = 0;
    double drape_coefficient_percent = 0;
    std::vector<double> node_angles_deg;
    bool converged = false;
    int steps = 0;
    double wall_time_s = 0;
};

struct CusickRequest {
    std::string fabric;            ///< a built-in fabric name or a fabric .toml file
    GivenFabric given_fabric;      ///< a fabric given as data instead (Python's woven.Fabric)
    double specimen_cm = 30;
    double disc_cm = 18;
    std::optional<double> spacing_cm;  ///< default: testers::CusickOptions's
    int seeds = 1;                 ///< runs, seeds seed .. seed + seeds - 1
    std::uint64_t seed = 1;
    std::optional<int> threads;
    std::optional<int> max_steps;
    std::optional<model::ShearLaw> shear_law;
    std::optional<model::Hysteresis> hysteresis;    ///< default loading-branch
    std::optional<testers::CusickProtocol> protocol;  ///< default release
    std::optional<int> shakes;
    std::optional<model::BiasBending> bias;
    std::optional<sim::SolverKind> solver;             ///< default fast
    std::optional<model::Discretization> discretization;  ///< default convergent
    std::optional<double> fall_s;                      ///< fast solver: FastSolverOptions::fall_duration (s)
    std::optional<double> thread_compression;          ///< ModelOptions::thread_compression, [0, 1]
    std::optional<double> grid_rotation_deg;           ///< CusickOptions::grid_rotation_deg
    std::optional<testers::CusickClamp> clamp;      ///< default pinned
    std::optional<double> clamp_margin;             ///< pinned clamp only, spacings
    std::optional<double> clamp_gap_mm;             ///< discs clamp only
    std::optional<std::filesystem::path> start;     ///< a cusick.obj to start from (not with search)
    bool search = false;                            ///< the search of rest states (testers::search_cusick)
    std::optional<std::vector<int>> modes;          ///< search: the guide counts (default {2})
    std::optional<int> jobs;                        ///< search: starts run at once
    std::optional<std::filesystem::path> out;       ///< absent: out/cusick-<fabric>
    bool render = true;                             ///< drape.png
    /// Each may be empty: the fabric's warnings once read; the run's one-line description
    /// before the runs (when the output folder is checked: a front end installs its signal
    /// handlers there); each run's line once it is done.
    std::function<void(const std::vector<std::string>&)> on_warnings;
    std::function<void(const std::string&)> on_start;
    std::function<void(const CusickRunLine&)> on_run;
    /// Progress, interrupts and the display while the job runs (progress.hpp).
    Monitor monitor;
};

struct CusickResult {
    nlohmann::json report;                ///< cusick.json as written (with its `files`)
    std::vector<CusickRunLine> runs;
    std::string out_dir;
    std::vector<std::string> files;       ///< the files written besides cusick.json
    bool all_converged = true;
    bool interrupted = false;             ///< stopped by a signal or on_step: the runs done are written
};

/// Checks the request, the fabric, the specimen, the memory and the output folder before
/// anything is written, runs the seeds (each with its callbacks) and writes the set.
CusickResult cusick(const CusickRequest& request);

/// The modes' default with search (one guide count: 2).
inline const std::vector<int> kCusickDefaultModes{2};

}  // namespace woven::app
