#pragma once
// Obstacle meshes from Wavefront OBJ files (tinyobjloader), triangulated.
#include <string>
#include <string_view>

#include "woven/geometry/triangle_mesh.hpp"

namespace woven::io {

/// Loads an OBJ file as one triangle mesh (m): the vertices and the faces of every shape, with
/// polygons triangulated as fans; normals, texture coordinates and materials are ignored.
/// Throws InputError "<path>: file: ..." for a missing or unreadable file, and
/// "<path>: faces: ..." for a file with no faces or with a vertex index out of range.
geometry::TriangleMesh load_obj_mesh(const std::string& path);

/// Parses OBJ text (e.g. an embedded asset) as load_obj_mesh does; `source` names it in errors.
geometry::TriangleMesh parse_obj_mesh(std::string_view text, const std::string& source);

}  // namespace woven::io
