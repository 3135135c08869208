#pragma once
// `woven garment FILE`: a garment's pattern pieces cut from the fabric's thread grid, placed
// around the body, sewn and draped (docs/GARMENT-FORMAT.md). The seams are pulled closed by a
// stiffness ramped over successive drapes (each from the state the last reached) and then held;
// the report gives what a designer reads: the hem's nodes, radius per angle and flare, its
// height, and each seam's gaps and forces.
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "woven/app/progress.hpp"
#include "woven/app/run_checks.hpp"
#include "woven/geometry/obstacle.hpp"
#include "woven/io/garment_file.hpp"
#include "woven/kes/fabric.hpp"
#include "woven/model/cloth_model.hpp"
#include "woven/model/garment.hpp"
#include "woven/sim/drape.hpp"

namespace woven::app {

/// What to drape: a garment file, and overrides of its values (absent: the file's).
struct GarmentRequest {
    std::string file;
    std::optional<std::string> fabric;  ///< a built-in fabric name or a fabric .toml file
    std::optional<double> spacing_cm;   ///< io::kGarmentSpacingCm
    std::optional<int> threads;         ///< 0: all cores
    std::optional<int> max_steps;       ///< per stage, 0: the solver's default
    std::optional<std::uint64_t> seed;
};

/// A garment ready to drape: its pieces cut and sewn, the body, the model. Not copied.
struct GarmentSetup {
    io::GarmentSpec spec;
    kes::FabricData fabric;
    std::string fabric_label;
    model::GarmentCloth cloth;
    std::optional<model::ClothModel> model;
    geometry::ObstacleSet body;
    sim::SolverOptions solver;
    /// N/m, the ramp's stages: the file's, else E_t (the thread's tensile stiffness) alone when
    /// every seam starts closed (gaps within half a spacing), else E_t x 0.01, 0.1, 1.
    std::vector<double> seam_stiffness;
    ThreadCount threads;
    /// The memory the run was checked against before it started (check_memory: the grid's
    /// particles and the threads used); report.json's memory_estimate_bytes is its resident part.
    sim::MemoryEstimate memory;
    double waist_radius_m = 0, waist_height_m = 0;  ///< of the waist particles at the start
    /// The particles held where they start: the waist's, but for those a seam stitches (two
    /// edges' ends held apart could not close).
    std::vector<int> held;

    GarmentSetup() = default;
    GarmentSetup(const GarmentSetup&) = delete;
    GarmentSetup& operator=(const GarmentSetup&) = delete;
};

/// Reads the file, applies the overrides, cuts and sews the pattern, builds the body and the
/// model and checks the start: InputError (exit 2) for bad input, a piece that starts inside
/// the body (its field "piece[k].place") or a seam whose stitches pass through the body
/// ("seam[k]"). Writes nothing.
std::unique_ptr<GarmentSetup> prepare_garment(const GarmentRequest& request, std::vector<std::string>& warnings);

/// One stage of the ramp, for progress.
struct GarmentStage {
    int stage = 0;         ///< from 1
    double stiffness = 0;  ///< N/m
    sim::Result result;
};

/// The drape: one sim::drape per stage of the seam stiffness ramp, each from the last state.
struct GarmentRun {
    Positions x;
    std::vector<GarmentStage> stages;
    sim::Result total;  ///< counters summed; the last stage's energy, equilibrium, converged
    bool interrupted = false;
};

/// Called before each stage: its number (from 1), the stages, the seams' stiffness (N/m).
using StageCallback = std::function<void(int stage, int stages, double stiffness)>;

/// Runs the stages; `progress` and `iteration` as sim::drape's (false stops).
GarmentRun solve_garment(GarmentSetup& setup, const sim::ProgressCallback& progress = {}, const sim::IterationCallback& iteration = {},
                         const StageCallback& on_stage = {});

/// The hem and seam measures of a state (report.json's "hem", "waist", "seams").
struct HemMeasures {
    std::vector<double> angle_deg;  ///< bin centres, 5 degrees apart, from +x towards +y
    std::vector<double> radius_m;   ///< the hem's mean radius from the body's axis in each bin
    std::vector<double> height_m;   ///< its mean height in each bin
    int nodes = 0;
    std::vector<double> node_angle_deg;           ///< each node's azimuth (its peak refined between bins), in [0, 360)
    double mean_radius_m = 0, flare = 0;          ///< flare: mean hem radius / waist radius
    double mean_height_m = 0, length_drop_m = 0;  ///< length drop: highest minus lowest bin of the hem
    double min_prominence_m = 0;
};
HemMeasures hem_measures(const GarmentSetup& setup, const Positions& x);

/// report.json of a garment drape (SI units).
nlohmann::json garment_report(const GarmentSetup& setup, const GarmentRun& run);

/// Writes garment.glb (the sewn cloth and the body), garment.png (unless no_render) and
/// report.json last (naming the others with their SHA-256) to `dir`; returns the report.
nlohmann::json write_garment_outputs(const GarmentSetup& setup, const GarmentRun& run, const std::string& dir, int width, int height,
                                     bool no_render);

/// The whole job as the Python module runs it (woven.garment): prepare, the stages with their
/// progress events (app/progress.hpp, one Progress per stage) under `monitor`, the outputs.
struct GarmentJob {
    nlohmann::json report;
    std::vector<std::string> warnings;
    bool interrupted = false;
};
GarmentJob garment(const GarmentRequest& request, const std::string& out_dir, int width, int height, bool render, const Monitor& monitor);

/// The cloth's surface: each piece cut to its outline (model::cut_surface), merged.
geometry::TriangleMesh garment_surface(const GarmentSetup& setup, const Positions& x, std::vector<Vec2>* uv);

}  // namespace woven::app
