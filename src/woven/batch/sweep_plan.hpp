#pragma once
// Sweep plans (docs/SWEEP-FORMAT.md): a TOML file naming one command (drape, cusick or kes-test),
// the axes whose Cartesian product are the sweep's points, and the options every point shares.
// Each point becomes one command line of that command and one result folder, named from its
// axis values. Read with the TomlReader: errors "<file>: <field>: <what is expected>".
#include <cstddef>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace woven::batch {

/// The largest number of points a plan may have.
inline constexpr std::size_t kMaxSweepPoints = 1'000'000;

/// One value of an axis or of a shared option, as the command line takes it.
struct SweepValue {
    std::string key;    ///< the plan's key ("seed", "spacing_cm", "scene.cloth.grid")
    std::string text;   ///< the command-line text ("1", "0.5", a resolved file path)
    std::string label;  ///< the value as the folder name shows it ("1", "0.5", a file's stem)
    bool number = false;
};

struct SweepAxis {
    std::string key;
    std::vector<SweepValue> values;
};

/// One point: its values (one per axis, in axis order), its folder name and its command line.
struct SweepPoint {
    std::size_t index = 0;          ///< position in the plan's order (0-based)
    std::string name;               ///< folder name, e.g. "fabric-cotton_seed-1"
    std::vector<SweepValue> values; ///< one per axis
    /// The command line after the binary, without --out: the command, then its arguments.
    /// Keys `scene.<key>` / `fabric.<key>` are not in it: they are the point's overrides.
    std::vector<std::string> args;
    /// Overrides of the scene's and the fabric's own TOML keys ("cloth.grid", "bending_scale"),
    /// applied to a copy of the scene / fabric file written for the point.
    std::vector<SweepValue> scene_overrides, fabric_overrides;
};

struct SweepPlan {
    std::string source;       ///< the plan's path (errors name it)
    std::string name;         ///< `name`, default the file's stem
    std::string description;
    std::string command;      ///< "drape", "cusick" or "kes-test"
    std::vector<SweepAxis> axes;
    std::vector<SweepValue> fixed;  ///< [options]: the same for every point
    bool render = true;             ///< false: --no-render

    std::size_t size() const;
    /// Point `index` (< size()), made on demand: a plan of a million points is listed without
    /// holding them all.
    SweepPoint point(std::size_t index) const;
    /// Every point, in plan order: the last axis varies fastest.
    std::vector<SweepPoint> points() const;
};

/// Parses a plan; `base_dir` resolves relative fabric and scene file paths. Unknown keys are
/// appended to `warnings`.
SweepPlan parse_sweep_plan(std::string_view text, const std::string& source, const std::string& base_dir,
                           std::vector<std::string>* warnings = nullptr);
/// Reads a plan file (io::read_input_file: "<path>: file: no such plan file" when missing, a FIFO
/// or a device refused as not a regular file).
SweepPlan load_sweep_plan(const std::string& path, std::vector<std::string>* warnings = nullptr);

/// The TOML text `text` with each override's dotted key set to its value (a number or a
/// string, replacing what was there or adding it). InputError naming `source` and the key when
/// a part of the key is not a table.
std::string apply_toml_overrides(std::string_view text, const std::string& source, const std::vector<SweepValue>& overrides);

/// The TOML text of a built-in scene or fabric, or of a file (`kind`: "scene" or "fabric").
std::string scene_or_fabric_text(const std::string& name_or_path, const std::string& kind);

}  // namespace woven::batch
