#pragma once
// The obstacles of a scene file ([[obstacle]] tables), one builder per `type` (see
// docs/SCENE-FORMAT.md), and the lookup of the files compiled into the binary.
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "woven/geometry/obstacle.hpp"
#include "woven/io/toml_reader.hpp"

namespace woven::io {

/// What an obstacle builder needs besides its table.
struct ObstacleContext {
    std::string base_dir;  ///< folder that relative mesh paths resolve against
    bool builtin = false;  ///< a built-in scene: meshes come from the embedded assets
};

/// Builds the obstacle of one [[obstacle]] table; `kind` receives its `type`. Every number is
/// range-checked; errors name the table's field ("obstacle[2].radius_m").
std::unique_ptr<geometry::Obstacle> build_obstacle(const TomlTable& table, const ObstacleContext& context,
                                                   std::string& kind);

/// The embedded (built-in) file at `path` ("scenes/cube.toml"), if any.
std::optional<std::string_view> embedded_file(const std::string& path);

/// Lexically normalised generic path ("a/b/../c" -> "a/c").
std::string normal_path(const std::filesystem::path& p);

}  // namespace woven::io
