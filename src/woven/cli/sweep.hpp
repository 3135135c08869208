#pragma once
// What `woven sweep` (cmd_sweep.cpp) shares with `woven report` and the tests: the shard a
// process runs, the merge of a sweep folder and the main outputs of a point's manifest.
#include <cstddef>
#include <functional>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "woven/io/sweep_plan.hpp"

namespace woven::cli {

/// Shard `index` of `count` (0-based): the points whose index modulo count is index.
struct ShardSpec {
    int index = 0;
    int count = 1;
    std::string source = "one process";  ///< "--shard", "Open MPI", "PMI", "Slurm array"
};

/// The shard from --shard I/N (when given), else from the launcher's environment read through
/// `env` (getenv): OMPI_COMM_WORLD_RANK/SIZE, PMI_RANK/SIZE, SLURM_ARRAY_TASK_ID/COUNT (with
/// SLURM_ARRAY_TASK_MIN/STEP), else the whole plan. Bad values: InputError naming the option or
/// the variable.
ShardSpec shard_from(const std::optional<std::string>& option, const std::function<const char*(const char*)>& env);

/// True when point `point_index` belongs to shard `s`.
bool in_shard(std::size_t point_index, const ShardSpec& s);

/// The main outputs of a point from its manifest, one flat object per command: drape (energy_J,
/// max_residual_rel, converged, steps, folds...), cusick (drape_coefficient_percent and _std,
/// nodes per run, energy_J...), kes-test (each test's simulated and input summary values).
nlohmann::json point_outputs(const std::string& command, const nlohmann::json& manifest);

struct MergeCounts {
    std::size_t done = 0, failed = 0, missing = 0;
};

/// Writes <dir>/sweep.json and sweep.csv (one row per point of the plan, in plan order) from
/// the point folders that verify, under an exclusive lock on the folder; idempotent.
MergeCounts merge_sweep(const io::SweepPlan& plan, const std::string& dir);

}  // namespace woven::cli
