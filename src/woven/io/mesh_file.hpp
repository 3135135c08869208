#pragma once
// Obstacle meshes from Wavefront OBJ files: vertices (`v`) and polygons (`f`, triangulated as
// fans); normals, texture coordinates, groups and materials are ignored.
#include <cstddef>
#include <string>
#include <string_view>

#include "woven/geometry/triangle_mesh.hpp"

namespace woven::io {

inline constexpr std::size_t kMaxObjBytes = 256u << 20;  ///< largest OBJ file read (256 MiB)
inline constexpr long long kMaxObjVertices = 10'000'000;  ///< most vertices of one mesh
inline constexpr double kMaxObjCoordinate = 1e6;           ///< largest |coordinate| in the file (file units)
/// Most rows of a mesh given as values (`vertices_m`, `faces`: woven.Obstacle.mesh): each costs
/// about 1 KB on its way in (a Python list, JSON, a TOML array: 2 M faces took 2.1 GB and 43 s),
/// so 200,000 rows are some 0.2 GB. A larger mesh is read from a file (about 100 bytes a face).
inline constexpr long long kMaxInlineMeshRows = 200'000;

/// Parses OBJ text; `source` names it in errors. Every number is checked: a coordinate that is
/// not a finite number within +-kMaxObjCoordinate, a vertex index that is not an integer, is 0,
/// overflows or is out of range are InputError "<source>:<line>: v|f: <what is expected>"; a
/// file with no (non-degenerate) faces is "<source>: faces: ...". Degenerate triangles (a
/// repeated vertex) are dropped.
geometry::TriangleMesh parse_obj_mesh(std::string_view text, const std::string& source);

/// Loads an OBJ file as parse_obj_mesh does; "<path>: file: ..." when it is missing, unreadable
/// or larger than kMaxObjBytes.
geometry::TriangleMesh load_obj_mesh(const std::string& path);

}  // namespace woven::io
