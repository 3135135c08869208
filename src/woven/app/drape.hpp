#pragma once
// `woven drape` in its stages, so that the command (cmd_drape.cpp) and the Python module
// (python/) run the same code and write the same files: prepare_drape validates and builds the
// model, solve_drape runs the solver, finish_drape checks and measures the state reached,
// drape_report_json makes report.json and write_drape_outputs writes the output set.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "woven/analysis/folds.hpp"
#include "woven/app/files.hpp"
#include "woven/app/progress.hpp"
#include "woven/app/run_checks.hpp"
#include "woven/io/scene_file.hpp"
#include "woven/kes/fabric.hpp"
#include "woven/model/cloth_model.hpp"
#include "woven/model/outline.hpp"
#include "woven/render/drape_view.hpp"
#include "woven/sim/drape.hpp"

namespace woven::app {

/// Everything a drape needs once its inputs are validated. Not copied or moved: `problem`
/// points into `scene` and `model`.
struct DrapeSetup {
    io::SceneSpec scene;               ///< with the options applied; solver.threads = threads.used
    kes::FabricData fabric;
    std::string fabric_label;          ///< the fabric's name (report: `fabric`)
    model::Grid grid;
    std::optional<model::ClothModel> model;
    std::optional<model::ClothCut> cut;  ///< a cloth cut to [cloth.outline]
    sim::Problem problem;
    double energy_initial = 0;         ///< J, at the start
    std::string start_sha256;          ///< --start: the start file's SHA-256 (empty: the scene's flat start)
    ThreadCount threads;
    int max_steps = 0;                 ///< the step limit in force (the solver's default for 0)

