#pragma once
// The experiment job (woven experiment cube|map|figure1): the paper's experiments (Sec. 6,
// Fig. 1, Fig. 8), drawn and measured. Each experiment's drapes are a sweep plan written into its
// sweep folder and run there by the sweep's own point loop (sweep.hpp: resume, verify, jobs,
// ranks); the experiment then reads each point's report.json and drape.obj back and writes
// pictures, tables (Markdown) and the raw numbers (JSON) as one set.
#include <array>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "woven/app/progress.hpp"
#include "woven/batch/sweep.hpp"
#include "woven/common/choice.hpp"

namespace woven::batch {

enum class Experiment { CUBE, MAP, FIGURE1 };
inline constexpr std::array<Named<Experiment>, 3> kExperimentNames{
    {{Experiment::CUBE, "cube"}, {Experiment::MAP, "map"}, {Experiment::FIGURE1, "figure1"}}};

/// The limits of an experiment's options (the job checks them; --help shows them).
inline constexpr long long kExperimentSeedsRange[2] = {1, 100};  ///< --seeds
inline constexpr long long kExperimentGridRange[2] = {3, 401};   ///< --grid
inline constexpr long long kMapGridRange[2] = {2, 9};            ///< --map-grid: each of R and L
/// What --map-grid expects: "expected RxL: R ratios by L bending lengths, each an integer in [2, 9]".
std::string map_grid_expected();

struct ExperimentRequest {
    Experiment which = Experiment::CUBE;
    std::filesystem::path executable;  ///< the woven program that runs each drape (SweepRunOptions::executable)
    /// Not docs/experiments: a run in a clone must not overwrite the committed figures.
    std::filesystem::path out = "out/experiments";
    int seeds = 5;                  ///< cube: seeds 1 .. seeds per fabric, kExperimentSeedsRange
    std::optional<int> grid;        ///< particles along the cloth's longer side, kExperimentGridRange (default: the scene's)
    int threads = 1;                ///< per drape (0: all cores)
    int map_rows = 5, map_columns = 4;           ///< map: ratios by bending lengths, each in kMapGridRange
    std::optional<std::filesystem::path> reuse;  ///< map: an earlier corner_map.json whose drapes to analyse again
    std::optional<std::filesystem::path> sweep;  ///< the sweep folder (default out/experiment-<which>)
    bool plan_only = false;         ///< write the plan (and the map's fabric files) and stop
    int jobs = 1;                   ///< drapes at once on this machine, kJobsRange
    ShardSpec shard;                ///< this process's drapes
    std::vector<std::string> fabrics = {"cotton", "wool", "polyester_cotton"};
    std::string command;            ///< the command line the results record
    /// Each may be empty: the inputs' warnings; each drape as it starts (what it drapes).
    std::function<void(const std::vector<std::string>&)> on_warnings;
    std::function<void(const std::string&)> on_drape;
    /// The lines the sweep of its drapes reports (SweepRunOptions::on_line).
    std::function<void(const std::string& line, bool out)> on_sweep_line;
    /// Progress, interrupts and the display while the job runs (progress.hpp).
    app::Monitor monitor;
};

struct ExperimentResult {
    std::string message;       ///< what was written (or the plan, or this shard's share done), one line
    nlohmann::json report;     ///< the set's JSON as written (cube_results.json, corner_map.json, figure1.json); null without a set
    bool interrupted = false;  ///< SIGINT / SIGTERM: nothing written (the folder keeps the previous set)
    int signal = 0;            ///< the signal (0: drape's interrupt flag)
};

/// Runs the experiment's drapes (those not done yet) and writes its set. InputError for a bad
/// request (nothing written); RuntimeError when a drape failed.
ExperimentResult experiment(const ExperimentRequest& request);

}  // namespace woven::batch
