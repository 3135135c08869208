#pragma once
// What the pieces of the sweep job share (batch/sweep_*.cpp): its folder's files and the state of
// a point's folder, and the checks made before the points run. Not a public header.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "woven/batch/sweep_plan.hpp"

namespace woven::batch {

/// Writes `text` to `path` through a unique temporary in the same folder and a rename.
void write_atomic(const std::filesystem::path& path, const std::string& text);

/// What the plan asks of a point, as point.json records it: a finished folder is this point's
/// only when these match.
nlohmann::json point_signature(const batch::SweepPoint& p);

/// A JSON file of the sweep folder (point.json, a manifest, a failure record), read as
/// io::read_output_json reads it; nullopt (and the reason in `why`) when it cannot be.
std::optional<nlohmann::json> read_sweep_json(const std::filesystem::path& p, std::string* why = nullptr);
/// The manifest of a point's folder (kManifests), if it reads.
std::optional<nlohmann::json> read_manifest(const std::filesystem::path& dir);

/// A value as JSON: a number as a number (integers as integers), else the text.
nlohmann::json value_json(const batch::SweepValue& v);
/// A point as point.json and sweep.json's rows name it: {"point", "index", "values": {key: value}}.
nlohmann::json point_json(const batch::SweepPoint& p);

/// The sweep's own folders (.work, failed) are made here, never followed: a symlink planted in
/// their place (which would send failure records or work folders elsewhere) is bad usage.
void require_own_folders(const std::filesystem::path& sweep);

/// A point's status in the sweep folder.
struct PointState {
    bool done = false;
    std::string problem;  ///< why a folder that is there does not count ("" when absent)
};
PointState point_state(const std::filesystem::path& sweep, const batch::SweepPoint& p);

/// The launcher's ranks on this node, which share its cores (1 when none is known).
int local_ranks();

/// A drape plan's points (and so an experiment's drapes) are held to the drape's memory
/// estimate before the first starts: the largest of the points to run (up to 1,000 distinct
/// scenes and grids looked at), `jobs` of them at once sharing the machine's memory, each its
/// own address space.
void check_points_memory(const batch::SweepPlan& plan, const std::vector<std::size_t>& todo, int jobs, int threads);

}  // namespace woven::batch