    DrapeSetup() = default;
    DrapeSetup(const DrapeSetup&) = delete;
    DrapeSetup& operator=(const DrapeSetup&) = delete;
};

/// The limits of a drape request's values (the command's options check the same).
inline constexpr long long kGridRange[2] = {3, 100000};            ///< --grid
inline constexpr long long kMaxStepsRange[2] = {0, 1'000'000'000};  ///< --max-steps
inline constexpr long long kPictureSizeRange[2] = {1, 16384};       ///< --width, --height, pixels

/// A drape's options as a front end got them (drape_request checks and reads them); absent:
/// the scene's.
struct DrapeValues {
    std::optional<Given<long long>> grid;  ///< particles along the cloth's longer side, kGridRange
    std::optional<std::string> solver;     ///< sim::kSolverKindNames
    std::optional<Given<std::uint64_t>> seed;
    std::optional<Given<long long>> threads;    ///< 0: all cores available; at most io::kMaxThreads
    std::optional<Given<long long>> max_steps;  ///< 0: the solver's default; kMaxStepsRange
    std::optional<Given<double>> perturb_m;     ///< the fast solver's start perturbation, [0, io::kMaxPerturbation_m]
    std::optional<std::string> hysteresis;      ///< model::kHysteresisNames
    std::optional<std::string> bias;            ///< model::kBiasBendingNames
    std::optional<std::string> start;           ///< a drape.obj path (the command's --start)
};

/// What to drape: a scene (by name or file, or given as a spec), its overrides, and a start.
/// Absent overrides keep the scene's. The overrides come checked from drape_request (prepare_drape
/// does not check their ranges again); errors found later (a grid too large for the memory, a
/// solver without the hysteresis asked for) name a field as `naming` says.
struct DrapeRequest {
    std::string scene = "cube";                ///< a built-in scene name or a scene .toml file
    std::optional<io::SceneSpec> scene_spec;   ///< a scene given as an object (Python's woven.Scene) instead of `scene`
    std::optional<std::string> fabric;         ///< a built-in fabric name or a fabric .toml file
    std::optional<kes::FabricData> fabric_data;  ///< a fabric given as data (Python's woven.Fabric) instead of `fabric`
    std::string fabric_source;                 ///< names `fabric_data` in the fitting's errors
    std::optional<int> grid;                   ///< particles along the cloth's longer side, kGridRange
    std::optional<sim::SolverKind> solver;
    std::optional<std::uint64_t> seed;
    std::optional<int> threads;                ///< 0: all cores available; at most io::kMaxThreads
    std::optional<int> max_steps;              ///< 0: the solver's default; kMaxStepsRange
    std::optional<double> perturb_m;           ///< the fast solver's start perturbation, [0, io::kMaxPerturbation_m]
    std::optional<model::Hysteresis> hysteresis;
    std::optional<model::BiasBending> bias;
    std::optional<std::filesystem::path> start;  ///< a drape.obj of the same scene and grid to start from
    /// A start instead of the scene's (the Python module's initial_positions=): one position
    /// per grid particle (m), the scene's pinned particles where the scene puts them; its
    /// SHA-256 goes into report.json's start_sha256. Not with `start`.
    std::optional<Positions> initial;
    std::string initial_sha256;
    /// How errors name the options: the command's (--grid) or Python's keywords (grid).
    Naming naming = Naming::OPTIONS;
    /// Progress, interrupts and the display while the job runs (progress.hpp).
    Monitor monitor;
};

/// A request with `values` checked, each once, and read ("command line: --grid: expected an
/// integer in [3, 100000], got '2'" or, with Naming::KEYWORDS, "grid: expected ..."); the front
/// end then sets the scene, the fabric and the monitor. The command line and the Python module
/// both build their requests here.
DrapeRequest drape_request(const DrapeValues& values, Naming naming);

/// Step 1 of a drape: the request's values checked, the scene and its overrides, threads and
/// memory, the fabric, the model. Warnings are appended to `warnings` (the front end shows
/// them). Writes nothing.
std::unique_ptr<DrapeSetup> prepare_drape(DrapeRequest request, std::vector<std::string>& warnings);

/// The one-line description the command prints before the solve.
std::string drape_banner(const DrapeSetup& setup);

/// Runs the solver (sim::drape) on the setup.
sim::Result solve_drape(const DrapeSetup& setup, const sim::ProgressCallback& progress,
                        const sim::IterationCallback& iteration);

/// The state reached, checked (RuntimeError on a non-finite position) and measured: the cut
/// cloth's surface and the corner folds over a box.
struct DrapeRun {
    const DrapeSetup* setup = nullptr;
    sim::Result result;
    bool interrupted = false;
    std::optional<render::ClothSurface> cut_surface;  ///< a cut cloth: its surface, clipped to the outline
    std::optional<analysis::FoldAnalysis> folds;      ///< over a box (the paper's cube): the corner folds
};
DrapeRun finish_drape(const DrapeSetup& setup, sim::Result result, bool interrupted);

/// report.json without its `files` (keys documented in README.md), naming `outputs` as the
/// files written besides it; `interrupted` also when a signal came since the solve.
/// RuntimeError on a non-finite number.
nlohmann::json drape_report_json(const DrapeRun& run, const std::vector<std::string>& outputs);

/// How write_drape_outputs writes.
struct DrapeWriteOptions {
    bool no_render = false;
    bool ply_ascii = false;
    int width = 1024;
    int height = 768;
    /// Progress, interrupts and the display while the job runs (progress.hpp).
    Monitor monitor;
};

/// The files `woven drape` writes in its --out directory (created if missing): drape.obj,
/// drape.ply, drape.glb, drape.png (unless no_render, or an interrupt) and report.json last, as
/// one output set (io::OutputSet). Returns the report written.
nlohmann::json write_drape_outputs(const DrapeRun& run, const std::string& out_dir, const DrapeWriteOptions& options);

/// The files of the set besides report.json.
inline const std::vector<std::string> kDrapeFiles{"drape.obj", "drape.ply", "drape.glb", "drape.png"};

}  // namespace woven::app
