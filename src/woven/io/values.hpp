#pragma once
// Fabrics and scenes from values held in memory (a tree of objects, arrays, strings, numbers and
// booleans, here a nlohmann::json document): what a Python caller passes as dicts and keyword
// arguments. The tree is made into the TOML document it stands for (table_from_values,
// toml_reader.hpp) and read by the files' own readers, so a value has the same names, ranges,
// messages and warnings as in a file; messages name `source` and the dotted field, without a line.
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "woven/io/scene_file.hpp"
#include "woven/kes/fabric.hpp"

namespace woven::io {

/// A fabric (docs/FABRIC-FORMAT.md) from values; InputError "<source>: <field>: ..." as
/// parse_fabric. Unknown keys and range warnings are appended to `warnings` (when given).
kes::FabricData fabric_from_values(const nlohmann::json& values, const std::string& source,
                                   std::vector<std::string>* warnings = nullptr);

/// A scene (docs/SCENE-FORMAT.md) from values, its relative mesh and fabric paths resolved
/// against `base_dir`; InputError and warnings as parse_scene.
SceneSpec scene_from_values(const nlohmann::json& values, const std::string& source, const std::string& base_dir,
                            std::vector<std::string>* warnings = nullptr);

/// One obstacle (a scene's [[obstacle]] table, docs/SCENE-FORMAT.md) from values, built and
/// checked as the scene reader builds it; `kind` receives its type. InputError "<source>:
/// <field>: ..."; unknown keys are appended to `warnings` (when given).
std::unique_ptr<geometry::Obstacle> obstacle_from_values(const nlohmann::json& values, const std::string& source,
                                                         const std::string& base_dir, std::string* kind = nullptr,
                                                         std::vector<std::string>* warnings = nullptr);

}  // namespace woven::io
