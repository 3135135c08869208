#pragma once
// The sweep job (sweep_*.cpp: shard, pool, folder, merge, checks), which `woven sweep` runs and
// shares with `woven experiment`: the shard a process runs, the run of a plan's points (resume,
// verify, jobs), each a child process of the woven program, and the merge of a sweep folder.
#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "woven/batch/sweep_plan.hpp"

namespace woven::batch {

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

struct MergeCounts {
    std::size_t done = 0, failed = 0, missing = 0;
};

/// The points (or an experiment's drapes) run at once on one machine: --jobs.
inline constexpr long long kJobsRange[2] = {1, 4096};

/// How run_sweep_points runs a plan.
struct SweepRunOptions {
    /// The woven program each point runs as a child process, with the point's command line (the
    /// command line gives its own, /proc/self/exe). Required.
    std::filesystem::path executable;
    int jobs = 1;     ///< points at once on this machine
    ShardSpec shard;  ///< the points of this process
    /// Called as each point's process starts (`woven experiment` prints what it drapes).
    std::function<void(const batch::SweepPoint&)> on_start;
    /// Gets each line the run reports, without its newline: `out` for the result (stdout),
    /// else the word on the run (stderr): the plan's counts, each point's end, a rerun's reason.
    /// Empty: nothing is shown.
    std::function<void(const std::string& line, bool out)> on_line;
};

struct SweepRunResult {
    std::size_t points = 0;       ///< in the plan
    std::size_t mine = 0;         ///< in this shard
    std::size_t done_before = 0;  ///< of this shard, complete before the run (resumed)
    std::size_t to_run = 0;       ///< of this shard, run now
    int ran = 0, failed = 0;
    int signal = 0;               ///< SIGINT / SIGTERM that stopped the run (0: none); nothing merged then
    MergeCounts merged;           ///< the merge at the end
};

/// `woven sweep`'s run of a plan, the one point loop of woven (`woven sweep` and `woven
/// experiment` both run their points here): reads every point's overridden scene and fabric
/// (InputError naming the plan and the point), creates `dir`, takes over SIGINT and SIGTERM,
/// runs the points of the shard whose folders do not verify (point_complete), `jobs` at once,
/// each as a child process, and merges sweep.csv / sweep.json. Reports a line before the run,
/// one per point and the merge's counts (SweepRunOptions::on_line).
SweepRunResult run_sweep_points(const batch::SweepPlan& plan, const std::string& dir, const SweepRunOptions& options);

/// The SIGINT / SIGTERM received since run_sweep_points took them over (0: none).
int sweep_signal_received();

/// Reads each point's overridden scene and fabric with the commands' own readers: a bad value
/// or a key the file does not have is an InputError naming the plan and the point.
void validate_sweep_overrides(const batch::SweepPlan& plan);

/// True when <dir>/<point name>/ is complete (its manifest's files verify) and its point.json
/// records the plan's command line for the point: resume skips it.
bool point_complete(const std::string& dir, const batch::SweepPoint& point);

/// An exclusive flock on a folder (a sweep folder, which ranks share) for its lifetime.
class SweepFolderLock {
public:
    explicit SweepFolderLock(const std::string& dir);
    SweepFolderLock(const SweepFolderLock&) = delete;
    SweepFolderLock& operator=(const SweepFolderLock&) = delete;
    ~SweepFolderLock();

private:
    int fd_ = -1;
};

/// Writes <dir>/sweep.json and sweep.csv (one row per point of the plan, in plan order) from
/// the point folders that verify, under an exclusive lock on the folder; idempotent.
MergeCounts merge_sweep(const batch::SweepPlan& plan, const std::string& dir);

}  // namespace woven::batch
