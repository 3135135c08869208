#pragma once
// `woven drape` in its stages, so that the command (cmd_drape.cpp) and the Python module
// (python/) run the same code and write the same files: prepare_drape validates and builds the
// model, solve_drape runs the solver, finish_drape checks and measures the state reached,
// drape_report_json makes report.json and write_drape_outputs writes the output set.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "woven/analysis/folds.hpp"
#include "woven/cli/commands.hpp"
#include "woven/cli/run_checks.hpp"
#include "woven/io/scene_file.hpp"
#include "woven/kes/fabric.hpp"
#include "woven/model/cloth_model.hpp"
#include "woven/model/outline.hpp"
#include "woven/render/drape_view.hpp"
#include "woven/sim/drape.hpp"

namespace woven::cli {

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

/// A scene or fabric given as an object rather than by `DrapeOptions::scene` / `fabric` (the
/// Python module's woven.Scene, woven.Fabric).
struct DrapeInputs {
    std::optional<io::SceneSpec> scene;        ///< absent: io::find_scene(options.scene)
    std::optional<kes::FabricData> fabric;     ///< absent: options.fabric, else the scene's
    std::string fabric_source;                 ///< names `fabric` in the fitting's errors
};

/// Step 1 of `woven drape`: the options (grid, solver, seed, threads, max-steps, perturb;
/// InputError "command line: --<option>: ..." as the command), the scene and its overrides,
/// threads and memory, the fabric, the model. Warnings are appended to `warnings` (the command
/// prints them). Writes nothing.
std::unique_ptr<DrapeSetup> prepare_drape(const DrapeOptions& options, std::vector<std::string>& warnings,
                                          DrapeInputs inputs = {});

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
};

/// The files `woven drape` writes in its --out directory (created if missing): drape.obj,
/// drape.ply, drape.glb, drape.png (unless no_render, or an interrupt) and report.json last, as
/// one output set (io::OutputSet). Returns the report written.
nlohmann::json write_drape_outputs(const DrapeRun& run, const std::string& out_dir, const DrapeWriteOptions& options);

/// The files of the set besides report.json.
inline const std::vector<std::string> kDrapeFiles{"drape.obj", "drape.ply", "drape.glb", "drape.png"};

}  // namespace woven::cli
